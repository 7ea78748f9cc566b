// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// `bimslam map`'s project of visits (issue 33, item 1; host_tools/mapping/README.md, "Visits"),
// on three short hand-held walks of the sample office on two days:
// - visits added one at a time give the same project, figures and files as all at once;
// - the visits' dates come from the recordings (capture.json, else the first packet) and order
//   them, whatever order the recordings are given in; recordings of one UTC day form one visit,
//   unless --visit names it;
// - a re-run with no new recording does nothing (every step skipped, no file written);
// - a damaged visit folder exits 2 naming it, and the other visits are kept;
// - --add to a folder that is not a project exits 2 naming it;
// - a recording re-recorded in place replaces the old one;
// - --near is kept in the project for the recordings it was given with, and their anchoring holds
//   to it;
// - a visit through a room fitted out since the model anchors through the earlier visit that saw
//   the room (issue 33, item 2), where the model alone does not anchor it.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "algorithms/io/file_util.hpp"
#include "algorithms/io/las.hpp"
#include "algorithms/io/ply.hpp"
#include "algorithms/io/trajectory.hpp"
#include "tests/integration/map_test_support.hpp"
#include "tests/integration/web_ifc_support.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam {
namespace {
namespace BIMSLAM_UNITY_ID {
namespace fs = std::filesystem;
using nlohmann::json;
using namespace map_test;
using namespace map_test::two_days;

// One at a time: b, then a (an earlier date), then c (b's day). run<k>.json: what each printed.
fs::path OneAtATime() {
    return Fixture("visits_one", [](const fs::path& d) {
        const std::string out = (d / "out").string();
        const json runs[] = {MapJson("map " + Model() + " " + B() + " -o " + out),
                             MapJson("map " + out + " --add " + A()),
                             MapJson("map " + out + " --add " + C())};
        for (size_t k = 0; k < 3; ++k)
            io::WriteFileAtomic(d / ("run" + std::to_string(k + 1) + ".json"), runs[k].dump(1));
    });
}

// A visit's summary without what names its folder or measures time.
json Comparable(json s) {
    s.erase("output");
    s.erase("anchor_times_s");
    s["reference"].erase("dir");
    for (json& r : s.at("recordings")) {
        r.erase("path");
        if (r["odometry"].is_object()) {
            for (const char* k :
                 {"recording", "pcap", "wall_s", "scan_ms_p50", "scan_ms_p99", "scan_ms_max",
                  "scan_cpu_ms_p50", "scan_cpu_ms_p99", "scan_cpu_ms_max", "preprocess_ms_p50",
                  "preprocess_ms_p99", "register_ms_p50", "register_ms_p99", "map_ms_p50",
                  "map_ms_p99"}) {
                r["odometry"].erase(k);
            }
        }
    }
    return s;
}

// A copy of the one-at-a-time project in tmp/out, run once: the summaries name their folder
// ("output"), so that run writes them (every step skipped); the test starts after it.
fs::path CopyOfProject(const test::TempDir& tmp) {
    fs::copy(OneAtATime() / "out", tmp / "out", fs::copy_options::recursive);
    const json steps = Steps(MapJson("map " + (tmp / "out").string()));
    for (const auto& [step, skipped] : steps.items()) EXPECT_TRUE(skipped.get<bool>()) << step;
    return tmp / "out";
}

// Every file under `dir` with its modification time.
using Mtimes = std::map<std::string, fs::file_time_type>;
Mtimes MtimesOf(const fs::path& dir) {
    Mtimes m;
    for (const auto& e : fs::recursive_directory_iterator(dir)) {
        if (e.is_regular_file()) m[e.path().lexically_relative(dir).string()] = e.last_write_time();
    }
    return m;
}

// The files written (made, changed or removed) between two listings: none is expected.
std::vector<std::string> Written(const Mtimes& before, const Mtimes& after) {
    std::vector<std::string> w;
    for (const auto& [file, t] : after) {
        const auto b = before.find(file);
        if (b == before.end() || b->second != t) w.push_back(file);
    }
    for (const auto& [file, t] : before) {
        if (!after.count(file)) w.push_back(file + " (removed)");
    }
    return w;
}

TEST(MapVisits, VisitsAddedOneAtATimeGiveTheSameProjectAsAllAtOnce) {
    const fs::path all = AllAtOnce() / "out", one = OneAtATime() / "out";
    const json pa = ReadJson(all / "project.json"), po = ReadJson(one / "project.json");
    ASSERT_EQ(pa.at("visits").size(), 2u) << pa.dump(1);
    ASSERT_EQ(po.at("visits").size(), 2u) << po.dump(1);
    for (size_t v = 0; v < 2; ++v) {
        const json &a = pa["visits"][v], &o = po["visits"][v];
        EXPECT_EQ(a.at("label"), o.at("label"));
        EXPECT_EQ(a.at("start"), o.at("start"));
        ASSERT_EQ(a.at("recordings").size(), o.at("recordings").size()) << v;
        for (size_t k = 0; k < a["recordings"].size(); ++k) {
            json ra = a["recordings"][k], ro = o["recordings"][k];
            EXPECT_EQ(ra, ro) << "the same names, paths, dates and identities";
        }
        // The same figures: odometry, anchoring, accuracy, changes and their scores (to 0.1 mm:
        // map_test_support.hpp, ExpectJsonNear).
        const std::string dir = a.at("dir");
        const json sa = ReadJson(all / dir / "summary.json"),
                   so = ReadJson(one / dir / "summary.json");
        ASSERT_TRUE(sa.at("recordings").at(0).at("anchor").is_object()) << sa.dump(1);
        EXPECT_EQ(sa["recordings"][0]["anchor"]["verdict"], "anchored") << sa.dump(1);
        ExpectJsonNear(Comparable(sa), Comparable(so), 1e-4, dir);
    }
    // OUT/summary.json describes the newest visit (b and c) and lists both.
    const json top = ReadJson(one / "summary.json");
    EXPECT_EQ(top.at("visit").at("label"), kDayB);
    EXPECT_EQ(top.at("visits").size(), 2u);
    EXPECT_EQ(top.at("recordings").size(), 2u);
    ExpectJsonNear(Comparable(ReadJson(all / "summary.json")), Comparable(top), 1e-4, "summary");

    // Earlier visits are not processed again: adding a (an earlier day) ran its steps and the
    // anchoring and changes of b's day, which is anchored against the visits before it (a now),
    // not b's odometry; adding c (b's day) ran c's odometry and b's day's anchoring and changes,
    // not a's.
    const json second = Steps(ReadJson(OneAtATime() / "run2.json"));
    EXPECT_EQ(second.at("odometry b"), true) << second.dump();
    for (const std::string& s :
         std::vector<std::string>{"odometry lidar", "anchor " + kDayA, "changes " + kDayA,
                                  "anchor " + kDayB, "changes " + kDayB})
        EXPECT_EQ(second.at(s), false) << s << " " << second.dump();
    const json third = Steps(ReadJson(OneAtATime() / "run3.json"));
    for (const std::string& s : std::vector<std::string>{
             "reference", "odometry lidar", "anchor " + kDayA, "changes " + kDayA, "odometry b"})
        EXPECT_EQ(third.at(s), true) << s << " " << third.dump();
    for (const std::string& s :
         std::vector<std::string>{"odometry c", "anchor " + kDayB, "changes " + kDayB, "report"})
        EXPECT_EQ(third.at(s), false) << s << " " << third.dump();
}

// OUT/history.json (issue 33 item 3; its rules are tested on findings made by hand in
// tests/unit/mapping/map_history_test.cpp): every visit in it, each element's verdict per visit
// as that visit's changes found it, and the same history whichever order the visits were added.
TEST(MapVisits, TheHistoryHoldsEveryVisitsVerdictsWhateverTheOrderVisitsWereAdded) {
    const fs::path all = AllAtOnce() / "out", one = OneAtATime() / "out";
    const json h = ReadJson(all / "history.json");
    EXPECT_EQ(h.at("format"), "bimslam-history");
    ASSERT_EQ(h.at("visits").size(), 2u) << h.dump(1);
    EXPECT_EQ(h["visits"][0].at("label"), kDayA);
    EXPECT_EQ(h["visits"][1].at("label"), kDayB);
    EXPECT_EQ(h["visits"][1].at("recordings"), json::array({"b", "c"}));
    ExpectJsonNear(h, ReadJson(one / "history.json"), 1e-4, "history");
    // Visit a's one recording: the verdicts counted in its changes.json.
    const json c = ReadJson(all / "visits" / kDayA / "changes" / "lidar" / "changes.json");
    std::map<std::string, size_t> counts;
    for (const json& e : h.at("elements")) ++counts[e.at("verdicts").at(0).get<std::string>()];
    EXPECT_EQ(counts["missing"], c.at("missing").size());
    EXPECT_EQ(counts["deviating"], c.at("deviating").size());
    EXPECT_EQ(counts["confirmed"], c.at("confirmed").get<size_t>());
    EXPECT_GT(counts["confirmed"], 10u) << "the walk saw the storey's walls";
    EXPECT_EQ(h.at("changes").at(0).at("since_model").at("new_objects").size(),
              c.at("new_objects").size());
    // The crate found on 2 March is gone on 9 March (its place seen empty; the cabinet is new,
    // not the crate moved: another shape), and the columns missing on 2 March stand on 9 March:
    // they reappeared, and the contradiction is kept.
    ASSERT_EQ(h.at("objects").size(), 2u) << h.at("objects").dump(1);
    const json& crate = h["objects"][0];
    const json& cabinet = h["objects"][1];
    const json& centroid = crate.at("sightings").at(0).at("centroid");
    EXPECT_NEAR(centroid[0].get<double>(), 24.0, 0.15) << crate.dump(1);
    EXPECT_NEAR(centroid[1].get<double>(), 7.75, 0.15) << crate.dump(1);
    EXPECT_EQ(crate.at("first_seen"), kDayA);
    EXPECT_EQ(crate.at("gone_in"), kDayB);
    const json& since = h["changes"][1].at("since_previous");
    EXPECT_EQ(since.at("gone"), json::array({crate.at("id")}));
    EXPECT_EQ(since.at("new"), json::array({cabinet.at("id")})) << "b and c found it: once";
    EXPECT_TRUE(since.at("moved").empty()) << since.dump(1);
    const json& seen = cabinet.at("sightings").at(0).at("centroid");
    EXPECT_NEAR(seen[0].get<double>(), 19.6, 0.15) << cabinet.dump(1);
    EXPECT_NEAR(seen[1].get<double>(), 4.0, 0.15) << cabinet.dump(1);
    // The columns a's changes found missing (two of the three; the third, behind the others,
    // was hardly seen), every one a removed column.
    const json truth = ReadJson(Walks() / "a" / "changes.json");
    std::set<std::string> columns, missing;
    for (const json& r : truth.at("removed")) columns.insert(r.at("global_id").get<std::string>());
    for (const json& m : c.at("missing")) missing.insert(m.at("global_id").get<std::string>());
    EXPECT_GE(missing.size(), 2u);
    for (const std::string& id : missing) EXPECT_TRUE(columns.count(id)) << id;
    EXPECT_EQ(since.at("reappeared").get<std::set<std::string>>(), missing);
    ASSERT_EQ(h.at("contradictions").size(), missing.size()) << h.at("contradictions").dump(1);
    for (const json& k : h["contradictions"]) {
        EXPECT_EQ(k.at("verdict"), "missing");
        EXPECT_EQ(k.at("visit"), kDayA);
        EXPECT_EQ(k.at("by_verdict"), "confirmed");
        EXPECT_EQ(k.at("contradicted_by"), kDayB);
    }
    EXPECT_TRUE(h["changes"][1].at("since_model").at("missing").empty());
    EXPECT_EQ(h["changes"][1].at("since_model").at("new_objects").size(), 1u);
    // The building's map (item 5): after the second day, nothing of the crate's faces (gone),
    // and its size per visit in the summary.
    const json bm = ReadJson(all / "building_map.json");
    ASSERT_EQ(bm.at("visits").size(), 2u) << bm.dump(1);
    EXPECT_GT(bm["visits"][1].at("dropped").at("superseded_objects").get<size_t>(), 50u)
        << bm.dump(1);
    EXPECT_GT(bm["visits"][1].at("dropped").at("seen_again").get<size_t>(),
              bm["visits"][0].at("voxels").get<size_t>() / 4)
        << "the second day saw most of what the first saw";
    // building_map.las (issue 34): every voxel, the visit that last saw it as point source (both
    // days have some); each visit's map_bim.las carries the visit's number (1, 2 by date).
    const io::LasData las = io::ReadLas(all / "building_map.las");
    EXPECT_EQ(las.size(), bm["visits"][1].at("voxels").get<size_t>());
    EXPECT_EQ(std::set<uint16_t>(las.point_source_id.begin(), las.point_source_id.end()),
              (std::set<uint16_t>{1, 2}));
    for (const auto& [day, number] : {std::pair{kDayA, 1}, {kDayB, 2}}) {
        size_t maps = 0;
        for (const auto& e : fs::directory_iterator(all / "visits" / day / "changes")) {
            const io::LasData m = io::ReadLas(e.path() / "map_bim.las");
            EXPECT_EQ(m.size(), io::ReadPly(e.path() / "map_bim.ply").vertices.size());
            EXPECT_EQ(std::set<uint16_t>(m.point_source_id.begin(), m.point_source_id.end()),
                      std::set<uint16_t>{uint16_t(number)})
                << e.path();
            EXPECT_TRUE(m.adjusted_standard_gps_time) << "the odometry wrote the clock offset";
            ++maps;
        }
        EXPECT_GT(maps, 0u) << day;
    }
    // The project's summary counts the newest visit's changes.
    const json s = ReadJson(one / "summary.json");
    EXPECT_EQ(s.at("history").at("building_map_voxels"),
              json::array({bm["visits"][0]["voxels"], bm["visits"][1]["voxels"]}));
    EXPECT_EQ(s.at("history").at("visits"), 2);
    EXPECT_EQ(s["history"].at("since_previous").at("previous"), kDayA);
    EXPECT_EQ(s["history"]["since_previous"].at("gone"), 1);
    EXPECT_EQ(s["history"]["since_previous"].at("new"), 1);
    EXPECT_EQ(s["history"]["since_previous"].at("reappeared"), missing.size());
}

// The as-is model (issue 33 item 4): the model file with the new objects present after the
// newest visit as proxies and every observed element's history as a property set, read by
// IFC++ (`bimslam bim info`) and by web-ifc.
TEST(MapVisits, TheAsIsModelHoldsTheHistoryAndBothReadersOpenIt) {
    const fs::path out = AllAtOnce() / "out";
    const std::string original = io::ReadFileToString(Model());
    const std::string asis = io::ReadFileToString(out / "model_asis.ifc");
    const size_t data_end = original.rfind("ENDSEC;");
    ASSERT_NE(data_end, std::string::npos);
    EXPECT_EQ(asis.compare(0, data_end, original, 0, data_end), 0) << "the original, then more";

    // IFC++: the model's elements and one proxy, the cabinet present on 9 March.
    const auto before = Cli("bim info " + Model() + " --json");
    const auto after = Cli("bim info " + (out / "model_asis.ifc").string() + " --json");
    ASSERT_EQ(after.exit_code, 0) << after.err;
    const json b = json::parse(before.out), a = json::parse(after.out);
    EXPECT_TRUE(a.at("failed").empty()) << a.at("failed").dump();
    EXPECT_EQ(a.at("elements").value("IfcBuildingElementProxy", 0), 1) << a.at("elements").dump();
    EXPECT_EQ(a.at("elements").at("IfcColumn"), b.at("elements").at("IfcColumn"));

    if (const std::string why = web_ifc::Missing(); !why.empty()) GTEST_SKIP() << why;
    const json w = web_ifc::Read(out / "model_asis.ifc");
    ASSERT_TRUE(w.is_object());
    EXPECT_EQ(w.at("mesh_classes").value("IfcBuildingElementProxy", 0), 1);
    // The columns missing on 2 March and standing on 9 March: their history on each of them.
    const json c = ReadJson(out / "visits" / kDayA / "changes" / "lidar" / "changes.json");
    ASSERT_GE(c.at("missing").size(), 2u);
    for (const json& m : c.at("missing")) {
        const std::string id = m.at("global_id");
        const json* found = nullptr;
        for (const json& set : w.at("bimslam_psets")) {
            if (set.at("name") == "bimslam_History" && set.at("objects") == json::array({id}))
                found = &set;
        }
        ASSERT_NE(found, nullptr) << id << " has no bimslam_History";
        const json& p = found->at("properties");
        EXPECT_EQ(p.at("VerdictsByVisit"), kDayA + " missing; " + kDayB + " confirmed") << id;
        EXPECT_EQ(p.at("AsIs"), "confirmed") << id;
        EXPECT_EQ(p.at("FirstSeenBuilt"), kDayB) << id;
    }
    EXPECT_TRUE(w.at("bimslam_groups").empty()) << "nothing is missing as of 9 March";
}

TEST(MapVisits, VisitDatesComeFromTheRecordingsAndOrderTheVisits) {
    const json p = ReadJson(AllAtOnce() / "out" / "project.json");
    ASSERT_EQ(p.at("visits").size(), 2u) << p.dump(1);
    const json& first = p["visits"][0];
    const json& second = p["visits"][1];
    // c, b, a given: a's day first, then b and c (one day: one visit), b before c.
    EXPECT_EQ(first.at("label"), kDayA);
    EXPECT_EQ(second.at("label"), kDayB);
    EXPECT_EQ(second.at("dir"), "visits/" + kDayB);
    ASSERT_EQ(first.at("recordings").size(), 1u);
    ASSERT_EQ(second.at("recordings").size(), 2u);
    EXPECT_EQ(second["recordings"][0].at("name"), "b");
    EXPECT_EQ(second["recordings"][1].at("name"), "c");
    // b and c: their capture.json's start; a (its pcap alone): its first packet, just after.
    EXPECT_EQ(second["recordings"][0].at("start"), "2026-03-09T09:00:00Z");
    EXPECT_EQ(second["recordings"][0].at("start_from"), "capture.json");
    EXPECT_EQ(second["recordings"][1].at("start"), "2026-03-09T15:30:00Z");
    EXPECT_EQ(second.at("start"), "2026-03-09T09:00:00Z");
    const json& a = first["recordings"][0];
    EXPECT_EQ(a.at("name"), "lidar");
    EXPECT_EQ(a.at("start_from"), "first packet");
    const int64_t a_ns = a.at("start_ns");
    const int64_t a_start = 1'772'442'000'000'000'000;  // 2026-03-02T09:00:00Z
    EXPECT_GE(a_ns, a_start);
    EXPECT_LT(a_ns, a_start + 1'000'000'000) << "the first packet, within the first frame";
    // The summary lists the visits in that order, with their dates.
    const json s = ReadJson(AllAtOnce() / "out" / "summary.json");
    ASSERT_EQ(s.at("visits").size(), 2u);
    EXPECT_EQ(s["visits"][0].at("label"), kDayA);
    EXPECT_EQ(s["visits"][1].at("start"), "2026-03-09T09:00:00Z");
    // The rule is said in --help.
    const auto h = Cli("map --help");
    EXPECT_NE(h.out.find("same calendar day (UTC)"), std::string::npos) << h.out;
    EXPECT_NE(h.out.find("--add"), std::string::npos) << h.out;
}

TEST(MapVisits, ARerunWithNoNewRecordingDoesNothing) {
    test::TempDir tmp;
    const std::string out = CopyOfProject(tmp).string();
    const Mtimes before = MtimesOf(out);
    // The project alone, the first command line with every recording again, and --add of one
    // already there (noted, not added): every step skipped, exit 0 as the run before.
    for (const std::string& args :
         {"map " + out, "map " + Model() + " " + B() + " " + A() + " " + C() + " -o " + out,
          "map " + out + " --add " + B()}) {
        const auto r = Cli(args + kBudget + " --json");
        ASSERT_EQ(r.exit_code, 0) << args << "\n" << r.err;
        const json steps = Steps(json::parse(r.out));
        EXPECT_EQ(steps.size(), 10u)
            << steps.dump();  // reference, 3 odometry, 2 x 2, history, report
        for (const auto& [step, skipped] : steps.items())
            EXPECT_TRUE(skipped.get<bool>()) << args << ": " << step;
        if (args.find("--add") != std::string::npos) {
            EXPECT_NE(r.err.find("already in visit " + kDayB + " (as b), not added again"),
                      std::string::npos)
                << r.err;
        }
    }
    EXPECT_EQ(Written(before, MtimesOf(out)), std::vector<std::string>{}) << "no file written";
}

// The entry named `name` of a JSON array, or null (a failure).
json Named(const json& array, const std::string& name, const std::string& where) {
    for (size_t k = 0; k < array.size(); ++k) {
        if (array[k].at("name") == name) return array[k];
    }
    ADD_FAILURE() << name << " is not in " << where;
    return json(nullptr);
}

// Recording `name`'s entry in visit `label`'s anchor.json, and in project.json.
json AnchoredEntry(const fs::path& out, const std::string& label, const std::string& name) {
    const fs::path file = out / "visits" / label / "anchor" / "anchor.json";
    return Named(ReadJson(file).at("sessions"), name, file.string());
}

json RecordingEntry(const fs::path& out, const std::string& name) {
    const json project = ReadJson(out / "project.json");
    json all = json::array();
    for (size_t v = 0; v < project.at("visits").size(); ++v) {
        for (const json& r : project.at("visits")[v].at("recordings")) all.push_back(r);
    }
    return Named(all, name, "project.json");
}

TEST(MapVisits, NearIsKeptForItsRecordingsAndTheirAnchoringHoldsToIt) {
    test::TempDir tmp;
    const fs::path out = CopyOfProject(tmp);
    EXPECT_FALSE(RecordingEntry(out, "b").contains("near"));
    // Told that b starts 100 m off: its visit is anchored again and b fails, naming the hint;
    // the first day's visit is not touched.
    const auto far =
        Cli("map " + out.string() + " --add " + B() + " --near 100 100" + kBudget + " --json");
    ASSERT_EQ(far.exit_code, 1) << far.err;
    const json far_steps = Steps(json::parse(far.out));
    EXPECT_FALSE(far_steps.at("anchor " + kDayB).get<bool>()) << far_steps.dump();
    EXPECT_TRUE(far_steps.at("anchor " + kDayA).get<bool>()) << far_steps.dump();
    EXPECT_EQ(RecordingEntry(out, "b").at("near"), json({100.0, 100.0, 3.0}));
    EXPECT_FALSE(RecordingEntry(out, "c").contains("near"));
    const json b = AnchoredEntry(out, kDayB, "b");
    EXPECT_EQ(b.at("verdict"), "failed");
    EXPECT_NE(b.at("reason").get<std::string>().find("within 3.0 m of (100.00, 100.00) (--near)"),
              std::string::npos)
        << b.at("reason");
    EXPECT_EQ(b.at("near"), json({100.0, 100.0, 3.0}));
    // A run that does not say it again keeps it: nothing to do.
    const auto again = Cli("map " + out.string() + kBudget + " --json");
    ASSERT_EQ(again.exit_code, 1) << again.err;
    const json again_steps = Steps(json::parse(again.out));
    for (const auto& [step, skipped] : again_steps.items())
        EXPECT_TRUE(skipped.get<bool>()) << step;
    // Where it does start (its truth's first position): anchored as before.
    const io::StampedPose start = io::ReadTum(Walks() / "b" / "ground_truth.tum").front();
    MapJson("map " + out.string() + " --add " + B() + " --near " +
            std::to_string(start.translation.x()) + " " + std::to_string(start.translation.y()));
    EXPECT_EQ(AnchoredEntry(out, kDayB, "b").at("verdict"), "anchored");
}

TEST(MapVisits, ADamagedVisitFolderIsReportedAndTheOtherVisitsAreKept) {
    test::TempDir tmp;
    const fs::path out = CopyOfProject(tmp);
    const fs::path day_a = out / "visits" / kDayA, day_b = out / "visits" / kDayB;
    // A step's output unreadable: exit 2 naming the folder and the file, nothing written.
    const fs::path anchor_json = day_a / "anchor" / "anchor.json";
    const std::string kept = io::ReadFileToString(anchor_json);
    io::WriteFileAtomic(anchor_json, "{\"sessions\": [");
    Mtimes before = MtimesOf(out);
    auto r = Cli("map " + out.string() + kBudget);
    EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
    EXPECT_NE(r.err.find(day_a.string() + ": visit " + kDayA +
                         " is damaged: anchor/anchor.json is unreadable"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(Written(before, MtimesOf(out)), std::vector<std::string>{});
    io::WriteFileAtomic(anchor_json, kept);

    // A step's output missing: the same.
    fs::remove(day_b / "changes" / "b" / "changes.json");
    before = MtimesOf(out);
    r = Cli("map " + out.string() + " --add " + C() + kBudget);
    EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
    EXPECT_NE(r.err.find(day_b.string() + ": visit " + kDayB +
                         " is damaged: changes/b/changes.json is missing"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(Written(before, MtimesOf(out)), std::vector<std::string>{});

    // The folder removed, as the message says: that visit is made again, the other kept.
    const Mtimes a_files = MtimesOf(day_a);
    fs::remove_all(day_b);
    const json steps = Steps(MapJson("map " + out.string()));
    for (const std::string& s : std::vector<std::string>{"reference", "odometry lidar",
                                                         "anchor " + kDayA, "changes " + kDayA})
        EXPECT_EQ(steps.at(s), true) << s;
    for (const std::string& s : std::vector<std::string>{"odometry b", "odometry c",
                                                         "anchor " + kDayB, "changes " + kDayB})
        EXPECT_EQ(steps.at(s), false) << s;
    EXPECT_EQ(Written(a_files, MtimesOf(day_a)), std::vector<std::string>{})
        << "the other visit untouched";
    EXPECT_TRUE(fs::exists(day_b / "changes" / "b" / "changes.json"));
}

TEST(MapVisits, AddingToAFolderThatIsNotAProjectOrABadVisitLabelExits2) {
    test::TempDir tmp;
    fs::create_directories(tmp / "empty");
    auto r = Cli("map " + (tmp / "empty").string() + " --add " + B());
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find((tmp / "empty").string() + ": not a `bimslam map` project"),
              std::string::npos)
        << r.err;
    EXPECT_TRUE(fs::is_empty(tmp / "empty")) << "nothing written";
    r = Cli("map " + Model() + " " + B() + " -o " + (tmp / "out").string() + " --visit ../up");
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("--visit '../up'"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(tmp / "out"));
}

// --visit names the visit of the run's new recordings, whatever their days; a named visit is not
// joined by date: a later recording of b's day makes a visit of its own.
TEST(MapVisits, VisitNamesAVisitOfRecordingsOfSeveralDaysThatNoDateJoins) {
    test::TempDir tmp;
    const std::string out = (tmp / "out").string();
    MapJson("map " + Model() + " " + A() + " " + B() + " -o " + out + " --visit survey-1");
    const json steps = Steps(MapJson("map " + out + " --add " + C()));
    EXPECT_EQ(steps.at("anchor survey-1"), true) << steps.dump();
    EXPECT_EQ(steps.at("anchor " + kDayB), false) << steps.dump();
    const json p = ReadJson(tmp / "out" / "project.json");
    ASSERT_EQ(p.at("visits").size(), 2u) << p.dump(1);
    EXPECT_EQ(p["visits"][0].at("label"), "survey-1");
    EXPECT_EQ(p["visits"][0].at("named"), true);
    EXPECT_EQ(p["visits"][0].at("start"), p["visits"][0]["recordings"][0].at("start"));
    ASSERT_EQ(p["visits"][0].at("recordings").size(), 2u);
    EXPECT_EQ(p["visits"][0]["recordings"][0].at("name"), "lidar");
    EXPECT_EQ(p["visits"][0]["recordings"][1].at("name"), "b");
    EXPECT_EQ(p["visits"][1].at("label"), kDayB);
    ASSERT_EQ(p["visits"][1].at("recordings").size(), 1u);
    EXPECT_EQ(p["visits"][1]["recordings"][0].at("name"), "c");
}

// A folder re-recorded in place (another walk at the same path) is not the recording the project
// had: it replaces it, dated by itself, with a note.
TEST(MapVisits, ARecordingReRecordedInPlaceReplacesTheOldOne) {
    test::TempDir tmp;
    fs::copy(Walks() / "b", tmp / "walk", fs::copy_options::recursive);
    const std::string out = (tmp / "out").string();
    MapJson("map " + Model() + " " + (tmp / "walk").string() + " -o " + out);
    fs::remove_all(tmp / "walk");
    fs::copy(Walks() / "a", tmp / "walk", fs::copy_options::recursive);  // another day's walk
    const auto r = Cli("map " + Model() + " " + (tmp / "walk").string() + " -o " + out + kBudget);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find(": not the recording walk of visit " + kDayB + " any more"),
              std::string::npos)
        << r.err;
    const json p = ReadJson(tmp / "out" / "project.json");
    ASSERT_EQ(p.at("visits").size(), 1u) << p.dump(1);
    EXPECT_EQ(p["visits"][0].at("label"), kDayA);
    ASSERT_EQ(p["visits"][0].at("recordings").size(), 1u);
    EXPECT_EQ(p["visits"][0]["recordings"][0].at("name"), "walk");
    EXPECT_EQ(ReadJson(tmp / "out" / "summary.json").at("visit").at("label"), kDayA);
}

// The sample office's open office (x 10.5 .. 22.5, y 0.3 .. 6.0) fitted out since the model:
// 2.4 m cabinets along its south, east and west walls (the model's walls behind them out of
// view below 2.4 m) and two full-height partitions between the desks.
const char* const kFittedOut = R"(edits:
  boxes:
    - {name: cabinets south, center: [16.5, 0.65, 1.2], size: [11.8, 0.6, 2.4], yaw_deg: 0}
    - {name: cabinets east, center: [22.1, 2.9, 1.2], size: [0.6, 3.6, 2.4], yaw_deg: 0}
    - {name: cabinets west, center: [10.9, 2.0, 1.2], size: [0.6, 3.0, 2.4], yaw_deg: 0}
    - {name: partition 1, center: [15.95, 1.7, 1.4], size: [0.1, 1.5, 2.8], yaw_deg: 0}
    - {name: partition 2, center: [18.6, 1.7, 1.4], size: [0.1, 1.5, 2.8], yaw_deg: 0}
)";
bool InFittedOutRoom(const Eigen::Vector3d& p) {
    return p.x() > 10.5 && p.x() < 22.5 && p.y() < 6.0;
}

// Visit 1 (2 March): along the corridor, once through the room and out by its other door (39 %
// of its 29 m in the room). Visit 2 (9 March): from the corridor into the room, around it twice
// and back (74 % of its 31 m in the room). Hand-held, OS1-16 at 512x10; about 2 s to simulate
// both. alone/: visit 2 mapped alone (against the model); both/: the two visits.
fs::path FittedOut() {
    return Fixture("fitted_out", [](const fs::path& d) {
        const std::string head =
            "platform: handheld\nsensor: {model: OS1-16, lidar_mode: 512x10}\n";
        io::WriteFileAtomic(d / "v1.yaml", head + R"(seed: 21
duration_s: 35
path:
  mode: waypoints
  waypoints: [[2.0, 7.2], [11.6, 7.2], [11.8, 5.2], [21.2, 5.2], [21.5, 7.2], [28.5, 7.2]]
)" + kFittedOut);
        io::WriteFileAtomic(d / "v2.yaml", head + R"(seed: 22
duration_s: 40
path:
  mode: waypoints
  waypoints: [[5.0, 7.2], [11.6, 7.2], [11.8, 5.2], [21.2, 5.2], [21.2, 3.9], [13.3, 3.9],
              [13.3, 5.2], [16.0, 5.2], [11.8, 5.4], [11.6, 7.2], [4.0, 7.2]]
)" + kFittedOut);
        for (const auto& [v, day] : {std::pair{"v1", kDayA}, std::pair{"v2", kDayB}}) {
            MustRun("simulate --model " + Model() + " --scenario " +
                    (d / (v + std::string(".yaml"))).string() + " --start " + day +
                    "T09:00:00Z -o " + (d / v).string());
        }
        // Exit 1 alone (not anchored) is what the test checks, not a failure of the fixture.
        (void)Cli("map " + Model() + " " + (d / "v2").string() + " -o " + (d / "alone").string() +
                  kBudget + " --no-report");
        MustRun("map " + Model() + " " + (d / "v1").string() + " " + (d / "v2").string() + " -o " +
                (d / "both").string() + kBudget + " --no-report");
    });
}

TEST(MapVisits, AVisitThroughARoomFittedOutSinceTheModelAnchorsThroughTheEarlierVisitThatSawIt) {
    const fs::path d = FittedOut();
    const fs::path visit2 = d / "both" / "visits" / kDayB;
    const json both = ReadJson(visit2 / "summary.json").at("recordings").at(0);
    const json alone =
        ReadJson(d / "alone" / "visits" / kDayB / "summary.json").at("recordings").at(0);
    // With visit 1 as a target: anchored within 3 cm RMSE in BIM coordinates, no alignment
    // (every scan; measured 0.87-1.83 cm over three seeds).
    ASSERT_EQ(both.at("anchor").at("verdict"), "anchored") << both.dump(1);
    const double rmse = both.at("accuracy").at("ape_trans_rmse_m");
    EXPECT_LT(rmse, 0.03);
    // Against the model alone it was not anchored (failed on three seeds when written). With the
    // odometry's deskew rounds from 1 cm (stop 79) the walk can be anchored alone through the
    // room, as well: 1.2038 cm alone, 1.2041 jointly. The earlier visit must not make it worse
    // (by more than a millimetre); the loops below show that it holds the walk in the room.
    if (alone.at("anchor").at("verdict") == "anchored") {
        EXPECT_GT(alone.at("accuracy").at("ape_trans_rmse_m").get<double>() + 0.001, rmse);
    }
    // The loops that hold it in the room are to visit 1's keyframes: accepted loops to
    // "<day>/v1" from visit 2's keyframes inside the room (measured 42 loops to visit 1 in all).
    const std::vector<Eigen::Isometry3d> poses =
        io::ReadKitti(visit2 / "anchor" / "v2" / "optimized_poses.txt");
    size_t to_visit1 = 0, to_model = 0;
    for (const json& l : ReadJson(visit2 / "anchor" / "loops.json")) {
        if (!l.at("accepted").get<bool>()) continue;
        const size_t k = l.at("query_index");
        ASSERT_LT(k, poses.size());
        if (!InFittedOutRoom(poses[k].translation())) continue;
        (l.at("target") == kDayA + "/v1" ? to_visit1 : to_model) += 1;
    }
    EXPECT_GE(to_visit1, 15u) << to_model << " loops in the room to the model";
    EXPECT_GT(to_visit1, to_model);
    // Visit 1 is held by its priors: the joint solution moved it a few millimetres (0.2-0.3).
    const json earlier = ReadJson(visit2 / "anchor" / "anchor.json").at("earlier_sessions");
    ASSERT_EQ(earlier.size(), 1u);
    EXPECT_EQ(earlier[0].at("name"), kDayA + "/v1");
    EXPECT_LT(earlier[0].at("max_move_m").get<double>(), 0.02);
    // Visit 1, the first, is anchored against the model alone, as before.
    const json first = ReadJson(d / "both" / "visits" / kDayA / "anchor" / "anchor.json");
    EXPECT_FALSE(first.contains("earlier_sessions"));
}

// The same by hand: `bimslam anchor --prior-session` with visit 1's anchored session; an
// odometry session (not in BIM coordinates) is refused, exit 2 naming its session.json.
TEST(MapVisits, AnchorTakesAnEarlierVisitsAnchoredSessionByHand) {
    const fs::path d = FittedOut();
    const fs::path b = d / "both";
    test::TempDir tmp;
    const std::string args = "anchor --reference " + (b / "reference").string() + " --query " +
                             (b / "visits" / kDayB / "odometry" / "v2").string() + " --threads 2";
    const auto r =
        Cli(args + " --prior-session " + (b / "visits" / kDayA / "anchor" / "v1").string() +
            " -o " + (tmp / "with").string());
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
    EXPECT_NE(r.out.find("earlier    v1 ("), std::string::npos) << r.out;
    const json a = ReadJson(tmp / "with" / "anchor.json");
    EXPECT_EQ(a.at("sessions").at(0).at("verdict"), "anchored");
    EXPECT_EQ(a.at("earlier_sessions").at(0).at("name"), "v1");
    EXPECT_GE(a["earlier_sessions"][0].at("accepted_loops").get<int>(), 15);
    const fs::path odometry = b / "visits" / kDayA / "odometry" / "v1";
    const auto bad =
        Cli(args + " --prior-session " + odometry.string() + " -o " + (tmp / "bad").string());
    EXPECT_EQ(bad.exit_code, 2) << bad.err;
    EXPECT_NE(bad.err.find((odometry / "session.json").string() + ": not an anchored session"),
              std::string::npos)
        << bad.err;
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam
