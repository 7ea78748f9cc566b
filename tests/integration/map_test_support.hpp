// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Fixtures of the `bimslam map` tests (map_cli_test.cpp, map_visits_test.cpp,
// report_browser_test.cpp), made once per build of `bimslam` in the build folder and shared by
// the test processes (test::CachedFixture: one process makes each, the others wait for it; one
// that failed to build is not kept).
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>

#include "algorithms/io/file_util.hpp"
#include "algorithms/io/session.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::map_test {
namespace fs = std::filesystem;

inline const std::string kCli = BIMSLAM_CLI_PATH;
inline const std::string kScenarios = BIMSLAM_SCENARIO_DIR;
// A 40 s Go1 walk: long enough to anchor (the anchor tests' walks) and to pass the scenario's
// crate, cabinet, clutter and people; short enough for CI.
inline constexpr int kSeconds = 40;
// The visit a simulated capture of the default date is mapped into: OUT/visits/2023-11-14
// (`bimslam simulate` starts its clocks at 2023-11-14T22:13:20Z unless told).
inline const std::string kVisit = "2023-11-14";
inline fs::path VisitOf(const fs::path& out) { return out / "visits" / kVisit; }

inline test::CommandResult Cli(const std::string& args) {
    return test::RunCommand(kCli + " " + args);
}

inline void MustRun(const std::string& args) {
    const auto r = Cli(args);
    ASSERT_EQ(r.exit_code, 0) << "bimslam " << args << "\n" << r.out << r.err;
}

inline nlohmann::json ReadJson(const fs::path& file) {
    return nlohmann::json::parse(io::ReadFileToString(file));
}

// a and b have the same structure, strings and integers, and floating-point numbers within tol.
// Ceres evaluates residual blocks on several threads and sums them in the order they finish, so
// two runs of the same anchoring may differ in the last digits (an as-built wall's offset came
// out 0.012134 m and 0.012142 m in two runs of 8).
inline void ExpectJsonNear(const nlohmann::json& a, const nlohmann::json& b, double tol,
                           const std::string& path = "") {
    if (a.is_number_float() || b.is_number_float()) {
        ASSERT_TRUE(a.is_number() && b.is_number()) << path;
        EXPECT_NEAR(a.get<double>(), b.get<double>(), tol) << path;
    } else if (a.is_object() && b.is_object()) {
        ASSERT_EQ(a.size(), b.size()) << path;
        for (const auto& [key, value] : a.items()) {
            ASSERT_TRUE(b.contains(key)) << path << "/" << key;
            ExpectJsonNear(value, b.at(key), tol, path + "/" + key);
        }
    } else if (a.is_array() && b.is_array()) {
        ASSERT_EQ(a.size(), b.size()) << path;
        for (size_t i = 0; i < a.size(); ++i) {
            ExpectJsonNear(a[i], b[i], tol, path + "/" + std::to_string(i));
        }
    } else {
        EXPECT_EQ(a, b) << path;
    }
}

// The steps of a `bimslam map --json` run: {step: skipped}.
inline nlohmann::json Steps(const nlohmann::json& j) {
    nlohmann::json s = nlohmann::json::object();
    for (const nlohmann::json& step : j.at("steps"))
        s[step.at("step").get<std::string>()] = step.at("skipped");
    return s;
}

inline fs::path FixtureRoot() {
    static const fs::path root = test::FixtureRootFor(BIMSLAM_TEST_BINARY_DIR "/map_fixtures", kCli);
    return root;
}

inline fs::path Fixture(const std::string& name, const std::function<void(const fs::path&)>& make) {
    return test::CachedFixture(FixtureRoot(), name, make);
}

// The sample office building (the GlobalIds of changed_building.yaml are its).
inline fs::path Building() {
    return Fixture("office", [](const fs::path& d) {
        MustRun("bim sample -o " + (d / "building.ifc").string());
    });
}

// The odometry stops refining a scan at its time budget: on a loaded machine (ctest -j2, other
// engineers) two runs could differ. A budget no scan reaches makes the runs comparable.
inline const std::string kBudget = " --budget-ms 10000";

inline std::string MapArgs(const fs::path& capture, const fs::path& out) {
    return "map " + (Building() / "building.ifc").string() + " " + capture.string() + " -o " +
           out.string() + kBudget;
}

// capture/: the changed building walked for kSeconds; out/: `bimslam map` of it.
inline fs::path Mapped() {
    return Fixture("mapped", [](const fs::path& d) {
        MustRun("simulate --model " + (Building() / "building.ifc").string() + " --scenario " +
                kScenarios + "/changed_building.yaml --duration " + std::to_string(kSeconds) +
                " -o " + (d / "capture").string());
        MustRun(MapArgs(d / "capture", d / "out"));
    });
}

// A hand-held walk up the office's stair and back down (issue 31, item 6): from a metre before
// the flight's foot to a metre past its head and back (`bimslam bim stairs`: entry (22.975,
// 0.875), exit (28.225, 0.875)), with a box added on each storey in the stair's room. OS1-16 at
// 512x10 to stay cheap: about 2 s to simulate and 8 s to map on the shared machine.
inline fs::path TwoStoreys() {
    return Fixture("two_storeys", [](const fs::path& d) {
        io::WriteFileAtomic(d / "scenario.yaml", R"(platform: handheld
storey: all
seed: 3
sensor: {model: OS1-16, lidar_mode: 512x10}
path:
  mode: waypoints
  waypoints: [[21.975, 0.875], [29.225, 0.875], [21.975, 0.875]]
  waypoint_storeys: [Ground Floor, First Floor, Ground Floor]
edits:
  boxes:
    - {name: crate downstairs, center: [25.5, 3.5, 0.4], size: [0.8, 0.6, 0.8], yaw_deg: 0}
    - {name: crate upstairs, center: [25.5, 3.5, 3.6], size: [0.8, 0.6, 0.8], yaw_deg: 0}
)");
        MustRun("simulate --model " + (Building() / "building.ifc").string() + " --scenario " +
                (d / "scenario.yaml").string() + " -o " + (d / "capture").string());
        MustRun(MapArgs(d / "capture", d / "out"));
    });
}

// A walk through another building (the hall) mapped against the office: it cannot be anchored.
// map.out holds what `bimslam map` printed; its exit code must be 1.
inline fs::path Unanchorable() {
    return Fixture("unanchorable", [](const fs::path& d) {
        MustRun("bim sample --layout hall -o " + (d / "hall.ifc").string());
        MustRun("simulate --model " + (d / "hall.ifc").string() + " --duration 30 -o " +
                (d / "capture").string());
        const auto r = Cli(MapArgs(d / "capture", d / "out"));
        EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
        io::WriteFileAtomic(d / "map.out", r.out + r.err);
    });
}

// The mapped walk with its odometry's verdict turned to untrusted (one failed stretch), as
// `bimslam odometry` writes it for a 2 Hz folder (odometry_large_motion_test.cpp makes real ones;
// a pcap at 10 Hz never fails its checks). What the map does with the verdict is tested here: its
// summary, exit code and report. A copy of Mapped(): its first run redoes the odometry (the stamps
// name the recording's path), then the verdict is edited and the report's stamp removed, so the
// second run gathers the summary and writes the report again. map.out: what the second printed.
inline fs::path Untrusted() {
    return Fixture("untrusted", [](const fs::path& d) {
        fs::copy(Mapped(), d, fs::copy_options::recursive);
        MustRun(MapArgs(d / "capture", d / "out"));
        const fs::path odo_file = VisitOf(d / "out") / "odometry" / "capture.json";
        nlohmann::json odo = ReadJson(odo_file);
        odo["verdict"] = "untrusted";
        odo["verdict_text"] = "UNTRUSTED: 4 failed scans in 1 stretches: scans 120-131";
        odo["failed_stretches"] = nlohmann::json::array({{{"first_scan", 120},
                                                          {"last_scan", 131},
                                                          {"first_s", 12.0},
                                                          {"last_s", 13.1},
                                                          {"failed", 4},
                                                          {"reasons", {"low overlap"}}}});
        io::WriteFileAtomic(odo_file, odo.dump() + "\n");
        fs::remove(d / "out" / "stamps" / "report.json");
        const auto r = Cli(MapArgs(d / "capture", d / "out"));
        EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
        io::WriteFileAtomic(d / "map.out", r.out + r.err);
    });
}

// The mapped walk with the session's own odometry verdict (odometry_verdict.json, which the
// anchoring reads) and capture.json turned untrusted over the scans around its middle keyframe, as
// the odometry writes them when scans fail their checks: the anchoring splits the session there
// (host_tools/anchor/README.md, "Untrusted odometry"). A copy of Mapped(): its first run redoes
// the odometry (the stamps name the recording's path), then the verdict is edited and the anchor,
// changes and report steps run again. map.out: what the second run printed (exit 1 asserted).
inline fs::path InParts() {
    return Fixture("in_parts", [](const fs::path& d) {
        fs::copy(Mapped(), d, fs::copy_options::recursive);
        MustRun(MapArgs(d / "capture", d / "out"));
        const fs::path session = VisitOf(d / "out") / "odometry" / "capture";
        const std::vector<int64_t> times = io::ReadTimes(session / "times.txt");
        ASSERT_GT(times.size(), 12u);
        const int64_t mid = times[times.size() / 2];
        const nlohmann::json stretch = {{"first_scan", 200},
                                        {"last_scan", 210},
                                        {"first_s", 20.0},
                                        {"last_s", 21.0},
                                        {"first_stamp_ns", mid - 50'000'000},
                                        {"last_stamp_ns", mid + 50'000'000},
                                        {"failed", 3},
                                        {"reasons", {"low overlap with the map"}}};
        nlohmann::json v = ReadJson(session / "odometry_verdict.json");
        v["verdict"] = "untrusted";
        v["failed_stretches"] = nlohmann::json::array({stretch});
        io::WriteFileAtomic(session / "odometry_verdict.json", v.dump());
        const fs::path odo_file = VisitOf(d / "out") / "odometry" / "capture.json";
        nlohmann::json odo = ReadJson(odo_file);
        odo["verdict"] = "untrusted";
        odo["verdict_text"] = "UNTRUSTED: 3 failed scans in 1 stretches: scans 200-210";
        odo["failed_stretches"] = nlohmann::json::array({stretch});
        io::WriteFileAtomic(odo_file, odo.dump() + "\n");
        for (const char* step : {"anchor", "changes"})
            fs::remove(VisitOf(d / "out") / "stamps" / (std::string(step) + ".json"));
        fs::remove(d / "out" / "stamps" / "report.json");
        const auto r = Cli(MapArgs(d / "capture", d / "out"));
        EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
        io::WriteFileAtomic(d / "map.out", r.out + r.err);
    });
}

// Two visits of the sample office (map_visits_test.cpp, report_browser_test.cpp): three short
// hand-held walks on two days, mapped as one project.
namespace two_days {

// Walk a on 2 March, b and c on 9 March (morning and afternoon): two visits. On 2 March a crate
// stood in the corridor and the open office's columns were not built yet; on 9 March the crate
// is gone, the columns stand, as modelled, and a cabinet stands in the open office.
inline const std::string kDayA = "2026-03-02", kDayB = "2026-03-09";
struct Walk {
    const char* name;
    const char* start;
    int seed;
    const char* edits;
};
inline const char* const kFirstDay =
    "edits:\n"
    "  boxes: [{name: crate in the corridor, center: [24.0, 7.75, 0.4], size: [0.8, 0.6, 0.8], "
    "yaw_deg: 0}]\n"
    "  removed: {classes: [IfcColumn]}\n";
inline const char* const kSecondDay =
    "edits:\n"
    "  boxes: [{name: cabinet in the open office, center: [19.6, 4.0, 0.5], size: [1.0, 0.6, "
    "1.0], yaw_deg: 0}]\n";
inline const Walk kWalks[] = {{"a", "2026-03-02T09:00:00Z", 11, kFirstDay},
                              {"b", "2026-03-09T09:00:00Z", 12, kSecondDay},
                              {"c", "2026-03-09T15:30:00Z", 13, kSecondDay}};

// Hand-held, OS1-16 at 512x10 and 30 s to stay cheap (about 2 s to simulate each).
inline fs::path Walks() {
    return Fixture("visit_walks", [](const fs::path& d) {
        for (const Walk& w : kWalks) {
            io::WriteFileAtomic(d / (std::string(w.name) + ".yaml"),
                                "platform: handheld\nseed: " + std::to_string(w.seed) +
                                    "\nduration_s: 30\nsensor: {model: OS1-16, lidar_mode: "
                                    "512x10}\n" +
                                    w.edits);
            MustRun("simulate --model " + (Building() / "building.ifc").string() + " --scenario " +
                    (d / (std::string(w.name) + ".yaml")).string() + " --start " + w.start +
                    " -o " + (d / w.name).string());
        }
    });
}

inline std::string Model() { return (Building() / "building.ifc").string(); }

// a is given as its pcap (metadata.json beside it, no capture.json): dated by its first packet,
// named "lidar".
inline std::string A() { return (Walks() / "a" / "lidar.pcap").string(); }
inline std::string B() { return (Walks() / "b").string(); }
inline std::string C() { return (Walks() / "c").string(); }

inline nlohmann::json MapJson(const std::string& args, int exit_code = 0) {
    const auto r = Cli(args + kBudget + " --json");
    EXPECT_EQ(r.exit_code, exit_code) << args << "\n" << r.err;
    return r.exit_code == 0 ? nlohmann::json::parse(r.out) : nlohmann::json(nullptr);
}

// All at once, given in reverse order of their dates. out.json: what it printed.
inline fs::path AllAtOnce() {
    return Fixture("visits_all", [](const fs::path& d) {
        const nlohmann::json j = MapJson("map " + Model() + " " + C() + " " + B() + " " + A() +
                                         " -o " + (d / "out").string());
        io::WriteFileAtomic(d / "out.json", j.dump(1));
    });
}

}  // namespace two_days

}  // namespace bimslam::map_test
