// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The anchoring problem (anchoring_problem.hpp) and its Solve: each query against the reference,
// a failed one again against the reference and the anchored ones, the loops between anchored
// query sessions, and all optimised together (step 6 of anchoring.hpp).
#include "host_tools/anchor/anchoring_problem.hpp"

#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>

#include "algorithms/common/stopwatch.hpp"

namespace bimslam::anchor {
namespace {
using Clock = std::chrono::steady_clock;
}  // namespace

AnchoringProblem::AnchoringProblem(const std::vector<AnchorSession>& sessions,
                                   const AnchorConfig& config, const Progress& progress)
    : sessions_(sessions), config_(config), progress_(progress), state_(sessions.size()) {
    for (size_t s = 0; s < sessions.size(); ++s) {
        state_[s] = {Eigen::Isometry3d::Identity(), sessions[s].poses, true};
        if (s > 0 && !sessions[s].earlier) queries_ = s;
    }
}

AnchorResult AnchoringProblem::Solve() {
    std::unique_ptr<tbb::global_control> limit;
    if (config_.threads > 0) {
        limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                      size_t(config_.threads));
    }
    const auto t_start = Clock::now();
    // 1-4: each query against the reference (and the earlier visits, 7).
    if (progress_) progress_("reference map", 0, 1);
    const Target reference = TargetOf(ReferenceAndEarlier());
    // Negative evidence comes from the model alone: an earlier visit's surfaces hold people,
    // clutter and objects that have gone since, and rays through them are no contradiction (the
    // demo's second visit saw through 8.4 % of them and was refused; 0.7 % of the model's).
    if (queries_ + 1 < sessions_.size()) model_only_.emplace(TargetOf({{0, state_[0].World()}}));
    for (size_t q = 1; q <= queries_; ++q) {
        outcomes_.push_back(AnchorQuery(q, reference));
    }
    for (size_t q : Anchored()) state_[q] = outcomes_[q - 1].state;
    RetryWithAnchored();
    // 6: loops between anchored query sessions, by proximity, then all together.
    std::vector<LoopRecord> joint = LoopsBetweenSessions();
    const std::vector<size_t> now = Anchored();
    for (size_t q : now) state_[q].fixed = false;
    // 7: the earlier visits free too, each keyframe held by its prior.
    for (size_t e = queries_ + 1; e < sessions_.size(); ++e) {
        state_[e].fixed = false;
        state_[e].held = true;
    }
    if (!now.empty()) {
        OptimizeStates(sessions_, &state_, joint, config_, times(), {}, nullptr, &result_.graph);
        if (config_.repair_odometry_breaks && RepairOdometryBreaks(&joint))
            result_.graph = BuildGraph(sessions_, state_, joint, config_);
    }
    Gather();
    GatherEarlier();
    times()->total_s = common::SecondsSince(t_start);
    return std::move(result_);
}

// The target of `members` (session index, world poses of its keyframes); its build time goes to
// the stage times.
Target AnchoringProblem::TargetOf(const Members& members) {
    const auto t0 = Clock::now();
    Target target(sessions_, members, config_);
    times()->map_s += common::SecondsSince(t0);
    return target;
}

// The reference and the earlier visits' sessions at their world poses.
AnchoringProblem::Members AnchoringProblem::ReferenceAndEarlier() const {
    Members members{{0, state_[0].World()}};
    for (size_t e = queries_ + 1; e < sessions_.size(); ++e)
        members.push_back({e, state_[e].World()});
    return members;
}

// The queries anchored so far, in input order.
std::vector<size_t> AnchoringProblem::Anchored() const {
    std::vector<size_t> a;
    for (size_t q = 1; q <= queries_; ++q) {
        if (outcomes_[q - 1].result.verdict == Verdict::kAnchored) a.push_back(q);
    }
    return a;
}

// A session that failed alone, against the reference and the sessions anchored alone; one
// anchored so is placed at once, before the next is tried.
void AnchoringProblem::RetryWithAnchored() {
    const std::vector<size_t> alone = Anchored();
    if (alone.empty() || alone.size() >= queries_) return;
    Members members = ReferenceAndEarlier();
    for (size_t q : alone) members.push_back({q, state_[q].World()});
    const Target all = TargetOf(members);
    for (size_t q = 1; q <= queries_; ++q) {
        if (outcomes_[q - 1].result.verdict == Verdict::kAnchored) continue;
        QueryOutcome retry = AnchorQuery(q, all);
        if (retry.result.verdict == Verdict::kAnchored) {
            retry.result.via_other_sessions = true;
            outcomes_[q - 1] = std::move(retry);
            state_[q] = outcomes_[q - 1].state;
        }
    }
}

// Every anchored query's accepted loops, and the verified proximity loops from each anchored
// query session to the earlier ones (each pair once), which also join their records.
std::vector<LoopRecord> AnchoringProblem::LoopsBetweenSessions() {
    std::vector<LoopRecord> joint;
    const std::vector<size_t> now = Anchored();
    for (size_t q : now) {
        for (const LoopRecord& l : outcomes_[q - 1].accepted) joint.push_back(l);
    }
    if (now.size() < 2) return joint;
    for (size_t q : now) {
        Members others;
        for (size_t o : now) {
            if (o != q) others.push_back({o, state_[o].World()});
        }
        const Target target = TargetOf(others);
        const std::vector<LoopRecord> loops =
            ProximityLoops(target, state_[q].World(), q, {},
                           [q](const TargetKeyframe& tk) { return tk.session < q; });
        for (LoopRecord r : loops) {
            if (r.verified) {
                r.accepted = true;
                r.reason = "accepted";
                joint.push_back(r);
            }
            outcomes_[q - 1].records.push_back(r);
        }
    }
    return joint;
}

// The result per query (an anchored one at its jointly optimised state) and every loop.
void AnchoringProblem::Gather() {
    for (size_t q = 1; q <= queries_; ++q) {
        QueryOutcome& o = outcomes_[q - 1];
        if (o.result.verdict == Verdict::kAnchored) {
            o.result.anchor = state_[q].anchor;
            o.result.world_poses = state_[q].World();
            if (sessions_[q].odometry.stretches.empty()) FindOdometryBreaks(q, &o.result);
        }
        result_.sessions.push_back(o.result);
        for (LoopRecord& r : o.records) result_.loops.push_back(std::move(r));
    }
}

// The trusted odometry edges of query q that its anchored state breaks
// (SessionResult::odometry_breaks), said in the reason.
void AnchoringProblem::FindOdometryBreaks(size_t q, SessionResult* r) const {
    r->odometry_breaks = OdometryBreaks(sessions_[q], state_[q].poses, config_);
    if (r->odometry_breaks.empty()) return;
    double worst = 0;
    for (const SessionResult::OdometryBreak& b : r->odometry_breaks)
        worst = std::max(worst, b.offset_m);
    char b[200];
    std::snprintf(b, sizeof b,
                  "; but it breaks the trusted odometry at %zu edge(s), up to %.2f m: loops and "
                  "odometry disagree there (anchor.json odometry_breaks), do not trust those "
                  "keyframes",
                  r->odometry_breaks.size(), worst);
    r->reason += b;
}

// Each earlier visit's session: the accepted loops to it and how far the joint solution moved
// its keyframes from their priors.
void AnchoringProblem::GatherEarlier() {
    for (size_t e = queries_ + 1; e < sessions_.size(); ++e) {
        EarlierResult r{sessions_[e].name, sessions_[e].keyframes(), 0, 0.0};
        for (const LoopRecord& l : result_.loops)
            r.accepted_loops += l.accepted && l.target_session == e;
        const std::vector<Eigen::Isometry3d> world = state_[e].World();
        for (size_t k = 0; k < world.size(); ++k) {
            r.max_move_m =
                std::max(r.max_move_m,
                         (world[k].translation() - sessions_[e].poses[k].translation()).norm());
        }
        result_.earlier.push_back(r);
    }
}

}  // namespace bimslam::anchor
