// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// bimslam localize: a session's keyframes fed one by one to the relocaliser the rig will run
// (algorithms/localization/relocalizer.hpp) against a rig map package: the states it would have
// shown live, its live poses in the model, and, with the ground truth, how far off they were.
#include <time.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "algorithms/common/status.hpp"
#include "algorithms/io/file_util.hpp"
#include "algorithms/io/session.hpp"
#include "algorithms/io/trajectory.hpp"
#include "algorithms/localization/relocalizer.hpp"
#include "algorithms/localization/rig_map.hpp"
#include "algorithms/scancontext/descriptor.hpp"
#include "host_tools/anchor/pieces.hpp"
#include "host_tools/cli/command.hpp"
#include "host_tools/evaluation/trajectory_metrics.hpp"
#include "host_tools/replay/capture_odometry.hpp"

namespace bimslam::cli {
namespace {
namespace fs = std::filesystem;
using localization::RelocalizerState;
using nlohmann::json;

struct LocalizeArgs {
    std::string map;
    std::string session;
    std::string out;
    std::string truth;
    double inject_false_loops = 0;
    uint64_t seed = 1;
    std::vector<double> near;  // x y [radius]
    bool json = false;
};

double ThreadCpuMs() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}

// The keyframe's descriptor as the package's were made: the session's own when it was made the
// same way (the rig's indoor Scan Context), else computed from the cloud.
scancontext::Descriptor PackageDescriptor(const io::SessionKeyframe& k, bool same,
                                          const scancontext::ScanContextConfig& config) {
    if (same) return k.descriptor;
    return scancontext::MakeDescriptor(k.cloud, config);
}

json PoseJson(const Eigen::Isometry3d& T) {
    const Eigen::Quaterniond q(T.rotation());
    const Eigen::Vector3d t = T.translation();
    return {t.x(), t.y(), t.z(), q.w(), q.x(), q.y(), q.z()};
}

// Every scan's live pose in the model: the session's odometry composed with the T_bim_odom the
// relocaliser held at the scan's time (its last keyframe at or before it), while localised.
std::vector<io::StampedPose> LivePoses(
    const io::Session& s, const std::map<int64_t, std::optional<Eigen::Isometry3d>>& held) {
    std::vector<io::StampedPose> out;
    for (const io::StampedPose& p : s.trajectory) {
        auto it = held.upper_bound(p.stamp_ns);
        if (it == held.begin()) continue;
        --it;
        if (it->second) out.push_back(localization::LivePose(*it->second, p));  // localised then
    }
    return out;
}

// Which keyframes come after a scan whose height the odometry flagged ambiguous (its
// odometry_verdict.json's height_ambiguous_stretches), since the keyframe before: as the rig's
// odometry thread marks the keyframes it hands to its localiser (firmware/modules/rig_types.hpp).
std::vector<bool> HeightAmbiguousKeyframes(const io::Session& s, const fs::path& dir) {
    const anchor::OdometryVerdict v = anchor::ReadOdometryVerdict(dir);
    std::vector<bool> out(s.keyframes.size(), false);
    int64_t after_ns = INT64_MIN;
    for (size_t k = 0; k < s.keyframes.size(); ++k) {
        const int64_t t = s.keyframes[k].stamp_ns;
        out[k] = anchor::StretchBetween(v.height_ambiguous, after_ns, t);
        after_ns = t + 1;
    }
    return out;
}

// What the relocaliser did, keyframe by keyframe.
struct LocalizeRun {
    json steps = json::array();    // localization.json's keyframes
    json changes = json::array();  // the state changes
    std::vector<double> cpu_ms;
    // T_bim_odom from each keyframe's stamp on; nullopt while not localised.
    std::map<int64_t, std::optional<Eigen::Isometry3d>> held;
    std::map<std::string, size_t> counts;
    std::optional<size_t> first_localised;
    RelocalizerState last_state = RelocalizerState::kSearching;
    size_t height_ambiguous = 0;  // keyframes told the odometry's height may be off
};

json StepJson(size_t k, const io::SessionKeyframe& kf, const localization::RelocalizerStep& step,
              const localization::RigMap& map, double cpu_ms, bool height_ambiguous) {
    json j = {{"keyframe", k},
              {"t_s", double(kf.stamp_ns) * 1e-9},
              {"state", localization::ToString(step.state)},
              {"consistent_loops", step.consistent_loops},
              {"hypotheses", step.hypotheses.size()},
              {"registrations", step.registrations},
              {"injected", step.injected},
              {"cpu_ms", cpu_ms}};
    if (height_ambiguous) j["odometry_height_ambiguous"] = true;
    if (step.state == RelocalizerState::kLocalised) {
        j["T_bim_lidar"] = PoseJson(step.T_bim_lidar);
        j["accepted"] = step.accepted;
        j["storey"] = step.storey >= 0 ? json(map.storeys[size_t(step.storey)].name) : json();
    }
    return j;
}

LocalizeRun RunRelocaliser(const LocalizeArgs& a, const localization::RigMap& map,
                           const io::Session& s) {
    localization::RelocalizerConfig config;
    config.inject_false_loops = a.inject_false_loops;
    config.seed = a.seed;
    if (!a.near.empty()) config.start = localization::StartHint::FromList(a.near);
    localization::Relocalizer relocalizer(map, config);
    const io::SessionManifest::Descriptor& md = s.manifest.descriptor;
    const bool same =
        md.kind == map.descriptor.kind && md.rings == map.descriptor.rings &&
        md.sectors == map.descriptor.sectors && md.max_radius_m == map.descriptor.max_radius_m &&
        md.min_points == map.descriptor.min_points &&
        md.min_z_span_m == map.descriptor.min_z_span_m && md.cell_rule == map.descriptor.cell_rule;
    const scancontext::ScanContextConfig sc = map.DescriptorConfig();
    const std::vector<bool> ambiguous = HeightAmbiguousKeyframes(s, a.session);
    LocalizeRun run;
    double path_m = 0;
    for (size_t k = 0; k < s.keyframes.size(); ++k) {
        const io::SessionKeyframe& kf = s.keyframes[k];
        if (k > 0) {
            path_m +=
                (kf.T_world_lidar.translation() - s.keyframes[k - 1].T_world_lidar.translation())
                    .norm();
        }
        const double t0 = ThreadCpuMs();
        const localization::RelocalizerStep& step = relocalizer.AddKeyframe(
            kf.cloud, PackageDescriptor(kf, same, sc), kf.T_world_lidar, path_m, ambiguous[k]);
        run.cpu_ms.push_back(ThreadCpuMs() - t0);
        run.height_ambiguous += ambiguous[k];
        const std::string state(localization::ToString(step.state));
        ++run.counts[state];
        const bool localised = step.state == RelocalizerState::kLocalised;
        run.held[kf.stamp_ns] = localised ? std::optional(step.T_bim_odom) : std::nullopt;
        if (localised && !run.first_localised) run.first_localised = k;
        if (k == 0 || step.state != run.last_state) {
            run.changes.push_back(
                {{"keyframe", k}, {"t_s", double(kf.stamp_ns) * 1e-9}, {"state", state}});
        }
        run.last_state = step.state;
        run.steps.push_back(StepJson(k, kf, step, map, run.cpu_ms.back(), ambiguous[k]));
    }
    return run;
}

json Summary(const LocalizeArgs& a, const io::Session& s, const LocalizeRun& run,
             size_t live_poses) {
    const double t_first = double(s.keyframes.front().stamp_ns) * 1e-9;
    const auto& first = run.first_localised;
    return {{"map", a.map},
            {"session", a.session},
            {"keyframes", s.keyframes.size()},
            {"states", run.counts},
            {"state_changes", run.changes},
            {"final_state", localization::ToString(run.last_state)},
            {"localised_at_keyframe", first ? json(*first) : json()},
            {"time_to_localised_s",
             first ? json(double(s.keyframes[*first].stamp_ns) * 1e-9 - t_first) : json()},
            {"live_poses", live_poses},
            {"odometry_height_ambiguous_keyframes", run.height_ambiguous},
            {"cpu_ms_per_keyframe",
             {{"p50", replay::Percentile(run.cpu_ms, 0.5)},
              {"p99", replay::Percentile(run.cpu_ms, 0.99)},
              {"max", replay::Percentile(run.cpu_ms, 1.0)}}}};
}

void PrintRun(const io::Session& s, const LocalizeRun& run, const json& summary) {
    std::cout << "localize " << s.keyframes.size() << " keyframes: ";
    for (const auto& [state, n] : run.counts) std::cout << state << " " << n << "  ";
    std::cout << "\n";
    const std::string final_state(localization::ToString(run.last_state));
    if (run.first_localised) {
        std::cout << "         localised at keyframe " << *run.first_localised << " after "
                  << Fixed(summary["time_to_localised_s"].get<double>(), 1) << " s; final state "
                  << final_state << "\n";
    } else {
        std::cout << "         never localised; final state " << final_state << "\n";
    }
    if (run.height_ambiguous > 0) {
        std::cout << "         " << run.height_ambiguous
                  << " keyframes after a height the odometry flagged ambiguous "
                     "(odometry_verdict.json): tracked with the height's bound of the climb\n";
    }
    std::cout << "cpu      per keyframe p50 " << Fixed(replay::Percentile(run.cpu_ms, 0.5), 1)
              << " ms, p99 " << Fixed(replay::Percentile(run.cpu_ms, 0.99), 1) << " ms\n";
}

json TruthJson(const std::vector<io::StampedPose>& live, const std::string& truth) {
    evaluation::EvaluationConfig ec;
    ec.align = evaluation::Alignment::kNone;
    const evaluation::EvaluationResult r =
        evaluation::Evaluate(live, io::ReadTum(truth), ec, "live poses", truth);
    std::cout << "truth    live poses against " << truth << ": " << r.matched << " matched, APE "
              << Fixed(r.ape_trans_m.rmse * 100, 2) << " cm RMSE, max "
              << Fixed(r.ape_trans_m.max * 100, 2) << " cm; " << Fixed(r.ape_rot_deg.rmse, 2)
              << " deg RMSE, max " << Fixed(r.ape_rot_deg.max, 2) << " deg\n";
    return {{"matched", r.matched},
            {"ape_rmse_m", r.ape_trans_m.rmse},
            {"ape_max_m", r.ape_trans_m.max},
            {"rot_rmse_deg", r.ape_rot_deg.rmse},
            {"rot_max_deg", r.ape_rot_deg.max}};
}

int Localize(const LocalizeArgs& a) {
    const localization::RigMap map = localization::ReadRigMap(a.map);
    const io::Session s = io::ReadSession(a.session);
    if (s.keyframes.empty()) {
        throw common::FileError(
            common::StatusCode::kInvalidArgument, a.session, 0,
            std::string("the session has no keyframes (") + io::kNoKeyframesHint + ")");
    }
    const LocalizeRun run = RunRelocaliser(a, map, s);
    fs::create_directories(a.out);
    const std::vector<io::StampedPose> live = LivePoses(s, run.held);
    io::WriteTum(fs::path(a.out) / "trajectory_bim_live.tum", live);
    json summary = Summary(a, s, run, live.size());
    if (!a.near.empty()) summary["near"] = localization::StartHint::FromList(a.near).List();
    PrintRun(s, run, summary);
    if (!a.truth.empty() && live.size() >= 3) summary["truth"] = TruthJson(live, a.truth);
    io::WriteFileAtomic(fs::path(a.out) / "localization.json",
                        json{{"summary", summary}, {"keyframes", run.steps}}.dump(1) + "\n");
    std::cout << "wrote    " << (fs::path(a.out) / "localization.json").string() << ", "
              << (fs::path(a.out) / "trajectory_bim_live.tum").string() << "\n";
    if (a.json) std::cout << summary.dump(2) << "\n";
    return kExitOk;
}

}  // namespace

void AddLocalizeCommand(CLI::App& app, int& exit_code) {
    auto a = std::make_shared<LocalizeArgs>();
    auto* cmd = app.add_subcommand(
        "localize",
        "Feed a session's keyframes, one by one, to the relocaliser made for the rig, against a "
        "map "
        "package (bimslam rig-map): the states it would show live (searching, candidate, "
        "localised, ambiguous, lost), its live poses in the model (OUT/trajectory_bim_live.tum, "
        "every scan once localised), OUT/localization.json; with --truth, their error. Where "
        "the session's odometry_verdict.json lists a height the odometry saw again while "
        "uncertain (height_ambiguous_stretches), the keyframes after it are told, as the rig's "
        "odometry tells its localiser (algorithms/localization/README.md)");
    cmd->add_option("SESSION", a->session, "a rig or odometry session folder")->required();
    cmd->add_option("--map", a->map, "the map package (bimslam rig-map)")->required();
    cmd->add_option("--out,-o", a->out, "output folder")->required();
    cmd->add_option("--truth", a->truth,
                    "ground truth T_bim_sensor (TUM, the session's clock), e.g. a simulated "
                    "capture's ground_truth.tum: the live poses' error, with no alignment");
    cmd->add_option("--inject-false-loops", a->inject_false_loops,
                    "robustness tests: while searching, each keyframe adds with this probability "
                    "a loop to a random reference keyframe, kept whatever its fitness")
        ->check(CLI::Range(0.0, 0.95));
    cmd->add_option("--seed", a->seed, "the injected loops' seed")->capture_default_str();
    cmd->add_option("--near", a->near,
                    "X Y [R]: where the walk starts, in model metres, when you know it (within "
                    "R, default 3 m; the rig's localization.near): hypotheses that put the first "
                    "keyframe farther away are set aside. For buildings of identical parts, "
                    "where the rig is otherwise ambiguous")
        ->expected(2, 3);
    cmd->add_flag("--json", a->json, "also print the summary as JSON");
    cmd->callback([a, &exit_code] { exit_code = Run([&] { return Localize(*a); }); });
}

}  // namespace bimslam::cli
