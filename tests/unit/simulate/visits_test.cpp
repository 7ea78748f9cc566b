// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Issue 33, item 7: a scenario's visits simulated one capture each (the synthetic floor, short
// OS1-16 walks), visits.json's order and pair truth, and one visit simulated alone equal to its
// folder of the whole run (what `bimslam simulate --visit` does).
#include "host_tools/simulate/visits.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "algorithms/io/file_util.hpp"
#include "drivers/ouster/metadata.hpp"
#include "host_tools/capture/ouster_capture.hpp"
#include "host_tools/simulate/scenario_yaml.hpp"
#include "tests/support/test_support.hpp"
#include "tests/unit/bim/synthetic_floor.hpp"

namespace bimslam::simulate {
namespace {
namespace BIMSLAM_UNITY_ID {
namespace fs = std::filesystem;
using nlohmann::json;

// The synthetic floor (12 x 8 m; its corridor y 3.5 .. 5): box7 is the wall between its two south
// rooms, box4 a corridor wall, box12 the north room's desk. Listed later visit first: visits.json
// orders them by date.
constexpr const char* kVisits = R"(platform: handheld
duration_s: 6
sensor: {model: OS1-16, lidar_mode: 512x10}
path: {mode: waypoints, waypoints: [[1.5, 4.2], [10.5, 4.2]]}
visits:
  - label: after
    date: "2026-06-01T10:00:00Z"
    seed: 2
    edits:
      boxes:
        - {name: crate, center: [4.5, 1.5, 0.3], size: [0.6, 0.6, 0.6], yaw_deg: 10}
        - {name: bin, center: [10.0, 6.0, 0.4], size: [0.4, 0.4, 0.8]}
      removed: {global_ids: [box7]}
      moved: [{global_id: box4, translation: [0.05, 0, 0]}]
  - label: before
    date: "2026-01-15T09:00:00Z"
    seed: 1
    edits:
      boxes:
        - {name: crate, center: [4.0, 1.5, 0.3], size: [0.6, 0.6, 0.6]}
        - {name: cabinet, center: [4.0, 4.7, 0.5], size: [0.8, 0.3, 1.0]}
      removed: {global_ids: [box12]}
)";

class VisitsTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        dir_ = new test::TempDir;
        scenario_ = new Scenario(ParseScenario("visits.yaml", kVisits, {}));
        model_ = new bim::BimModel(bim::test_floor::Floor());
        captures_ = SimulateVisits(*scenario_, *model_, "none", dir_->path());
        visits_ = json::parse(io::ReadFileToString(dir_->path() / "visits.json"));
    }
    static void TearDownTestSuite() {
        delete dir_;
        delete scenario_;
        delete model_;
    }
    static const json& Pair() { return visits_["pairs"][0]; }
    static test::TempDir* dir_;
    static Scenario* scenario_;
    static bim::BimModel* model_;
    static std::vector<VisitCapture> captures_;
    static json visits_;
};
test::TempDir* VisitsTest::dir_ = nullptr;
Scenario* VisitsTest::scenario_ = nullptr;
bim::BimModel* VisitsTest::model_ = nullptr;
std::vector<VisitCapture> VisitsTest::captures_;
json VisitsTest::visits_;

TEST_F(VisitsTest, OneCapturePerVisitEachOnItsDateInDateOrder) {
    ASSERT_EQ(captures_.size(), 2u);
    EXPECT_EQ(captures_[0].label, "before");
    EXPECT_EQ(captures_[1].label, "after");
    ASSERT_EQ(visits_["visits"].size(), 2u);
    int64_t last = 0;
    for (size_t k = 0; k < 2; ++k) {
        const json& v = visits_["visits"][k];
        EXPECT_EQ(v["label"], captures_[k].label);
        EXPECT_EQ(v["folder"], captures_[k].label);
        EXPECT_GT(v["start_ns"].get<int64_t>(), last);
        last = v["start_ns"].get<int64_t>();
        const fs::path folder = dir_->path() / v["folder"].get<std::string>();
        // Each capture's manifest carries its own date, and its lidar decodes like a real one.
        const json manifest = json::parse(io::ReadFileToString(folder / "capture.json"));
        EXPECT_EQ(manifest["start"], v["date"]);
        EXPECT_EQ(manifest["start_ns"], v["start_ns"]);
        capture::OusterCapture capture(folder / "lidar.pcap",
                                       ouster::LoadMetadata(folder / "metadata.json"));
        size_t frames = 0, complete = 0;
        while (const ouster::LidarFrame* f = capture.NextFrame()) ++frames, complete += f->complete;
        EXPECT_EQ(frames, captures_[k].report.frames);
        EXPECT_EQ(complete, frames);
        EXPECT_EQ(frames, 60u);  // 6 s at 10 Hz
        // Its scenario.yaml is the visit's alone.
        const Scenario own = LoadScenario(folder / "scenario.yaml");
        EXPECT_TRUE(own.visits.empty());
        EXPECT_EQ(own, VisitScenario(*scenario_, FindVisit(*scenario_, captures_[k].label)));
    }
    ASSERT_EQ(visits_["pairs"].size(), 1u);
    EXPECT_EQ(Pair()["earlier"], "before");
    EXPECT_EQ(Pair()["later"], "after");
    EXPECT_TRUE(Pair()["consecutive"].get<bool>());
}

std::vector<std::string> Names(const json& list, const char* key = "name") {
    std::vector<std::string> out;
    for (const json& e : list) out.push_back(e[key]);
    return out;
}

TEST_F(VisitsTest, PairTruthSaysWhatWasAddedMovedAndGone) {
    const json& o = Pair()["objects"];
    EXPECT_EQ(Names(o["new"]), std::vector<std::string>{"bin"});
    EXPECT_EQ(Names(o["gone"]), std::vector<std::string>{"cabinet"});
    EXPECT_TRUE(o["unchanged"].empty());
    ASSERT_EQ(Names(o["moved"]), std::vector<std::string>{"crate"});
    const json& crate = o["moved"][0];
    EXPECT_NEAR(crate["translation"][0].get<double>(), 0.5, 1e-9);
    EXPECT_NEAR(crate["translation"][1].get<double>(), 0.0, 1e-9);
    EXPECT_NEAR(crate["yaw_deg"].get<double>(), 10.0, 1e-9);
    // What each walk saw of them: the later's beam hits and the earlier's.
    EXPECT_TRUE(crate.contains("beam_hits"));
    EXPECT_TRUE(crate.contains("beam_hits_earlier"));
    EXPECT_FALSE(o["new"][0].contains("beam_hits_earlier"));
    // The gone cabinet stood against the corridor's wall, which both walks pass: the earlier's
    // beams on it, and the later's on where it stood, are counted.
    EXPECT_GT(o["gone"][0]["beam_hits"].get<long>(), 0);
    EXPECT_GT(o["gone"][0]["beam_hits_earlier"].get<long>(), 0);

    const json& e = Pair()["elements"];
    EXPECT_EQ(Names(e["newly_removed"], "global_id"), std::vector<std::string>{"box7"});
    EXPECT_EQ(Names(e["rebuilt"], "global_id"), std::vector<std::string>{"box12"});
    // The rebuilt desk: the later walk's returns on it.
    EXPECT_GT(e["rebuilt"][0]["beam_hits"].get<long>(), 0);
    ASSERT_EQ(Names(e["newly_moved"], "global_id"), std::vector<std::string>{"box4"});
    EXPECT_NEAR(e["newly_moved"][0]["translation"][0].get<double>(), 0.05, 1e-9);
    EXPECT_FALSE(e["newly_moved"][0]["at_model_place"].get<bool>());
    // The demolished wall stood across the walk's view: its beams are counted.
    EXPECT_GT(e["newly_removed"][0]["beam_hits"].get<long>(), 0);
}

// `bimslam simulate --visit LABEL` simulates VisitScenario alone: the same files, byte for byte.
TEST_F(VisitsTest, OneVisitAloneEqualsItsFolder) {
    test::TempDir alone;
    const size_t i = FindVisit(*scenario_, "after");
    SimulateCapture(VisitScenario(*scenario_, i), *model_, "none", alone.path());
    size_t files = 0;
    for (const auto& entry : fs::recursive_directory_iterator(dir_->path() / "after")) {
        if (!entry.is_regular_file()) continue;
        const fs::path rel = fs::relative(entry.path(), dir_->path() / "after");
        SCOPED_TRACE(rel.string());
        ASSERT_TRUE(fs::exists(alone.path() / rel));
        EXPECT_TRUE(io::ReadFileToString(entry.path()) == io::ReadFileToString(alone.path() / rel));
        ++files;
    }
    EXPECT_GE(files,
              7u);  // lidar.pcap, metadata, ground truth, changes (+ PLYs), scenario, manifest
}

// A gone object's `beam_hits` are the later walk's beams that would have hit it where it stood.
// Two visits with the same walk and seed, a box in the first only (off the walk, so both walks
// are the same): the later's count of the absent box is the earlier's returns on the real one,
// plus the beams that dropped out on it (no return, but counted on the absent box: the noise
// model's dropouts grow at grazing incidence; 2.8 % more here, 2.6 % with no base dropout).
TEST(VisitsGone, TheLaterWalksBeamsOnWhereAGoneObjectStoodMatchTheEarliersOnIt) {
    const std::string text = R"(platform: handheld
duration_s: 5
seed: 4
sensor: {model: OS1-16, lidar_mode: 512x10}
path: {mode: waypoints, waypoints: [[1.5, 4.2], [10.5, 4.2]]}
visits:
  - label: with
    date: "2026-01-15T09:00:00Z"
    edits: {boxes: [{name: chest, center: [4.0, 1.5, 0.5], size: [0.8, 0.6, 1.0]}]}
  - label: without
    date: "2026-02-15T09:00:00Z"
    edits: {}
)";
    test::TempDir dir;
    const Scenario s = ParseScenario("gone.yaml", text, {});
    SimulateVisits(s, bim::test_floor::Floor(), "none", dir.path());
    EXPECT_EQ(io::ReadFileToString(dir / "with/ground_truth.tum"),
              io::ReadFileToString(dir / "without/ground_truth.tum"));
    const json visits = json::parse(io::ReadFileToString(dir / "visits.json"));
    const json& gone = visits["pairs"][0]["objects"]["gone"];
    ASSERT_EQ(gone.size(), 1u);
    const double earlier = gone[0]["beam_hits_earlier"].get<double>();
    const double later = gone[0]["beam_hits"].get<double>();
    EXPECT_GT(earlier, 1000);
    EXPECT_GE(later, earlier);
    EXPECT_LT(later / earlier, 1.05) << later << " " << earlier;
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::simulate
