// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The anchoring problem held in one object (internal to host_tools/anchor): the sessions (the
// reference first), the config, where each session is (the graph state), the loops found per
// query, the stage times and the progress callback. Its steps are its methods, so they share
// these instead of passing them along beside each other (as Ceres' examples/slam/pose_graph_3d
// holds its poses and constraints in one problem). The steps are those of anchoring.hpp:
//   place_recognition.cpp  FindPlaceLoops, InjectFalseLoops, RegisterLoops (step 1)
//   anchor_query.cpp       AnchorQuery and its steps: hypotheses (2), ranking and verdict (4)
//   hypothesis.cpp         FollowHypothesis and its steps, ProximityLoops (step 3)
//   anchoring_problem.cpp  Solve: every query, the retries, the loops between query sessions
//                          and the joint optimisation (step 6)
//   break_repair.cpp       RepairOdometryBreaks: a trusted odometry the joint solution broke (6)
#pragma once

#include <Eigen/Geometry>
#include <functional>
#include <optional>
#include <utility>
#include <vector>

#include "algorithms/registration/free_space.hpp"
#include "host_tools/anchor/anchoring.hpp"
#include "host_tools/anchor/graph_state.hpp"
#include "host_tools/anchor/hypothesis.hpp"
#include "host_tools/anchor/target.hpp"

namespace bimslam::anchor {

// One query session anchored against a target: its result, every loop candidate with its
// verdict, the accepted loops and the query's state when anchored.
struct QueryOutcome {
    SessionResult result;
    size_t cliques_seen_through = 0;  // consistent sets passed over (Cliques)
    std::vector<LoopRecord> records;
    std::vector<LoopRecord> accepted;
    State state;
};

class AnchoringProblem {
public:
    // sessions[0] is the reference (fixed); every session starts at its odometry. The sessions
    // and the config must outlive the problem.
    AnchoringProblem(const std::vector<AnchorSession>& sessions, const AnchorConfig& config,
                     const Progress& progress);

    // Steps 1-6 (anchoring.hpp) for sessions that are each anchored whole. Once: the result is
    // moved out.
    AnchorResult Solve();

    // Steps 1-4 for query session q against `target`, the other sessions where the state has
    // them (the state is not changed).
    QueryOutcome AnchorQuery(size_t q, const Target& target);

    // Step 1: every keyframe of q's best Scan Context candidates among the target's keyframes
    // (of other sessions than q), registered and verified.
    std::vector<LoopRecord> FindPlaceLoops(size_t q, const Target& target);
    // Replaces config.inject_false_loops of the verified loops by wrong pairs (see AnchorConfig).
    void InjectFalseLoops(size_t q, const Target& target, std::vector<LoopRecord>* records);
    // Registers each record's query keyframe to the target's map from `init[k]` (world frame)
    // and fills its registration, T_target_query and verified (the place-recognition test unless
    // `proximity`). Parallel; adds the wall time and the count to the stage times.
    void RegisterLoops(const Target& target, const std::vector<Eigen::Isometry3d>& init,
                       size_t first_level, bool proximity, std::vector<LoopRecord>* records);

    // Step 3: follows a hypothesis whose place-recognition loops are seed_loops; q's state
    // starts at its odometry, placed by `anchor`; the other sessions stay where the state has
    // them.
    Evaluation FollowHypothesis(size_t q, const Target& target, std::vector<LoopRecord> seed_loops,
                                const Eigen::Isometry3d& anchor);
    // Proximity loops of session q's keyframes placed at `world`: each keyframe j with wanted(j)
    // whose nearest target keyframe (within the proximity radius and height) passes use_target
    // is registered from its estimate (from AnchorConfig::proximity_first_level) and verified;
    // one that moved farther than the gate from its estimate is not.
    std::vector<LoopRecord> ProximityLoops(
        const Target& target, const std::vector<Eigen::Isometry3d>& world, size_t q,
        const std::function<bool(size_t)>& wanted,
        const std::function<bool(const TargetKeyframe&)>& use_target);

private:
    StageTimes* times() { return &result_.times; }
    using Members = std::vector<std::pair<size_t, std::vector<Eigen::Isometry3d>>>;

    // AnchorQuery's steps.
    std::vector<size_t> PlaceRecognition(size_t q, const Target& target, QueryOutcome* out);
    std::vector<std::vector<size_t>> Cliques(const std::vector<size_t>& verified,
                                             QueryOutcome* out);
    std::optional<Evaluation> FollowClique(size_t q, const Target& target,
                                           const std::vector<size_t>& clique, int h,
                                           std::vector<LoopRecord>* records);
    std::vector<Evaluation> Rank(size_t q, std::vector<Evaluation> evals, SessionResult* res) const;
    void Decide(size_t q, const std::vector<Evaluation>& ranked, QueryOutcome* out) const;
    void Accept(const std::vector<Evaluation>& ranked, size_t keyframes, QueryOutcome* out) const;

    // FollowHypothesis's steps. The rounds of proximity registration from q's estimate in
    // *state, optimising after each, until the keyframes with loops and the poses stop changing
    // (at most max_rounds, counted in *rounds); a keyframe's proximity loop replaces its
    // place-recognition one. Returns the last round's loops; (*near)[j] is keyframe j's last
    // proximity loop, verified or not.
    std::vector<LoopRecord> ProximityRounds(size_t q, const Target& target,
                                            const std::vector<LoopRecord>& seed_loops,
                                            std::vector<State>* state,
                                            std::vector<std::optional<LoopRecord>>* near,
                                            int* rounds);
    // The loops the solution in *state explains (chi2 up to max_loop_chi2), optimised again
    // without the others, which go to *rejected with the reason.
    std::vector<LoopRecord> DropUnexplained(const std::vector<LoopRecord>& loops,
                                            std::vector<State>* state,
                                            std::vector<LoopRecord>* rejected);

    // RepairOdometryBreaks's bookkeeping (break_repair.cpp): q's result and every record.
    void Repaired(size_t q, const std::vector<SessionResult::OdometryBreak>& breaks,
                  const std::vector<LoopRecord>& dropped);

    // Negative evidence: each keyframe of q near the target, placed by query_state, cast
    // through the target's surfels (registration::CheckFreeSpace; with earlier visits, the
    // model's alone: model_only_). Fills h's seen_through (the median share of rays seen through
    // over the keyframes checked; left as it is when none is), removed_surfaces and
    // seen_through_unexplained (registration::FindRemovedSurfaces).
    std::vector<registration::FreeSpaceResult> SeenThrough(size_t q, const Target& target,
                                                           const State& query_state,
                                                           Hypothesis* h) const;
    // Where negative evidence is looked for: the model alone (model_only_) when earlier visits
    // are targets too, else `target`. Both the loops' seen_through (RegisterLoops, which the
    // cliques are passed over by) and the hypotheses' (SeenThrough) use it.
    const Target& FreeSpaceTarget(const Target& target) const {
        return model_only_ ? *model_only_ : target;
    }

    // Solve's steps.
    Target TargetOf(const Members& members);
    Members ReferenceAndEarlier() const;
    std::vector<size_t> Anchored() const;
    void RetryWithAnchored();
    std::vector<LoopRecord> LoopsBetweenSessions();
    // A trusted odometry the joint solution broke, mended (RepairBreaks): true when one was.
    bool RepairOdometryBreaks(std::vector<LoopRecord>* loops);
    void Gather();
    void FindOdometryBreaks(size_t q, SessionResult* r) const;
    void GatherEarlier();

    const std::vector<AnchorSession>& sessions_;
    const AnchorConfig& config_;
    size_t queries_ = 0;  // sessions 1..queries_; the earlier visits' after them
    // With earlier visits: the reference alone, for the free-space check (SeenThrough).
    std::optional<Target> model_only_;
    Progress progress_;
    std::vector<State> state_;            // per session
    std::vector<QueryOutcome> outcomes_;  // per query: outcomes_[q - 1]
    AnchorResult result_;                 // its times filled as the steps run
};

}  // namespace bimslam::anchor
