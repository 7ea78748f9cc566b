// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/bim/reference_session.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>

#include "algorithms/common/se3.hpp"
#include "algorithms/common/status.hpp"
#include "algorithms/common/stopwatch.hpp"
#include "algorithms/io/trajectory.hpp"
#include "algorithms/scancontext/descriptor.hpp"
#include "algorithms/scancontext/session_descriptor.hpp"
#include "algorithms/simulation/scene.hpp"
#include "host_tools/bim/reference_walk.hpp"

namespace bimslam::bim {
namespace {
using common::StatusCode;
using Clock = std::chrono::steady_clock;

// Per-pixel ray origin and direction of the sensor (the driver's XYZ table), computed once.
struct RayTable {
    std::vector<Eigen::Vector3f> direction, origin;
    std::vector<uint32_t> column_offset_ns;
    explicit RayTable(const simulation::LidarModel& m) {
        for (int u = 0; u < m.beams(); ++u) {
            for (int v = 0; v < m.columns; ++v) {
                direction.push_back(m.Direction(u, v).cast<float>());
                origin.push_back(m.Origin(u, v).cast<float>());
            }
        }
        for (int v = 0; v < m.columns; ++v) {
            column_offset_ns.push_back(uint32_t(m.ColumnTimeOffsetNs(v)));
        }
    }
};

// The scan's points in the sensor frame, as the driver decodes a real frame (ouster::ToPointCloud):
// range * direction + origin, intensity = reflectivity, ring = beam, t = the column's time.
void ToCloud(const simulation::ScanImage& img, const RayTable& rays, int64_t stamp_ns,
             common::PointCloud* cloud) {
    cloud->Clear();
    cloud->stamp = common::SensorTime{stamp_ns};
    cloud->frame = "os_sensor";
    for (int v = 0; v < img.w; ++v) {
        for (int u = 0; u < img.h; ++u) {
            const size_t i = img.Index(u, v);
            if (img.range_mm[i] == 0) continue;
            const float r = 1e-3f * float(img.range_mm[i]);
            cloud->PushBack(r * rays.direction[i] + rays.origin[i], float(img.reflectivity[i]),
                            uint16_t(u), rays.column_offset_ns[v]);
        }
    }
}
}  // namespace

void ReferenceSessionOptions::Validate() const {
    if (!(keyframe_gap_m >= 0.05 && keyframe_gap_m <= 100)) {
        throw common::Error(
            StatusCode::kInvalidArgument,
            "keyframe gap " + std::to_string(keyframe_gap_m) + " m: must be in [0.05, 100] m");
    }
    lidar.Validate();
    noise.Validate();
    grid.Validate();
    path.Validate();
}

std::string StoreyFileStem(const std::string& storey_name) {
    std::string out;
    for (const char c : storey_name) {
        if (std::isalnum(static_cast<unsigned char>(c))) {
            out += char(std::tolower(static_cast<unsigned char>(c)));
        } else if (!out.empty() && out.back() != '_') {
            out += '_';
        }
    }
    while (!out.empty() && out.back() == '_') out.pop_back();
    return out.empty() ? "storey" : out;
}

void WriteStoreyPlan(const std::filesystem::path& dir, const OccupancyGrid& grid,
                     const CoveragePath& path) {
    std::filesystem::create_directories(dir);
    const std::string stem = StoreyFileStem(grid.storey);
    WriteGrid(grid, dir / stem);
    io::WritePng(dir / (stem + "_path.png"), PathImage(grid, path));
    io::WriteTum(dir / (stem + "_path.tum"), path.poses);
}

namespace {

// Step 1's report: each walked storey's grid and walk (its other regions added to it), written
// to options.plan_dir when given.
void ReportPlan(const ReferenceWalk& walk, const ReferenceSessionOptions& options,
                ReferenceSessionReport& report) {
    for (size_t k = 0; k < walk.storeys.size(); ++k) {
        const CoveragePath& path = walk.coverage[k];
        if (!options.plan_dir.empty()) WriteStoreyPlan(options.plan_dir, walk.grids[k], path);
        StoreyReport sr;
        sr.name = walk.grids[k].storey;
        sr.rooms = path.rooms;
        sr.viewpoints = int(path.viewpoints.size());
        sr.unreachable_viewpoints = path.unreachable_viewpoints;
        sr.free_area_m2 =
            double(walk.grids[k].FreeCells()) * walk.grids[k].resolution * walk.grids[k].resolution;
        sr.walk_m = path.length_m;
        sr.walk_s = path.duration_s;
        report.storeys.push_back(sr);
    }
    for (const RegionWalk& r : walk.more_regions) {
        const size_t k = size_t(std::find(walk.storeys.begin(), walk.storeys.end(), r.storey) -
                                walk.storeys.begin());
        if (!options.plan_dir.empty()) {
            OccupancyGrid named = r.grid;  // its own files beside the storey's
            named.storey += " region " + std::to_string(r.region + 1);
            WriteStoreyPlan(options.plan_dir, named, r.coverage);
        }
        StoreyReport& sr = report.storeys[k];
        ++sr.regions;
        sr.rooms += r.coverage.rooms;
        sr.viewpoints += int(r.coverage.viewpoints.size());
        sr.unreachable_viewpoints += r.coverage.unreachable_viewpoints;
        sr.free_area_m2 += double(r.grid.FreeCells()) * r.grid.resolution * r.grid.resolution;
        sr.walk_m += r.coverage.length_m;
        sr.walk_s += r.coverage.duration_s;
    }
    for (const auto& piece : walk.pieces)
        report.walk_s += 1e-9 * double(piece.back().stamp_ns - piece.front().stamp_ns);
    report.flights_walked = walk.flights_walked;
    report.notes = walk.notes;
}

io::SessionManifest Manifest(const BimModel& model, const std::string& model_sha256,
                             const ReferenceWalk& walk, const ReferenceSessionOptions& options,
                             const scancontext::ScanContextConfig& sc) {
    io::SessionManifest manifest;
    manifest.source = "bim";
    manifest.world_frame = "bim";
    manifest.sensor = {options.sensor_model, options.lidar.beams(), options.lidar.columns,
                       options.metadata_file};
    manifest.keyframe = {options.keyframe_gap_m, 360.0};  // by distance along the walk only
    manifest.descriptor = scancontext::SessionDescriptor(sc);
    io::SessionManifest::Model m;
    m.file = std::filesystem::path(model.file).filename().string();
    m.sha256 = model_sha256;
    for (const int s : walk.storeys) m.storeys.push_back(model.storeys[s].name);
    manifest.model = m;
    return manifest;
}

// Step 3: the keyframes cast from the scene along the walk, written with their descriptors and
// their exact edges.
class KeyframeCaster {
public:
    KeyframeCaster(const simulation::Scene& scene, const ReferenceWalk& walk,
                   const ReferenceSessionOptions& options, io::SessionWriter& writer,
                   ReferenceSessionReport& report)
        : scene_(scene),
          walk_(walk),
          options_(options),
          writer_(writer),
          report_(report),
          rays_(options.lidar),
          builder_(scancontext::ScanContextConfig::Indoor()) {
        for (const StoreyReport& sr : report.storeys)
            planned_ += size_t(sr.walk_m / options.keyframe_gap_m) + 1;
        planned_ += size_t(walk.flight_m / options.keyframe_gap_m);
    }

    // Frames at the sensor's rate along each piece of the walk; a keyframe every gap metres.
    void Run() {
        for (const std::vector<io::StampedPose>& piece : walk_.pieces) {
            double since_key = options_.keyframe_gap_m;  // the piece's first frame is a keyframe
            Eigen::Vector3d last = piece.front().translation;
            for (const io::StampedPose& frame : SampleWalk(piece, options_.lidar.frame_rate_hz)) {
                const Eigen::Isometry3d T = frame.Pose();
                writer_.AddScanPose(frame);
                since_key += (T.translation() - last).norm();
                last = T.translation();
                if (since_key < options_.keyframe_gap_m) continue;
                since_key = 0;
                Keyframe(frame.stamp_ns, T);
            }
        }
    }

private:
    void Keyframe(int64_t t, const Eigen::Isometry3d& T) {
        const auto t_sim = Clock::now();
        io::SessionKeyframe kf;
        kf.stamp_ns = t;
        kf.T_world_lidar = T;
        const auto stats =
            simulation::SimulateScan(scene_, options_.lidar, T, options_.noise,
                                     options_.seed ^ uint64_t(report_.keyframes), &image_);
        report_.rays += stats.rays;
        ToCloud(image_, rays_, t, &kf.cloud);
        builder_.Build(kf.cloud, &kf.descriptor);
        report_.points += kf.cloud.size();
        report_.simulate_s += common::SecondsSince(t_sim);

        const auto t_write = Clock::now();
        const size_t i = writer_.AddKeyframe(kf);
        if (previous_key_) {
            // Ground truth: the edge is exact; 1 mm and 1 mrad keep the graph well scaled.
            io::SessionEdge e{uint32_t(i - 1), uint32_t(i), common::Between(*previous_key_, T),
                              common::Matrix6d::Identity()};
            e.information.diagonal().setConstant(1e6);
            writer_.AddEdge(e);
        }
        report_.write_s += common::SecondsSince(t_write);
        previous_key_ = T;
        ++report_.keyframes;
        const WalkSegment& seg = walk_.SegmentAt(t);
        if (seg.flight) {
            ++report_.flight_keyframes;
        } else {
            const size_t k =
                size_t(std::find(walk_.storeys.begin(), walk_.storeys.end(), seg.storey) -
                       walk_.storeys.begin());
            ++report_.storeys[k].keyframes;
        }
        if (options_.progress) options_.progress(report_.keyframes, planned_);
    }

    const simulation::Scene& scene_;
    const ReferenceWalk& walk_;
    const ReferenceSessionOptions& options_;
    io::SessionWriter& writer_;
    ReferenceSessionReport& report_;
    const RayTable rays_;
    scancontext::DescriptorBuilder builder_;
    simulation::ScanImage image_;
    std::optional<Eigen::Isometry3d> previous_key_;
    size_t planned_ = 0;
};

}  // namespace

ReferenceSessionReport WriteReferenceSession(const BimModel& model, const std::string& model_sha256,
                                             const std::filesystem::path& dir,
                                             const ReferenceSessionOptions& options) {
    options.Validate();
    const std::vector<int> storeys = StoreyIndices(model, options.storeys);
    if (storeys.empty()) {
        throw common::Error(StatusCode::kInvalidArgument,
                            model.file + ": the model has no storeys");
    }
    ReferenceSessionReport report;

    // 1. Plan: a grid and a coverage walk per storey, joined by the flights between them.
    const auto t_plan = Clock::now();
    const ReferenceWalk walk = PlanReferenceWalk(model, storeys, options.grid, options.path);
    ReportPlan(walk, options, report);
    report.plan_s = common::SecondsSince(t_plan);

    // 2. The scene: the paper's semantic filter keeps the permanent structure.
    const BimModel structure =
        options.all_elements ? BimModel{} : SelectElements(model, [](const BimElement& e) {
            return e.role == ElementRole::kStructure;
        });
    const BimModel& cast = options.all_elements ? model : structure;
    const simulation::Scene scene(cast.mesh, cast.triangle_element);
    // Offline and re-runnable: the line files are rewritten every 50 keyframes, and the files are
    // synced once before session.json rather than each on its own (milliseconds each).
    io::SessionWriter writer(
        dir, Manifest(model, model_sha256, walk, options, scancontext::ScanContextConfig::Indoor()),
        {.overwrite = options.overwrite, .flush_every = 50, .sync_each_file = false});

    // 3. Frames at the sensor's rate along each walk; a keyframe every gap metres of it.
    KeyframeCaster(scene, walk, options, writer, report).Run();
    const auto t_finish = Clock::now();
    writer.Finish();
    report.write_s += common::SecondsSince(t_finish);
    return report;
}

}  // namespace bimslam::bim
