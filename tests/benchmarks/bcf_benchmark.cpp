// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// changes.bcf for 100 changes on the sample office (issue 34's target: written in <= 2 s,
// snapshots included). A harness that prints figures, not Google Benchmark.
//
// The model: `bimslam bim sample` (the two-storey office, IFC4, spaces with their volumes). The
// changes, made up on it so that the count is exact (a simulated walk finds a handful): 30 new
// objects (0.6 m crates at the rooms' centres), 35 deviating elements (its 26 walls and the next
// elements, 3 cm off), 25 missing elements and 10 moved ones (the next elements, 1.2 m along x).
// The keyframes: one per room, 1.4 m above its floor at its centre, so each camera is chosen among
// them as from a walk. Timed: ChangesBcf (topics and cameras, 100 renders by OSMesa, 100 PNGs by
// libpng, the zip) and the file's atomic write, in BCF 2.1 and 3.0, three runs each (the best and
// the last printed); the renderer's set-up (the model's meshes, once per command) apart.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>

#include "algorithms/common/stopwatch.hpp"
#include "algorithms/io/file_util.hpp"
#include "host_tools/bim/ifc_model.hpp"
#include "host_tools/bim/ifc_writer.hpp"
#include "host_tools/bim/sample_building.hpp"
#include "host_tools/changes/bim_change_model.hpp"
#include "host_tools/changes/change_bcf.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam {
namespace {
namespace cd = change_detection;

// A box's surface, 12 triangles (counter-clockwise from outside).
common::TriangleMesh BoxMesh(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    common::TriangleMesh m;
    for (int i = 0; i < 8; ++i) {
        m.vertices.emplace_back(float(i & 1 ? hi.x() : lo.x()), float(i & 2 ? hi.y() : lo.y()),
                                float(i & 4 ? hi.z() : lo.z()));
    }
    m.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                   {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
    return m;
}

changes::NewObject Crate(const Eigen::Vector3d& base) {
    changes::NewObject o;
    o.box_min = base + Eigen::Vector3d(-0.3, -0.3, 0);
    o.box_max = base + Eigen::Vector3d(0.3, 0.3, 0.6);
    o.centroid = 0.5 * (o.box_min + o.box_max);
    o.volume_m3 = 0.216;
    o.mesh = BoxMesh(o.box_min, o.box_max);
    o.points.assign(500, 0);
    o.on_floor = true;
    return o;
}

void Run() {
    bim::IfcLoadOptions load;
    load.space_geometry = true;
    const bim::SampleLayout layout = bim::SampleBuildingLayout({});
    const bim::BimModel model =
        bim::ParseIfc("sample_office.ifc", bim::SampleBuildingIfc({}), load);
    const Eigen::Vector3d o = model.origin_m;

    cd::SessionInput input;
    input.dir = "bench";
    cd::SessionChanges found;
    found.label = "bench";
    found.input = &input;
    changes::ChangeResult& r = found.result;
    r.elements.resize(model.elements.size());
    for (auto& e : r.elements) e.verdict = changes::Verdict::kConfirmed;

    std::vector<Eigen::Vector3d> room_centres;
    for (const bim::SampleRoom& room : layout.rooms) {
        const Eigen::Vector2d c = room.Bounds().center();
        const double floor = layout.storeys[size_t(room.storey)].elevation_m;
        room_centres.emplace_back(c.x(), c.y(), floor);
        changes::MapKeyframe kf;
        kf.T_world_lidar.translation() = Eigen::Vector3d(c.x(), c.y(), floor + 1.4) - o;
        input.keyframes.push_back(kf);
    }
    // 30 new objects, at the rooms' centres (two per room where there are fewer rooms).
    for (size_t k = 0; k < 30; ++k) {
        const Eigen::Vector3d c = room_centres[k % room_centres.size()] +
                                  Eigen::Vector3d(k >= room_centres.size() ? 1.0 : 0.0, 0, 0);
        r.objects.push_back(Crate(c - o));
    }
    // 35 deviating (walls first), the next 25 missing, the next 10 moved.
    std::vector<size_t> candidates;
    for (const bool walls : {true, false}) {
        for (size_t e = 0; e < model.elements.size(); ++e) {
            const bim::BimElement& el = model.elements[e];
            if (cd::Physical(el) && el.triangle_count > 0 &&
                el.ifc_class.starts_with("IfcWall") == walls)
                candidates.push_back(e);
        }
    }
    size_t deviating = 0, missing = 0, moved = 0;
    for (size_t i = 0; i < std::min<size_t>(70, candidates.size()); ++i) {
        const size_t e = candidates[i];
        const bim::BimElement& el = model.elements[e];
        changes::ElementReport& rep = r.elements[e];
        if (i < 35) {
            rep.verdict = changes::Verdict::kDeviating;
            rep.offset = Eigen::Vector3d(0, 0.03, 0);
            rep.support_points = 800;
            rep.mean_signed_m = 0.03;
            ++deviating;
        } else if (i < 60) {
            rep.verdict = changes::Verdict::kMissing;
            rep.evidence.expected_area_m2 = 1.5;
            rep.evidence.rays_through = 400;
            ++missing;
        } else {
            rep.verdict = changes::Verdict::kDeviating;
            rep.moved = true;
            rep.offset = Eigen::Vector3d(1.2, 0, 0);
            rep.moved_yaw_deg = 15;
            rep.moved_object = int(r.objects.size());
            changes::NewObject to;
            to.moved_element = uint32_t(e);
            to.mesh = model.mesh;  // the element's triangles, moved
            to.mesh.triangles.assign(
                model.mesh.triangles.begin() + el.first_triangle,
                model.mesh.triangles.begin() + el.first_triangle + el.triangle_count);
            for (auto& v : to.mesh.vertices) v.x() += 1.2f;
            to.box_min = to.box_max = to.mesh.vertices[to.mesh.triangles[0][0]].cast<double>();
            for (const auto& t : to.mesh.triangles) {
                for (const uint32_t v : t) {
                    to.box_min = to.box_min.cwiseMin(to.mesh.vertices[v].cast<double>());
                    to.box_max = to.box_max.cwiseMax(to.mesh.vertices[v].cast<double>());
                }
            }
            r.objects.push_back(std::move(to));
            ++moved;
        }
    }
    found.places = cd::PlaceObjects(model, r.objects);
    for (size_t k = 0; k < r.objects.size(); ++k)
        found.object_global_ids.push_back(
            bim::IfcWriter::GlobalId(7, "new object " + std::to_string(k)));
    const changes::ChangeDetectorConfig config;

    std::cout << "model     sample office: " << model.elements.size() << " elements, "
              << model.mesh.triangles.size() << " triangles; " << input.keyframes.size()
              << " keyframes (room centres)\n"
              << "changes   30 new objects, " << deviating << " deviating, " << missing
              << " missing, " << moved << " moved\n";
    auto t0 = common::SteadyClock::now();
    cd::SnapshotRenderer renderer(model, 640, 480);
    std::printf("renderer  %.3f s to set up (OSMesa context, the model's %zu triangles)\n",
                common::SecondsSince(t0), model.mesh.triangles.size());

    test::TempDir tmp;
    for (const cd::BcfVersion version : {cd::BcfVersion::k2_1, cd::BcfVersion::k3_0}) {
        double best = 1e9;
        for (int run = 0; run < 3; ++run) {
            cd::ChangeBcfOptions options;
            options.version = version;
            options.date_ns = 1772443800LL * 1000000000LL;
            options.model_sha256 = "bench";
            t0 = common::SteadyClock::now();
            const cd::ChangeBcf bcf = cd::ChangesBcf(model, found, config, options, renderer);
            io::WriteFileAtomic(tmp.path() / "changes.bcf", bcf.zip);
            const double s = common::SecondsSince(t0);
            best = std::min(best, s);
            std::printf(
                "BCF %s    run %d: %zu topics in %.3f s (topics and cameras %.3f, render %.3f, "
                "PNG %.3f, zip %.3f, write %.3f); %.1f kB\n",
                cd::ToString(version), run + 1, bcf.topics, s, bcf.topics_s, bcf.render_s,
                bcf.png_s, bcf.zip_s, s - bcf.topics_s - bcf.render_s - bcf.png_s - bcf.zip_s,
                bcf.zip.size() / 1024.0);
        }
        std::printf("BCF %s    best %.3f s for 100 changes with snapshots (target <= 2 s)\n",
                    cd::ToString(version), best);
        // BIMSLAM_BENCH_KEEP=DIR keeps the files (DIR/changes_<version>.bcf) to look at.
        if (const char* keep = std::getenv("BIMSLAM_BENCH_KEEP"); keep && *keep) {
            std::filesystem::copy_file(
                tmp.path() / "changes.bcf",
                std::filesystem::path(keep) /
                    ("changes_" + std::string(cd::ToString(version)) + ".bcf"),
                std::filesystem::copy_options::overwrite_existing);
        }
    }
}

}  // namespace
}  // namespace bimslam

int main() {
    try {
        bimslam::Run();
    } catch (const std::exception& e) {
        std::cerr << "bcf_benchmark: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
