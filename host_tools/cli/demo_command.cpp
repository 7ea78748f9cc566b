// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// bimslam demo: the whole product on data the project makes itself: the sample building as IFC,
// a version of it changed on both storeys walked by a Go1 that starts outside, goes in and up the
// stairs (host_tools/simulate/scenarios/whole_building.yaml), the rig's firmware replaying the
// recording
// (bimslam-rig replay, a separate process: the on-board part), then `bimslam map` in-process:
// reference session, odometry, anchoring into BIM coordinates, change detection, the report. Then
// a second visit three months later (a person with the rig through the ground floor,
// whole_building_later.yaml) is added to the project, anchored against the model and the first
// visit, and what changed between the two is printed (history.json) beside the simulator's truth.
// It ends with the accuracy in BIM coordinates, the change scores and the path to report.html.
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "algorithms/common/status.hpp"
#include "algorithms/io/file_util.hpp"
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

// The building: the project's sample office with its entrances, as IFC4, read back.
bim::BimModel WriteBuilding(const fs::path& file) {
    const auto t0 = Clock::now();
    bim::SampleBuildingOptions sample;
    sample.exterior_doors = true;  // the rig walks in from outside
    bim::WriteSampleBuilding(file, sample);
    bim::BimModel model = bim::LoadIfc(file);
    std::cout << "bimslam demo: the sample office building, " << model.storeys.size()
              << " storeys, " << model.elements.size() << " elements, "
              << model.mesh.triangles.size() << " triangles (IFC4 written and read back through "
              << "IFC++ in " << std::setprecision(2) << Seconds(t0) << " s)\n"
              << std::setprecision(1) << "           " << file.string() << "\n";
    return model;
}

// A shipped scenario walked through the building as it was found, into `dir`.
simulate::CaptureReport SimulateVisit(const std::string& name, const DemoOptions& opt,
                                      const bim::BimModel& model, const fs::path& building_file,
                                      const fs::path& dir, simulate::Scenario* scenario) {
    *scenario = simulate::ParseScenario(name, ShippedScenario(name), "");
    scenario->model = building_file;
    if (name == "whole_building.yaml") scenario->duration_s = opt.duration_s;
    scenario->sensor.lidar_mode = std::to_string(opt.columns) + "x10";
    fs::create_directories(dir);
    return simulate::SimulateCapture(*scenario, model, io::Sha256File(building_file), dir);
}

// `bimslam map` in-process over the recordings given (a later one added as a new visit), with
// the steps it ran.
mapping::MapRun Map(const fs::path& building_file, const std::vector<fs::path>& recordings,
                    const fs::path& map_dir) {
    mapping::MapConfig mc;
    mc.model = building_file;
    mc.recordings = recordings;
    mc.out = map_dir;
    ProgressBar bar(ProgressBar::Terminal());
    mapping::MapRun run =
        mapping::RunMap(mc, [&](const std::string& s, double f) { bar.Update(s, f); });
    bar.Clear();
    for (const mapping::StepRun& s : run.steps) {
        if (s.skipped) continue;  // the earlier visit's steps, up to date
        std::cout << "    " << std::left << std::setw(24) << s.step << std::right
                  << Fixed(s.seconds, 1) << " s\n";
    }
    return run;
}

// A visit's anchoring, accuracy, changes and scores (a recording of summary.json); true when it
// was anchored.
bool PrintVisit(const nlohmann::json& r, const std::string& from) {
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
                  << Fixed(a["ape_rot_rmse_deg"], 2) << " deg with no alignment, " << from
                  << " (the paper's BIM-SLAM: 10.6 cm / 2.07 deg)\n";
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
    return anchored;
}

std::string Xy(const nlohmann::json& p) {
    return "(" + Fixed(p[0].get<double>(), 1) + ", " + Fixed(p[1].get<double>(), 1) + ")";
}

// What changed between the two visits as the history found it, beside the simulator's truth
// (the two captures' changes.json, compared by name).
void PrintChangesBetween(const fs::path& map_dir, const fs::path& first, const fs::path& later) {
    const auto h = nlohmann::json::parse(io::ReadFileToString(map_dir / "history.json"));
    const nlohmann::json& change = h.at("changes").at(1);
    const nlohmann::json& since = change.at("since_previous");
    std::map<std::string, nlohmann::json> objects, elements;
    for (const nlohmann::json& o : h.at("objects")) objects[o.at("id")] = o;
    for (const nlohmann::json& e : h.at("elements")) elements[e.at("global_id")] = e;
    std::cout << "  what changed from " << change.at("previous").get<std::string>() << " to "
              << change.at("visit").get<std::string>() << " ("
              << (map_dir / "history.json").string() << "):\n    new       ";
    for (const nlohmann::json& id : since.at("new")) {
        const nlohmann::json& placed = objects[id].at("sightings").back();
        std::cout << id.get<std::string>() << " at " << Xy(placed.at("centroid")) << " ";
    }
    std::cout << "\n    gone      ";
    for (const nlohmann::json& id : since.at("gone")) {
        const nlohmann::json& o = objects[id];
        std::cout << id.get<std::string>() << " from " << Xy(o.at("box_min")) << "-"
                  << Xy(o.at("box_max")) << " ";
    }
    std::cout << "\n    moved     ";
    for (const nlohmann::json& m : since.at("moved")) {
        const nlohmann::json& d = m.at("offset_m");
        std::cout << m.at("id").get<std::string>() << " by "
                  << Fixed(std::hypot(d[0].get<double>(), d[1].get<double>()), 2) << " m ";
    }
    std::cout << "\n    elements  " << since.at("newly_missing").size() << " newly missing, "
              << since.at("newly_deviating").size() << " newly deviating, "
              << since.at("reappeared").size() << " reappeared (built since:";
    for (const nlohmann::json& id : since.at("reappeared"))
        std::cout << " " << elements[id].at("name").get<std::string>();
    size_t unseen = 0;
    for (const auto& [id, o] : objects) {
        const nlohmann::json& s = o.at("sightings");
        unseen += s.back().at("status") == "not_observed";
    }
    std::cout << ")\n    not seen  " << unseen
              << " objects of the first visit were not seen again (the first floor was not "
                 "walked): kept, as of the first visit\n";
    const auto a = nlohmann::json::parse(io::ReadFileToString(first / "changes.json"));
    const auto b = nlohmann::json::parse(io::ReadFileToString(later / "changes.json"));
    std::map<std::string, nlohmann::json> before, after;
    size_t clutter = 0;
    for (const nlohmann::json& o : a.at("added")) {
        if (o.at("kind") == "clutter")
            ++clutter;
        else
            before[o.at("name")] = o;
    }
    for (const nlohmann::json& o : b.at("added")) after[o.at("name")] = o;
    std::cout << "  the truth (the captures' changes.json):";
    for (const auto& [name, o] : before) {
        if (!after.count(name)) {
            std::cout << " " << name << " gone;";
            continue;
        }
        // The boxes' centres in plan, from the earlier place to the later.
        const auto mid = [](const nlohmann::json& x, int k) {
            return 0.5 * (x["box_min"][k].get<double>() + x["box_max"][k].get<double>());
        };
        const double d =
            std::hypot(mid(after[name], 0) - mid(o, 0), mid(after[name], 1) - mid(o, 1));
        if (d > 0.05) std::cout << " " << name << " moved " << Fixed(d, 2) << " m;";
    }
    for (const auto& [name, o] : after) {
        if (!before.count(name)) std::cout << " " << name << " new;";
    }
    std::set<std::string> removed_later;
    for (const nlohmann::json& r : b.at("removed")) removed_later.insert(r.at("global_id"));
    size_t rebuilt = 0;
    for (const nlohmann::json& r : a.at("removed"))
        rebuilt += !removed_later.count(r.at("global_id"));
    std::cout << " " << rebuilt << " removed elements built since (on both floors); " << clutter
              << " clutter objects cleared\n";
}

int RunDemo(const DemoOptions& opt) {
    const auto t_start = Clock::now();
    const fs::path out = opt.out;
    const fs::path building_file = out / "building.ifc";
    const fs::path session_dir = out / "session";
    const fs::path capture_dir = out / "capture";
    const fs::path later_dir = out / "capture_later";
    const fs::path map_dir = out / "map";
    for (const fs::path& p : {building_file, session_dir, capture_dir, later_dir, map_dir}) {
        if (fs::exists(p) && !opt.overwrite) {
            throw common::FileError(
                common::StatusCode::kAlreadyExists, out.string(), 0,
                "holds an earlier demo; pass --overwrite or choose another --out");
        }
    }
    for (const fs::path& p : {capture_dir, later_dir, map_dir}) fs::remove_all(p);
    fs::create_directories(out);
    std::cout << std::fixed << std::setprecision(1);

    // 1. The building.
    const bim::BimModel model = WriteBuilding(building_file);

    // 2. The building as it was found: whole_building.yaml's edits on both storeys (added objects
    //    and clutter, removed furniture and columns, a moved desk, walls built off their place,
    //    two people), walked by a Go1 that starts 5 m outside the main entrance, goes in, through
    //    the ground floor and up the stairs to the first floor, recorded as the rig records it
    //    (host_tools/simulate).
    simulate::Scenario scenario;
    const simulate::CaptureReport cap =
        SimulateVisit("whole_building.yaml", opt, model, building_file, capture_dir, &scenario);
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
              << " keyframes in " << odo.wall_s << " s at full speed (" << odo.lcm_paced_s
              << " s of it holding its LCM output to a pace lcm-logger keeps up with)"
              << "\n           " << session_dir.string() << "/"
              << (odo.lcm_log.empty() ? "" : ", LCM recorded in " + odo.lcm_log.string()) << "\n";

    // 4. bimslam map: reference session, odometry, anchoring, change detection, report.
    std::cout << "  bimslam map " << building_file.string() << " " << capture_dir.string() << " -o "
              << map_dir.string() << "\n";
    const mapping::MapRun run = Map(building_file, {capture_dir}, map_dir);
    bool anchored = PrintVisit(run.summary["recordings"][0], "from outside the building");

    // 5. The second visit, three months later: a person carries the rig through the ground floor
    //    (whole_building_later.yaml); bimslam map adds it to the project and anchors it against
    //    the model and the first visit (issue 33).
    simulate::Scenario later_scenario;
    const simulate::CaptureReport later = SimulateVisit("whole_building_later.yaml", opt, model,
                                                        building_file, later_dir, &later_scenario);
    std::cout << "second visit, " << later_scenario.date << ": a person carrying the rig through "
              << "the ground floor, " << later.duration_s << " s (" << later.walk_length_m
              << " m), simulated in " << later.wall_s << " s\n           " << later_dir.string()
              << "/\n  bimslam map " << building_file.string() << " " << capture_dir.string() << " "
              << later_dir.string() << " -o " << map_dir.string()
              << "   (the first visit is kept)\n";
    const mapping::MapRun run2 = Map(building_file, {capture_dir, later_dir}, map_dir);
    anchored =
        PrintVisit(run2.summary["recordings"][0], "from inside, no initial pose") && anchored;
    PrintChangesBetween(map_dir, capture_dir, later_dir);

    const std::string report =
        run2.summary.contains("report") ? run2.summary["report"].get<std::string>() : "";
    std::cout << "results in " << out.string() << "/:\n"
              << "  building.ifc  the sample building (bimslam bim info " << building_file.string()
              << ")\n"
              << "  capture/      the rig's recording of the changed building and its truth\n"
              << "  capture_later/ the second visit's recording and its truth\n"
              << "  session/      bimslam-rig's session (bimslam session info "
              << session_dir.string() << ")\n"
              << "  map/          project.json, reference/, visits/<date>/ (odometry/, anchor/, "
                 "changes/), history.json, model_asis.ifc, building_map.ply, report/, "
                 "summary.json\n"
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
