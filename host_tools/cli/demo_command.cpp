// bimslam demo: the whole product on data the project makes itself: the sample building as IFC,
// a version of it changed on both storeys walked by a Go1 that starts outside, goes in and up the
// stairs (host_tools/simulate/scenarios/whole_building.yaml), the rig's firmware replaying the
// recording
// (bimslam-rig replay, a separate process: the on-board part), then `bimslam map` in-process:
// reference session, odometry, anchoring into BIM coordinates, change detection, the report. It
// ends with the accuracy in BIM coordinates, the change scores and the path to report.html.
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "algorithms/common/status.hpp"
#include "algorithms/io/sha256.hpp"
#include "host_tools/bim/ifc_model.hpp"
#include "host_tools/bim/sample_building.hpp"
#include "host_tools/cli/command.hpp"
#include "host_tools/cli/progress.hpp"
#include "host_tools/cli/rig_replay.hpp"
#include "host_tools/cli/shipped_scenarios.hpp"
#include "host_tools/mapping/map_pipeline.hpp"
#include "host_tools/simulate/scenario.hpp"
#include "host_tools/simulate/scenario_yaml.hpp"
#include "host_tools/simulate/simulate.hpp"

namespace bimslam::cli {
namespace {
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct DemoOptions {
    std::string out = "demo_output";
    bool overwrite = false;
    int columns = 1024;
    double duration_s = 0;  // 0: the whole walk (about 3.5 minutes), from outside up the stairs
};

double Seconds(Clock::time_point since) {
    return std::chrono::duration<double>(Clock::now() - since).count();
}

int RunDemo(const DemoOptions& opt) {
    const auto t_start = Clock::now();
    const fs::path out = opt.out;
    const fs::path building_file = out / "building.ifc";
    const fs::path session_dir = out / "session";
    const fs::path capture_dir = out / "capture";
    const fs::path map_dir = out / "map";
    for (const fs::path& p : {building_file, session_dir, capture_dir, map_dir}) {
        if (fs::exists(p) && !opt.overwrite) {
            throw common::FileError(
                common::StatusCode::kAlreadyExists, out.string(), 0,
                "holds an earlier demo; pass --overwrite or choose another --out");
        }
    }
    for (const fs::path& p : {capture_dir, map_dir}) fs::remove_all(p);
    fs::create_directories(capture_dir);
    std::cout << std::fixed << std::setprecision(1);

    // 1. The building: the project's sample office with its entrances, as IFC4, read back.
    const auto t_building = Clock::now();
    bim::SampleBuildingOptions sample;
    sample.exterior_doors = true;  // the rig walks in from outside
    bim::WriteSampleBuilding(building_file, sample);
    const bim::BimModel model = bim::LoadIfc(building_file);
    std::cout << "bimslam demo: the sample office building, " << model.storeys.size()
              << " storeys, " << model.elements.size() << " elements, "
              << model.mesh.triangles.size() << " triangles (IFC4 written and read back through "
              << "IFC++ in " << std::setprecision(2) << Seconds(t_building) << " s)\n"
              << std::setprecision(1) << "           " << building_file.string() << "\n";

    // 2. The building as it was found: whole_building.yaml's edits on both storeys (added objects
    //    and clutter, removed furniture and columns, a moved desk, walls built off their place,
    //    two people), walked by a Go1 that starts 5 m outside the main entrance, goes in, through
    //    the ground floor and up the stairs to the first floor, recorded as the rig records it
    //    (host_tools/simulate).
    simulate::Scenario scenario =
        simulate::ParseScenario("whole_building.yaml", ShippedScenario("whole_building.yaml"), "");
    scenario.model = building_file;
    scenario.duration_s = opt.duration_s;
    scenario.sensor.lidar_mode = std::to_string(opt.columns) + "x10";
    const simulate::CaptureReport cap =
        simulate::SimulateCapture(scenario, model, io::Sha256File(building_file), capture_dir);
    std::cout << "  captured " << cap.frames << " frames, " << cap.duration_s << " s of a Go1 "
              << "walking in from 5 m outside, through the ground floor and up the stairs to the "
              << "first floor (" << cap.walk_length_m << " m; OS-1-32 "
              << scenario.sensor.lidar_mode << ", " << cap.imu_packets << " IMU packets, "
              << cap.can_frames << " Go1 CAN frames), simulated in " << cap.wall_s
              << " s\n           in a changed building: "
              << scenario.edits.boxes.size() + scenario.edits.cylinders.size()
              << " objects added and clutter, elements removed and moved, walls built off, "
              << scenario.edits.people.size() << " people walking\n           "
              << capture_dir.string() << "/: lidar.pcap, metadata.json, go1_can.log, "
              << "ground_truth.tum, changes.json\n";

    // 3. The on-board part: the firmware replays the capture (bimslam-rig replay, a process).
    const RigReplayRun odo = RunRigReplay(capture_dir, out / "rig");
    fs::remove_all(session_dir);
    fs::rename(odo.session, session_dir);
    std::cout << "  bimslam-rig replay " << odo.scans << " scans, " << odo.keyframes
              << " keyframes in " << odo.wall_s << " s (last packet to odometry on LCM p50 "
              << std::setprecision(2) << odo.latency_p50_ms << " ms)" << std::setprecision(1)
              << "\n           " << session_dir.string() << "/"
              << (odo.lcm_log.empty() ? "" : ", LCM recorded in " + odo.lcm_log.string()) << "\n";

    // 4. bimslam map: reference session, odometry, anchoring, change detection, report.
    std::cout << "  bimslam map " << building_file.string() << " " << capture_dir.string() << " -o "
              << map_dir.string() << "\n";
    mapping::MapConfig mc;
    mc.model = building_file;
    mc.recordings = {capture_dir};
    mc.out = map_dir;
    ProgressBar bar(ProgressBar::Terminal());
    const mapping::MapRun run =
        mapping::RunMap(mc, [&](const std::string& s, double f) { bar.Update(s, f); });
    bar.Clear();
    for (const mapping::StepRun& s : run.steps) {
        std::cout << "    " << std::left << std::setw(18) << s.step << std::right
                  << (s.skipped ? std::string("up to date") : Fixed(s.seconds, 1) + " s") << "\n";
    }
    const nlohmann::json& r = run.summary["recordings"][0];
    const bool anchored = !r["anchor"].is_null() && r["anchor"]["verdict"] == "anchored";
    std::cout << "  anchoring "
              << (r["anchor"].is_null() ? std::string("not run")
                                        : r["anchor"]["verdict"].get<std::string>() + ": " +
                                              r["anchor"]["reason"].get<std::string>())
              << "\n";
    if (!r["accuracy"].is_null()) {
        const nlohmann::json& a = r["accuracy"];
        std::cout << "  accuracy in BIM coordinates APE "
                  << Fixed(a["ape_trans_rmse_m"].get<double>() * 100, 2) << " cm (max "
                  << Fixed(a["ape_trans_max_m"].get<double>() * 100, 1) << ") / "
                  << Fixed(a["ape_rot_rmse_deg"], 2) << " deg with no alignment, from outside the "
                  << "building (the paper's BIM-SLAM: 10.6 cm / 2.07 deg)\n";
    }
    if (!r["changes"].is_null()) {
        const nlohmann::json& c = r["changes"];
        std::cout << "  changes   " << c["new_objects"] << " new objects, " << c["missing"]
                  << " missing and " << c["deviating"] << " deviating elements, " << c["transients"]
                  << " transient clusters (people walking) set aside\n";
    }
    if (!r["seen_scores"].is_null()) {  // what the walk saw first, then everything placed
        const nlohmann::json& e = r["change_scores"];
        std::cout << "  scores    " << mapping::SeenScoresText(r["seen_scores"]) << "\n"
                  << "            (" << mapping::InViewRuleText(r["seen_scores"]) << ")\n"
                  << "            " << mapping::AllScoresText(r["seen_scores"])
                  << "; as-built walls within 1 cm: " << e["as_built"]["within_1cm"] << "/"
                  << e["as_built"]["observed"]
                  << "; people reported as objects: " << e["people"]["reported_as_new_objects"]
                  << "\n";
    }
    const std::string report =
        run.summary.contains("report") ? run.summary["report"].get<std::string>() : "";
    std::cout << "results in " << out.string() << "/:\n"
              << "  building.ifc  the sample building (bimslam bim info " << building_file.string()
              << ")\n"
              << "  capture/      the rig's recording of the changed building and its truth\n"
              << "  session/      bimslam-rig's session (bimslam session info "
              << session_dir.string() << ")\n"
              << "  map/          project.json, reference/, visits/<date>/ (odometry/, anchor/, "
                 "changes/), report/, summary.json\n"
              << "report: " << fs::absolute(report).string() << "\n"
              << "demo " << (anchored ? "finished" : "FAILED") << " in " << Seconds(t_start)
              << " s\n";
    return anchored ? kExitOk : kExitFailure;
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
    demo->add_option("--duration", opt->duration_s,
                     "seconds of the rig's walk, from 5 m outside the entrance (0: the whole "
                     "walk, through the ground floor and up the stairs to the first floor)")
        ->check(CLI::Range(0.0, 3600.0))
        ->capture_default_str();
    demo->callback([opt, &exit_code] { exit_code = Run([&] { return RunDemo(*opt); }); });
}

}  // namespace bimslam::cli
