// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The report page of `bimslam map` opened in a real browser: Debian's chromium, headless, WebGL
// through SwiftShader (no GPU here: --use-angle=swiftshader --enable-unsafe-swiftshader). The page
// runs its self-test when opened as report.html#selftest (assets/report.js, at its end) and
// writes the result into <pre id="selftest">; chromium --dump-dom prints the DOM after the virtual
// time budget, and --screenshot saves the page as PNG in the same run. Checked:
// - no console errors: none caught by the page (window 'error' events, console.error) and no
//   console line in chromium's own log (--enable-logging=stderr);
// - the floor plans (with walls) and the four plots are present;
// - the 3D canvas is not blank: pixels of its WebGL drawing buffer differ from the background;
// - clicking a change row selects it (the row, and its mark in the plan);
// - the visits' timeline, the change list's filter and an element's history (two visits);
// - the deviation views: elements coloured by their deviation on the plans and in 3D (issue 34).
// Skips, saying so, when chromium is not installed (make test installs it:
// toolchain/install-deps.sh --test).
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "algorithms/io/file_util.hpp"
#include "tests/integration/headless_chromium.hpp"
#include "tests/integration/map_test_support.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam {
namespace {
namespace BIMSLAM_UNITY_ID {
namespace fs = std::filesystem;
using nlohmann::json;
using namespace map_test;

// The window, and so the screenshot: the whole page (1400 x 5200) for the page of one walk, its
// first screen (1400 x 1200) for the others. Chromium composites the window in software each
// frame: a run of the 40 s walk's page took 27-34 s of CPU at 5200 px and 18 s at 1200, with the
// same self-test result but for the 3D canvas' width (no scroll bar; tests/tools/cpu_time.py).
enum class Window { kWholePage, kFirstScreen };

test::PageRun OpenPage(const fs::path& html, const std::string& shot_name,
                       Window window = Window::kFirstScreen) {
    return test::OpenHeadless("file://" + fs::absolute(html).string() + "#selftest", shot_name,
                              window == Window::kWholePage ? "1400,5200" : "1400,1200");
}

bool IsPng(const fs::path& file) {
    std::error_code ec;
    if (!fs::is_regular_file(file, ec) || fs::file_size(file) < 10000) return false;
    return io::ReadFileToString(file).substr(0, 8) == "\x89PNG\r\n\x1a\n";
}

// The summary's change scores say first what the walk's keyframes saw, with the counts of
// summary.json's seen_scores (issue 31, item 8), then all objects.
void ExpectScoresInView(const json& t, const fs::path& fixture) {
    const json summary = ReadJson(fixture / "out" / "summary.json");
    const json& s = summary.at("recordings").at(0).at("seen_scores");
    ASSERT_TRUE(s.is_object());
    const std::string in_view = t.at("scores_in_view");
    EXPECT_EQ(in_view.rfind("in view: added ≥ 0.3 m P ", 0), 0u) << in_view;
    const auto count = [](const json& x, const json& out, const json& no_beam) {
        return "(" + std::to_string(x.at("truth_matched").get<size_t>()) + " of " +
               std::to_string(x.at("truth").get<size_t>()) + "; " +
               std::to_string(out.get<size_t>()) + " out of view, " +
               std::to_string(no_beam.get<size_t>()) + " of them in no beam)";
    };
    EXPECT_NE(in_view.find(
                  count(s.at("added_in_view"), s.at("added_out_of_view"), s.at("added_no_beam"))),
              std::string::npos)
        << in_view;
    EXPECT_NE(in_view.find(count(s.at("removed_in_view"), s.at("removed_out_of_view"),
                                 s.at("removed_no_beam"))),
              std::string::npos)
        << in_view;
    EXPECT_EQ(t.at("scores_all").get<std::string>().rfind("all: added ≥ 0.3 m P ", 0), 0u)
        << t.at("scores_all");
}

// The bound each chromium run has (headless_chromium.hpp): a command that sits idle, or nearly
// (a hung chromium wakes up now and then), is stopped with timeout(1)'s 124 and says why; one
// that keeps a core busy past the idle time runs to its end; the command's own status comes
// through.
TEST(ReportBrowser, AChromiumRunThatSitsIdleIsStoppedAndABusyOneIsNot) {
    const std::string tool =
        "/usr/bin/python3 " BIMSLAM_SOURCE_ROOT "/tests/tools/idle_timeout.py ";
    const auto idle = test::RunCommand(tool + "1 60 sleep 60");
    EXPECT_EQ(idle.exit_code, 124);
    EXPECT_NE(idle.err.find("idle_timeout: stopped sleep (idle: "), std::string::npos) << idle.err;
    const auto nearly = test::RunCommand(tool + "2 60 sh -c 'while true; do sleep 0.2; done'");
    EXPECT_EQ(nearly.exit_code, 124);
    EXPECT_NE(nearly.err.find("idle_timeout: stopped sh (idle: "), std::string::npos) << nearly.err;
    const auto busy =
        test::RunCommand(tool +
                         "1 60 /usr/bin/python3 -c 'import time\nt = time.monotonic()\n"
                         "while time.monotonic() - t < 3: pass\nprint(\"done\")'");
    EXPECT_EQ(busy.exit_code, 0) << busy.err;
    EXPECT_EQ(busy.out, "done\n");
    EXPECT_EQ(test::RunCommand(tool + "1 60 sh -c 'exit 3'").exit_code, 3);
    const auto limit = test::RunCommand(tool + "60 1 /usr/bin/python3 -c 'while True: pass'");
    EXPECT_EQ(limit.exit_code, 124);
    EXPECT_NE(limit.err.find("still running after 1 s"), std::string::npos) << limit.err;
    // A process of the session in a process group of its own is counted, and stopped too.
    const fs::path pid_file =
        fs::temp_directory_path() / ("idle_timeout_" + std::to_string(::getpid()) + ".pid");
    const auto grouped =
        test::RunCommand(tool +
                         "1 60 /usr/bin/python3 -c 'import subprocess, time\n"
                         "p = subprocess.Popen([\"sleep\", \"60\"], process_group=0)\n"
                         "open(\"" +
                         pid_file.string() + "\", \"w\").write(str(p.pid))\ntime.sleep(60)'");
    EXPECT_EQ(grouped.exit_code, 124) << grouped.err;
    std::ifstream in(pid_file);
    int child = 0;
    ASSERT_TRUE(in >> child) << pid_file;
    fs::remove(pid_file);
    std::ifstream stat("/proc/" + std::to_string(child) + "/stat");
    std::string line;
    const bool alive = std::getline(stat, line) && line.substr(line.rfind(')') + 2, 1) != "Z";
    EXPECT_FALSE(alive) << "the sleep in its own process group outlived the stop: " << line;
    if (alive) ::kill(child, SIGKILL);
}

TEST(ReportBrowser, ThePageRendersItsPlansPlotsAnd3DViewWithoutErrorsAndARowClickSelects) {
    if (test::Chromium().empty()) {
        GTEST_SKIP() << "chromium is not installed (apt-get install chromium; `make test` "
                        "installs it through toolchain/install-deps.sh --test)";
    }
    const test::PageRun run =
        OpenPage(Mapped() / "out" / "report" / "report.html", "report.png", Window::kWholePage);
    const json& t = run.selftest;
    ASSERT_TRUE(t.is_object());
    EXPECT_TRUE(t.at("errors").empty()) << t.at("errors").dump(1);
    EXPECT_TRUE(run.console.empty()) << run.console;
    EXPECT_EQ(t.at("plans"), 2) << "one floor plan per storey of the office";
    EXPECT_EQ(t.at("not_anchored_banners"), 0);
    EXPECT_EQ(t.at("untrusted_banners"), 0);
    EXPECT_EQ(t.at("plan_paths"), 2) << "walls in each plan";
    // APE, time per scan, fitness, loop statistics, and a Scan-vs-BIM histogram per storey with
    // points on the model (issue 34 item 3): the ground floor walked; its points seen through
    // the stairwell may give the first floor one too.
    const json& histograms = t.at("histograms");
    ASSERT_GE(histograms.size(), 1u) << t.dump();
    EXPECT_EQ(t.at("plots"), 4 + histograms.size()) << t.dump();
    EXPECT_EQ(histograms[0].at("storey"), "Ground Floor") << histograms.dump();
    EXPECT_GT(histograms[0].at("points").get<int>(), 10000) << histograms.dump();
    for (const json& h : histograms) {
        EXPECT_EQ(h.at("bars"), h.at("bins")) << h.dump();
        EXPECT_GT(h.at("within_share").get<double>(), 0.0) << h.dump();
        EXPECT_LE(h.at("within_share").get<double>(), 1.0) << h.dump();
    }
    ASSERT_EQ(t.at("histogram_labels").size(), histograms.size());
    for (const json& labels : t.at("histogram_labels"))
        EXPECT_EQ(labels, json::array({"distance to model (cm)", "points"}));
    const json& px = t.at("pixels");
    ASSERT_TRUE(px.is_object()) << "no WebGL view";
    EXPECT_GT(px.at("drawn").get<double>(), 0.05 * px.at("total").get<double>())
        << "the 3D view is (nearly) blank";
    ASSERT_GT(t.at("changes").get<int>(), 0);
    EXPECT_EQ(t.at("selected_row"), true);
    // The project's visits: the page is of the newest, the only one here.
    EXPECT_EQ(t.at("visits_text"), "Visit " + kVisit + " (" + kVisit +
                                       "T22:13:20Z), the newest of 1: " + kVisit + " (" + kVisit +
                                       "T22:13:20Z: capture anchored).");
    EXPECT_EQ(t.at("selected_change"), 0);
    EXPECT_GE(t.at("selected_plan").get<int>(), 1);
    // The model's class toggles change what is drawn: all off draws less, on again as before.
    const json& toggles = t.at("toggles");
    EXPECT_GT(toggles.at("classes").get<int>(), 3) << toggles.dump();
    EXPECT_LT(toggles.at("none").get<double>(), 0.9 * toggles.at("all").get<double>())
        << toggles.dump();
    EXPECT_EQ(toggles.at("again"), toggles.at("all")) << toggles.dump();
    // A click in the middle of the 3D view inspects what it hits: an element (class, name,
    // GlobalId) or a map point (its distance to the model), with where it is.
    const std::string inspected = t.at("inspect").get<std::string>();
    EXPECT_NE(inspected.find(") m"), std::string::npos) << inspected;
    EXPECT_TRUE(inspected.rfind("Ifc", 0) == 0 || inspected.rfind("map point", 0) == 0 ||
                inspected.rfind("new object", 0) == 0)
        << inspected;
    ExpectScoresInView(t, Mapped());
    // Issue 34 item 3: the elements coloured by their deviation against the tolerance (1 cm by
    // default): the walls built off their place (changed_building.yaml: 2 cm sigma, the
    // corridor's north wall 3 cm) and the removed columns beyond it, the floor within; on the
    // ground floor's plan, in the 3D view's buffers and on its screen (red pixels by deviation,
    // none by class), with the scale in cm on the plans and beside the 3D view.
    const json& dev = t.at("deviation");
    EXPECT_EQ(dev.at("tolerance_cm"), 1) << dev.dump();
    for (const char* v : {"within", "beyond", "not_observed"}) {
        EXPECT_GT(dev.at("elements").at(v).get<int>(), 0) << v << " " << dev.dump();
        EXPECT_GT(dev.at("triangles").at(v).get<int>(), 0) << v << " " << dev.dump();
    }
    EXPECT_GT(dev.at("plans").at(0).at("beyond").get<int>(), 3) << dev.dump();
    EXPECT_EQ(dev.at("triangles").at("not_compared"), 0) << "every element by its GlobalId";
    const json& on_screen = dev.at("pixels");
    EXPECT_GT(on_screen.at("deviation").at("red").get<int>(),
              on_screen.at("classes").at("red").get<int>() + 100)
        << on_screen.dump();
    ASSERT_EQ(dev.at("legends").size(), 2u) << dev.dump();
    for (const json& legend : dev.at("legends")) {
        const std::string text = legend;
        EXPECT_NE(text.find("deviation from the model (cm; tolerance ±1 cm)"), std::string::npos)
            << text;
        EXPECT_NE(text.find("beyond 1 cm"), std::string::npos) << text;
        EXPECT_NE(text.find("not observed"), std::string::npos) << text;
    }
    // Each storey's plan: the stair that joins them, the reference walk's part on it; the walk of
    // the ground floor only there, and never on a flight.
    const json& plans = t.at("plan_stats");
    ASSERT_EQ(plans.size(), 2u) << plans.dump();
    for (const json& p : plans) {
        EXPECT_EQ(p.at("stairs"), 1) << p.dump();
        EXPECT_GE(p.at("walk").get<int>(), 1) << p.dump();
        EXPECT_EQ(p.at("trajectory_on_flights"), 0) << p.dump();
    }
    EXPECT_GE(plans[0].at("trajectory").get<int>(), 1) << plans.dump();
    EXPECT_EQ(plans[1].at("trajectory"), 0) << plans.dump();
    // The 3D view's storey filter: each storey alone draws fewer pixels than all; all again, as
    // many as before.
    const json& filter = t.at("storey_filter");
    ASSERT_EQ(filter.at("each").size(), 2u) << filter.dump();
    for (const json& each : filter.at("each")) {
        EXPECT_LT(each.get<double>(), 0.95 * filter.at("all").get<double>()) << filter.dump();
    }
    EXPECT_EQ(filter.at("again"), filter.at("all")) << filter.dump();
    // The plots' axes name quantities, not functions.
    for (const json& labels : t.at("axis_labels")) {
        for (const json& l : labels) {
            EXPECT_EQ(l.get<std::string>().find("::"), std::string::npos) << l;
            EXPECT_FALSE(l.get<std::string>().empty());
        }
    }
    EXPECT_EQ(t.at("axis_labels").at(1).at(1), "odometry time per scan (ms)");
    // One visit on the timeline, its walk on the plans; nothing before it, so the change list
    // shows the changes since the model at first.
    const json& v = t.at("visits_test");
    EXPECT_EQ(v.at("visits"), json::array({kVisit})) << v.dump();
    EXPECT_EQ(v.at("walks").at(kVisit), json::array({"capture"})) << v.dump();
    EXPECT_EQ(v.at("filter"), "model") << v.dump();
    EXPECT_TRUE(v.at("rows").at(kVisit).at("previous").empty()) << v.dump();
    EXPECT_FALSE(v.at("rows").at(kVisit).at("model").empty()) << v.dump();
    EXPECT_TRUE(IsPng(run.screenshot)) << run.screenshot;
}

// The rows the change list should show for a visit's changes since the previous visit and since
// the model, as history.json lists them ("kind: name"; report_visits.js, rowsSincePrevious and
// rowsSinceModel).
json ExpectedRows(const json& history, const std::string& visit) {
    const auto element = [&](const std::string& gid) {
        for (const json& e : history.at("elements")) {
            if (e.at("global_id") == gid)
                return e.at("name").get<std::string>() + " (" + e.at("class").get<std::string>() +
                       ")";
        }
        return gid;
    };
    json c;
    for (const json& x : history.at("changes")) {
        if (x.at("visit") == visit) c = x;
    }
    json previous = json::array(), model = json::array();
    if (c.at("since_previous").is_object()) {
        const json& p = c["since_previous"];
        for (const char* k : {"new", "gone"}) {
            for (const json& id : p.at(k))
                previous.push_back(std::string(k) + ": object " + id.get<std::string>());
        }
        for (const json& m : p.at("moved"))
            previous.push_back("moved: object " + m.at("id").get<std::string>());
        for (const char* k : {"newly_missing", "newly_deviating", "reappeared", "in_place_again"}) {
            std::string kind = k;
            std::replace(kind.begin(), kind.end(), '_', ' ');
            for (const json& g : p.at(k)) previous.push_back(kind + ": " + element(g));
        }
    }
    const json& m = c.at("since_model");
    for (const json& o : m.at("new_objects"))
        model.push_back("new object: object " + o.at("id").get<std::string>());
    for (const char* k : {"missing", "deviating"}) {
        for (const json& e : m.at(k))
            model.push_back(std::string(k) + ": " + element(e.at("global_id")));
    }
    return {{"previous", previous}, {"model", model}};
}

// The project of two visits (issue 33 item 6; map_test_support.hpp, two_days: a crate and no
// columns on 2 March; on 9 March the crate gone, the columns built, a cabinet new): the timeline
// selects each visit and the plans draw its walks; the change list's filter shows the changes
// since the previous visit and since the model, as of the selected visit; a contradiction (a
// column missing, then built) is marked, and a click on it shows its history: missing, then
// confirmed; a click on the gone crate's plan mark shows its sightings.
TEST(ReportBrowser, TheTimelineSelectsAVisitsWalksAndChangesAndARowShowsItsHistory) {
    if (test::Chromium().empty()) {
        GTEST_SKIP() << "chromium is not installed (apt-get install chromium; `make test` "
                        "installs it through toolchain/install-deps.sh --test)";
    }
    using namespace two_days;
    const fs::path out = AllAtOnce() / "out";
    const test::PageRun run = OpenPage(out / "report" / "report.html", "report_visits.png");
    const json& t = run.selftest;
    ASSERT_TRUE(t.is_object());
    EXPECT_TRUE(t.at("errors").empty()) << t.at("errors").dump(1);
    EXPECT_TRUE(run.console.empty()) << run.console;
    const json& v = t.at("visits_test");
    EXPECT_EQ(v.at("visits"), json::array({kDayA, kDayB})) << "in date order";
    EXPECT_EQ(v.at("selected"), kDayB) << "the newest at first";
    EXPECT_EQ(v.at("filter"), "previous") << v.dump();
    EXPECT_EQ(v.at("walks").at(kDayA), json::array({"lidar"})) << v.dump();
    EXPECT_EQ(v.at("walks").at(kDayB), json::array({"b", "c"})) << v.dump();
    // The newest's walks are drawn at first (the plans' trajectory lines, before the timeline's
    // clicks).
    EXPECT_GE(t.at("plan_stats").at(0).at("trajectory").get<int>(), 2) << t.at("plan_stats");

    const json history = ReadJson(out / "history.json");
    for (const std::string& day : {kDayA, kDayB})
        EXPECT_EQ(v.at("rows").at(day), ExpectedRows(history, day)) << day;
    // What the project holds (map_visits_test checks the history itself): the crate gone and the
    // cabinet new since the previous visit, the two columns built again; since the model, the
    // cabinet only on 9 March, the crate and the columns missing on 2 March.
    const json& b = v.at("rows").at(kDayB);
    ASSERT_EQ(b.at("previous").size(), 4u) << b.dump();
    EXPECT_EQ(b["previous"][0].get<std::string>().rfind("new: object", 0), 0u) << b.dump();
    EXPECT_EQ(b["previous"][1].get<std::string>().rfind("gone: object", 0), 0u) << b.dump();
    for (size_t k : {2, 3}) {
        const std::string row = b["previous"][k];
        EXPECT_TRUE(row.starts_with("reappeared: Column") && row.ends_with("(IfcColumn)")) << row;
    }
    EXPECT_EQ(b.at("model").size(), 1u) << b.dump();
    const json& a = v.at("rows").at(kDayA);
    EXPECT_TRUE(a.at("previous").empty()) << a.dump();
    EXPECT_EQ(a.at("model").size(), 3u) << a.dump();

    // The contradictions are marked, and a click on one shows its verdict per visit.
    EXPECT_EQ(v.at("contradiction_rows"), 2) << v.dump();
    EXPECT_EQ(v.at("history"), json::array({kDayA + " missing", kDayB + " confirmed"})) << v.dump();
    EXPECT_EQ(v.at("history_contradictions"), 1) << v.dump();
    // The crate's mark on the plan (drawn dashed: gone) shows its sightings: new, then gone.
    EXPECT_EQ(v.at("plan_history"), json::array({kDayA + " new", kDayB + " gone"})) << v.dump();
    EXPECT_TRUE(IsPng(run.screenshot)) << run.screenshot;
}

// A walk up the office's stair and back (issue 31, item 6): each storey's plan draws its part of
// the trajectory, the flights dashed on both plans; the storey filter draws less for each storey.
TEST(ReportBrowser, ATwoStoreyWalkIsDrawnOnEachStoreysPlanWithItsFlightsOnBoth) {
    if (test::Chromium().empty()) {
        GTEST_SKIP() << "chromium is not installed (apt-get install chromium; `make test` "
                        "installs it through toolchain/install-deps.sh --test)";
    }
    const test::PageRun run =
        OpenPage(TwoStoreys() / "out" / "report" / "report.html", "report_two_storeys.png");
    const json& t = run.selftest;
    ASSERT_TRUE(t.is_object());
    EXPECT_TRUE(t.at("errors").empty()) << t.at("errors").dump(1);
    EXPECT_TRUE(run.console.empty()) << run.console;
    const json& plans = t.at("plan_stats");
    ASSERT_EQ(plans.size(), 2u) << plans.dump();
    // Ground floor: before and after the climb, and the two flights; first floor: its stretch
    // and the same two flights.
    EXPECT_EQ(plans[0].at("trajectory"), 4) << plans.dump();
    EXPECT_EQ(plans[1].at("trajectory"), 3) << plans.dump();
    for (const json& p : plans) {
        EXPECT_EQ(p.at("trajectory_on_flights"), 2) << p.dump();
        EXPECT_EQ(p.at("stairs"), 1) << p.dump();
    }
    const json& filter = t.at("storey_filter");
    for (const json& each : filter.at("each")) {
        EXPECT_LT(each.get<double>(), 0.95 * filter.at("all").get<double>()) << filter.dump();
    }
    EXPECT_EQ(filter.at("again"), filter.at("all")) << filter.dump();
    EXPECT_EQ(t.at("changes"), 2) << "a box on each storey";
    EXPECT_TRUE(IsPng(run.screenshot)) << run.screenshot;
}

TEST(ReportBrowser, ANotAnchoredRecordingIsShownAsSuchWithoutErrors) {
    if (test::Chromium().empty()) {
        GTEST_SKIP() << "chromium is not installed (apt-get install chromium; `make test` "
                        "installs it through toolchain/install-deps.sh --test)";
    }
    const fs::path html = Unanchorable() / "out" / "report" / "report.html";
    const test::PageRun run = OpenPage(html, "report_not_anchored.png");
    const json& t = run.selftest;
    ASSERT_TRUE(t.is_object());
    EXPECT_TRUE(t.at("errors").empty()) << t.at("errors").dump(1);
    EXPECT_TRUE(run.console.empty()) << run.console;
    EXPECT_EQ(t.at("changes"), 0);
    EXPECT_EQ(t.at("not_anchored_banners"), 1) << "the summary says so";
    EXPECT_EQ(t.at("own_frame_plans"), 1) << "the odometry map in its own frame";
    EXPECT_EQ(t.at("plans"), 3) << "the model's two storeys and the own-frame map";
    EXPECT_TRUE(IsPng(run.screenshot)) << run.screenshot;
}

TEST(ReportBrowser, AnUntrustedOdometryGetsABannerNamingItsStretches) {
    if (test::Chromium().empty()) {
        GTEST_SKIP() << "chromium is not installed (apt-get install chromium; `make test` "
                        "installs it through toolchain/install-deps.sh --test)";
    }
    const fs::path html = Untrusted() / "out" / "report" / "report.html";
    const test::PageRun run = OpenPage(html, "report_untrusted.png");
    const json& t = run.selftest;
    ASSERT_TRUE(t.is_object());
    EXPECT_TRUE(t.at("errors").empty()) << t.at("errors").dump(1);
    EXPECT_TRUE(run.console.empty()) << run.console;
    EXPECT_EQ(t.at("untrusted_banners"), 1) << "the summary says so";
    EXPECT_NE(
        t.at("untrusted_text").get<std::string>().find("scans 120–131 (12.0–13.1 s: low overlap)"),
        std::string::npos)
        << t.at("untrusted_text");
    EXPECT_EQ(t.at("not_anchored_banners"), 0) << "it was still anchored";
    EXPECT_GT(t.at("changes").get<int>(), 0);
}

TEST(ReportBrowser, ARecordingAnchoredInPartsGetsItsBannerAndItsAnchoredPieces) {
    if (test::Chromium().empty()) {
        GTEST_SKIP() << "chromium is not installed (apt-get install chromium; `make test` "
                        "installs it through toolchain/install-deps.sh --test)";
    }
    const fs::path html = InParts() / "out" / "report" / "report.html";
    const test::PageRun run = OpenPage(html, "report_in_parts.png");
    const json& t = run.selftest;
    ASSERT_TRUE(t.is_object());
    EXPECT_TRUE(t.at("errors").empty()) << t.at("errors").dump(1);
    EXPECT_TRUE(run.console.empty()) << run.console;
    EXPECT_EQ(t.at("in_parts_banners"), 1);
    EXPECT_EQ(t.at("untrusted_banners"), 1);
    EXPECT_EQ(t.at("not_anchored_banners"), 0) << "its anchored pieces are placed and shown";
    EXPECT_GT(t.at("changes").get<int>(), 0);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam
