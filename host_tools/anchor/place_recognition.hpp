// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Steps 1 and 2 of anchoring (anchoring.hpp): loop candidates by Scan Context, verified by
// registration (place_recognition.cpp defines them as AnchoringProblem's FindPlaceLoops,
// InjectFalseLoops and RegisterLoops); the hypotheses of mutually consistent loops (PCM).
#pragma once

#include <vector>

#include "host_tools/anchor/anchoring.hpp"
#include "host_tools/anchor/target.hpp"

namespace bimslam::anchor {

// The loop of query keyframe (query, index) at a target keyframe, not registered yet.
LoopRecord NewLoop(size_t query, size_t index, const TargetKeyframe& target, LoopSource source);

// T_world_local the loop implies for its query session: the registered pose times the inverse of
// the keyframe's pose in its session.
Eigen::Isometry3d ImpliedAnchor(const LoopRecord& loop, const std::vector<AnchorSession>& sessions);

// Two loops of one query session agree: the query keyframe of b, placed through a's anchor and
// the odometry, lies where b's registration put it, within the consistency bounds that grow
// with the distance travelled between the two keyframes.
bool Consistent(const LoopRecord& a, const LoopRecord& b,
                const std::vector<AnchorSession>& sessions, const AnchorConfig& config);

// The cliques of mutually consistent loops among `loops` (indices into records): the largest
// first, then the largest among the loops that disagree with every clique found so far, while a
// clique has at least min_clique loops and rival_min_ratio of the first's; at most
// max_hypotheses. A clique whose loops see through the model (median seen_through over
// max_seen_through) is passed over: not returned, but added to `passed_over` when given;
// max_cliques bounds the search.
std::vector<std::vector<size_t>> ConsistentHypotheses(
    const std::vector<LoopRecord>& records, const std::vector<size_t>& loops,
    const std::vector<AnchorSession>& sessions, const AnchorConfig& config,
    std::vector<std::vector<size_t>>* passed_over = nullptr);

}  // namespace bimslam::anchor
