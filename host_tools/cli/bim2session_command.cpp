// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/common/stopwatch.hpp"
// bimslam bim plan: a storey's occupancy grid and coverage walk.
// bimslam bim2session: the reference session of a building (paper, Step 1).
#include <algorithm>
#include <chrono>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "algorithms/common/status.hpp"
#include "algorithms/io/file_util.hpp"
#include "algorithms/io/sha256.hpp"
#include "host_tools/bim/ifc_model.hpp"
#include "host_tools/bim/lidar_from_metadata.hpp"
#include "host_tools/bim/reference_session.hpp"
#include "host_tools/bim/reference_walk.hpp"
#include "host_tools/cli/command.hpp"

namespace bimslam::cli {
namespace {
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// The options of the grid and the walk, shared by both commands.
struct PlanOptions {
    std::vector<std::string> storeys;
    bim::GridConfig grid;
    bim::PathConfig path;
    bool no_objects = false;
    bool no_railings = false;
    std::vector<double> free_seed;  // x y
};

void AddPlanOptions(CLI::App* cmd, PlanOptions& o) {
    cmd->add_option("--storey", o.storeys, "storey by name (repeatable; default: every storey)");
    cmd->add_option("--resolution", o.grid.resolution_m, "grid cell size, m")
        ->capture_default_str();
    cmd->add_option("--sensor-height", o.grid.slice_height_m,
                    "sensor height above the floor, m: the grid's slice and the walk's height")
        ->capture_default_str();
    cmd->add_option("--clearance", o.path.clearance_m, "least distance of the walk from walls, m")
        ->capture_default_str();
    cmd->add_option("--speed", o.path.speed_mps, "walking speed, m/s")->capture_default_str();
    cmd->add_option("--view-spacing", o.path.view_spacing_m,
                    "viewpoints in a large room at most this far apart, m")
        ->capture_default_str();
    cmd->add_flag("--no-objects", o.no_objects,
                  "furniture and other objects do not block the walk");
    cmd->add_flag("--no-railings", o.no_railings,
                  "railings are not structure: they neither block the walk nor are scanned");
    cmd->add_option("--free-seed", o.free_seed,
                    "X Y (model metres): free space is what this point reaches on every storey "
                    "(default: the largest enclosed region)")
        ->expected(2);
}

void Finalise(PlanOptions& o) {
    o.path.sensor_height_m = o.grid.slice_height_m;
    o.grid.object_footprints = !o.no_objects;
    if (o.free_seed.size() == 2) o.grid.seed = Eigen::Vector2d(o.free_seed[0], o.free_seed[1]);
}

bim::BimModel LoadPlanned(const std::string& file, const PlanOptions& o) {
    const auto t0 = Clock::now();
    bim::IfcLoadOptions load;
    load.railings_are_structure = !o.no_railings;
    bim::BimModel model = bim::LoadIfc(file, load);
    std::cout << std::fixed << std::setprecision(1) << "loaded   " << file << ": " << model.schema
              << ", " << model.storeys.size() << " storeys, " << model.elements.size()
              << " elements with geometry, " << model.mesh.triangles.size() << " triangles in "
              << std::setprecision(2) << common::SecondsSince(t0) << " s";
    if (!model.failed.empty()) std::cout << " (" << model.failed.size() << " elements failed)";
    std::cout << "\n";
    return model;
}

struct PlanArgs {
    std::string model;
    std::string out;
    PlanOptions plan;
    bool json = false;
};

int Plan(PlanArgs& a) {
    Finalise(a.plan);
    const bim::BimModel model = LoadPlanned(a.model, a.plan);
    const std::vector<int> storeys = bim::StoreyIndices(model, a.plan.storeys);
    nlohmann::json summary = nlohmann::json::array();
    for (const int s : storeys) {
        const bim::OccupancyGrid grid = bim::BuildOccupancyGrid(model, s, a.plan.grid);
        const std::string stem = (fs::path(a.out) / bim::StoreyFileStem(grid.storey)).string();
        fs::create_directories(a.out);
        bim::WriteGrid(grid, stem);  // first, so that a storey without a walk can be looked at
        bim::CoveragePath path;
        try {
            path = bim::PlanCoveragePath(grid, a.plan.path);
        } catch (const common::Error& e) {
            throw common::Error(e.code(), std::string(e.what()) + " (see " + stem + ".png)");
        }
        bim::WriteStoreyPlan(a.out, grid, path);
        const double area = double(grid.FreeCells()) * grid.resolution * grid.resolution;
        std::cout << std::setprecision(1) << "storey   '" << grid.storey << "': " << area
                  << " m2 free, " << path.rooms << " rooms, " << path.viewpoints.size()
                  << " viewpoints (" << path.unreachable_viewpoints << " unreachable), walk "
                  << path.length_m << " m, " << path.duration_s << " s at " << a.plan.path.speed_mps
                  << " m/s, clearance >= " << std::setprecision(2) << path.min_clearance_m
                  << " m\n";
        // The regions a reference session walks, and how many pockets are too small for it.
        const std::vector<double>& regions = grid.region_areas_m2;
        const auto walked = size_t(std::count_if(
            regions.begin(), regions.end(), [](double r) { return r >= bim::kMinWalkedRegionM2; }));
        if (walked > 1) {
            std::cout << "         " << walked << " enclosed regions of " << bim::kMinWalkedRegionM2
                      << " m2 or more, each walked by bim2session (this plan walks the first):";
            for (size_t i = 0; i < walked; ++i) std::cout << " " << regions[i];
            std::cout << " m2\n";
        }
        std::cout << "         " << stem << ".{pgm,yaml,png}, " << stem << "_path.{png,tum}\n";
        summary.push_back({{"storey", grid.storey},
                           {"free_area_m2", area},
                           {"region_areas_m2", grid.region_areas_m2},
                           {"rooms", path.rooms},
                           {"viewpoints", path.viewpoints.size()},
                           {"unreachable_viewpoints", path.unreachable_viewpoints},
                           {"walk_m", path.length_m},
                           {"walk_s", path.duration_s},
                           {"min_clearance_m", path.min_clearance_m},
                           {"files", stem}});
    }
    io::WriteFileAtomic(fs::path(a.out) / "plan.json", summary.dump(2) + "\n");
    if (a.json) std::cout << summary.dump(2) << "\n";
    return kExitOk;
}

struct SessionArgs {
    std::string model;
    std::string out;
    std::string sensor;
    std::string plan_dir;
    PlanOptions plan;
    double gap_m = 1.0;
    bool all_elements = false;
    bool noise = false;
    uint64_t seed = 1;
    bool overwrite = false;
    bool json = false;
};

int ToSession(SessionArgs& a) {
    Finalise(a.plan);
    const auto t0 = Clock::now();
    const bim::BimModel model = LoadPlanned(a.model, a.plan);
    const double load_s = common::SecondsSince(t0);
    bim::ReferenceSessionOptions o;
    o.storeys = a.plan.storeys;
    o.grid = a.plan.grid;
    o.path = a.plan.path;
    o.keyframe_gap_m = a.gap_m;
    o.all_elements = a.all_elements;
    o.seed = a.seed;
    o.overwrite = a.overwrite;
    o.plan_dir = a.plan_dir;
    if (a.noise) o.noise = simulation::NoiseModel{};
    if (!a.sensor.empty()) {
        o.lidar = bim::LidarModelFromMetadataFile(a.sensor);
        o.sensor_model = "from " + fs::path(a.sensor).filename().string();
        o.metadata_file = a.sensor;
    }
    o.progress = [](size_t done, size_t planned) {
        if (done % 50 == 0)
            std::cerr << "\r  " << done << " / ~" << planned << " keyframes" << std::flush;
    };
    const std::string sha = io::Sha256File(a.model);
    const bim::ReferenceSessionReport r = bim::WriteReferenceSession(model, sha, a.out, o);
    std::cerr << "\r";
    const double total_s = common::SecondsSince(t0);
    for (const auto& s : r.storeys) {
        std::cout << std::setprecision(1) << "storey   '" << s.name << "': "
                  << (s.regions > 1 ? std::to_string(s.regions) + " enclosed regions, " : "")
                  << s.rooms << " rooms, " << s.viewpoints << " viewpoints, walk " << s.walk_m
                  << " m (" << s.walk_s << " s), " << s.keyframes << " keyframes\n";
    }
    if (r.storeys.size() > 1) {
        std::cout << "stairs   " << r.flights_walked << " of " << r.storeys.size() - 1
                  << " storey changes walked by a flight, " << r.flight_keyframes
                  << " keyframes on the flights and the ways to them\n";
    }
    for (const std::string& note : r.notes) std::cout << "note     " << note << "\n";
    const double per_key_ms =
        1e3 * (r.simulate_s + r.write_s) / double(std::max<size_t>(r.keyframes, 1));
    const double ratio = r.walk_s / std::max(total_s, 1e-9);
    std::cout << std::setprecision(2) << "session  " << a.out << ": " << r.keyframes
              << " keyframes every " << a.gap_m << " m, " << r.points << " points, " << r.rays / 1e6
              << " M rays cast\n"
              << "time     load " << load_s << " s, plan " << r.plan_s << " s, simulate "
              << r.simulate_s << " s, write " << r.write_s << " s (" << per_key_ms
              << " ms a keyframe); " << std::setprecision(0) << ratio << "x the real-time walk at "
              << std::setprecision(2) << a.plan.path.speed_mps << " m/s\n";
    if (a.json) {
        nlohmann::json j = {{"session", a.out},
                            {"keyframes", r.keyframes},
                            {"flights_walked", r.flights_walked},
                            {"flight_keyframes", r.flight_keyframes},
                            {"notes", r.notes},
                            {"points", r.points},
                            {"rays", r.rays},
                            {"walk_s", r.walk_s},
                            {"load_s", load_s},
                            {"plan_s", r.plan_s},
                            {"simulate_s", r.simulate_s},
                            {"write_s", r.write_s},
                            {"total_s", total_s},
                            {"ms_per_keyframe", per_key_ms},
                            {"realtime_ratio", ratio},
                            {"model_sha256", sha}};
        std::cout << j.dump(2) << "\n";
    }
    return kExitOk;
}
}  // namespace

void AddBimPlanCommand(CLI::App& bim, int& exit_code) {
    auto a = std::make_shared<PlanArgs>();
    auto* cmd = bim.add_subcommand(
        "plan",
        "Occupancy grid (PGM + YAML as ROS map_server reads, PNG) and coverage walk (TUM, PNG) of "
        "each storey");
    cmd->add_option("MODEL", a->model, "IFC model (IFC2X3 or IFC4, any length unit)")->required();
    cmd->add_option("--out,-o", a->out, "output folder")->required();
    AddPlanOptions(cmd, a->plan);
    cmd->add_flag("--json", a->json, "print the summary as JSON (also written to plan.json)");
    cmd->callback([a, &exit_code] { exit_code = Run([&] { return Plan(*a); }); });
}

void AddBim2SessionCommand(CLI::App& app, int& exit_code) {
    auto a = std::make_shared<SessionArgs>();
    auto* cmd = app.add_subcommand(
        "bim2session",
        "Reference session of a building: LiDAR scans simulated along a coverage walk of every "
        "room of every storey, the storeys joined by walking the stairs between them (keyframes "
        "on the flights; storeys no walkable flight joins are walked one after the other, with a "
        "note why), as ground-truth session data (specs/session-data.md)");
    cmd->add_option("MODEL", a->model, "IFC model (IFC2X3 or IFC4, any length unit)")->required();
    cmd->add_option("--out,-o", a->out, "session folder to write")->required();
    cmd->add_option("--sensor", a->sensor,
                    "Ouster metadata JSON of the sensor to simulate (default: the built-in "
                    "OS-1-32, 1024x10, beams uniform over +-22.5 deg)");
    cmd->add_option("--keyframe-gap", a->gap_m, "metres of walk between keyframes")
        ->capture_default_str();
    AddPlanOptions(cmd, a->plan);
    cmd->add_option("--plan-dir", a->plan_dir, "also write each storey's grid and walk here");
    cmd->add_flag("--all-elements", a->all_elements,
                  "cast against every element, not only the permanent structure");
    cmd->add_flag("--noise", a->noise,
                  "simulate range noise (1 cm) and dropouts; default: exact ranges (1 mm steps)");
    cmd->add_option("--seed", a->seed, "noise seed")->capture_default_str();
    cmd->add_flag("--overwrite", a->overwrite, "replace an existing session");
    cmd->add_flag("--json", a->json, "also print the figures as JSON");
    cmd->callback([a, &exit_code] { exit_code = Run([&] { return ToSession(*a); }); });
}

}  // namespace bimslam::cli
