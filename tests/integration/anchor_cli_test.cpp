// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// `bimslam anchor` as a user runs it, on sessions of captures the project simulates: a Go1 and a
// handheld walk anchor to the sample building's BIM reference within centimetres with no
// initial pose (scored with `bimslam evaluate --align none` against the simulator's ground
// truth, which is in BIM coordinates); so does a query moved 100 m and turned 170 degrees, one
// that starts outside the building, one in the SC-A-LOAM/LT-mapper layout, and two sessions at
// once; a first-floor walk that fails alone against a ground-floor reference is anchored through a
// two-storey walk; injected false loops stay out of the accepted set; a mirror-symmetric building
// is reported ambiguous and a ground-floor walk against a first-floor reference is not anchored; a
// session whose odometry failed midway is anchored in parts, not anchored; damaged sessions exit 2
// naming the file.
//
// The bounds are about twice the figures measured on these walks (ExpectTargets); the issue's
// targets (3 cm / 8 cm, 0.5 / 1.5 deg) and the measured spread are anchor_benchmark's.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <tuple>

#include "algorithms/common/se3.hpp"
#include "algorithms/io/file_util.hpp"
#include "algorithms/io/session.hpp"
#include "algorithms/io/trajectory.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam {
namespace {
namespace BIMSLAM_UNITY_ID {
namespace fs = std::filesystem;
using nlohmann::json;

const std::string kCli = BIMSLAM_CLI_PATH;
const std::string kScenarios = BIMSLAM_SCENARIO_DIR;
constexpr int kSeconds = 40;

// Data the tests share, made once per build of `bimslam` and kept in the build folder: ctest runs
// each test in a process of its own, and simulating every building and walk per test would take
// minutes (test::CachedFixture: one process makes it, the others wait for it; a fixture that
// failed to build is not kept).
fs::path FixtureRoot() {
    static const fs::path root =
        test::FixtureRootFor(BIMSLAM_TEST_BINARY_DIR "/anchor_fixtures", kCli);
    return root;
}

test::CommandResult Cli(const std::string& args) { return test::RunCommand(kCli + " " + args); }

void MustRun(const std::string& args) {
    const auto r = Cli(args);
    ASSERT_EQ(r.exit_code, 0) << "bimslam " << args << "\n" << r.out << r.err;
}

fs::path Fixture(const std::string& name, const std::function<void(const fs::path&)>& make) {
    return test::CachedFixture(FixtureRoot(), name, make);
}

// A building (`bim sample` with extra flags) and its BIM reference session.
fs::path Building(const std::string& name, const std::string& sample_flags,
                  const std::string& reference_flags = "") {
    return Fixture(name, [&](const fs::path& d) {
        MustRun("bim sample -o " + (d / "building.ifc").string() + " " + sample_flags);
        MustRun("bim2session " + (d / "building.ifc").string() + " -o " +
                (d / "reference").string() + " " + reference_flags);
    });
}
fs::path Office() { return Building("office", ""); }

// A capture of `building` simulated with `flags`, turned into a session by `bimslam odometry`;
// the pcap is dropped once the session exists (the tests need the session and the truth). The
// odometry runs with an unbounded budget: with its 50 ms default, a session made on an
// overloaded machine cuts scans short and is another session (a handheld walk came out 10 cm off
// at one keyframe, or ambiguous between storeys), and these tests are about anchoring.
fs::path Walk(const std::string& name, const fs::path& building, const std::string& flags,
              int seconds = kSeconds) {
    return Fixture(name, [&](const fs::path& d) {
        MustRun("simulate --model " + (building / "building.ifc").string() + " --duration " +
                std::to_string(seconds) + " -o " + (d / "capture").string() + " " + flags);
        MustRun("odometry " + (d / "capture").string() + " -o " + (d / "session").string() +
                " --budget-ms 10000");
        fs::remove(d / "capture" / "lidar.pcap");
    });
}

// The sample office with its entrances, and a walk into it from 5 m outside
// (host_tools/simulate/scenarios/outdoor_start.yaml).
fs::path OfficeWithEntrances() { return Building("office_entrances", "--exterior-doors"); }
fs::path WalkFromOutside(const std::string& name, int seconds) {
    return Walk(name, OfficeWithEntrances(), "--scenario " + kScenarios + "/outdoor_start.yaml",
                seconds);
}

json ReadJson(const fs::path& file) { return json::parse(io::ReadFileToString(file)); }

struct Accuracy {
    double rmse_cm = 1e9, max_cm = 1e9, rot_rmse_deg = 1e9, rot_max_deg = 1e9;
    size_t matched = 0;
};

// `bimslam evaluate --align none` of a trajectory against a capture's ground truth.
Accuracy Evaluate(const fs::path& trajectory, const fs::path& walk) {
    const auto r = Cli("evaluate --align none --json --est " + trajectory.string() + " --ref " +
                       (walk / "capture" / "ground_truth.tum").string());
    EXPECT_EQ(r.exit_code, 0) << r.err;
    Accuracy a;
    if (r.exit_code != 0) return a;
    const json j = json::parse(r.out);
    a.rmse_cm = 100 * j["ape_trans_rmse_m"].get<double>();
    a.max_cm = 100 * j["ape_trans_max_m"].get<double>();
    a.rot_rmse_deg = j["ape_rot_rmse_deg"].get<double>();
    a.rot_max_deg = j["ape_rot_max_deg"].get<double>();
    a.matched = j["matched"].get<size_t>();
    std::cout << trajectory.string() << ": APE " << a.rmse_cm << " cm (max " << a.max_cm << "), "
              << a.rot_rmse_deg << " deg (max " << a.rot_max_deg << ")\n";
    return a;
}

// Runs `bimslam anchor` into a fresh folder; returns its exit code.
int Anchor(const fs::path& reference, const std::vector<fs::path>& queries, const fs::path& out,
           const std::string& flags = "", std::string* err = nullptr) {
    std::string args =
        "anchor --reference " + reference.string() + " -o " + out.string() + " " + flags;
    for (const fs::path& q : queries) args += " --query " + q.string();
    const auto r = Cli(args);
    if (err) *err = r.err;
    std::cout << r.out << r.err;
    return r.exit_code;
}

// The keyframes of an anchored session as a TUM file (times.txt and optimized_poses.txt).
fs::path KeyframeTum(const fs::path& session) {
    std::vector<io::StampedPose> poses;
    const auto T = io::ReadKitti(session / "optimized_poses.txt");
    const std::string text = io::ReadFileToString(session / "times.txt");
    size_t k = 0, pos = 0;
    while (pos < text.size() && k < T.size()) {
        const size_t end = text.find('\n', pos);
        const std::string line = text.substr(pos, end - pos);
        if (!line.empty())
            poses.push_back(
                io::StampedPose::FromIsometry(std::llround(std::stod(line) * 1e9), T[k++]));
        if (end == std::string::npos) break;
        pos = end + 1;
    }
    const fs::path file = session / "keyframes_bim.tum";
    io::WriteTum(file, poses);
    return file;
}

// About twice the figures measured on these tests' walks (the Go1 and handheld walks, far off,
// two sessions, the SC-A-LOAM layout: keyframes 0.61-0.63 cm RMSE, max 1.01-1.56 cm, 0.05-0.09
// deg RMSE, max 0.11-0.19 deg; every scan 0.62-0.69 cm RMSE, max 1.01-1.56 cm), so that a
// regression shows before it reaches the targets (3 cm / 8 cm, 0.5 / 1.5 deg), which
// anchor_benchmark checks on its 120 s walks. A scan between keyframes is placed by the odometry
// from them: on longer handheld walks its excursions reach 10-15 cm within a metre (the
// benchmark's "every scan max"), which anchoring cannot see.
void ExpectTargets(const fs::path& anchored_session, const fs::path& walk) {
    const Accuracy k = Evaluate(KeyframeTum(anchored_session), walk);
    EXPECT_LT(k.rmse_cm, 1.5);
    EXPECT_LT(k.max_cm, 3.5);
    EXPECT_LT(k.rot_rmse_deg, 0.2);
    EXPECT_LT(k.rot_max_deg, 0.4);
    const Accuracy a = Evaluate(anchored_session / "trajectory_bim.tum", walk);
    EXPECT_LT(a.rmse_cm, 1.5);
    EXPECT_LT(a.rot_rmse_deg, 0.2);
    EXPECT_LT(a.max_cm, 3.5);
}

class AnchorCli : public ::testing::Test {
protected:
    void SetUp() override { out_ = std::make_unique<test::TempDir>(); }
    fs::path Out(const std::string& name) const { return *out_ / name; }
    std::unique_ptr<test::TempDir> out_;
};

TEST_F(AnchorCli, AGo1WalkAnchorsWithinCentimetresAndWritesEverything) {
    const fs::path office = Office();
    const fs::path walk = Walk("go1", office, "--platform go1 --seed 11");
    const fs::path out = Out("anchor");
    ASSERT_EQ(Anchor(office / "reference", {walk / "session"}, out), 0);
    const json summary = ReadJson(out / "anchor.json");
    EXPECT_EQ(summary["verdict"], "anchored");
    EXPECT_EQ(summary["sessions"][0]["verdict"], "anchored");
    EXPECT_EQ(summary["sessions"][0]["odometry_verdict"], "trusted");
    EXPECT_FALSE(summary["sessions"][0].contains("pieces"));
    ExpectTargets(out / "session", walk);

    // Every scan placed, the anchored session readable with world frame "bim".
    const auto scans = io::ReadTum(walk / "session" / "trajectory.tum").size();
    EXPECT_EQ(io::ReadTum(out / "session" / "trajectory_bim.tum").size(), scans);
    const auto info = Cli("session info --json " + (out / "session").string());
    ASSERT_EQ(info.exit_code, 0) << info.err;
    EXPECT_EQ(json::parse(info.out)["world_frame"], "bim");
    // loops.json: every candidate with a verdict; accepted ones on most keyframes.
    const json loops = ReadJson(out / "loops.json");
    size_t accepted = 0;
    for (const json& l : loops) {
        accepted += l["accepted"].get<bool>();
        EXPECT_FALSE(l["reason"].get<std::string>().empty());
    }
    EXPECT_GT(accepted, summary["sessions"][0]["keyframes"].get<size_t>() / 2);
    // The multi-session g2o: fixed reference vertices, odometry and loop edges.
    const std::string g2o = io::ReadFileToString(out / "posegraph.g2o");
    EXPECT_NE(g2o.find("FIX 0\n"), std::string::npos);
    EXPECT_NE(g2o.find("EDGE_SE3:QUAT 1000000 1000001 "), std::string::npos);
}

TEST_F(AnchorCli, AHandheldWalkAnchorsWithinCentimetres) {
    const fs::path office = Office();
    const fs::path walk = Walk("handheld", office, "--platform handheld --seed 12");
    const fs::path out = Out("anchor");
    ASSERT_EQ(Anchor(office / "reference", {walk / "session"}, out), 0);
    ExpectTargets(out / "session", walk);
}

// Rewrites a session's poses (keyframes, odometry, every scan) as seen from a frame T_new_old
// away: the same walk with another odometry origin.
void MoveSession(const fs::path& from, const fs::path& to, const Eigen::Isometry3d& T_new_old) {
    fs::copy(from, to, fs::copy_options::recursive);
    for (const char* file : {"optimized_poses.txt", "odom_poses.txt"}) {
        std::vector<Eigen::Isometry3d> poses = io::ReadKitti(to / file);
        for (auto& T : poses) T = T_new_old * T;
        io::WriteKitti(to / file, poses);
    }
    std::vector<io::StampedPose> scans = io::ReadTum(to / "trajectory.tum");
    for (auto& p : scans) p = io::StampedPose::FromIsometry(p.stamp_ns, T_new_old * p.Pose());
    io::WriteTum(to / "trajectory.tum", scans);
}

TEST_F(AnchorCli, AQueryHundredMetresAwayAndTurned170DegreesAnchors) {
    const fs::path office = Office();
    const fs::path walk = Walk("go1", office, "--platform go1 --seed 11");
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(170 * M_PI / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    T.translation() = Eigen::Vector3d(100, -60, 5);
    MoveSession(walk / "session", Out("moved"), T);
    const fs::path out = Out("anchor");
    ASSERT_EQ(Anchor(office / "reference", {Out("moved")}, out), 0);
    ExpectTargets(out / "moved", walk);
}

TEST_F(AnchorCli, AWalkThatStartsOutsideAnchors) {
    const fs::path building = OfficeWithEntrances();
    // 80 s: in 40 s the walk sees only the corridor, whose doors repeat along it, and that is
    // not enough to tell where it is (it fails, saying so).
    const fs::path walk = WalkFromOutside("outdoor", 80);
    const fs::path out = Out("anchor");
    ASSERT_EQ(Anchor(building / "reference", {walk / "session"}, out), 0);
    // The start, 5 m outside, is placed through the odometry from the first loops inside.
    const auto truth = io::ReadTum(walk / "capture" / "ground_truth.tum");
    const auto placed = io::ReadTum(out / "session" / "trajectory_bim.tum");
    ASSERT_FALSE(placed.empty());
    EXPECT_LT(truth.front().Pose().translation().x(), -3.0);  // it did start outside
    EXPECT_LT((placed.front().translation - truth.front().translation).norm(), 0.10);
    const Accuracy a = Evaluate(out / "session" / "trajectory_bim.tum", walk);
    EXPECT_LT(a.rmse_cm, 1.5);  // measured 0.71 cm (max 1.29)
    EXPECT_LT(a.max_cm, 3.0);
}

TEST_F(AnchorCli, AMinuteFromOutsideAnchorsOnTheFewRightLoopsItHas) {
    // The same start, 60 s: of 35 verified loops 3 are right (a clique of 3), the rest mostly on
    // the storey above, whose cliques see through the model. It was not anchored while cliques
    // needed 4 loops and the wrong ones were followed first (host_tools/anchor/README.md, "Walks
    // from outside").
    const fs::path building = OfficeWithEntrances();
    const fs::path walk = WalkFromOutside("outdoor_60", 60);
    const fs::path out = Out("anchor");
    ASSERT_EQ(Anchor(building / "reference", {walk / "session"}, out), 0);
    const Accuracy a = Evaluate(out / "session" / "trajectory_bim.tum", walk);
    EXPECT_LT(a.rmse_cm, 1.5);  // measured 0.75 cm (max 1.35)
    EXPECT_LT(a.max_cm, 3.0);
}

TEST_F(AnchorCli, WithTheCauchyLossAloneEachLoopIsListedOnceWithWhatHappenedToIt) {
    // The walk from outside against the sample office drawn without its entrances (a model
    // that differs from the building). Outside, a keyframe has no proximity loop to supersede
    // its place-recognition loops, so the final solution drops the wrong ones itself
    // (chi-square). loops.json listed each such loop twice: once "consistent; superseded by a
    // proximity loop", once as dropped. And with --outliers none nothing tested the loops'
    // consistency: they are "in the hypothesis". The 80 s walk (57 keyframes): the minute from
    // outside (37) gave the Cauchy loss alone enough right loops with stop 59's odometry, not
    // with stop 60's (its deskew rounds, algorithms/odometry/README.md): that solution then saw
    // 14 % of its rays through the model even with no loop injected, where the default outlier
    // rejection anchors it to 0.75 cm. The 80 s walk anchors with seeds 1-4 (1-3 loops dropped).
    const fs::path office = Office();
    const fs::path walk = WalkFromOutside("outdoor", 80);
    const fs::path out = Out("none");
    ASSERT_EQ(Anchor(office / "reference", {walk / "session"}, out,
                     "--outliers none --inject-false-loops 0.3 --seed 1"),
              0);
    std::set<std::tuple<size_t, size_t, std::string>> seen;
    size_t dropped = 0;
    for (const json& l : ReadJson(out / "loops.json")) {
        const auto key =
            std::make_tuple(l["query_index"].get<size_t>(), l["target_index"].get<size_t>(),
                            l["source"].get<std::string>());
        EXPECT_TRUE(seen.insert(key).second)
            << "listed twice: keyframe " << std::get<0>(key) << " to " << std::get<1>(key);
        const std::string reason = l["reason"];
        EXPECT_NE(reason.rfind("consistent", 0), 0u) << reason;
        dropped += reason.rfind("inconsistent with the solution: chi2", 0) == 0;
    }
    EXPECT_GT(dropped, 0u);  // measured 2 (seeds 1-4: 1-3; each listed twice before)
}

TEST_F(AnchorCli, InjectedFalseLoopsStayOutOfTheAcceptedHypothesis) {
    const fs::path office = Office();
    const fs::path walk = Walk("go1", office, "--platform go1 --seed 11");
    const fs::path out = Out("anchor");
    ASSERT_EQ(Anchor(office / "reference", {walk / "session"}, out, "--inject-false-loops 0.3"), 0);
    ExpectTargets(out / "session", walk);
    // Each injected loop against the truth: those that are wrong by more than half a metre must
    // not be in the clique the accepted hypothesis grew from.
    const json loops = ReadJson(out / "loops.json");
    const auto reference = io::ReadKitti(office / "reference" / "optimized_poses.txt");
    const auto truth = io::ReadTum(walk / "capture" / "ground_truth.tum");
    const int chosen =
        ReadJson(out / "anchor.json")["sessions"][0]["hypotheses"][0]["clique_index"].get<int>();
    std::vector<int64_t> kf_stamps;
    {
        const std::string text = io::ReadFileToString(walk / "session" / "times.txt");
        size_t pos = 0;
        while (pos < text.size()) {
            const size_t end = text.find('\n', pos);
            const std::string line = text.substr(pos, end - pos);
            if (!line.empty()) kf_stamps.push_back(std::llround(std::stod(line) * 1e9));
            if (end == std::string::npos) break;
            pos = end + 1;
        }
    }
    auto truth_at = [&](int64_t stamp) {
        for (const auto& p : truth) {
            if (std::llabs(p.stamp_ns - stamp) < 1'000'000) return p.Pose();
        }
        ADD_FAILURE() << "no truth at " << stamp;
        return Eigen::Isometry3d::Identity();
    };
    size_t injected = 0, wrong = 0, wrong_in_accepted = 0;
    for (const json& l : loops) {
        if (l["source"] != "injected") continue;
        ++injected;
        const std::vector<double> c = l["T_target_query"].get<std::vector<double>>();
        const Eigen::Isometry3d T_ref_query = common::FromQuaternionTranslation(
            Eigen::Quaterniond(c[6], c[3], c[4], c[5]), Eigen::Vector3d(c[0], c[1], c[2]));
        const Eigen::Isometry3d placed =
            reference.at(l["target_index"].get<size_t>()) * T_ref_query;
        const Eigen::Isometry3d gt = truth_at(kf_stamps.at(l["query_index"].get<size_t>()));
        if ((placed.translation() - gt.translation()).norm() < 0.5) continue;  // right by chance
        ++wrong;
        if (l["hypothesis"].get<int>() == chosen) ++wrong_in_accepted;
        EXPECT_FALSE(l["accepted"].get<bool>());
    }
    EXPECT_GT(injected, 20u);
    EXPECT_GT(wrong, injected / 2);
    EXPECT_EQ(wrong_in_accepted, 0u);
}

// The other outlier methods (README.md, "Wrong loops: which method works"): graduated
// non-convexity holds against 30 % injected wrong loops and rejects some of them by their
// weight; the Cauchy loss alone anchors a walk without injected loops.
TEST_F(AnchorCli, OutlierMethodsGncAndNoneOnTheCommandLine) {
    const fs::path office = Office();
    const fs::path walk = Walk("go1", office, "--platform go1 --seed 11");
    const fs::path gnc = Out("gnc");
    ASSERT_EQ(Anchor(office / "reference", {walk / "session"}, gnc,
                     "--outliers gnc --inject-false-loops 0.3"),
              0);
    const json summary = ReadJson(gnc / "anchor.json");
    EXPECT_EQ(summary["config"]["outliers"], "gnc");
    EXPECT_EQ(summary["sessions"][0]["verdict"], "anchored");
    ExpectTargets(gnc / "session", walk);
    size_t rejected_by_weight = 0, injected_accepted = 0;
    for (const json& l : ReadJson(gnc / "loops.json")) {
        rejected_by_weight += l["reason"].get<std::string>().rfind("rejected by GNC", 0) == 0;
        injected_accepted += l["source"] == "injected" && l["accepted"].get<bool>();
    }
    EXPECT_GT(rejected_by_weight, 0u);
    EXPECT_EQ(injected_accepted, 0u);

    const fs::path none = Out("none");
    ASSERT_EQ(Anchor(office / "reference", {walk / "session"}, none, "--outliers none"), 0);
    EXPECT_EQ(ReadJson(none / "anchor.json")["config"]["outliers"], "none");
    ExpectTargets(none / "session", walk);
}

// --model-tolerance reaches the graph: the anchored poses move (every loop to the reference gets
// the model's covariance) and stay within the bounds; anchor.json records it.
TEST_F(AnchorCli, TheModelToleranceOnTheCommandLine) {
    const fs::path office = Office();
    const fs::path walk = Walk("go1", office, "--platform go1 --seed 11");
    const fs::path plain = Out("plain"), tolerant = Out("tolerant");
    ASSERT_EQ(Anchor(office / "reference", {walk / "session"}, plain), 0);
    ASSERT_EQ(Anchor(office / "reference", {walk / "session"}, tolerant, "--model-tolerance 0.02"),
              0);
    const json config = ReadJson(tolerant / "anchor.json")["config"];
    EXPECT_DOUBLE_EQ(config["model_tolerance_m"].get<double>(), 0.02);
    EXPECT_DOUBLE_EQ(ReadJson(plain / "anchor.json")["config"]["model_tolerance_m"].get<double>(),
                     0.0);
    ExpectTargets(tolerant / "session", walk);
    const auto a = io::ReadKitti(plain / "session" / "optimized_poses.txt");
    const auto b = io::ReadKitti(tolerant / "session" / "optimized_poses.txt");
    ASSERT_EQ(a.size(), b.size());
    double moved = 0;
    for (size_t k = 0; k < a.size(); ++k) {
        moved = std::max(moved, (a[k].translation() - b[k].translation()).norm());
    }
    std::cout << "--model-tolerance 0.02 moved the keyframes by up to " << 100 * moved << " cm\n";
    EXPECT_GT(moved, 1e-4) << "the tolerance changed nothing";
    const auto r =
        Cli("anchor --reference " + (office / "reference").string() + " --query " +
            (walk / "session").string() + " -o " + Out("bad").string() + " --model-tolerance -1");
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("model"), std::string::npos) << r.err;
}

TEST_F(AnchorCli, AMirrorSymmetricBuildingIsAmbiguousNotAnchored) {
    const fs::path building = Building("symmetric", "--layout symmetric");
    const fs::path walk = Walk("symmetric_walk", building, "--platform go1 --seed 13");
    const fs::path out = Out("anchor");
    EXPECT_EQ(Anchor(building / "reference", {walk / "session"}, out), 1);
    const json summary = ReadJson(out / "anchor.json");
    EXPECT_EQ(summary["sessions"][0]["verdict"], "ambiguous") << summary.dump(2);
    EXPECT_GE(summary["sessions"][0]["hypotheses"].size(), 2u);
    EXPECT_FALSE(fs::exists(out / "session"));  // nothing placed
}

TEST_F(AnchorCli, AGroundFloorWalkAgainstAFirstFloorReferenceIsNotAnchored) {
    // The storeys share the corridor and the outer walls; the partitions differ. Registration
    // alone fits most keyframes; free space contradicts the placement.
    const fs::path office = Office();
    const fs::path walk = Walk("go1", office, "--platform go1 --seed 11");
    const fs::path first = Fixture("office_first_floor", [&](const fs::path& d) {
        MustRun("bim2session " + (office / "building.ifc").string() +
                " --storey \"First Floor\" -o " + (d / "reference").string());
    });
    const fs::path out = Out("anchor");
    EXPECT_EQ(Anchor(first / "reference", {walk / "session"}, out), 1);
    // Failed: free space contradicts every placement registration found (each hypothesis's
    // keyframes see through the first floor's partitions), or the wrong storey's loops do not
    // even agree on one. With stop 59's odometry this walk had two hypotheses, refused by free
    // space (7.6 % of their rays through the model); with stop 60's its loops form no clique of 3
    // (the same loops, a few centimetres apart). The free-space rule itself:
    // anchoring_rules_test.cpp.
    const json s = ReadJson(out / "anchor.json")["sessions"][0];
    EXPECT_EQ(s["verdict"], "failed") << s.dump(2);
    const std::string reason = s["reason"];
    const bool by_free_space = reason.find("contradicted by free space") != std::string::npos;
    EXPECT_TRUE(by_free_space ||
                reason.find("no set of at least 3 mutually consistent loops") != std::string::npos)
        << reason;
    if (by_free_space) {
        EXPECT_FALSE(s["hypotheses"].empty()) << s.dump(2);
    }
    for (const json& h : s["hypotheses"]) {
        std::cout << "wrong storey: a hypothesis sees through "
                  << 100 * h["seen_through"].get<double>() << " % of its rays\n";
        EXPECT_TRUE(h["contradicted"].get<bool>()) << h.dump();
    }
}

// A hand-held walk that starts on the office's first floor, takes the stairs down and walks the
// ground floor (the office's two storeys share the corridor and the outer walls).
fs::path Upstairs(const fs::path& office) {
    return Fixture("upstairs", [&](const fs::path& d) {
        fs::create_directories(d);
        io::WriteFileAtomic(d / "upstairs.yaml",
                            "storey: all\nplatform: handheld\nseed: 21\npath:\n"
                            "  mode: waypoints\n"
                            "  waypoints: [[2.0, 7.2], [15.0, 7.2], [20.0, 7.2], [2.0, 7.2]]\n"
                            "  waypoint_storeys: [First Floor, First Floor, Ground Floor, "
                            "Ground Floor]\n");
        MustRun("simulate --model " + (office / "building.ifc").string() + " --scenario " +
                (d / "upstairs.yaml").string() + " -o " + (d / "capture").string());
        MustRun("odometry " + (d / "capture").string() + " -o " + (d / "session").string() +
                " --budget-ms 10000");
        fs::remove(d / "capture" / "lidar.pcap");
    });
}

// Anchored, not ambiguous, every keyframe on its true storey (issue 31: "a two-storey capture
// anchored with every keyframe on its storey", "a walk that starts on the upper storey ... is
// anchored").
TEST_F(AnchorCli, AWalkThatStartsUpstairsAndTakesTheStairsDownAnchorsOnBothStoreys) {
    const fs::path office = Office();
    const fs::path walk = Upstairs(office);
    const fs::path out = Out("anchor");
    ASSERT_EQ(Anchor(office / "reference", {walk / "session"}, out), 0);
    EXPECT_EQ(ReadJson(out / "anchor.json")["sessions"][0]["verdict"], "anchored");
    // Each keyframe's height against the truth's, and its storey: the floor under it (its height
    // less the sensor's height above the truth's floor) nearest to the truth's.
    const auto truth = io::ReadTum(walk / "capture" / "ground_truth.tum");
    std::map<int64_t, std::pair<std::string, double>> storey_at;  // stamp -> storey, floor z
    for (const test::StoreyTruthRow& r :
         test::ReadStoreyTruth(walk / "capture" / "ground_truth_storeys.csv")) {
        if (!r.on_flight) storey_at[r.stamp_ns] = {r.storey, r.floor_z_m};
    }
    size_t on_floor = 0, wrong_storey = 0, flights = 0;
    std::set<std::string> storeys;
    double max_dz = 0;
    for (const io::StampedPose& k : io::ReadTum(KeyframeTum(out / "session"))) {
        const auto t =
            std::lower_bound(truth.begin(), truth.end(), k.stamp_ns,
                             [](const io::StampedPose& p, int64_t s) { return p.stamp_ns < s; });
        ASSERT_NE(t, truth.end());
        max_dz = std::max(max_dz, std::abs(k.translation.z() - t->translation.z()));
        const auto s = storey_at.find(t->stamp_ns);
        if (s == storey_at.end()) {
            ++flights;
            continue;
        }
        ++on_floor;
        storeys.insert(s->second.first);
        const double floor = k.translation.z() - (t->translation.z() - s->second.second);
        if (std::abs(floor - s->second.second) > 1.6) ++wrong_storey;  // half the 3.2 m storey
    }
    std::cout << on_floor << " keyframes on floors, " << flights << " on the flight; max height "
              << "error " << 100 * max_dz << " cm\n";
    EXPECT_EQ(storeys.size(), 2u);
    EXPECT_GT(flights, 0u);
    EXPECT_EQ(wrong_storey, 0u);
    EXPECT_LT(max_dz, 0.08);  // the 8 cm max over keyframes
    const Accuracy k = Evaluate(KeyframeTum(out / "session"), walk);
    EXPECT_LT(k.rmse_cm, 3.0);
    EXPECT_LT(k.max_cm, 8.0);
}

// A walk on the first floor only, against a reference of the ground floor only: it fails alone
// (the reference has no first floor), and is anchored through a walk over both storeys that the
// ground floor anchors (README step 7, AnchoringProblem::RetryWithAnchored): its loops to the
// two-storey walk's first-floor keyframes place it. Both handheld walks are short (about 68 s and
// 25 s); the two-storey one goes up the stairs from the ground floor's corridor and back along
// the first floor's, and the first-floor walk walks that way too, from the head of the flight.
// (Until stop 76 it walked the corridor only, 8 m of it shared: a corridor that Scan Context
// cannot tell from its storey twin nor from itself a few metres on, the right target ranked 2nd
// to 9th of ten candidates, so 3 right loops of 27 held the test, and 2 with a better odometry:
// host_tools/anchor/README.md, "Limits".)
fs::path ScenarioWalk(const std::string& name, const fs::path& building, const std::string& yaml) {
    return Fixture(name, [&](const fs::path& d) {
        fs::create_directories(d);
        io::WriteFileAtomic(d / "walk.yaml", yaml);
        MustRun("simulate --model " + (building / "building.ifc").string() + " --scenario " +
                (d / "walk.yaml").string() + " -o " + (d / "capture").string());
        MustRun("odometry " + (d / "capture").string() + " -o " + (d / "session").string() +
                " --budget-ms 10000");
        fs::remove(d / "capture" / "lidar.pcap");
    });
}

TEST_F(AnchorCli, AFirstFloorWalkThatFailsAloneIsAnchoredThroughATwoStoreyWalk) {
    const fs::path office = Office();
    const fs::path ground = Fixture("office_ground_floor", [&](const fs::path& d) {
        MustRun("bim2session " + (office / "building.ifc").string() +
                " --storey \"Ground Floor\" -o " + (d / "reference").string());
    });
    const fs::path both = ScenarioWalk("two_storeys", office,
                                       "storey: all\nplatform: handheld\nseed: 31\npath:\n"
                                       "  mode: waypoints\n"
                                       "  waypoints: [[12.0, 7.2], [12.0, 7.2]]\n"
                                       "  waypoint_storeys: [Ground Floor, First Floor]\n");
    const fs::path upstairs =
        ScenarioWalk("first_floor_from_stairs", office,
                     "storey: First Floor\nplatform: handheld\nseed: 32\n"
                     "path:\n  mode: waypoints\n"
                     "  waypoints: [[28.3, 1.5], [28.5, 6.5], [14.0, 7.2]]\n");
    // Alone: not anchored.
    const fs::path alone = Out("alone");
    EXPECT_EQ(Anchor(ground / "reference", {upstairs / "session"}, alone), 1);
    const json a = ReadJson(alone / "anchor.json")["sessions"][0];
    EXPECT_EQ(a["verdict"], "failed") << a.dump(2);
    EXPECT_FALSE(a["via_other_sessions"].get<bool>());
    EXPECT_FALSE(fs::exists(alone / "session"));

    // With the two-storey walk: both anchored, the first-floor walk through the other session.
    fs::copy(both / "session", Out("both"), fs::copy_options::recursive);
    fs::copy(upstairs / "session", Out("upstairs"), fs::copy_options::recursive);
    const fs::path out = Out("anchor");
    const auto r =
        Cli("anchor --reference " + (ground / "reference").string() + " --query " +
            Out("both").string() + " --query " + Out("upstairs").string() + " -o " + out.string());
    std::cout << r.out << r.err;
    ASSERT_EQ(r.exit_code, 0);
    const json summary = ReadJson(out / "anchor.json");
    EXPECT_EQ(summary["verdict"], "anchored");
    const json& s0 = summary["sessions"][0];
    const json& s1 = summary["sessions"][1];
    EXPECT_EQ(s0["name"], "both");
    EXPECT_EQ(s0["verdict"], "anchored") << s0.dump(2);
    EXPECT_FALSE(s0["via_other_sessions"].get<bool>());
    EXPECT_EQ(s1["name"], "upstairs");
    EXPECT_EQ(s1["verdict"], "anchored") << s1.dump(2);
    EXPECT_TRUE(s1["via_other_sessions"].get<bool>());
    EXPECT_NE(r.out.find("(through other sessions)"), std::string::npos);
    // Loops from the first-floor walk to the two-storey walk, accepted.
    size_t to_both = 0;
    for (const json& l : ReadJson(out / "loops.json")) {
        to_both += l["accepted"].get<bool>() && l["query"] == "upstairs" && l["target"] == "both";
    }
    EXPECT_GT(to_both, 3u);
    // In BIM coordinates within centimetres. Measured (stop 76): keyframes 0.74 cm RMSE (max
    // 1.23 cm), 0.08 deg (max 0.15 deg); every scan 1.00 cm (max 2.21 cm), 0.08 deg (max 0.23
    // deg). The first floor is tied to the reference only by the two-storey walk's odometry up
    // the stairs; the corridor walk of before stop 76 was 2.06 cm. The bounds: the 3 cm
    // RMSE, and twice the rest as it was measured then.
    const Accuracy k = Evaluate(KeyframeTum(out / "upstairs"), upstairs);
    EXPECT_LT(k.rmse_cm, 3.0);
    EXPECT_LT(k.max_cm, 6.0);
    EXPECT_LT(k.rot_rmse_deg, 0.25);
    EXPECT_LT(k.rot_max_deg, 0.4);
    const Accuracy t = Evaluate(out / "upstairs" / "trajectory_bim.tum", upstairs);
    EXPECT_LT(t.rmse_cm, 3.0);
    EXPECT_LT(t.max_cm, 6.5);
    EXPECT_EQ(t.matched, io::ReadTum(upstairs / "session" / "trajectory.tum").size());
    Evaluate(KeyframeTum(out / "both"), both);  // printed for comparison (0.78 cm, max 1.6)
}

TEST_F(AnchorCli, TwoSessionsAnchorTogetherWithLoopsBetweenThem) {
    const fs::path office = Office();
    const fs::path go1 = Walk("go1", office, "--platform go1 --seed 11");
    const fs::path handheld = Walk("handheld", office, "--platform handheld --seed 12");
    fs::copy(go1 / "session", Out("go1"), fs::copy_options::recursive);
    fs::copy(handheld / "session", Out("handheld"), fs::copy_options::recursive);
    const fs::path out = Out("anchor");
    ASSERT_EQ(Anchor(office / "reference", {Out("go1"), Out("handheld")}, out), 0);
    ExpectTargets(out / "go1", go1);
    ExpectTargets(out / "handheld", handheld);
    size_t between = 0;
    for (const json& l : ReadJson(out / "loops.json")) {
        between += l["accepted"].get<bool>() && l["target"] != "reference";
    }
    EXPECT_GT(between, 5u);
}

TEST_F(AnchorCli, ASessionInTheScALoamLayoutIsReadAndAnchored) {
    const fs::path office = Office();
    const fs::path walk = Walk("go1", office, "--platform go1 --seed 11");
    const fs::path foreign = Out("foreign");
    fs::create_directories(foreign);
    fs::copy(walk / "session" / "Scans", foreign / "Scans", fs::copy_options::recursive);
    for (const char* f : {"optimized_poses.txt", "odom_poses.txt", "times.txt"}) {
        fs::copy(walk / "session" / f, foreign / f);
    }
    const auto info = Cli("session info " + foreign.string());
    EXPECT_EQ(info.exit_code, 0);
    EXPECT_NE(info.out.find("SC-A-LOAM/LT-mapper layout"), std::string::npos) << info.out;
    const fs::path out = Out("anchor");
    ASSERT_EQ(Anchor(office / "reference", {foreign}, out), 0);
    const json notes = ReadJson(out / "anchor.json")["sessions"][0]["notes"];
    EXPECT_NE(notes.dump().find("derived from the poses"), std::string::npos) << notes.dump();
    EXPECT_NE(notes.dump().find("descriptors computed"), std::string::npos) << notes.dump();
    // Keyframes only (no trajectory.tum there): still on the truth.
    ExpectTargets(out / "foreign", walk);
}

TEST_F(AnchorCli, DamagedOrMissingSessionsExit2NamingTheFile) {
    const fs::path office = Office();
    const fs::path walk = Walk("go1", office, "--platform go1 --seed 11");
    std::string err;
    // A missing reference.
    EXPECT_EQ(Anchor(Out("nowhere"), {walk / "session"}, Out("a1"), "", &err), 2);
    EXPECT_NE(err.find("nowhere"), std::string::npos) << err;
    // A keyframe cloud cut off.
    fs::copy(walk / "session", Out("cut"), fs::copy_options::recursive);
    const fs::path pcd = Out("cut") / "Scans" / "000003.pcd";
    fs::resize_file(pcd, fs::file_size(pcd) / 2);
    EXPECT_EQ(Anchor(office / "reference", {Out("cut")}, Out("a2"), "", &err), 2);
    EXPECT_NE(err.find("000003.pcd"), std::string::npos) << err;
    // A pose file with garbage in it.
    fs::copy(walk / "session", Out("garbage"), fs::copy_options::recursive);
    test::WriteBytes(Out("garbage") / "optimized_poses.txt", "1 0 0 x\n");
    EXPECT_EQ(Anchor(office / "reference", {Out("garbage")}, Out("a3"), "", &err), 2);
    EXPECT_NE(err.find("optimized_poses.txt"), std::string::npos) << err;
    // An output folder in the way.
    fs::create_directories(Out("taken"));
    test::WriteBytes(Out("taken") / "x", "x");
    EXPECT_EQ(Anchor(office / "reference", {walk / "session"}, Out("taken"), "", &err), 2);
    EXPECT_NE(err.find("--overwrite"), std::string::npos) << err;
}

// A session whose odometry failed in the middle of the walk (issue 32, item 3; issue 31, item 5):
// the Go1 walk's session with its odometry_verdict.json turned untrusted over the scans around
// its middle keyframe, as `bimslam odometry` writes it when scans fail their checks (a simulated
// 10 Hz walk does not fail; odometry_large_motion_test.cpp makes real failures). The session is
// split there: each piece is anchored on its own, the keyframe inside the stretch is not placed,
// the verdict is anchored-in-parts (never anchored) and the exit code 1.
TEST_F(AnchorCli, ASessionWhoseOdometryFailedMidwayIsAnchoredInPartsNeverAnchored) {
    const fs::path office = Office();
    const fs::path walk = Walk("go1", office, "--platform go1 --seed 11");
    // `bimslam odometry` wrote its verdict into the session.
    EXPECT_EQ(ReadJson(walk / "session" / "odometry_verdict.json").at("verdict"), "trusted");
    const fs::path session = Out("walk");
    fs::copy(walk / "session", session, fs::copy_options::recursive);
    const std::vector<int64_t> times = io::ReadTimes(session / "times.txt");
    const size_t n = times.size(), middle = n / 2;
    ASSERT_GT(n, 12u);
    json verdict = ReadJson(session / "odometry_verdict.json");
    const int64_t first = times[middle] - 50'000'000, last = times[middle] + 50'000'000;
    ASSERT_LT(times[middle - 1], first);
    ASSERT_GT(times[middle + 1], last);
    verdict["verdict"] = "untrusted";
    verdict["failed_stretches"] = json::array({{{"first_scan", 200},
                                                {"last_scan", 210},
                                                {"first_s", 20.0},
                                                {"last_s", 21.0},
                                                {"first_stamp_ns", first},
                                                {"last_stamp_ns", last},
                                                {"failed", 3},
                                                {"reasons", {"low overlap with the map"}}}});
    io::WriteFileAtomic(session / "odometry_verdict.json", verdict.dump());

    const fs::path out = Out("anchor");
    const auto r = Cli("anchor --reference " + (office / "reference").string() + " --query " +
                       session.string() + " -o " + out.string());
    std::cout << r.out << r.err;
    EXPECT_EQ(r.exit_code, 1) << "a session anchored in parts is not a good result";
    const json a = ReadJson(out / "anchor.json");
    EXPECT_EQ(a.at("verdict"), "anchored-in-parts");
    const json& s = a.at("sessions").at(0);
    EXPECT_EQ(s.at("verdict"), "anchored-in-parts");
    EXPECT_EQ(s.at("odometry_verdict"), "untrusted");
    EXPECT_FALSE(s.contains("T_world_local")) << "no one anchor for the whole session";
    ASSERT_EQ(s.at("failed_stretches").size(), 1u);
    EXPECT_EQ(s.at("failed_stretches")[0].at("text"),
              "scans 200-210 (20.0-21.0 s: low overlap with the map)");
    EXPECT_EQ(s.at("keyframes_inside_stretches"), json::array({middle}));
    const json& pieces = s.at("pieces");
    ASSERT_EQ(pieces.size(), 2u);
    EXPECT_EQ(pieces[0].at("first_keyframe"), 0);
    EXPECT_EQ(pieces[0].at("last_keyframe"), middle - 1);
    EXPECT_EQ(pieces[1].at("first_keyframe"), middle + 1);
    EXPECT_EQ(pieces[1].at("last_keyframe"), n - 1);
    for (const json& p : pieces) {  // each half of the walk sees enough of the building
        EXPECT_EQ(p.at("verdict"), "anchored") << p.dump(1);
        EXPECT_TRUE(p.contains("T_world_local"));
    }
    EXPECT_EQ(s.at("placed_keyframes"), n - 1);
    const std::string reason = s.at("reason");
    EXPECT_NE(reason.find("the odometry is untrusted"), std::string::npos) << reason;
    EXPECT_NE(reason.find("scans 200-210"), std::string::npos) << reason;
    // Printed: the verdict, each piece, the keyframe not placed.
    EXPECT_NE(r.out.find("  anchored-in-parts: the odometry is untrusted"), std::string::npos);
    EXPECT_NE(r.out.find("  piece 0-" + std::to_string(middle - 1) + ": anchored"),
              std::string::npos);
    EXPECT_NE(r.out.find("  not placed: 1 keyframes inside the odometry's failed stretches (" +
                         std::to_string(middle) + ")"),
              std::string::npos);

    // The anchored pieces' keyframes and scans in BIM coordinates, as precise as the whole walk;
    // no scan of the failed stretch.
    EXPECT_EQ(io::ReadKitti(out / "walk" / "optimized_poses.txt").size(), n - 1);
    const auto scans = io::ReadTum(out / "walk" / "trajectory_bim.tum");
    EXPECT_GT(scans.size(), io::ReadTum(session / "trajectory.tum").size() / 2);
    for (const io::StampedPose& p : scans) {
        EXPECT_FALSE(p.stamp_ns >= first && p.stamp_ns <= last) << p.stamp_ns;
    }
    ExpectTargets(out / "walk", walk);
}

// The relocaliser the rig will run live (algorithms/localization/relocalizer.hpp), fed a walk's
// keyframes one by one by `bimslam localize` against the building's map package (`bimslam
// rig-map` of its reference): localization.json's summary.
json Localize(const fs::path& building, const fs::path& walk, const fs::path& out,
              const std::string& flags = "") {
    fs::create_directories(out);
    const fs::path package = out / "building.rigmap";
    MustRun("rig-map " + (building / "building.ifc").string() + " --reference " +
            (building / "reference").string() + " -o " + package.string());
    const auto r = Cli("localize " + (walk / "session").string() + " --map " + package.string() +
                       " -o " + out.string() + " --truth " +
                       (walk / "capture" / "ground_truth.tum").string() + " " + flags);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    std::cout << r.out;
    return ReadJson(out / "localization.json");
}

// Localised within the time (30 s at most from the start or, for the walk from outside,
// from entering the building: its west wall, x = 0) and followed within its accuracy (5 cm
// RMSE, 0.5 deg) with no alignment, also with a false loop added in about 3 of 10 keyframes
// while searching (issue 35: "0 localised more than 1 m or 5 deg off"). Measured: the Go1 walk
// 6.9 s, 0.70 cm RMSE, max 1.24 cm, 0.20 deg; from outside 8-18 s after entering (two fixtures),
// 0.72 cm, max 1.49 cm; a person from outside 16 s after entering, 0.75 cm, max 2.22 cm (40 s
// while three contradicted cliques could keep the right one from guiding registrations).
TEST_F(AnchorCli, LiveTheRelocaliserLocalisesAGo1WalkAndAWalkFromOutsideAndFollowsThem) {
    const fs::path office = Office();
    const fs::path entrances = OfficeWithEntrances();
    // A person from the same start (the scenario is the Go1's).
    const fs::path carried = Fixture("outdoor_handheld_scenario", [](const fs::path& d) {
        std::string text = io::ReadFileToString(kScenarios + "/outdoor_start.yaml");
        const size_t at = text.find("platform: go1");
        ASSERT_NE(at, std::string::npos);
        text.replace(at, 13, "platform: handheld");
        io::WriteFileAtomic(d / "scenario.yaml", text);
    });
    const fs::path walks[][2] = {
        {office, Walk("go1", office, "--platform go1 --seed 11")},
        {entrances, WalkFromOutside("outdoor", 80)},
        {entrances, Walk("outdoor_handheld", entrances,
                         "--scenario " + (carried / "scenario.yaml").string() + " --seed 1", 60)},
    };
    for (const auto& [building, walk] : walks) {
        const auto truth = io::ReadTum(walk / "capture" / "ground_truth.tum");
        const auto inside = std::find_if(truth.begin(), truth.end(), [](const io::StampedPose& p) {
            return p.translation.x() >= 0;
        });
        ASSERT_NE(inside, truth.end());
        const double entered_s = double(inside->stamp_ns - truth.front().stamp_ns) * 1e-9;
        for (const std::string flags : {"", "--inject-false-loops 0.3 --seed 4"}) {
            SCOPED_TRACE(walk.filename().string() + " " + flags);
            const fs::path out = Out(walk.filename().string() + std::to_string(flags.size()));
            const json s = Localize(building, walk, out, flags)["summary"];
            EXPECT_EQ(s["final_state"], "localised");
            ASSERT_TRUE(s["time_to_localised_s"].is_number()) << s.dump(1);
            std::cout << "localised " << s["time_to_localised_s"].get<double>() - entered_s
                      << " s after entering the building\n";
            EXPECT_LE(s["time_to_localised_s"].get<double>() - entered_s, 30.0);
            EXPECT_LT(s["truth"]["ape_rmse_m"].get<double>(), 0.02);
            EXPECT_LT(s["truth"]["ape_max_m"].get<double>(), 0.04);
            EXPECT_LT(s["truth"]["rot_max_deg"].get<double>(), 0.5);
            EXPECT_GT(s["truth"]["matched"].get<size_t>(), 200u);
        }
    }
}

// Carried between storeys: localised once the walk has told the storeys apart, and from then on
// every keyframe on a floor on its true storey. Measured: 14.8 s, 1.02 cm RMSE, max 4.55 cm.
TEST_F(AnchorCli, LiveTheRelocaliserKeepsAWalkFromUpstairsOnItsTrueStoreys) {
    const fs::path office = Office();
    const fs::path walk = Upstairs(office);
    const json j = Localize(office, walk, Out("live"));
    const json& s = j["summary"];
    EXPECT_EQ(s["final_state"], "localised");
    EXPECT_LT(s["truth"]["ape_rmse_m"].get<double>(), 0.03);
    EXPECT_LT(s["truth"]["ape_max_m"].get<double>(), 0.08);
    std::map<int64_t, std::string> storey_at;  // stamp -> storey, on floors
    for (const test::StoreyTruthRow& r :
         test::ReadStoreyTruth(walk / "capture" / "ground_truth_storeys.csv")) {
        if (!r.on_flight) storey_at[r.stamp_ns] = r.storey;
    }
    std::set<std::string> seen;
    size_t checked = 0;
    for (const json& k : j["keyframes"]) {
        if (k["state"] != "localised") continue;
        const auto t = storey_at.find(std::llround(k["t_s"].get<double>() * 1e9));
        if (t == storey_at.end()) continue;  // on the flight, or between truth stamps
        ++checked;
        seen.insert(t->second);
        EXPECT_EQ(k["storey"], t->second) << k.dump();
    }
    EXPECT_GT(checked, 20u);
    EXPECT_EQ(seen.size(), 2u);
}

// On a flight the stairwell hides floor and ceiling and the odometry's height drifts faster
// than on a floor (issue 31: 50 cm over the held-out Office_A's first Go1 climb). The upstairs
// walk with its odometry's every height change overstated by 40 % (16 cm a keyframe on the
// office's stair, 1.3 m low at its foot): the tracking takes the registrations that put the
// height right, and the rig stays localised. Measured: 5.2 cm RMSE, max 23 cm (between fixes on
// the flight), never unlocalised; with the distance's bound in height too, the hypothesis was
// dropped on the flight, searched for again, and 61 cm RMSE.
TEST_F(AnchorCli, LiveTheRelocaliserFollowsAnOdometryWhoseHeightDriftsOnTheStair) {
    const fs::path office = Office();
    const fs::path walk = Upstairs(office);
    const fs::path drifted = Out("drifted");
    fs::create_directories(drifted);
    fs::copy(walk / "session", drifted / "session", fs::copy_options::recursive);
    fs::create_directories(drifted / "capture");
    fs::copy(walk / "capture" / "ground_truth.tum", drifted / "capture" / "ground_truth.tum");
    auto keyframes = io::ReadKitti(walk / "session" / "optimized_poses.txt");
    auto scans = io::ReadTum(walk / "session" / "trajectory.tum");
    ASSERT_FALSE(keyframes.empty());
    const double z0 = keyframes.front().translation().z();
    for (Eigen::Isometry3d& T : keyframes) T.translation().z() += 0.4 * (T.translation().z() - z0);
    for (io::StampedPose& p : scans) p.translation.z() += 0.4 * (p.translation.z() - z0);
    io::WriteKitti(drifted / "session" / "optimized_poses.txt", keyframes);
    io::WriteTum(drifted / "session" / "trajectory.tum", scans);

    const json j = Localize(office, drifted, Out("live"));
    const json& s = j["summary"];
    EXPECT_EQ(s["final_state"], "localised");
    size_t after = 0;  // keyframes from the first localised one on that are not localised
    bool localised = false;
    for (const json& k : j["keyframes"]) {
        localised = localised || k["state"] == "localised";
        after += localised && k["state"] != "localised";
    }
    EXPECT_TRUE(localised);
    EXPECT_EQ(after, 0u) << s["state_changes"].dump(1);
    EXPECT_LT(s["truth"]["ape_rmse_m"].get<double>(), 0.10);
}

// The upstairs walk with its odometry's height 1 m low from the foot of the stair on, as the
// held-out Office_A's Go1 climb ended when a scan saw the height again while it was 30 cm
// uncertain and a registration took the nearest tread (algorithms/odometry/README.md). With the
// odometry's flag in odometry_verdict.json (height_ambiguous_stretches, as `bimslam odometry`
// writes it), the relocaliser tracks from the coarse level and takes a registration that
// measured the height within the climb; without it, the height's bound (0.5 m) refuses them.
// Measured: with the flag, 0 s off by over 0.5 m, 0.98 cm RMSE (max 4.4 cm); without it, 1 m
// off for the walk's last 40.4 s, never dropped, 64.8 cm RMSE.
TEST_F(AnchorCli, LiveTheRelocaliserCorrectsAHeightTheOdometryFlaggedAmbiguous) {
    const fs::path office = Office();
    const fs::path walk = Upstairs(office);
    int64_t foot_ns = -1;  // the first stamp on the ground floor after the flight
    bool flight = false;
    for (const test::StoreyTruthRow& r :
         test::ReadStoreyTruth(walk / "capture" / "ground_truth_storeys.csv")) {
        flight = flight || r.on_flight;
        if (flight && !r.on_flight) {
            foot_ns = r.stamp_ns;
            break;
        }
    }
    ASSERT_GT(foot_ns, 0);
    const auto times = io::ReadTimes(walk / "session" / "times.txt");
    auto keyframes = io::ReadKitti(walk / "session" / "optimized_poses.txt");
    auto scans = io::ReadTum(walk / "session" / "trajectory.tum");
    ASSERT_EQ(times.size(), keyframes.size());
    for (size_t k = 0; k < keyframes.size(); ++k)
        if (times[k] >= foot_ns) keyframes[k].translation().z() -= 1.0;
    size_t flagged = scans.size();
    for (size_t i = 0; i < scans.size(); ++i) {
        if (scans[i].stamp_ns < foot_ns) continue;
        scans[i].translation.z() -= 1.0;
        flagged = std::min(flagged, i);
    }
    ASSERT_LT(flagged, scans.size());
    const int64_t t_ns = scans[flagged].stamp_ns;
    const double t_s = double(t_ns - scans.front().stamp_ns) * 1e-9;
    const json stretch = {{"first_scan", flagged},  {"last_scan", flagged},
                          {"first_s", t_s},         {"last_s", t_s},
                          {"first_stamp_ns", t_ns}, {"last_stamp_ns", t_ns}};
    double off_s[2] = {0, 0}, rmse[2] = {0, 0};
    for (const bool flag : {false, true}) {
        const fs::path low = Out(flag ? "low_flagged" : "low");
        fs::create_directories(low / "capture");
        fs::copy(walk / "session", low / "session", fs::copy_options::recursive);
        fs::copy(walk / "capture" / "ground_truth.tum", low / "capture" / "ground_truth.tum");
        io::WriteKitti(low / "session" / "optimized_poses.txt", keyframes);
        io::WriteTum(low / "session" / "trajectory.tum", scans);
        io::WriteFileAtomic(
            low / "session" / "odometry_verdict.json",
            json{{"format", "bimslam-odometry-verdict"},
                 {"verdict", "trusted"},
                 {"failed_stretches", json::array()},
                 {"height_ambiguous_stretches", flag ? json::array({stretch}) : json::array()}}
                .dump());
        const json j = Localize(office, low, Out(flag ? "live_flagged" : "live"));
        EXPECT_EQ(j["summary"]["odometry_height_ambiguous_keyframes"], flag ? 1 : 0);
        rmse[flag] = j["summary"]["truth"]["ape_rmse_m"].get<double>();
        // Seconds of live poses over 0.5 m off the truth after the foot of the stair.
        const auto truth = io::ReadTum(walk / "capture" / "ground_truth.tum");
        std::map<int64_t, Eigen::Vector3d> at;
        for (const io::StampedPose& p : truth) at[p.stamp_ns] = p.translation;
        int64_t last_ns = -1;
        size_t matched = 0;
        for (const io::StampedPose& p :
             io::ReadTum(Out(flag ? "live_flagged" : "live") / "trajectory_bim_live.tum")) {
            const auto t = at.find(p.stamp_ns);
            if (p.stamp_ns < foot_ns || t == at.end()) continue;
            ++matched;
            if ((p.translation - t->second).norm() > 0.5 && last_ns >= 0)
                off_s[flag] += double(p.stamp_ns - last_ns) * 1e-9;
            last_ns = p.stamp_ns;
        }
        EXPECT_GT(matched, 50u) << "live poses on the ground floor matched to the truth";
        if (flag) {
            EXPECT_EQ(j["summary"]["final_state"], "localised");
            EXPECT_LT(rmse[flag], 0.05);
        }
    }
    std::cout << "over 0.5 m off: " << off_s[1] << " s with the flag, " << off_s[0]
              << " s without; RMSE " << rmse[1] * 100 << " / " << rmse[0] * 100 << " cm\n";
    EXPECT_LT(off_s[1], 3.0);
    EXPECT_LT(rmse[1], rmse[0]);
}

// The mirror-symmetric building: ambiguous with both placements, never localised, with or
// without false loops.
TEST_F(AnchorCli, LiveTheRelocaliserNeverLocalisesInAMirrorSymmetricBuilding) {
    const fs::path building = Building("symmetric", "--layout symmetric");
    const fs::path walk = Walk("symmetric_walk", building, "--platform go1 --seed 13");
    for (const std::string flags : {"", "--inject-false-loops 0.3 --seed 4"}) {
        const json j = Localize(building, walk, Out("live" + std::to_string(flags.size())), flags);
        EXPECT_EQ(j["summary"]["final_state"], "ambiguous") << flags;
        EXPECT_FALSE(j["summary"]["states"].contains("localised")) << j["summary"].dump(1);
        size_t two = 0;
        for (const json& k : j["keyframes"]) two += k["hypotheses"].get<size_t>() >= 2;
        EXPECT_GT(two, 20u) << flags;
    }
}

// The same walk told where it starts (the truth's first position, as its operator would say:
// localization.near on the rig): the twin placement is set aside and the rig localises, its live
// poses within centimetres. Told a start in the other half, it never localises on this one.
TEST_F(AnchorCli, LiveAHintOfWhereTheWalkStartsLocalisesInAMirrorSymmetricBuilding) {
    const fs::path building = Building("symmetric", "--layout symmetric");
    const fs::path walk = Walk("symmetric_walk", building, "--platform go1 --seed 13");
    const auto truth = io::ReadTum(walk / "capture" / "ground_truth.tum");
    ASSERT_FALSE(truth.empty());
    const Eigen::Vector3d start = truth.front().translation;
    const auto near = [&](double dx) {
        return "--near " + std::to_string(start.x() + dx) + " " + std::to_string(start.y() + 1.0);
    };
    const json told = Localize(building, walk, Out("live_near"), near(0.0))["summary"];
    EXPECT_EQ(told["final_state"], "localised") << told.dump(1);
    EXPECT_FALSE(told["states"].contains("ambiguous")) << told.dump(1);
    EXPECT_EQ(told["near"].size(), 3u);
    ASSERT_TRUE(told["truth"].is_object()) << told.dump(1);
    EXPECT_LT(told["truth"]["ape_rmse_m"].get<double>(), 0.05);
    EXPECT_LT(told["truth"]["rot_max_deg"].get<double>(), 1.0);
    // A start 100 m away (in no hypothesis's reach): nothing stands.
    const json wrong = Localize(building, walk, Out("live_far"), near(100.0))["summary"];
    EXPECT_FALSE(wrong["states"].contains("localised")) << wrong.dump(1);
    EXPECT_NE(Cli("localize x --map y -o z --near 1").exit_code, 0);
}

// A session made before the z_stack cell rule names none in session.json: its descriptors are
// z_span's, which the reference's are not. Its stored descriptors zeroed here (on them neither
// could place anything), the anchoring and the relocaliser compute them again from the clouds:
// anchored within centimetres, saying so, and localised.
TEST_F(AnchorCli, ASessionOfTheOlderCellRuleHasItsDescriptorsComputedAgain) {
    const fs::path office = Office();
    const fs::path walk = Walk("handheld", office, "--platform handheld --seed 12");
    const fs::path older = Out("older");
    fs::create_directories(older / "capture");
    fs::copy(walk / "session", older / "session", fs::copy_options::recursive);
    fs::copy(walk / "capture" / "ground_truth.tum", older / "capture" / "ground_truth.tum");
    json manifest = ReadJson(older / "session" / "session.json");
    ASSERT_EQ(manifest["descriptor"]["cell_rule"]["rule"], "z_stack");
    manifest["descriptor"]["cell_rule"].erase("rule");
    io::WriteFileAtomic(older / "session" / "session.json", manifest.dump(2));
    size_t zeroed = 0;
    for (const auto& e : fs::directory_iterator(older / "session" / "SCDs")) {
        const io::DescriptorMatrix d = io::ReadScd(e.path());
        io::WriteScd(e.path(), io::DescriptorMatrix::Zero(d.rows(), d.cols()));
        ++zeroed;
    }
    ASSERT_GT(zeroed, 10u);

    const fs::path out = Out("anchor_older");
    ASSERT_EQ(Anchor(office / "reference", {older / "session"}, out), 0);
    const json session = ReadJson(out / "anchor.json")["sessions"][0];
    EXPECT_EQ(session["verdict"], "anchored");
    const std::string notes = session["notes"].dump();
    EXPECT_NE(notes.find("descriptors recomputed: the session's (indoor, z_span)"),
              std::string::npos)
        << notes;
    ExpectTargets(out / "session", walk);

    const json live = Localize(office, older, Out("live_older"))["summary"];
    EXPECT_EQ(live["final_state"], "localised") << live.dump(1);
    EXPECT_LT(live["truth"]["ape_rmse_m"].get<double>(), 0.05);
}

TEST_F(AnchorCli, HelpNamesTheOutputs) {
    const auto r = Cli("anchor --help");
    EXPECT_EQ(r.exit_code, 0);
    for (const char* word :
         {"--reference", "--query", "--outliers", "loops.json", "anchor.json", "trajectory_bim.tum",
          "posegraph.g2o", "ambiguous", "anchored-in-parts", "odometry_verdict.json"}) {
        EXPECT_NE(r.out.find(word), std::string::npos) << word;
    }
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam
