// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// `bimslam map` and `bimslam report` as a user runs them, on a short simulated capture of the
// changed sample building (host_tools/simulate/scenarios/changed_building.yaml):
// - every step's output exists, and the summary's figures equal those of the individual commands
//   (bim2session, odometry, anchor, changes --truth, evaluate --align none) run on the same input;
// - a second run skips every step; touching the recording re-runs odometry and what follows;
// - a recording that cannot be anchored (another building) still gets a report that says so,
//   with its odometry map in its own frame;
// - a model that is not IFC or a recording that is not Ouster exits 2 naming the file, before
//   any step (nothing written).
// The browser test of the page is report_browser_test.cpp (same fixtures).
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "algorithms/io/file_util.hpp"
#include "algorithms/io/ply.hpp"
#include "algorithms/io/trajectory.hpp"
#include "host_tools/report/report_data.hpp"
#include "tests/integration/map_test_support.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam {
namespace {
namespace BIMSLAM_UNITY_ID {
namespace fs = std::filesystem;
using nlohmann::json;
using namespace map_test;

// The page's data, as embedded in report.html.
json PageData(const fs::path& html_file) {
    const std::string html = io::ReadFileToString(html_file);
    const std::string open = "<script id=\"report-data\" type=\"application/json\">";
    const size_t a = html.find(open), b = html.find("</script>", a);
    if (a == std::string::npos || b == std::string::npos) return nullptr;
    return json::parse(html.substr(a + open.size(), b - a - open.size()));
}

TEST(MapCli, EveryStepWritesItsFolderAndTheSummaryEqualsTheIndividualCommands) {
    const fs::path m = Mapped();
    for (const char* f :
         {"project.json", "reference/session.json", "report/report.html", "summary.json",
          "stamps/reference.json", "stamps/report.json", "changes.bcf"}) {
        EXPECT_TRUE(fs::exists(m / "out" / f)) << f;
    }
    for (const char* f :
         {"odometry/capture/session.json", "odometry/capture.json", "anchor/anchor.json",
          "anchor/loops.json", "anchor/capture/trajectory_bim.tum", "changes/capture/changes.json",
          "changes/capture/evaluation.json", "changes/capture/model_updated.ifc",
          "changes/capture/changes.bcf", "summary.json", "stamps/odometry_capture.json",
          "stamps/anchor.json", "stamps/changes.json"}) {
        EXPECT_TRUE(fs::exists(VisitOf(m / "out") / f)) << f;
    }
    // The project's changes.bcf holds the newest visit's recordings' topics: here its one
    // recording's, entry for entry.
    if (test::RunCommand("command -v unzip >/dev/null").exit_code == 0) {
        const auto listing = [](const fs::path& f) {
            return test::RunCommand("unzip -Z1 " + f.string() + " | sort").out;
        };
        EXPECT_EQ(listing(m / "out" / "changes.bcf"),
                  listing(VisitOf(m / "out") / "changes" / "capture" / "changes.bcf"));
    }
    const json summary = ReadJson(m / "out" / "summary.json");
    const json& r = summary.at("recordings").at(0);
    ASSERT_EQ(r.at("anchor").at("verdict"), "anchored") << summary.dump(1);

    // The same steps, one command each, into another folder.
    test::TempDir tmp;
    const fs::path b = Building(), c = m / "capture";
    MustRun("bim2session " + (b / "building.ifc").string() + " -o " + (tmp / "reference").string());
    MustRun("odometry " + c.string() + " -o " + (tmp / "capture").string() + kBudget);
    MustRun("anchor --reference " + (tmp / "reference").string() + " --query " +
            (tmp / "capture").string() + " -o " + (tmp / "anchor").string());
    MustRun("changes --model " + (b / "building.ifc").string() + " --session " +
            (tmp / "anchor" / "capture").string() + " --truth " + (c / "changes.json").string() +
            " -o " + (tmp / "changes").string());
    const auto ev = Cli("evaluate --align none --json --est " +
                        (tmp / "anchor" / "capture" / "trajectory_bim.tum").string() + " --ref " +
                        (c / "ground_truth.tum").string());
    ASSERT_EQ(ev.exit_code, 0) << ev.err;
    const json e = json::parse(ev.out);
    const json& acc = r.at("accuracy");
    EXPECT_NEAR(acc.at("ape_trans_rmse_m").get<double>(), e.at("ape_trans_rmse_m").get<double>(),
                1e-9);
    EXPECT_NEAR(acc.at("ape_rot_rmse_deg").get<double>(), e.at("ape_rot_rmse_deg").get<double>(),
                1e-9);
    EXPECT_EQ(acc.at("matched"), e.at("matched"));
    EXPECT_LT(acc.at("ape_trans_rmse_m").get<double>(), 0.05);
    // The change scores and counts: the same files (numbers to 0.1 mm: see ExpectJsonNear).
    ExpectJsonNear(r.at("change_scores"), ReadJson(tmp / "changes" / "evaluation.json"), 1e-4);
    const json changes = ReadJson(tmp / "changes" / "changes.json");
    EXPECT_EQ(r.at("changes").at("new_objects"), changes.at("new_objects").size());
    EXPECT_EQ(r.at("changes").at("missing"), changes.at("missing").size());
    EXPECT_EQ(r.at("changes").at("deviating"), changes.at("deviating").size());
    const json anchor = ReadJson(tmp / "anchor" / "anchor.json");
    EXPECT_EQ(r.at("anchor").at("accepted_loops"),
              anchor.at("sessions").at(0).at("accepted_loops"));
    EXPECT_EQ(r.at("odometry").at("keyframes"),
              ReadJson(tmp / "capture" / "session.json").at("counts").at("keyframes"));
}

TEST(MapCli, ASecondRunSkipsEveryStepAndTouchingTheRecordingRerunsOdometryAndAfter) {
    test::TempDir tmp;
    // A copy of the mapped fixture, its files' times kept (`cp -a`): the recording is touched
    // here, not in the shared one. The project is somewhere else now, recording and output, as
    // when a user moves a project folder: the stamps name no path, so only the report is made
    // again (its list of visits names the recording's new path)...
    const auto copy = test::RunCommand("cp -a " + Mapped().string() + "/. " + tmp.path().string());
    ASSERT_EQ(copy.exit_code, 0) << copy.err;
    const std::string args = MapArgs(tmp / "capture", tmp / "out") + " --json";
    const auto first = Cli(args);
    ASSERT_EQ(first.exit_code, 0) << first.err;
    const json moved = Steps(json::parse(first.out));
    for (const auto& [step, skipped] : moved.items()) {
        EXPECT_EQ(skipped.get<bool>(), step != "report") << step;
    }
    // ... and then nothing.
    const auto second = Cli(args);
    ASSERT_EQ(second.exit_code, 0) << second.err;
    const json steps = Steps(json::parse(second.out));
    for (const auto& [step, skipped] : steps.items()) EXPECT_TRUE(skipped.get<bool>()) << step;
    EXPECT_EQ(steps.size(), 6u)
        << steps.dump();  // reference, odometry, anchor, changes, history, report
    EXPECT_EQ(json::parse(second.out).at("recordings"), json::parse(first.out).at("recordings"));
    for (const json& s : json::parse(second.out).at("steps"))
        EXPECT_EQ(s.at("other_build"), false) << s.dump() << ": this build made every step";

    // Steps another build of bimslam made (their stamp names another program, or none: made
    // before stamps named it) are kept, not made again, and said, with how to make them again.
    const fs::path stamps = VisitOf(tmp / "out") / "stamps";
    json anchor_stamp = ReadJson(stamps / "anchor.json");
    ASSERT_TRUE(anchor_stamp.at("program").get<std::string>().rfind("build-id ", 0) == 0)
        << anchor_stamp.dump();
    anchor_stamp["program"] = "build-id 0123456789abcdef";
    io::WriteFileAtomic(stamps / "anchor.json", anchor_stamp.dump(2));
    json odometry_stamp = ReadJson(stamps / "odometry_capture.json");
    odometry_stamp.erase("program");
    io::WriteFileAtomic(stamps / "odometry_capture.json", odometry_stamp.dump(2));
    const auto older = Cli(args);
    ASSERT_EQ(older.exit_code, 0) << older.err;
    for (const json& s : json::parse(older.out).at("steps")) {
        const std::string step = s.at("step");
        EXPECT_EQ(s.at("skipped"), true) << step;
        EXPECT_EQ(s.at("other_build"), step == "anchor " + kVisit || step == "odometry capture")
            << step;
    }
    const auto said = Cli(MapArgs(tmp / "capture", tmp / "out"));
    ASSERT_EQ(said.exit_code, 0) << said.err;
    EXPECT_NE(said.out.find("made by another build of bimslam, kept: odometry capture; anchor " +
                            kVisit + "; --force makes every step again with this one"),
              std::string::npos)
        << said.out;

    const fs::path pcap = tmp / "capture" / "lidar.pcap";
    fs::last_write_time(pcap, fs::last_write_time(pcap) + std::chrono::seconds(5));
    const auto third = Cli(args);
    ASSERT_EQ(third.exit_code, 0) << third.err;
    const json again = Steps(json::parse(third.out));
    EXPECT_EQ(again.at("reference"), true);
    for (const std::string& s : std::vector<std::string>{"odometry capture", "anchor " + kVisit,
                                                         "changes " + kVisit, "report"}) {
        EXPECT_EQ(again.at(s), false) << s;
    }

    // A datum (two exterior walls surveyed at their true offsets, from the capture's truth)
    // reruns the changes and the report only, and the changes say which walls held the frame.
    std::string datum = "global_id,dx,dy,dz\n";
    const json truth = ReadJson(tmp / "capture" / "changes.json");
    for (const json& m : truth.at("moved")) {
        const std::string name = m.at("name");
        if (name != "Ground Floor exterior wall south" &&
            name != "Ground Floor exterior wall west") {
            continue;
        }
        const json& t = m.at("translation");
        datum += m.at("global_id").get<std::string>() + "," + std::to_string(t[0].get<double>()) +
                 "," + std::to_string(t[1].get<double>()) + "," +
                 std::to_string(t[2].get<double>()) + "\n";
    }
    io::WriteFileAtomic(tmp / "survey.csv", datum);
    const auto fourth = Cli(args + " --datum " + (tmp / "survey.csv").string());
    ASSERT_EQ(fourth.exit_code, 0) << fourth.err << datum;
    const json surveyed = Steps(json::parse(fourth.out));
    for (const std::string& s :
         std::vector<std::string>{"reference", "odometry capture", "anchor " + kVisit}) {
        EXPECT_EQ(surveyed.at(s), true) << s;
    }
    EXPECT_EQ(surveyed.at("changes " + kVisit), false);
    const fs::path visit = VisitOf(tmp / "out");
    const json changes = ReadJson(visit / "changes" / "capture" / "changes.json");
    EXPECT_EQ(changes.at("parameters").at("refinement").at("datum").size(), 2u) << datum;
    EXPECT_EQ(changes.at("counts").at("refinement").at("datum_seen"), 2);
    const json scores = ReadJson(visit / "changes" / "capture" / "evaluation.json");
    EXPECT_EQ(scores.at("as_built").at("surveyed"), 2);

    // A datum file that does not exist, one naming an element the model does not have, or one
    // with --no-refine, exits 2 before any step.
    auto bad = Cli(args + " --datum " + (tmp / "nowhere.csv").string());
    EXPECT_EQ(bad.exit_code, 2);
    EXPECT_NE(bad.err.find("nowhere.csv"), std::string::npos) << bad.err;
    io::WriteFileAtomic(tmp / "wrong.csv", "0000000000000000000000\n");
    bad = Cli(args + " --force --datum " + (tmp / "wrong.csv").string() + " --json");
    EXPECT_EQ(bad.exit_code, 2);
    EXPECT_NE(bad.err.find("wrong.csv:1: the model has no element"), std::string::npos) << bad.err;
    EXPECT_EQ(bad.out, "") << "no step ran";
    bad = Cli(args + " --no-refine --datum " + (tmp / "survey.csv").string());
    EXPECT_EQ(bad.exit_code, 2);
    EXPECT_NE(bad.err.find("--no-refine"), std::string::npos) << bad.err;

    // A step that fails (README.md: "step 'X' failed on FILE: why", exit 1, the steps before it
    // kept, the failed one run again next time): a file the report reads, damaged, and the
    // report's stamp gone (as after an interrupted run). With the datum of the last run, so
    // that no other step's inputs changed.
    const std::string same = args + " --datum " + (tmp / "survey.csv").string();
    const fs::path damaged = visit / "changes" / "capture" / "map_bim.ply";
    const std::string kept = io::ReadFileToString(damaged);
    io::WriteFileAtomic(damaged, "ply\nformat of no kind\n");
    fs::remove(tmp / "out" / "stamps" / "report.json");
    const auto failed = Cli(same + " --json");
    EXPECT_EQ(failed.exit_code, 1) << failed.out << failed.err;
    EXPECT_NE(failed.err.find("step 'report' failed on " + damaged.string()), std::string::npos)
        << failed.err;
    EXPECT_TRUE(fs::exists(visit / "stamps" / "changes.json")) << "the steps before kept";
    EXPECT_FALSE(fs::exists(tmp / "out" / "stamps" / "report.json"));
    io::WriteFileAtomic(damaged, kept);
    const auto after = Cli(same + " --json");
    ASSERT_EQ(after.exit_code, 0) << after.err;
    const json rerun = Steps(json::parse(after.out));
    for (const std::string& s : std::vector<std::string>{"reference", "odometry capture",
                                                         "anchor " + kVisit, "changes " + kVisit}) {
        EXPECT_EQ(rerun.at(s), true) << s;
    }
    EXPECT_EQ(rerun.at("report"), false) << "the failed step runs again";

    // The report's map is decimated to at most max_map_points (300 000 by default,
    // host_tools/report/README.md) and the page's data say how many of how many: a cap of 1000.
    EXPECT_EQ(report::ReportConfig{}.max_map_points, 300000u);
    report::ReportConfig capped;
    capped.max_map_points = 1000;
    const json data = report::CollectReportData(tmp / "out", capped);
    const size_t total = data.at("map").at("total").get<size_t>();
    const size_t shown = data.at("map").at("shown").get<size_t>();
    std::cout << "the map: " << total << " points, " << shown << " shown at a cap of 1000\n";
    EXPECT_GT(total, 10000u);
    EXPECT_LE(shown, 1000u);
    EXPECT_GT(shown, 500u);  // evenly thinned, not cut
    EXPECT_EQ(data.at("config").at("max_map_points"), 1000);
}

// Issue 34 item 3: `bimslam map --tolerance` reaches elements.csv's verdicts and the page; the
// changes step's stamp holds it, so another tolerance makes the changes, the history and the
// report again, and keeps the reference, the odometry and the anchoring.
TEST(MapCli, AnotherToleranceMakesTheChangesAndTheReportAgainAndReachesThePage) {
    test::TempDir tmp;
    // A copy of the mapped fixture, mapped once at its place (the stamps name the recording's
    // path), then with another tolerance.
    fs::copy(Mapped(), tmp.path(), fs::copy_options::recursive);
    const std::string args = MapArgs(tmp / "capture", tmp / "out");
    ASSERT_EQ(Cli(args).exit_code, 0);
    const auto r = Cli(args + " --tolerance 0.05 --json");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const json steps = Steps(json::parse(r.out));
    for (const std::string& s :
         std::vector<std::string>{"reference", "odometry capture", "anchor " + kVisit}) {
        EXPECT_EQ(steps.at(s), true) << s << " " << steps.dump();
    }
    for (const std::string& s : std::vector<std::string>{"changes " + kVisit, "history", "report"})
        EXPECT_EQ(steps.at(s), false) << s << " " << steps.dump();
    const fs::path changes = VisitOf(tmp / "out") / "changes" / "capture";
    EXPECT_DOUBLE_EQ(
        ReadJson(changes / "changes.json")["parameters"]["elements"]["tolerance_m"].get<double>(),
        0.05);
    // The corridor's north wall, built 3 cm off: beyond the default 1 cm, within 5 cm.
    const auto wall_verdict = [](const fs::path& csv) {
        const std::string text = io::ReadFileToString(csv);
        const size_t at = text.find("0EF31bAGn7cY_UpbsCA2np");
        if (at == std::string::npos) return std::string("no row");
        const size_t end = text.find('\n', at);
        const std::string row = text.substr(0, end);
        return row.substr(row.rfind(',') + 1);
    };
    EXPECT_EQ(wall_verdict(VisitOf(Mapped() / "out") / "changes" / "capture" / "elements.csv"),
              "beyond");
    EXPECT_EQ(wall_verdict(changes / "elements.csv"), "within");
    const json page = PageData(tmp / "out" / "report" / "report.html");
    ASSERT_TRUE(page.at("deviation").is_object());
    EXPECT_DOUBLE_EQ(page["deviation"]["tolerance_m"].get<double>(), 0.05);
    EXPECT_GT(page["deviation"]["elements"].size(), 10u);
    // The Scan-vs-BIM histograms count every map point on the model (map_bim.ply's class 0) at
    // the distance change detection measured (its scalar_distance), over the storeys.
    const io::PlyData ply = io::ReadPly(changes / "map_bim.ply");
    const io::PlyProperty* distance = ply.Find("scalar_distance");
    const io::PlyProperty* cls = ply.Find("scalar_class");
    ASSERT_TRUE(distance && cls);
    size_t on_model = 0;
    double sum = 0;
    for (size_t i = 0; i < ply.vertices.size(); ++i) {
        if (cls->values[i] != 0) continue;
        ++on_model;
        sum += distance->values[i];
    }
    const json& h = page.at("distances");
    ASSERT_EQ(h.at("storeys").size(), 2u) << h.dump();
    EXPECT_DOUBLE_EQ(h.at("bin_cm").get<double>(), 0.5);
    EXPECT_DOUBLE_EQ(h.at("range_cm").get<double>(), 10.0);  // the new-object threshold
    size_t counted = 0;
    double weighted_mean_cm = 0;
    for (const json& s : h.at("storeys")) {
        size_t n = 0;
        for (const json& c : s.at("counts")) n += c.get<size_t>();
        EXPECT_EQ(n, s.at("points").get<size_t>()) << s.at("name");
        EXPECT_EQ(s.at("counts").size(), 40u);
        counted += n;
        weighted_mean_cm += double(n) * s.at("mean_cm").get<double>();
    }
    EXPECT_GT(on_model, 10000u);
    EXPECT_EQ(counted, on_model);
    EXPECT_NEAR(weighted_mean_cm / double(counted), 100 * sum / double(on_model), 0.01);
    // A run again with the same tolerance skips every step.
    const auto again = Cli(args + " --tolerance 0.05 --json");
    ASSERT_EQ(again.exit_code, 0) << again.err;
    const json none = Steps(json::parse(again.out));
    for (const auto& [step, skipped] : none.items()) EXPECT_TRUE(skipped.get<bool>()) << step;
    EXPECT_NE(Cli("map --help").out.find("--tolerance"), std::string::npos);
}

// The report's data of a project of two visits (issue 33 item 6; map_test_support.hpp, two_days):
// each visit's walks (its anchored recordings' trajectories, split by storey like the newest's),
// the history with each element's box. The output of an older bimslam (no history.json, a summary
// without visits) gives neither, and the rest as before.
TEST(MapCli, TheReportsDataHoldsEachVisitsWalksAndTheHistoryAndAnOlderOutputNeither) {
    using namespace two_days;
    const fs::path out = AllAtOnce() / "out";
    const json data = report::CollectReportData(out, {});
    const json& visits = data.at("visits");
    ASSERT_EQ(visits.size(), 2u) << visits.dump().substr(0, 2000);
    const auto names = [](const json& v) {
        json n = json::array();
        for (const json& w : v.at("walks")) {
            EXPECT_FALSE(w.at("runs").empty()) << w.at("name");
            n.push_back(w.at("name"));
        }
        return n;
    };
    EXPECT_EQ(visits[0].at("label"), kDayA);
    EXPECT_EQ(names(visits[0]), json::array({"lidar"}));
    EXPECT_EQ(visits[1].at("label"), kDayB);
    EXPECT_EQ(names(visits[1]), json::array({"b", "c"}));
    for (size_t k = 0; k < 2; ++k) {  // the newest's walks are its recordings' trajectories
        EXPECT_EQ(visits[1]["walks"][k].at("runs"), data.at("sessions").at(k).at("runs")) << k;
    }
    const json& elements = data.at("history").at("elements");
    ASSERT_FALSE(elements.empty());
    for (const json& e : elements) {
        ASSERT_TRUE(e.contains("min") && e.contains("max")) << e.dump();
        if (e.at("class") != "IfcColumn") continue;  // the office's columns: 0.4 x 0.4 x 3 m
        for (int i = 0; i < 3; ++i) {
            EXPECT_NEAR(e["max"][i].get<double>() - e["min"][i].get<double>(), i < 2 ? 0.4 : 3.0,
                        1e-3)
                << e.dump();
        }
    }
    // An older output: the same folders, no history.json, a summary without visits.
    test::TempDir tmp;
    fs::create_directories(tmp / "out");
    for (const char* d : {"reference", "visits"})
        fs::create_directory_symlink(out / d, tmp / "out" / d);
    json summary = ReadJson(out / "summary.json");
    summary.erase("visits");
    summary.erase("visit");
    io::WriteFileAtomic(tmp / "out" / "summary.json", summary.dump());
    const json old = report::CollectReportData(tmp / "out", {});
    EXPECT_TRUE(old.at("visits").is_null());
    EXPECT_TRUE(old.at("history").is_null());
    // (Not the plans: two loads of the model may cut a wall's section a few mm apart.)
    for (const char* k : {"sessions", "changes", "loops"})
        EXPECT_EQ(old.at(k), data.at(k)) << k << json::diff(old.at(k), data.at(k)).dump();
}

// The report's data per storey (issue 31, item 6): the office's stair as a flight from the ground
// floor to the first; the reference session (both storeys, up the stairs) split into runs on
// each and the flight; the ground floor walk all on the ground floor; the map and each model
// class ordered storey by storey.
TEST(MapCli, TheReportsDataSplitsTheWalksByStoreyAndHoldsTheStairs) {
    // The page's own data (the fixture's summary names the folder it was made in, so the data
    // is read from the page rather than gathered again).
    const json data = PageData(Mapped() / "out" / "report" / "report.html");
    ASSERT_TRUE(data.is_object());
    ASSERT_EQ(data.at("storeys").size(), 2u);
    ASSERT_EQ(data.at("flights").size(), 1u) << data.at("flights").dump();
    const json& f = data.at("flights")[0];
    EXPECT_EQ(f.at("lower"), 0);
    EXPECT_EQ(f.at("upper"), 1);
    EXPECT_EQ(f.at("risers"), 16);
    EXPECT_EQ(f.at("treads").size() % 8, 0u);
    EXPECT_GE(f.at("treads").size(), 8u * 15) << "four corners of each of the 15 treads";
    // The reference walks the ground floor, up the flight, then the first floor.
    std::vector<std::pair<int, int>> reference_runs;
    for (const json& r : data.at("reference_runs")) {
        reference_runs.emplace_back(r.at("lower").get<int>(), r.at("upper").get<int>());
    }
    EXPECT_EQ(reference_runs, (std::vector<std::pair<int, int>>{{0, 0}, {0, 1}, {1, 1}}))
        << data.at("reference_runs").dump().substr(0, 400);
    const json& runs = data.at("sessions")[0].at("runs");
    ASSERT_EQ(runs.size(), 1u) << runs.dump().substr(0, 400);
    EXPECT_EQ(runs[0].at("lower"), 0);
    EXPECT_EQ(runs[0].at("upper"), 0);
    const json& map_ranges = data.at("map").at("sessions")[0].at("storeys");
    ASSERT_EQ(map_ranges.size(), 2u);
    EXPECT_EQ(map_ranges[0][0], 0);
    EXPECT_EQ(map_ranges[1][0], map_ranges[0][1]);
    EXPECT_EQ(map_ranges[0][1].get<size_t>() + map_ranges[1][1].get<size_t>(),
              data.at("map").at("shown").get<size_t>());
    const json& objects = data.at("objects").at(0).at("storeys");
    ASSERT_EQ(objects.size(), 2u);
    EXPECT_GT(objects[0][1].get<size_t>(), 0u) << "the ground floor's new objects";
    EXPECT_EQ(objects[1][1], 0) << "none upstairs";
    EXPECT_EQ(data.at("missing3d").at("storeys").size(), 2u);
    for (const json& c : data.at("model3d").at("classes")) {
        const json& r = c.at("storeys");
        ASSERT_EQ(r.size(), 2u) << c.at("name");
        EXPECT_EQ(r[0][1].get<size_t>() + r[1][1].get<size_t>(),
                  3 * c.at("triangles").get<size_t>())
            << c.at("name");
    }
}

// A walk up the stair and back (issue 31, item 6): anchored; the box added on each storey found
// and placed on its storey (the simulator's truth names it); the anchored trajectory split into
// floor, flight, floor, flight, floor for the plans.
TEST(MapCli, ATwoStoreyWalksChangesArePlacedOnTheirStoreysAndItsTrajectorySplitByStorey) {
    const fs::path f = TwoStoreys();
    const json summary = ReadJson(f / "out" / "summary.json");
    ASSERT_EQ(summary.at("recordings").at(0).at("anchor").at("verdict"), "anchored")
        << summary.dump(1);
    // A placement a storey up or down (the walk's first floor above the roof, or its ground
    // floor under the model) floats a tenth of the walk or more off every walk of the model, and
    // so is no rival (anchor::HeightsPrefer); the best floats none.
    const json anchor = ReadJson(VisitOf(f / "out") / "anchor" / "anchor.json").at("sessions")[0];
    const json& hyps = anchor.at("hypotheses");
    ASSERT_FALSE(hyps.empty());
    EXPECT_EQ(hyps[0].at("floating_keyframes"), 0) << hyps[0].dump();
    const double z0 = hyps[0].at("T_world_local").at("translation")[2];
    for (const json& h : hyps) {
        const double dz = h.at("T_world_local").at("translation")[2].get<double>() - z0;
        if (std::abs(dz) < 2.0) continue;
        EXPECT_GE(h.at("floating_keyframes").get<double>(),
                  0.1 * anchor.at("keyframes").get<double>())
            << h.dump();
    }
    const json truth = ReadJson(f / "capture" / "changes.json");
    const json found = ReadJson(VisitOf(f / "out") / "changes" / "capture" / "changes.json");
    ASSERT_EQ(truth.at("added").size(), 2u);
    ASSERT_EQ(found.at("new_objects").size(), 2u) << found.at("new_objects").dump();
    std::set<std::string> storeys;
    for (const json& o : found.at("new_objects")) {
        const auto centre = [](const json& box_min, const json& box_max) -> Eigen::Vector3d {
            Eigen::Vector3d c;
            for (int k = 0; k < 3; ++k) {
                c[k] = 0.5 * (box_min[k].get<double>() + box_max[k].get<double>());
            }
            return c;
        };
        const Eigen::Vector3d c = centre(o.at("box_min"), o.at("box_max"));
        const json* nearest = nullptr;
        double best = 1e9;
        for (const json& a : truth.at("added")) {
            const double d = (centre(a.at("box_min"), a.at("box_max")) - c).norm();
            if (d < best) best = d, nearest = &a;
        }
        ASSERT_LT(best, 0.3) << o.dump();
        EXPECT_EQ(o.at("storey").at("name"), nearest->at("storey")) << o.dump();
        storeys.insert(o.at("storey").at("name").get<std::string>());
    }
    EXPECT_EQ(storeys, (std::set<std::string>{"Ground Floor", "First Floor"}));

    const json data = PageData(f / "out" / "report" / "report.html");
    ASSERT_TRUE(data.is_object());
    std::vector<std::pair<int, int>> runs;
    for (const json& r : data.at("sessions")[0].at("runs"))
        runs.push_back({r.at("lower"), r.at("upper")});
    const std::vector<std::pair<int, int>> expected{{0, 0}, {0, 1}, {1, 1}, {0, 1}, {0, 0}};
    EXPECT_EQ(runs, expected);
    // The 3D view's storey filter draws each box with its storey.
    const json& objects = data.at("objects").at(0).at("storeys");
    ASSERT_EQ(objects.size(), 2u);
    EXPECT_GT(objects[0][1].get<size_t>(), 0u);
    EXPECT_GT(objects[1][1].get<size_t>(), 0u);
}

TEST(MapCli, ARecordingThatCannotBeAnchoredStillGetsAReportSayingSo) {
    const fs::path f = Unanchorable();
    const json summary = ReadJson(f / "out" / "summary.json");
    const json& r = summary.at("recordings").at(0);
    EXPECT_NE(r.at("anchor").at("verdict"), "anchored");
    EXPECT_TRUE(r.at("changes").is_null());
    ASSERT_TRUE(fs::exists(f / "out" / "report" / "report.html"));
    const std::string html = io::ReadFileToString(f / "out" / "report" / "report.html");
    // The page's data (the browser test checks what it shows: report_browser_test.cpp).
    EXPECT_NE(html.find("\"own_frame\":{"), std::string::npos) << "the odometry map in its frame";
    EXPECT_NE(html.find("\"anchored\":false"), std::string::npos);
    EXPECT_NE(io::ReadFileToString(f / "map.out").find("NOT ANCHORED"), std::string::npos);
}

TEST(MapCli, AnUntrustedOdometryIsSaidInTheSummaryTheExitCodeAndTheReport) {
    const fs::path f = Untrusted();
    const json summary = ReadJson(f / "out" / "summary.json");
    const json& odo = summary.at("recordings").at(0).at("odometry");
    EXPECT_EQ(odo.at("verdict"), "untrusted");
    EXPECT_EQ(odo.at("failed_stretches").size(), 1u);
    const std::string printed = io::ReadFileToString(f / "map.out");
    EXPECT_NE(printed.find("  ODOMETRY  UNTRUSTED: 4 failed scans"), std::string::npos) << printed;
    EXPECT_NE(printed.find("ODOMETRY UNTRUSTED: capture's trajectory failed its registration"),
              std::string::npos)
        << printed;
    // The fixture asserted exit 1; the page's banner is the browser test's.
    const std::string html = io::ReadFileToString(f / "out" / "report" / "report.html");
    EXPECT_NE(html.find("\"verdict\":\"untrusted\""), std::string::npos);
}

// A recording whose odometry failed midway (issue 32, item 3): the anchoring splits its session
// there; both halves are anchored, the keyframe inside the stretch is not placed; the changes are
// found over the anchored pieces; the summary, exit code and report say anchored in parts.
TEST(MapCli, ARecordingWhoseOdometryFailedMidwayIsAnchoredInPartsNotAnchored) {
    const fs::path f = InParts();
    const json summary = ReadJson(f / "out" / "summary.json");
    const json& r = summary.at("recordings").at(0);
    EXPECT_EQ(r.at("anchor").at("verdict"), "anchored-in-parts") << r.at("anchor").dump(1);
    const json a = ReadJson(VisitOf(f / "out") / "anchor" / "anchor.json");
    const json& s = a.at("sessions").at(0);
    ASSERT_EQ(s.at("pieces").size(), 2u) << s.dump(1);
    for (const json& p : s.at("pieces")) EXPECT_EQ(p.at("verdict"), "anchored");
    const size_t n = s.at("keyframes");
    EXPECT_EQ(
        io::ReadKitti(VisitOf(f / "out") / "anchor" / "capture" / "optimized_poses.txt").size(),
        n - 1);
    // As precise as the whole walk anchored at once (2.94 cm both, the changed building's walls
    // stand off their model).
    const json whole = ReadJson(Mapped() / "out" / "summary.json").at("recordings").at(0);
    ASSERT_TRUE(r.at("accuracy").is_object());
    EXPECT_LT(r.at("accuracy").at("ape_trans_rmse_m").get<double>(),
              whole.at("accuracy").at("ape_trans_rmse_m").get<double>() + 0.005);
    EXPECT_TRUE(r.at("changes").is_object()) << "the anchored pieces are compared";
    const std::string printed = io::ReadFileToString(f / "map.out");
    EXPECT_NE(printed.find("  anchoring anchored-in-parts: the odometry is untrusted"),
              std::string::npos)
        << printed;
    EXPECT_NE(printed.find("ANCHORED IN PARTS: capture"), std::string::npos) << printed;
    EXPECT_EQ(printed.find("NOT ANCHORED"), std::string::npos) << printed;
    const std::string html = io::ReadFileToString(f / "out" / "report" / "report.html");
    EXPECT_NE(html.find("\"verdict\":\"anchored-in-parts\""), std::string::npos);
}

// The change scores' headline is what the walk's keyframes saw (issue 31, item 8): the summary's
// seen_scores are evaluation.json's "seen" figures, no more than all of them, the objects out of
// view are exactly the rest, and those no beam hit are among them; every true object's figures
// are listed and follow the rule stated; the printed summary says them first, with the rule,
// then all.
TEST(MapCli, TheChangeScoresHeadlineCountsWhatTheKeyframesSawAndSaysHowManyWereOutOfView) {
    const fs::path f = Untrusted();  // a copy of Mapped() whose map.out holds the printed summary
    const json summary = ReadJson(f / "out" / "summary.json");
    const json& r = summary.at("recordings").at(0);
    const json& s = r.at("seen_scores");
    ASSERT_TRUE(s.is_object()) << r.dump(1);
    const json& e = r.at("change_scores");
    EXPECT_EQ(s.at("added_in_view"), e.at("seen").at("added_large"));
    EXPECT_EQ(s.at("added_all"), e.at("added_large"));
    EXPECT_EQ(s.at("removed_in_view"), e.at("seen").at("removed"));
    EXPECT_EQ(s.at("removed_all"), e.at("removed"));
    const json& rule = s.at("in_view_rule");
    EXPECT_EQ(rule.at("min_map_points"), 30);  // the detector's min_object_points
    EXPECT_EQ(rule.at("min_multi_view_fraction"), 0.25);
    EXPECT_EQ(rule.at("off_model_m"), 0.05);
    EXPECT_EQ(rule.at("min_expected_area_m2"), 0.25);
    for (const char* kind : {"added", "removed"}) {
        const json& seen = s.at(std::string(kind) + "_in_view");
        const json& all = s.at(std::string(kind) + "_all");
        const size_t out_of_view = s.at(std::string(kind) + "_out_of_view");
        EXPECT_LE(seen.at("truth").get<size_t>(), all.at("truth").get<size_t>()) << kind;
        EXPECT_LE(seen.at("truth_matched").get<size_t>(), all.at("truth_matched").get<size_t>())
            << kind;
        EXPECT_EQ(out_of_view, all.at("truth").get<size_t>() - seen.at("truth").get<size_t>())
            << kind;
        EXPECT_LE(s.at(std::string(kind) + "_no_beam").get<size_t>(), out_of_view) << kind;
        EXPECT_EQ(seen.at("found"), all.at("found")) << kind << ": precision is the same";
    }
    // Every true object's figures: in view exactly when the rule holds; one in view has beams.
    size_t large_in_view = 0;
    for (const json& o : e.at("seen").at("objects")) {
        const size_t points = o.at("map_points"), multi = o.at("multi_view_points");
        EXPECT_EQ(o.at("in_view").get<bool>(), points >= 30 && 4 * multi >= points) << o.dump();
        if (o.at("in_view").get<bool>()) {
            EXPECT_GT(o.at("beam_hits").get<long>(), 0) << o.dump();
        }
        large_in_view += o.at("in_view").get<bool>() && o.at("large").get<bool>();
    }
    EXPECT_EQ(large_in_view, s.at("added_in_view").at("truth").get<size_t>());
    // A 40 s walk of the ground floor leaves most added objects out of view (the upper storey's
    // and far rooms'), and sees some.
    EXPECT_GT(s.at("added_out_of_view").get<size_t>(), 0u) << s.dump(1);
    EXPECT_GT(s.at("added_in_view").at("truth").get<size_t>(), 0u) << s.dump(1);

    const std::string printed = io::ReadFileToString(f / "map.out");
    const auto of = [](const json& x, size_t out, size_t no_beam) {
        return "(" + std::to_string(x.at("truth_matched").get<size_t>()) + " of " +
               std::to_string(x.at("truth").get<size_t>()) + "; " + std::to_string(out) +
               " out of view, " + std::to_string(no_beam) + " of them in no beam)";
    };
    const size_t in_view = printed.find("  scores    in view: added >= 0.3 m P ");
    const size_t rule_line = printed.find(
        "            (in view = the keyframes put >= 30 map points on it, more than 5 cm off the "
        "model, 25 % of them seen twice; removed: >= 0.25 m2 of it in their beams)");
    const size_t all = printed.find("            all: added >= 0.3 m P ");
    ASSERT_NE(in_view, std::string::npos) << printed;
    ASSERT_NE(rule_line, std::string::npos) << printed;
    ASSERT_NE(all, std::string::npos) << printed;
    EXPECT_LT(in_view, rule_line) << "the headline first, then its rule";
    EXPECT_LT(rule_line, all);
    EXPECT_NE(
        printed.find(of(s.at("added_in_view"), s.at("added_out_of_view"), s.at("added_no_beam"))),
        std::string::npos)
        << printed;
    EXPECT_NE(printed.find(of(s.at("removed_in_view"), s.at("removed_out_of_view"),
                              s.at("removed_no_beam"))),
              std::string::npos)
        << printed;
}

TEST(MapCli, AModelThatIsNotIfcOrARecordingThatIsNotOusterExits2BeforeAnyStep) {
    test::TempDir tmp;
    const fs::path c = Mapped() / "capture";
    io::WriteFileAtomic(tmp / "model.ifc", "solid cube\nendsolid cube\n");
    auto r = Cli("map " + (tmp / "model.ifc").string() + " " + c.string() + " -o " +
                 (tmp / "out").string());
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("model.ifc"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("not an IFC model"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(tmp / "out"));

    // A capture folder whose pcap holds the Go1's UDP stream, not an Ouster's packets.
    fs::create_directories(tmp / "not_ouster");
    fs::copy_file(c / "metadata.json", tmp / "not_ouster" / "metadata.json");
    fs::copy_file(c / "go1_highstate.pcap", tmp / "not_ouster" / "lidar.pcap");
    const fs::path model = Building() / "building.ifc";
    r = Cli("map " + model.string() + " " + (tmp / "not_ouster").string() + " -o " +
            (tmp / "out").string());
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find((tmp / "not_ouster" / "lidar.pcap").string()), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(tmp / "out"));

    // x.pcap with an x.json that is no Ouster metadata.
    fs::copy_file(c / "lidar.pcap", tmp / "walk.pcap");
    io::WriteFileAtomic(tmp / "walk.json", "{\"hello\": 1}\n");
    r = Cli("map " + model.string() + " " + (tmp / "walk.pcap").string() + " -o " +
            (tmp / "out").string());
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("walk.json"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(tmp / "out"));

    r = Cli("map " + model.string() + " " + (tmp / "nowhere").string() + " -o " +
            (tmp / "out").string());
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("nowhere"), std::string::npos) << r.err;
}

TEST(MapCli, HelpNamesTheStepsAndReportNeedsAMapOutput) {
    const auto h = Cli("map --help");
    EXPECT_EQ(h.exit_code, 0);
    for (const char* s : {"reference", "odometry", "anchor", "changes", "report.html", "stamps"}) {
        EXPECT_NE(h.out.find(s), std::string::npos) << s;
    }
    EXPECT_EQ(Cli("report --help").exit_code, 0);
    test::TempDir tmp;
    const auto r = Cli("report " + tmp.path().string());
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("summary.json"), std::string::npos) << r.err;
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam
