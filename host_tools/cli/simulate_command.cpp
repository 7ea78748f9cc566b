// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// bimslam simulate: a capture of a Go1 or handheld walk through a (changed) building, written as
// the rig records it (host_tools/simulate/simulate.hpp).
#include <unistd.h>

#include <algorithm>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "algorithms/common/status.hpp"
#include "algorithms/io/sha256.hpp"
#include "host_tools/bim/ifc_model.hpp"
#include "host_tools/cli/command.hpp"
#include "host_tools/simulate/scenario_yaml.hpp"
#include "host_tools/simulate/simulate.hpp"
#include "host_tools/simulate/visits.hpp"

namespace bimslam::cli {
namespace {
namespace fs = std::filesystem;

struct SimulateArgs {
    std::string model;
    std::string storey;
    std::string scenario;
    std::string platform;
    std::string sensor;
    double duration_s = -1;
    int64_t seed = -1;
    std::string start;
    std::string visit;
    std::string out;
    bool overwrite = false;
    bool json = false;
};

// The scenario of the command line: the file's (or the platform's defaults) with the options in
// place. With visits, --duration, --storey and --sensor apply to every visit; --seed and --start
// only to the one --visit names (each visit has its own).
simulate::Scenario ScenarioOf(const SimulateArgs& a) {
    simulate::Scenario s;
    if (!a.scenario.empty()) {
        s = simulate::LoadScenario(a.scenario);
        if (!a.platform.empty()) {
            throw common::Error(common::StatusCode::kInvalidArgument,
                                "--platform: the scenario file sets the platform");
        }
    } else {
        s = simulate::DefaultScenario(
            simulate::PlatformFromString(a.platform.empty() ? "go1" : a.platform).value());
    }
    if (!a.visit.empty()) {
        s = simulate::VisitScenario(s, simulate::FindVisit(s, a.visit));
    } else if (!s.visits.empty() && (a.seed >= 0 || !a.start.empty())) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            "--seed and --start: each visit has its own (with --visit LABEL they "
                            "set that visit's)");
    }
    if (!a.model.empty()) s.model = a.model;
    if (!a.storey.empty()) s.storey = a.storey;
    if (a.duration_s >= 0) s.duration_s = a.duration_s;
    if (!a.sensor.empty()) {
        s.sensor.model = a.sensor;
        s.sensor.metadata.clear();
    }
    for (simulate::VisitSpec& v : s.visits) {
        if (!a.storey.empty()) v.storey.reset();
        if (a.duration_s >= 0) v.duration_s.reset();
    }
    if (a.seed >= 0) s.seed = uint64_t(a.seed);
    if (!a.start.empty()) s.date = a.start;
    if (s.model.empty()) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            "no model: give --model or set `model` in the scenario");
    }
    s.Validate();
    return s;
}

// What the capture holds, for the user (and as JSON with --json).
nlohmann::json PrintCapture(const simulate::Scenario& s, const simulate::CaptureReport& r,
                            const std::string& out) {
    const double mb = double(r.pcap_bytes) / 1e6;
    std::cout << std::fixed << std::setprecision(1) << "walk      "
              << simulate::ToString(s.platform) << ", " << r.captured_length_m << " m in "
              << r.duration_s << " s of a " << r.walk_length_m << " m walk"
              << (r.laps > 1 ? " (" + std::to_string(r.laps) + " laps)" : "")
              << (r.starts_outside ? ", starting outside" : "")
              << (r.storey.empty() ? "" : ", storey '" + r.storey + "'") << "\n"
              << "lidar     " << r.frames << " frames, " << r.lidar_packets << " lidar + "
              << r.imu_packets << " IMU packets (" << r.lost_packets << " lost), " << mb << " MB ("
              << mb / (r.duration_s / 60.0) << " MB/min)\n";
    if (s.platform == simulate::Platform::kGo1) {
        std::cout << "can       " << r.can_frames << " Go1 frames\n";
    }
    std::cout << "changes   " << r.added_objects << " added, " << r.removed_elements << " removed, "
              << r.moved_elements << " moved, " << r.people << " people\n"
              << "time      " << std::setprecision(2) << r.wall_s << " s, " << std::setprecision(1)
              << r.duration_s / r.wall_s << "x real time\n"
              << "capture   " << out << " (capture.json lists the files)\n";
    if (r.storeys.size() > 1 || !r.unreached_storeys.empty()) {
        std::cout << "storeys   " << r.storeys.size() << " walked (";
        for (size_t k = 0; k < r.storeys.size(); ++k) {
            std::cout << (k ? ", " : "") << "'" << r.storeys[k] << "'";
        }
        std::cout << "), " << r.flights_walked << " flights of stairs walked\n";
    }
    for (const std::string& n : r.notes) std::cout << "note      " << n << "\n";
    nlohmann::json j = {{"capture", out},
                        {"frames", r.frames},
                        {"duration_s", r.duration_s},
                        {"walk_length_m", r.walk_length_m},
                        {"captured_length_m", r.captured_length_m},
                        {"laps", r.laps},
                        {"starts_outside", r.starts_outside},
                        {"storey", r.storey},
                        {"lidar_packets", r.lidar_packets},
                        {"imu_packets", r.imu_packets},
                        {"lost_packets", r.lost_packets},
                        {"can_frames", r.can_frames},
                        {"pcap_bytes", r.pcap_bytes},
                        {"wall_s", r.wall_s},
                        {"real_time_factor", r.duration_s / r.wall_s},
                        {"notes", r.notes}};
    if (s.storey == simulate::kAllStoreys) {
        j["storeys"] = r.storeys;
        j["flights_walked"] = r.flights_walked;
        j["unreached_storeys"] = r.unreached_storeys;
    }
    return j;
}

// Exit 2 when the stairs left storeys out: the capture of those reached is written, the model's
// stairs are the bad input.
int CaptureExit(const simulate::Scenario& s, const simulate::CaptureReport& r) {
    if (r.unreached_storeys.empty()) return kExitOk;
    std::cerr << s.model.string() << ": " << r.unreached_storeys.size()
              << " storey(s) cannot be reached by the stairs (the notes say why); the walk "
                 "covers the storeys it reaches\n";
    return kExitBadInput;
}

int Simulate(const SimulateArgs& a) {
    const simulate::Scenario s = ScenarioOf(a);
    if (fs::exists(a.out) && !fs::is_empty(a.out) && !a.overwrite) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            a.out + ": exists and is not empty (--overwrite replaces its files)");
    }
    const bim::BimModel model = bim::LoadIfc(s.model.string());
    std::cout << "loaded    " << s.model.string() << ": " << model.schema << ", "
              << model.storeys.size() << " storeys, " << model.elements.size() << " elements\n";
    const bool tty = isatty(STDERR_FILENO);
    const auto progress = [tty](double f) {
        if (tty) std::cerr << "\r  simulating " << int(100 * f) << " %" << std::flush;
    };
    const std::string sha = io::Sha256File(s.model);
    if (s.visits.empty()) {
        const simulate::CaptureReport r = simulate::SimulateCapture(s, model, sha, a.out, progress);
        if (tty) std::cerr << "\r                      \r";
        const nlohmann::json j = PrintCapture(s, r, a.out);
        if (a.json) std::cout << j.dump(2) << "\n";
        return CaptureExit(s, r);
    }
    const std::vector<simulate::VisitCapture> visits =
        simulate::SimulateVisits(s, model, sha, a.out, progress);
    if (tty) std::cerr << "\r                      \r";
    nlohmann::json j = nlohmann::json::array();
    int exit = kExitOk;
    for (const simulate::VisitCapture& v : visits) {
        const simulate::Scenario vs = simulate::VisitScenario(s, simulate::FindVisit(s, v.label));
        std::cout << "visit     " << v.label << ", " << v.date << "\n";
        j.push_back(PrintCapture(vs, v.report, (fs::path(a.out) / v.label).string()));
        j.back()["label"] = v.label;
        j.back()["date"] = v.date;
        exit = std::max(exit, CaptureExit(vs, v.report));
    }
    std::cout << "visits    " << visits.size() << ", " << a.out
              << "/visits.json: the visits by date and what changed between them\n";
    if (a.json) std::cout << nlohmann::json{{"visits", j}}.dump(2) << "\n";
    return exit;
}

}  // namespace

void AddSimulateCommand(CLI::App& app, int& exit_code) {
    auto a = std::make_shared<SimulateArgs>();
    CLI::App* cmd = app.add_subcommand(
        "simulate",
        "simulate a capture: a Go1 or handheld walk through the model, with the scenario's "
        "changes, written as lidar.pcap + metadata.json, go1_can.log/.pcap, ground_truth.tum, "
        "changes.json and capture.json; a scenario with `visits` gives one capture per visit, "
        "each on its own date, and the truth of what changed between them (visits.json)");
    cmd->add_option("--model", a->model, "IFC model (overrides the scenario's `model`)");
    cmd->add_option(
        "--storey", a->storey,
        "storey by name, or 'all': every storey the stairs reach, joined by walking them (exit 2 "
        "when a storey cannot be reached; the capture covers those that can). Default: the "
        "scenario's, else the lowest with 2 m or more to the next: a foundation's level is "
        "passed over");
    cmd->add_option("--scenario", a->scenario,
                    "scenario YAML (host_tools/simulate/scenarios/ has examples; default: a Go1 "
                    "coverage walk with default noise)");
    cmd->add_option("--platform", a->platform,
                    "go1 or handheld, without a scenario file (a vehicle needs a scenario file "
                    "with its waypoints: scenarios/vehicle_outdoor.yaml)")
        ->check(CLI::IsMember({"go1", "handheld"}));
    cmd->add_option("--sensor", a->sensor,
                    "built-in sensor: OS0, OS1 or OS2 with 16, 32, 64 or 128 beams, e.g. OS0-64, "
                    "OS1-128 (overrides the scenario's sensor.model and metadata; default OS1-32)");
    cmd->add_option("--duration", a->duration_s,
                    "seconds to capture (default: the walk once; longer repeats the walk)")
        ->check(CLI::NonNegativeNumber);
    cmd->add_option("--seed", a->seed,
                    "random seed (overrides the scenario's; with visits, only with --visit)")
        ->check(CLI::NonNegativeNumber);
    cmd->add_option(
        "--start", a->start,
        "when the walk starts, ISO 8601 (e.g. 2026-03-02T09:30:00Z; overrides the "
        "scenario's date; default 2023-11-14T22:13:20Z): the pcap's and CAN log's "
        "clock, which `bimslam map` dates its visits by; with visits, only with --visit");
    cmd->add_option("--visit", a->visit,
                    "simulate only the visit of this label of the scenario's `visits`, into the "
                    "output as a capture of its own (the same files as OUTPUT/LABEL of the whole "
                    "run)");
    cmd->add_option("-o,--output", a->out,
                    "capture directory; with the scenario's `visits`, the folder of one capture "
                    "per visit (OUTPUT/LABEL/) and visits.json: the visits by date and what "
                    "changed between each pair")
        ->required();
    cmd->add_flag("--overwrite", a->overwrite,
                  "replace the files of an existing capture directory");
    cmd->add_flag("--json", a->json, "also print the figures as JSON");
    cmd->callback([a, &exit_code] { exit_code = Run([&] { return Simulate(*a); }); });
}

}  // namespace bimslam::cli
