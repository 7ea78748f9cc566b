#include "host_tools/anchor/hypothesis.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <optional>
#include <set>
#include <string>

#include "algorithms/registration/free_space.hpp"
#include "host_tools/anchor/place_recognition.hpp"

namespace bimslam::anchor {
using posegraph::PoseGraph;

bool Apart(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double m, double deg) {
    const Eigen::Isometry3d d = a.inverse() * b;
    return d.translation().norm() > m || common::RotationAngle(d) > deg * M_PI / 180;
}

std::vector<LoopRecord> ProximityLoops(const std::vector<AnchorSession>& sessions,
                                       const Target& target,
                                       const std::vector<Eigen::Isometry3d>& world, size_t q,
                                       const std::function<bool(size_t)>& wanted,
                                       const std::function<bool(const TargetKeyframe&)>& use_target,
                                       const AnchorConfig& config, StageTimes* times) {
    std::vector<LoopRecord> jobs;
    std::vector<Eigen::Isometry3d> init;
    for (size_t j = 0; j < world.size(); ++j) {
        if (wanted && !wanted(j)) continue;
        const size_t t = target.Nearest(world[j].translation(), config.proximity_radius_m,
                                        config.proximity_height_m);
        if (t == Target::kNone) continue;
        const TargetKeyframe& tk = target.keyframes()[t];
        if (use_target && !use_target(tk)) continue;
        jobs.push_back(NewLoop(q, j, tk, LoopSource::kProximity));
        init.push_back(world[j]);
    }
    RegisterLoops(sessions, target, config, init, config.proximity_first_level, true, &jobs, times);
    for (size_t k = 0; k < jobs.size(); ++k) {
        LoopRecord& r = jobs[k];
        if (!r.verified || !Apart(r.registration.T_target_source, init[k], config.proximity_gate_m,
                                  config.proximity_gate_deg)) {
            continue;
        }
        r.verified = false;
        const Eigen::Isometry3d d = init[k].inverse() * r.registration.T_target_source;
        r.reason = "moved " + std::to_string(d.translation().norm()).substr(0, 4) + " m / " +
                   std::to_string(common::RotationAngle(d) * 180 / M_PI).substr(0, 4) +
                   " deg from the estimate (gate " +
                   std::to_string(config.proximity_gate_m).substr(0, 4) + " m)";
    }
    return jobs;
}

Evaluation FollowHypothesis(const std::vector<AnchorSession>& sessions, std::vector<State> state,
                            size_t q, const Target& target, std::vector<LoopRecord> seed_loops,
                            const Eigen::Isometry3d& anchor, const AnchorConfig& config,
                            StageTimes* times) {
    const AnchorSession& query = sessions[q];
    const size_t n = query.keyframes();
    state[q] = {anchor, query.poses, false};
    OptimizeStates(sessions, &state, seed_loops, config, times);

    // The place-recognition loop of each keyframe, used where proximity finds none.
    std::vector<std::optional<LoopRecord>> seed(n), near(n);
    for (const LoopRecord& l : seed_loops) {
        if (!seed[l.query_index] || l.registration.fitness.inlier_ratio >
                                        seed[l.query_index]->registration.fitness.inlier_ratio) {
            seed[l.query_index] = l;
        }
    }
    std::vector<Eigen::Isometry3d> registered_at(n);
    std::set<size_t> previous;
    std::vector<LoopRecord> loops = seed_loops;
    Evaluation ev;
    for (int round = 1; round <= config.max_rounds; ++round) {
        ev.hypothesis.rounds = round;
        const std::vector<Eigen::Isometry3d> world = state[q].World();
        const auto wanted = [&](size_t j) {
            // A keyframe that has not moved since its last registration keeps its result.
            return !near[j] || Apart(world[j], registered_at[j], 0.02, 0.2);
        };
        const std::vector<LoopRecord> fresh =
            ProximityLoops(sessions, target, world, q, wanted, {}, config, times);
        for (size_t j = 0; j < n; ++j) {
            if (target.Nearest(world[j].translation(), config.proximity_radius_m,
                               config.proximity_height_m) == Target::kNone) {
                near[j].reset();
            }
        }
        for (const LoopRecord& r : fresh) {
            near[r.query_index] = r;
            registered_at[r.query_index] = world[r.query_index];
        }
        loops.clear();
        std::set<size_t> covered;
        for (size_t j = 0; j < n; ++j) {
            if (near[j] && near[j]->verified) {
                loops.push_back(*near[j]);
            } else if (seed[j]) {
                loops.push_back(*seed[j]);
            } else {
                continue;
            }
            covered.insert(j);
        }
        const double moved = OptimizeStates(sessions, &state, loops, config, times);
        if (covered == previous && moved < config.converged_m) break;
        previous = covered;
    }
    // Loops the solution cannot explain are dropped, and the rest optimised once more.
    PoseGraph g = BuildGraph(sessions, state, loops, config);
    std::vector<LoopRecord> kept;
    for (size_t k = 0; k < loops.size(); ++k) {
        const double chi2 = g.LoopChi2(k);
        if (chi2 > config.max_loop_chi2) {
            LoopRecord r = loops[k];
            r.reason = "inconsistent with the solution: chi2 " + std::to_string(chi2).substr(0, 6);
            ev.rejected.push_back(r);
        } else {
            kept.push_back(loops[k]);
        }
    }
    if (kept.size() != loops.size()) OptimizeStates(sessions, &state, kept, config, times);
    for (size_t j = 0; j < n; ++j) {
        if (near[j] && !near[j]->verified) ev.rejected.push_back(*near[j]);
    }
    // Negative evidence: the query's rays through the target's surfaces, where it is near.
    std::vector<registration::FreeSpaceResult> fs(n);
    const registration::SurfelMap& fs_map = target.map().level(config.free_space_level);
    tbb::parallel_for(size_t(0), n, [&](size_t j) {
        const Eigen::Isometry3d T = state[q].anchor * state[q].poses[j];
        if (target.Nearest(T.translation(), config.proximity_radius_m, config.proximity_height_m) ==
            Target::kNone) {
            return;
        }
        fs[j] = registration::CheckFreeSpace(query.clouds[j], fs_map, T, config.free_space);
    });
    std::vector<double> ratios;
    for (const auto& f : fs) {
        if (f.rays > 0) ratios.push_back(f.ratio());
    }
    if (!ratios.empty()) {
        std::nth_element(ratios.begin(), ratios.begin() + ratios.size() / 2, ratios.end());
        ev.hypothesis.seen_through = ratios[ratios.size() / 2];
    }
    for (LoopRecord& l : kept) l.seen_through = fs[l.query_index].ratio();
    double inliers = 0;
    for (const LoopRecord& l : kept) inliers += l.registration.fitness.inlier_ratio;
    ev.hypothesis.anchor = state[q].anchor;
    ev.hypothesis.clique = seed_loops.size();
    ev.hypothesis.loops = kept.size();
    std::set<size_t> covered;
    for (const LoopRecord& l : kept) covered.insert(l.query_index);
    ev.hypothesis.covered = covered.size();
    ev.hypothesis.mean_inlier_ratio = kept.empty() ? 0 : inliers / double(kept.size());
    ev.query = state[q];
    ev.accepted = std::move(kept);
    return ev;
}

}  // namespace bimslam::anchor
