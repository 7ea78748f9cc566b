// bimslam demo: the main job end to end on data the project makes itself. It grows with every
// issue; for now: write the sample building as IFC and read it back (IFC++), turn it into its
// BIM reference session (Step 1: grids, walks through every room, simulated scans), record a
// rig's walk through the same building as an Ouster capture (pcap + metadata), decode the
// capture with the driver into keyframes with Scan Context descriptors, write them as a session,
// read the session back and check it bit for bit, and recognise the rig's places among the
// reference's keyframes.
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "algorithms/common/se3.hpp"
#include "algorithms/common/status.hpp"
#include "algorithms/io/session.hpp"
#include "algorithms/scancontext/candidate_index.hpp"
#include "algorithms/scancontext/descriptor.hpp"
#include "drivers/ouster/builtin_sensor.hpp"
#include "drivers/ouster/metadata.hpp"
#include "host_tools/capture/ouster_capture.hpp"
#include "host_tools/cli/command.hpp"
#include "host_tools/cli/demo_capture.hpp"
#include "algorithms/io/sha256.hpp"
#include "host_tools/bim/coverage_path.hpp"
#include "host_tools/bim/ifc_model.hpp"
#include "host_tools/bim/reference_session.hpp"
#include "host_tools/bim/sample_building.hpp"

namespace bimslam::cli {
namespace {
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct DemoOptions {
    std::string out = "demo_output";
    bool overwrite = false;
    int columns = 1024;
    int laps = 1;
};

double Seconds(Clock::time_point since) {
    return std::chrono::duration<double>(Clock::now() - since).count();
}

double Yaw(const Eigen::Isometry3d& T) { return std::atan2(T.linear()(1, 0), T.linear()(0, 0)); }

std::string FixedString(double v) {
    std::ostringstream s;
    s << std::fixed << std::setprecision(1) << v;
    return s.str();
}

double WrapAngle(double a) { return std::remainder(a, 2.0 * M_PI); }

uintmax_t FolderBytes(const fs::path& dir) {
    uintmax_t bytes = 0;
    for (const auto& e : fs::recursive_directory_iterator(dir)) {
        if (e.is_regular_file()) bytes += e.file_size();
    }
    return bytes;
}

// Bit-identical xyz, intensity and ring. The per-point time is stored as float32 seconds
// (specs/session-data.md), exact to a few ns only: its largest error goes to max_t_error_ns.
bool SameCloud(const common::PointCloud& a, const common::PointCloud& b, int64_t& max_t_error_ns) {
    if (a.size() != b.size() || a.time_offset_ns.size() != b.time_offset_ns.size()) return false;
    for (size_t i = 0; i < a.time_offset_ns.size(); ++i) {
        max_t_error_ns = std::max<int64_t>(
            max_t_error_ns, std::abs(int64_t(a.time_offset_ns[i]) - int64_t(b.time_offset_ns[i])));
    }
    return a.xyz == b.xyz && a.intensity == b.intensity && a.ring == b.ring;
}

int RunDemo(const DemoOptions& opt) {
    const auto t_start = Clock::now();
    const fs::path out = opt.out;
    const fs::path building_file = out / "building.ifc";
    const fs::path reference_dir = out / "reference";
    const fs::path plan_dir = out / "plan";
    const fs::path session_dir = out / "session";
    const fs::path capture_dir = out / "capture";
    for (const fs::path& p : {building_file, reference_dir, session_dir, capture_dir}) {
        if (fs::exists(p) && !opt.overwrite) {
            throw common::FileError(common::StatusCode::kAlreadyExists, out.string(), 0,
                                    "holds an earlier demo; pass --overwrite or choose another --out");
        }
    }
    fs::remove_all(capture_dir);
    fs::create_directories(capture_dir);
    std::cout << std::fixed << std::setprecision(1);

    // 1. The building: the project's sample office as IFC4, read back through IFC++.
    const auto t_building = Clock::now();
    bim::WriteSampleBuilding(building_file);
    const bim::BimModel model = bim::LoadIfc(building_file);
    std::cout << "bimslam demo: the sample office building, " << model.storeys.size()
              << " storeys, " << model.elements.size() << " elements, "
              << model.mesh.triangles.size() << " triangles (IFC4 written and read back through "
              << "IFC++ in " << std::setprecision(2) << Seconds(t_building) << " s)\n"
              << std::setprecision(1) << "           " << building_file.string() << "\n";

    // 2. Step 1: its reference session, scans simulated along a walk through every room.
    bim::ReferenceSessionOptions ro;
    ro.plan_dir = plan_dir;
    ro.overwrite = opt.overwrite;
    ro.lidar = simulation::LidarModel::DefaultOs1_32(opt.columns);
    const auto t_reference = Clock::now();
    const bim::ReferenceSessionReport ref =
        bim::WriteReferenceSession(model, io::Sha256File(building_file), reference_dir, ro);
    const double reference_s = Seconds(t_reference);
    int rooms = 0;
    double walk_m = 0;
    for (const auto& st : ref.storeys) {
        rooms += st.rooms;
        walk_m += st.walk_m;
    }
    std::cout << "  reference " << ref.keyframes << " keyframes along " << walk_m
              << " m of walk through " << rooms << " rooms, the structure ray-cast in "
              << reference_s << " s (" << std::setprecision(0) << ref.walk_s / reference_s
              << "x real time at 0.5 m/s)\n" << std::setprecision(1) << "           "
              << reference_dir.string() << ", grids and walks in " << plan_dir.string() << "\n";

    // 3. The rig's walk of the ground floor, recorded as an Ouster capture (pcap + metadata) as a
    //    real rig would save it: the same rooms at a Go1's pace (1 m/s), starting halfway round
    //    and 0.15 m beside the reference walk, in the real building: furniture and doors, which
    //    the reference leaves out, are there.
    bim::PathConfig rig_path;
    rig_path.speed_mps = 1.0;
    const bim::OccupancyGrid grid = bim::BuildOccupancyGrid(model, 0, {});
    const bim::CoveragePath walk = bim::PlanCoveragePath(grid, rig_path);
    const double lap_m = walk.length_m;
    // The low-data-rate profile (8 mm range steps) keeps the demo's capture small.
    const ouster::SensorInfo sensor =
        ouster::BuiltinOs1_32(ouster::LidarProfile::kRng15Rfl8Nir8, opt.columns, 10);
    const std::vector<io::StampedPose> lap = bim::SampleWalk(walk.poses, sensor.frame_rate_hz);
    const int frames_per_lap = static_cast<int>(lap.size());
    std::vector<Eigen::Isometry3d> poses;
    Eigen::Isometry3d beside = Eigen::Isometry3d::Identity();
    beside.translation().y() = 0.15;  // to the left of the walk
    for (int k = 0; k < opt.laps * frames_per_lap; ++k) {
        poses.push_back(lap[size_t((k + frames_per_lap / 2) % frames_per_lap)].Pose() * beside);
    }
    const simulation::Scene world(model.mesh, model.triangle_element);
    simulation::NoiseModel noise;
    noise.range_resolution_mm = 8;
    const auto t_capture = Clock::now();
    const DemoCapture capture = WriteDemoCapture(world, poses, sensor, capture_dir, noise, 7);
    std::cout << "  captured " << poses.size() << " frames (" << opt.laps << " x " << lap_m
              << " m of the ground floor) of a built-in OS-1-32 "
              << ToString(sensor.format.lidar_profile) << " " << sensor.lidar_mode << ": "
              << capture.packets << " lidar packets in IPv4 fragments, "
              << fs::file_size(capture.pcap) / 1e6 << " MB, in " << Seconds(t_capture)
              << " s\n           " << capture.pcap.string() << " + "
              << capture.metadata.filename().string() << "\n";

    // 4. Decode it like any real recording; keep keyframes (1 m / 10 deg, on the true poses
    //    until the LiDAR odometry exists) with indoor Scan Context descriptors.
    const auto t_decode = Clock::now();
    const ouster::SensorInfo info = ouster::LoadMetadata(capture.metadata);
    capture::OusterCapture reader(capture.pcap, info);
    const scancontext::ScanContextConfig sc = scancontext::ScanContextConfig::Indoor();
    scancontext::DescriptorBuilder builder(sc);
    io::SessionManifest manifest;
    manifest.source = "simulation";
    manifest.world_frame = "bim";
    manifest.sensor = {info.prod_line, info.format.pixels_per_column, info.format.columns_per_frame,
                       capture.metadata.string()};
    manifest.descriptor = {"indoor",      sc.num_rings,         sc.num_sectors,
                           sc.max_radius, sc.indoor_min_points, sc.indoor_min_z_span};
    io::SessionWriter writer(session_dir, manifest, {.overwrite = opt.overwrite});
    std::vector<io::SessionKeyframe> keyframes;
    Eigen::Isometry3d last_key = Eigen::Isometry3d::Identity();
    size_t frames = 0, points = 0, keyframe_points = 0;
    common::PointCloud cloud;
    while (const ouster::LidarFrame* frame = reader.NextFrame()) {
        const size_t k = frames++;
        if (k >= poses.size() || frame->frame_id != (k & 0xFFFF)) {
            throw common::Error(common::StatusCode::kInternal,
                                "decoded frame " + std::to_string(frame->frame_id) +
                                    " where frame " + std::to_string(k) + " was recorded");
        }
        const Eigen::Isometry3d& T = poses[k];
        const auto stamp = static_cast<int64_t>(frame->start_ns);
        writer.AddScanPose(io::StampedPose::FromIsometry(stamp, T));
        ouster::ToPointCloud(*frame, &cloud);
        points += cloud.size();
        const Eigen::Isometry3d rel = common::Between(last_key, T);
        if (!keyframes.empty() && common::TranslationNorm(rel) < 1.0 &&
            common::RotationAngle(rel) < 10.0 * M_PI / 180.0) {
            continue;
        }
        io::SessionKeyframe kf;
        kf.stamp_ns = stamp;
        kf.T_world_lidar = T;
        kf.cloud = cloud;
        builder.Build(kf.cloud, &kf.descriptor);
        keyframe_points += kf.cloud.size();
        const size_t i = writer.AddKeyframe(kf);
        if (i > 0) {
            // Odometry edge from the ground truth, 1 cm / 0.1 deg standard deviation.
            io::SessionEdge e{uint32_t(i - 1), uint32_t(i),
                              common::Between(keyframes.back().T_world_lidar, T),
                              common::Matrix6d::Identity()};
            e.information.diagonal() << 1e4, 1e4, 1e4, 3.3e5, 3.3e5, 3.3e5;
            writer.AddEdge(e);
        }
        last_key = T;
        keyframes.push_back(std::move(kf));
    }
    writer.Finish();
    const double decode_s = Seconds(t_decode);
    const auto& ls = reader.lidar_stats();
    std::cout << "  decoded  " << frames << " frames (" << ls.frames_complete << " complete, "
              << ls.TotalRejected() << " packets rejected, " << reader.extractor_stats().reassembled
              << " datagrams reassembled), " << points / std::max<size_t>(frames, 1)
              << " points a frame\n"
              << "  kept     " << keyframes.size() << " keyframes (1 m / 10 deg), "
              << keyframe_points << " points, indoor Scan Context each; decoding, describing and "
              << "writing took " << decode_s << " s\n"
              << "  wrote    " << session_dir.string() << "  (" << FolderBytes(session_dir) / 1e6
              << " MB)\n";
    if (frames != poses.size() || ls.frames_complete != poses.size()) {
        throw common::Error(common::StatusCode::kInternal,
                            "the capture gave back " + std::to_string(ls.frames_complete) +
                                " complete frames of " + std::to_string(poses.size()));
    }

    // 5. Read the session back and compare everything.
    const auto t_read = Clock::now();
    const io::Session s = io::ReadSession(session_dir);
    size_t identical = 0;
    int64_t max_t_error_ns = 0;
    for (size_t i = 0; i < std::min(s.keyframes.size(), keyframes.size()); ++i) {
        const auto& a = keyframes[i];
        const auto& b = s.keyframes[i];
        identical += a.stamp_ns == b.stamp_ns &&
                     a.T_world_lidar.matrix() == b.T_world_lidar.matrix() &&
                     a.descriptor == b.descriptor && SameCloud(a.cloud, b.cloud, max_t_error_ns);
    }
    const bool read_ok = s.complete && identical == keyframes.size() &&
                         s.keyframes.size() == keyframes.size() && max_t_error_ns <= 8;
    std::cout << "  read     " << s.keyframes.size() << " keyframes, " << s.edges.size()
              << " edges, " << s.trajectory.size() << " scan poses in " << Seconds(t_read) << " s; "
              << identical << "/" << keyframes.size()
              << " keyframes bit-identical (points, descriptor, pose, time); per-point times "
                 "within "
              << max_t_error_ns << " ns (float32 seconds in PCD)\n";

    // 6. Place recognition across sessions, the start of Step 2: each rig keyframe against all
    //    keyframes of the BIM reference (both storeys) by Scan Context.
    const io::Session reference = io::ReadSession(reference_dir, {.load_clouds = false});
    scancontext::CandidateIndex index(sc);
    for (const auto& kf : reference.keyframes) {
        if (!index.Add(kf.descriptor).ok()) return kExitFailure;
    }
    index.Build();
    int found = 0;
    double yaw_err_sum = 0.0;
    for (const auto& kf : s.keyframes) {
        const auto match = index.Query(kf.descriptor);
        if (!match) continue;
        const auto& T_ref = reference.keyframes[match->index].T_world_lidar;
        if ((T_ref.translation() - kf.T_world_lidar.translation()).norm() > 2.0) continue;
        ++found;
        yaw_err_sum +=
            std::abs(WrapAngle(match->yaw - (Yaw(kf.T_world_lidar) - Yaw(T_ref))));
    }
    std::cout << "  matched  " << found << "/" << s.keyframes.size()
              << " rig keyframes to a BIM reference keyframe within 2 m by Scan Context"
              << (found
                      ? ", mean yaw error " + FixedString(yaw_err_sum / found * 180 / M_PI) + " deg"
                      : "")
              << "\n";
    std::cout << "results in " << out.string() << "/:\n"
              << "  building.ifc  the sample building (bimslam bim info " << building_file.string()
              << ")\n"
              << "  reference/    its BIM reference session; plan/ its grids and walks (PGM, PNG, TUM)\n"
              << "  capture/  lidar.pcap + metadata.json   (bimslam ouster info "
              << capture.pcap.string() << ")\n"
              << "  session/  keyframes, poses, descriptors (bimslam session info "
              << session_dir.string() << "; layout in algorithms/io/README.md)\n"
              << "demo " << (read_ok ? "finished" : "FAILED") << " in " << Seconds(t_start)
              << " s\n";
    return read_ok ? kExitOk : kExitFailure;
}

}  // namespace

void AddDemoCommand(CLI::App& app, int& exit_code) {
    auto opt = std::make_shared<DemoOptions>();
    CLI::App* demo = app.add_subcommand(
        "demo",
        "Run the main job end to end on a building and a walk the project generates "
        "itself, and print what it did and where the results are.");
    demo->add_option("--out,-o", opt->out, "output folder")->capture_default_str();
    demo->add_flag("--overwrite", opt->overwrite, "replace the results of an earlier demo");
    demo->add_option("--columns", opt->columns, "columns per scan (512, 1024 or 2048)")
        ->check(CLI::IsMember({512, 1024, 2048}))
        ->capture_default_str();
    demo->add_option("--laps", opt->laps, "laps of the rig's walk of the ground floor")
        ->check(CLI::Range(1, 10))
        ->capture_default_str();
    demo->callback([opt, &exit_code] { exit_code = Run([&] { return RunDemo(*opt); }); });
}

}  // namespace bimslam::cli
