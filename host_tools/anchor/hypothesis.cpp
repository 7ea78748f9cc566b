// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/anchor/hypothesis.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <optional>
#include <set>
#include <string>

#include "algorithms/registration/free_space.hpp"
#include "host_tools/anchor/anchoring_problem.hpp"
#include "host_tools/anchor/place_recognition.hpp"

namespace bimslam::anchor {
using posegraph::PoseGraph;

bool Apart(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double m, double deg) {
    const Eigen::Isometry3d d = a.inverse() * b;
    return d.translation().norm() > m || common::RotationAngle(d) > deg * M_PI / 180;
}

std::vector<LoopRecord> AnchoringProblem::ProximityLoops(
    const Target& target, const std::vector<Eigen::Isometry3d>& world, size_t q,
    const std::function<bool(size_t)>& wanted,
    const std::function<bool(const TargetKeyframe&)>& use_target) {
    std::vector<LoopRecord> jobs;
    std::vector<Eigen::Isometry3d> init;
    for (size_t j = 0; j < world.size(); ++j) {
        if (wanted && !wanted(j)) continue;
        const size_t t = target.Nearest(world[j].translation(), config_.proximity_radius_m,
                                        config_.proximity_height_m);
        if (t == Target::kNone) continue;
        const TargetKeyframe& tk = target.keyframes()[t];
        if (use_target && !use_target(tk)) continue;
        jobs.push_back(NewLoop(q, j, tk, LoopSource::kProximity));
        init.push_back(world[j]);
    }
    RegisterLoops(target, init, config_.proximity_first_level, true, &jobs);
    for (size_t k = 0; k < jobs.size(); ++k) {
        LoopRecord& r = jobs[k];
        if (!r.verified || !Apart(r.registration.T_target_source, init[k], config_.proximity_gate_m,
                                  config_.proximity_gate_deg)) {
            continue;
        }
        r.verified = false;
        const Eigen::Isometry3d d = init[k].inverse() * r.registration.T_target_source;
        r.reason = "moved " + std::to_string(d.translation().norm()).substr(0, 4) + " m / " +
                   std::to_string(common::RotationAngle(d) * 180 / M_PI).substr(0, 4) +
                   " deg from the estimate (gate " +
                   std::to_string(config_.proximity_gate_m).substr(0, 4) + " m)";
    }
    return jobs;
}

Evaluation AnchoringProblem::FollowHypothesis(size_t q, const Target& target,
                                              std::vector<LoopRecord> seed_loops,
                                              const Eigen::Isometry3d& anchor) {
    std::vector<State> state = state_;
    const AnchorSession& query = sessions_[q];
    const size_t n = query.keyframes();
    state[q] = {anchor, query.poses, false};
    OptimizeStates(sessions_, &state, seed_loops, config_, times());
    Evaluation ev;
    std::vector<std::optional<LoopRecord>> near(n);
    const std::vector<LoopRecord> loops =
        ProximityRounds(q, target, seed_loops, &state, &near, &ev.hypothesis.rounds);
    std::vector<LoopRecord> kept = DropUnexplained(loops, &state, &ev.rejected);
    for (size_t j = 0; j < n; ++j) {
        if (near[j] && !near[j]->verified) ev.rejected.push_back(*near[j]);
    }
    const std::vector<registration::FreeSpaceResult> fs =
        SeenThrough(q, target, state[q], &ev.hypothesis);
    for (LoopRecord& l : kept) {
        l.seen_through = fs[l.query_index].ratio();
        l.free_space = fs[l.query_index];
    }
    double inliers = 0;
    for (const LoopRecord& l : kept) inliers += l.registration.fitness.inlier_ratio;
    ev.hypothesis.anchor = state[q].anchor;
    ev.hypothesis.clique = seed_loops.size();
    ev.hypothesis.loops = kept.size();
    std::set<size_t> covered;
    for (const LoopRecord& l : kept) covered.insert(l.query_index);
    ev.hypothesis.covered = covered.size();
    ev.hypothesis.mean_inlier_ratio = kept.empty() ? 0 : inliers / double(kept.size());
    std::vector<Eigen::Vector3d> placed;
    for (const Eigen::Isometry3d& T : state[q].World()) placed.push_back(T.translation());
    ev.hypothesis.floating = target.walked().Floating(placed, Eigen::Isometry3d::Identity());
    ev.query = state[q];
    ev.accepted = std::move(kept);
    return ev;
}

std::vector<LoopRecord> AnchoringProblem::ProximityRounds(
    size_t q, const Target& target, const std::vector<LoopRecord>& seed_loops,
    std::vector<State>* state, std::vector<std::optional<LoopRecord>>* near, int* rounds) {
    const size_t n = sessions_[q].keyframes();
    // The place-recognition loop of each keyframe, used where proximity finds none.
    std::vector<std::optional<LoopRecord>> seed(n);
    for (const LoopRecord& l : seed_loops) {
        if (!seed[l.query_index] || l.registration.fitness.inlier_ratio >
                                        seed[l.query_index]->registration.fitness.inlier_ratio) {
            seed[l.query_index] = l;
        }
    }
    std::vector<Eigen::Isometry3d> registered_at(n);
    std::set<size_t> previous;
    std::vector<LoopRecord> loops = seed_loops;
    for (int round = 1; round <= config_.max_rounds; ++round) {
        *rounds = round;
        const std::vector<Eigen::Isometry3d> world = (*state)[q].World();
        const auto wanted = [&](size_t j) {
            // A keyframe that has not moved since its last registration keeps its result.
            return !(*near)[j] || Apart(world[j], registered_at[j], 0.02, 0.2);
        };
        const std::vector<LoopRecord> fresh = ProximityLoops(target, world, q, wanted, {});
        for (size_t j = 0; j < n; ++j) {
            if (target.Nearest(world[j].translation(), config_.proximity_radius_m,
                               config_.proximity_height_m) == Target::kNone) {
                (*near)[j].reset();
            }
        }
        for (const LoopRecord& r : fresh) {
            (*near)[r.query_index] = r;
            registered_at[r.query_index] = world[r.query_index];
        }
        loops.clear();
        std::set<size_t> covered;
        for (size_t j = 0; j < n; ++j) {
            if ((*near)[j] && (*near)[j]->verified) {
                loops.push_back(*(*near)[j]);
            } else if (seed[j]) {
                loops.push_back(*seed[j]);
            } else {
                continue;
            }
            covered.insert(j);
        }
        const double moved = OptimizeStates(sessions_, state, loops, config_, times());
        if (covered == previous && moved < config_.converged_m) break;
        previous = covered;
    }
    return loops;
}

std::vector<LoopRecord> AnchoringProblem::DropUnexplained(const std::vector<LoopRecord>& loops,
                                                          std::vector<State>* state,
                                                          std::vector<LoopRecord>* rejected) {
    PoseGraph g = BuildGraph(sessions_, *state, loops, config_);
    std::vector<LoopRecord> kept;
    for (size_t k = 0; k < loops.size(); ++k) {
        const double chi2 = g.LoopChi2(k);
        if (chi2 > config_.max_loop_chi2) {
            LoopRecord r = loops[k];
            r.reason = "inconsistent with the solution: chi2 " + std::to_string(chi2).substr(0, 6);
            rejected->push_back(r);
        } else {
            kept.push_back(loops[k]);
        }
    }
    if (kept.size() != loops.size()) OptimizeStates(sessions_, state, kept, config_, times());
    return kept;
}

std::vector<registration::FreeSpaceResult> AnchoringProblem::SeenThrough(size_t q,
                                                                         const Target& target,
                                                                         const State& query_state,
                                                                         Hypothesis* h) const {
    const size_t n = sessions_[q].keyframes();
    std::vector<registration::FreeSpaceResult> fs(n);
    const Target& model = FreeSpaceTarget(target);  // see Solve
    const registration::SurfelMap& fs_map = model.map().level(config_.free_space_level);
    tbb::parallel_for(size_t(0), n, [&](size_t j) {
        const Eigen::Isometry3d T = query_state.anchor * query_state.poses[j];
        if (model.Nearest(T.translation(), config_.proximity_radius_m,
                          config_.proximity_height_m) == Target::kNone) {
            return;
        }
        fs[j] = registration::CheckFreeSpace(sessions_[q].clouds[j], fs_map, T, config_.free_space);
    });
    std::vector<const registration::FreeSpaceResult*> views;
    for (const auto& f : fs) {
        if (f.rays > 0) views.push_back(&f);
    }
    if (!views.empty()) {
        h->seen_through = registration::MedianUnexplained(views, {}, config_.removed_surfaces);
        h->removed_surfaces = registration::FindRemovedSurfaces(views, config_.removed_surfaces);
        h->seen_through_unexplained =
            registration::MedianUnexplained(views, h->removed_surfaces, config_.removed_surfaces);
    }
    return fs;
}

}  // namespace bimslam::anchor
