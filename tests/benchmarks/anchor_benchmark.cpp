// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Multi-session anchoring measured against the simulator's ground truth (which is in BIM
// coordinates, so no alignment: evaluation Alignment::kNone), as `bimslam anchor` runs it: the
// BIM reference session, a simulated capture, the on-board odometry into a session, anchoring.
// A harness that prints tables (the figures of host_tools/anchor/README.md), not timed
// assertions. Suites, chosen on the command line (default: accuracy robustness speed):
//
//   accuracy    the sample office and the hall (a building not tuned on), Go1 and handheld,
//               furniture, people, clutter and a removed class, three seeds each, 120 s: APE of
//               the keyframes and of every scan; Scan Context candidate recall and precision;
//               the spread.
//   accuracy-asbuilt  the same with every wall built N(0, 2 cm) off its modelled place: what the
//               model's own error does to a placement that can only be as right as the model.
//   success     20 captures, 60 s, of changed buildings with different seeds and starts, half of
//               them outside (through an entrance): how many anchor within 10 cm RMSE, how many
//               are reported anchored wrongly (the issue: at least 19, and none).
//   robustness  30 % of the verified loops replaced by wrong pairs that registered, with each
//               outlier method (pcm, gnc, none): accuracy and verdict.
//   speed       about 1000 query keyframes against about 1000 reference keyframes: the time of
//               each stage (BIMSLAM_ANCHOR_SPEED_DATA=DIR keeps its sessions in DIR for the
//               next run).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "algorithms/common/stopwatch.hpp"
#include "algorithms/io/session.hpp"
#include "algorithms/io/sha256.hpp"
#include "algorithms/io/trajectory.hpp"
#include "host_tools/anchor/anchor_output.hpp"
#include "host_tools/anchor/anchoring.hpp"
#include "host_tools/bim/ifc_model.hpp"
#include "host_tools/bim/reference_session.hpp"
#include "host_tools/bim/sample_building.hpp"
#include "host_tools/evaluation/trajectory_metrics.hpp"
#include "host_tools/replay/capture_odometry.hpp"
#include "host_tools/simulate/simulate.hpp"
#include "tests/benchmarks/anchor_benchmark_support.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam {
namespace {
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using bench::Accuracy;
using bench::Ape;
using bench::Building;
using bench::MakeBuilding;
using bench::Spread;

// Changes every building can take without knowing its GlobalIds: clutter, people crossing the
// storey, every column removed, and with as_built every wall built off by N(0, 2 cm).
void ChangeBuilding(simulate::Scenario* s, const Building& b, uint64_t seed, bool as_built) {
    s->edits.clutter.density_per_m2 = 0.04;
    s->edits.as_built.wall_offset_sigma_m = as_built ? 0.02 : 0.0;
    s->edits.removed.classes = {"IfcColumn"};
    const Eigen::AlignedBox3d box = [&] {
        Eigen::AlignedBox3d a;
        for (const auto& v : b.model.mesh.vertices) a.extend(v.cast<double>());
        return a;
    }();
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> ux(box.min().x() + 2, box.max().x() - 2);
    std::uniform_real_distribution<double> uy(box.min().y() + 2, box.max().y() - 2);
    for (int k = 0; k < 2; ++k) {
        simulate::PersonSpec p;
        p.from = {ux(rng), uy(rng)};
        p.to = {ux(rng), uy(rng)};
        s->edits.people.push_back(p);
    }
}

struct Outcome {
    std::string verdict;
    Accuracy keyframes, scans;
    size_t query_keyframes = 0, candidates = 0, correct_candidates = 0, recalled = 0;
    size_t verified = 0, correct_verified = 0;
    // Of the verified place-recognition loops, right and wrong: seen-through and inlier ratios.
    std::vector<double> seen_right, seen_wrong, inlier_right, inlier_wrong;
    anchor::StageTimes times;
};

// Truth at each keyframe (the capture's ground truth is stamped at every frame's start).
std::vector<Eigen::Isometry3d> TruthAtKeyframes(const anchor::AnchorSession& q,
                                                const std::vector<io::StampedPose>& truth) {
    std::map<int64_t, Eigen::Isometry3d> by_stamp;
    for (const auto& p : truth) by_stamp[p.stamp_ns] = p.Pose();
    std::vector<Eigen::Isometry3d> out;
    for (const auto& kf : q.session.keyframes) {
        auto it = by_stamp.lower_bound(kf.stamp_ns - 1'000'000);
        out.push_back(it == by_stamp.end() ? Eigen::Isometry3d::Identity() : it->second);
    }
    return out;
}

// Simulates, runs the odometry, anchors; scores against the truth.
Outcome RunOne(const fs::path& tmp_dir, const Building& b, simulate::Scenario s,
               const anchor::AnchorConfig& config, const anchor::LoadOptions& load) {
    // BIMSLAM_ANCHOR_KEEP=DIR: the last run's capture, session and truth stay in DIR.
    const char* keep = std::getenv("BIMSLAM_ANCHOR_KEEP");
    const fs::path dir = keep ? fs::path(keep) : tmp_dir;
    // BIMSLAM_ANCHOR_CAUCHY: the finest registration level's Cauchy scale (experiments).
    anchor::AnchorConfig c = config;
    if (const char* e = std::getenv("BIMSLAM_ANCHOR_CAUCHY")) {
        c.registration.levels.back().cauchy_scale = std::atof(e);
    }
    fs::remove_all(dir);
    s.model = b.ifc;
    simulate::SimulateCapture(s, b.model, "", dir / "capture");
    replay::CaptureOdometryOptions oo;
    oo.capture_dir = dir / "capture";
    oo.session_dir = dir / "session";
    replay::RunCaptureOdometry(oo);
    if (!keep) fs::remove(dir / "capture" / "lidar.pcap");

    const auto t0 = Clock::now();
    std::vector<anchor::AnchorSession> sessions;
    sessions.push_back(anchor::LoadAnchorSession(b.reference, load));
    sessions.push_back(anchor::LoadAnchorSession(dir / "session", load));
    const double load_s = common::SecondsSince(t0);
    const anchor::AnchorResult r = anchor::Anchor(sessions, c);
    Outcome o;
    o.times = r.times;
    o.times.descriptors_s = load_s;
    const anchor::SessionResult& res = r.sessions[0];
    o.verdict = std::string(anchor::ToString(res.verdict));
    const auto truth = io::ReadTum(dir / "capture" / "ground_truth.tum");
    const anchor::AnchorSession& q = sessions[1];
    const std::vector<Eigen::Isometry3d> gt = TruthAtKeyframes(q, truth);
    o.query_keyframes = q.keyframes();
    if (res.verdict == anchor::Verdict::kAnchored) {
        std::vector<io::StampedPose> kfs;
        for (size_t k = 0; k < q.keyframes(); ++k) {
            kfs.push_back(
                io::StampedPose::FromIsometry(q.session.keyframes[k].stamp_ns, res.world_poses[k]));
        }
        o.keyframes = Ape(kfs, truth);
        o.scans = Ape(anchor::WorldTrajectory(q, res.world_poses), truth);
    }
    // Place recognition against the truth: a candidate is right when its reference keyframe is
    // within 2 m of where the query keyframe truly was (same storey); a verified loop when its
    // registration put the keyframe within 0.3 m of the truth.
    std::vector<char> recalled(q.keyframes(), 0);
    for (const anchor::LoopRecord& l : r.loops) {
        if (l.source != anchor::LoopSource::kScanContext) continue;
        const Eigen::Vector3d d =
            b.reference_poses[l.target_index].translation() - gt[l.query_index].translation();
        const bool right = d.head<2>().norm() < 2.0 && std::abs(d.z()) < 1.5;
        ++o.candidates;
        o.correct_candidates += right;
        if (right) recalled[l.query_index] = 1;
        if (l.verified) {
            ++o.verified;
            o.correct_verified +=
                (l.registration.T_target_source.translation() - gt[l.query_index].translation())
                    .norm() < 0.3;
        }
    }
    o.recalled = size_t(std::count(recalled.begin(), recalled.end(), 1));
    return o;
}

void PrintRow(const std::string& name, const Outcome& o) {
    std::printf(
        "%-30s %-9s kf %5.2f/%5.2f cm %5.3f/%5.3f deg | scans %5.2f/%6.2f cm | SC recall %3.0f%% "
        "precision %3.0f%% verified-precision %3.0f%% | %5.1f s\n",
        name.c_str(), o.verdict.c_str(), o.keyframes.rmse_cm, o.keyframes.max_cm,
        o.keyframes.rot_rmse_deg, o.keyframes.rot_max_deg, o.scans.rmse_cm, o.scans.max_cm,
        100.0 * double(o.recalled) / double(std::max<size_t>(1, o.query_keyframes)),
        100.0 * double(o.correct_candidates) / double(std::max<size_t>(1, o.candidates)),
        100.0 * double(o.correct_verified) / double(std::max<size_t>(1, o.verified)),
        o.times.total_s + o.times.descriptors_s);
    std::fflush(stdout);
}

void AccuracySuite(const fs::path& tmp, const std::vector<Building>& buildings, bool as_built) {
    std::printf(
        "\n== accuracy%s: 120 s walks of changed buildings (clutter, people, columns removed%s), "
        "APE with no alignment (rmse/max)\n",
        as_built ? "-asbuilt" : "", as_built ? ", walls built N(0, 2 cm) off" : "");
    std::vector<double> kf_rmse, kf_max, kf_rot, kf_rot_max, scan_rmse, scan_max, recall, precision;
    int runs = 0, within_targets = 0;
    for (const Building& b : buildings) {
        for (const auto platform : {simulate::Platform::kGo1, simulate::Platform::kHandheld}) {
            for (uint64_t seed : {1, 2, 3}) {
                simulate::Scenario s = simulate::DefaultScenario(platform);
                s.duration_s = 120;
                s.seed = seed;
                ChangeBuilding(&s, b, seed, as_built);
                const std::string name =
                    b.name + (platform == simulate::Platform::kGo1 ? " go1" : " handheld") +
                    " seed " + std::to_string(seed);
                // BIMSLAM_ANCHOR_ONLY: run only the walks whose name contains it.
                const char* only = std::getenv("BIMSLAM_ANCHOR_ONLY");
                if (only && name.find(only) == std::string::npos) continue;
                const Outcome o = RunOne(tmp / "run", b, s, {}, {});
                PrintRow(name, o);
                if (std::getenv("BIMSLAM_ANCHOR_LOOPS")) {
                    Spread("  right loops seen through", o.seen_right);
                    Spread("  wrong loops seen through", o.seen_wrong);
                    Spread("  right loops inlier ratio", o.inlier_right);
                    Spread("  wrong loops inlier ratio", o.inlier_wrong);
                }
                // The targets on the keyframes (issue 36: the tests' bounds are near the
                // figures measured on their own walks; the targets are kept here).
                ++runs;
                within_targets += o.keyframes.rmse_cm < 3.0 && o.keyframes.max_cm < 8.0 &&
                                  o.keyframes.rot_rmse_deg < 0.5 && o.keyframes.rot_max_deg < 1.5;
                kf_rmse.push_back(o.keyframes.rmse_cm);
                kf_max.push_back(o.keyframes.max_cm);
                kf_rot.push_back(o.keyframes.rot_rmse_deg);
                kf_rot_max.push_back(o.keyframes.rot_max_deg);
                scan_rmse.push_back(o.scans.rmse_cm);
                scan_max.push_back(o.scans.max_cm);
                recall.push_back(100.0 * double(o.recalled) / double(o.query_keyframes));
                precision.push_back(100.0 * double(o.correct_candidates) /
                                    double(std::max<size_t>(1, o.candidates)));
            }
        }
    }
    Spread("keyframes rmse (cm)", kf_rmse);
    Spread("keyframes max (cm)", kf_max);
    Spread("keyframes rot rmse (deg)", kf_rot);
    Spread("keyframes rot max (deg)", kf_rot_max);
    Spread("every scan rmse (cm)", scan_rmse);
    Spread("every scan max (cm)", scan_max);
    Spread("SC candidate recall (%)", recall);
    Spread("SC candidate precision (%)", precision);
    std::printf("  within the targets (keyframes 3 cm / 8 cm max, 0.5 / 1.5 deg): %d of %d\n",
                within_targets, runs);
}

void SuccessSuite(const fs::path& tmp, const std::vector<Building>& with_entrances) {
    std::printf(
        "\n== success: 20 captures of 60 s, changed buildings, different seeds and starts\n");
    int anchored_within = 0, wrong = 0, runs = 0;
    for (int k = 0; k < 20; ++k) {
        const Building& b = with_entrances[size_t(k) % with_entrances.size()];
        const auto platform = k % 4 < 2 ? simulate::Platform::kGo1 : simulate::Platform::kHandheld;
        simulate::Scenario s = simulate::DefaultScenario(platform);
        s.duration_s = 60;
        s.seed = 100 + uint64_t(k);
        ChangeBuilding(&s, b, s.seed, true);
        std::mt19937_64 rng(s.seed);
        std::uniform_real_distribution<double> u(0, 1);
        std::string start = "inside";
        if (k % 2 == 1) {
            // Outside, 3-8 m before the building's main entrance, facing it.
            const bim::BimModel& m = b.model;
            Eigen::AlignedBox3d box;
            for (const auto& v : m.mesh.vertices) box.extend(v.cast<double>());
            const double d = 3 + 5 * u(rng);
            simulate::Pose2d p;
            if (b.name == "hall") {  // its entrance is in the south wall, at the middle
                p.xy = {box.center().x(), box.min().y() - d};
                p.yaw_deg = 90;
            } else {  // the office's main entrance: west end of the corridor
                p.xy = {box.min().x() - d, 7.15};
                p.yaw_deg = 0;
            }
            s.path.start = p;
            start = "outside " + std::to_string(int(d)) + " m";
        }
        const std::string name = b.name +
                                 (platform == simulate::Platform::kGo1 ? " go1 " : " hh ") + start +
                                 " seed " + std::to_string(s.seed);
        const Outcome o = RunOne(tmp / "run", b, s, {}, {});
        PrintRow(name, o);
        ++runs;
        if (o.verdict == "anchored" && o.scans.rmse_cm < 10) ++anchored_within;
        if (o.verdict == "anchored" && !(o.scans.rmse_cm < 50)) ++wrong;
    }
    std::printf(
        "  anchored within 10 cm RMSE: %d of %d; reported anchored but wrong (> 50 cm): %d\n",
        anchored_within, runs, wrong);
}

void RobustnessSuite(const fs::path& tmp, const Building& b) {
    std::printf(
        "\n== robustness: 30 %% of the verified loops replaced by wrong pairs; each "
        "method with the proximity rounds, and alone (rounds 0)\n");
    const anchor::OutlierMethod methods[] = {
        anchor::OutlierMethod::kPcm, anchor::OutlierMethod::kGnc, anchor::OutlierMethod::kNone};
    for (const int rounds : {6, 0}) {
        for (const anchor::OutlierMethod method : methods) {
            for (uint64_t seed : {1, 2}) {
                simulate::Scenario s = simulate::DefaultScenario(
                    seed == 1 ? simulate::Platform::kGo1 : simulate::Platform::kHandheld);
                s.duration_s = 120;
                s.seed = seed;
                ChangeBuilding(&s, b, seed, false);
                anchor::AnchorConfig c;
                c.outliers = method;
                c.inject_false_loops = 0.3;
                c.seed = seed;
                c.max_rounds = rounds;
                PrintRow(b.name + " " + std::string(anchor::ToString(method)) + " rounds " +
                             std::to_string(rounds) + " seed " + std::to_string(seed),
                         RunOne(tmp / "run", b, s, c, {}));
            }
        }
    }
}

// The speed suite's reference and query session, simulated into `data` unless a previous run
// left them there (BIMSLAM_ANCHOR_SPEED_DATA), so that the anchoring can be timed again without
// the minutes of simulation and odometry.
struct SpeedData {
    fs::path reference, session, truth;
};

SpeedData MakeSpeedData(const fs::path& data) {
    const SpeedData d{data / "speed" / "hall_reference", data / "speed_run" / "session",
                      data / "speed_run" / "capture" / "ground_truth.tum"};
    if (fs::exists(d.reference / "session.json") && fs::exists(d.session / "session.json") &&
        fs::exists(d.truth)) {
        std::printf("  (sessions kept from a previous run in %s)\n", data.c_str());
        return d;
    }
    // The hall's reference every 0.5 m along its walks; a long Go1 walk of it with keyframes
    // every 0.3 m.
    const Building b = MakeBuilding(data / "speed", "hall", bim::BuildingLayout::kHall, false, 0.5);
    simulate::Scenario s = simulate::DefaultScenario(simulate::Platform::kGo1);
    s.duration_s = 600;
    s.model = b.ifc;
    const fs::path dir = data / "speed_run";
    simulate::SimulateCapture(s, b.model, "", dir / "capture");
    replay::CaptureOdometryOptions oo;
    oo.capture_dir = dir / "capture";
    oo.session_dir = d.session;
    oo.keyframes.distance_m = 0.3;
    replay::RunCaptureOdometry(oo);
    fs::remove(dir / "capture" / "lidar.pcap");
    return d;
}

void SpeedSuite(const fs::path& tmp) {
    std::printf("\n== speed: ~1000 query keyframes against ~1000 reference keyframes\n");
    // BIMSLAM_ANCHOR_SPEED_DATA=DIR: the sessions are made once in DIR and kept there.
    const char* keep = std::getenv("BIMSLAM_ANCHOR_SPEED_DATA");
    const SpeedData d = MakeSpeedData(keep ? fs::path(keep) : tmp);
    const auto t0 = Clock::now();
    std::vector<anchor::AnchorSession> sessions;
    sessions.push_back(anchor::LoadAnchorSession(d.reference, {}));
    const double ref_s = common::SecondsSince(t0);
    const auto t1 = Clock::now();
    sessions.push_back(anchor::LoadAnchorSession(d.session, {}));
    const double query_s = common::SecondsSince(t1);
    const anchor::AnchorResult r = anchor::Anchor(sessions, {});
    const auto truth = io::ReadTum(d.truth);
    const Accuracy a = Ape(anchor::WorldTrajectory(sessions[1], r.sessions[0].world_poses), truth);
    const anchor::StageTimes& t = r.times;
    std::printf("  reference %zu keyframes, query %zu keyframes: %s, APE %.2f cm\n",
                sessions[0].keyframes(), sessions[1].keyframes(),
                std::string(anchor::ToString(r.sessions[0].verdict)).c_str(), a.rmse_cm);
    std::printf("  read + descriptors + oriented clouds: reference %.2f s, query %.2f s\n", ref_s,
                query_s);
    std::printf(
        "  maps %.2f s | candidates %.2f s | registration %.2f s (%zu) | consistency %.2f s "
        "| optimisation %.2f s | anchoring total %.2f s | with reading %.2f s\n",
        t.map_s, t.candidates_s, t.registration_s, t.registrations, t.consistency_s,
        t.optimisation_s, t.total_s, t.total_s + ref_s + query_s);
}

}  // namespace
}  // namespace bimslam

int main(int argc, char** argv) {
    using namespace bimslam;
    const bench::Suites wants(argc, argv, {"accuracy", "robustness", "speed"});
    test::TempDir tmp;
    const auto t0 = Clock::now();
    if (wants("accuracy") || wants("accuracy-asbuilt") || wants("robustness")) {
        const std::vector<Building> buildings = {
            MakeBuilding(tmp / "b", "office", bim::BuildingLayout::kOffice, false),
            MakeBuilding(tmp / "b", "hall", bim::BuildingLayout::kHall, false)};
        if (wants("accuracy")) AccuracySuite(tmp.path(), buildings, false);
        if (wants("accuracy-asbuilt")) AccuracySuite(tmp.path(), buildings, true);
        if (wants("robustness")) RobustnessSuite(tmp.path(), buildings[0]);
    }
    if (wants("success")) {
        const std::vector<Building> entrances = {
            MakeBuilding(tmp / "e", "office", bim::BuildingLayout::kOffice, true),
            MakeBuilding(tmp / "e", "hall", bim::BuildingLayout::kHall, true)};
        SuccessSuite(tmp.path(), entrances);
    }
    if (wants("speed")) SpeedSuite(tmp.path());
    std::printf("\nanchor_benchmark: %.0f s\n", common::SecondsSince(t0));
    return 0;
}
