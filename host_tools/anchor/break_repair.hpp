// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// A trusted odometry that a solution breaks (internal to host_tools/anchor): the loops on the
// wrong side of the breaks dropped and the graph solved again (break_repair.cpp says why).
#pragma once

#include <optional>
#include <vector>

#include "host_tools/anchor/graph_state.hpp"

namespace bimslam::anchor {

struct BreakRepair {
    std::vector<SessionResult::OdometryBreak> found;  // the breaks of the state given
    std::vector<State> state;                         // solved with `kept`
    std::vector<LoopRecord> kept, dropped;            // `loops` split
    size_t explained = 0;                             // session q's loops within max_loop_chi2
    std::vector<SessionResult::OdometryBreak> left;   // what `state` still breaks
};

// Session q's odometry edges that `state` (solved with `loops`) breaks split q's keyframes into
// pieces (the components of the unbroken edges). Each piece is tried as the right one: the loops
// holding a keyframe of q outside it are left out, the graph solved, and the loops of q that
// solution explains (chi2 up to config.max_loop_chi2, every loop in the graph at the solved
// poses) are kept with all other sessions' loops; the rest are dropped and the graph solved
// again. The piece whose solution explains most of q's loops wins (then the fewest breaks left).
// Nothing (nullopt) when q has no break, when its pieces stay joined by other edges, or when
// the best repair drops no loop or leaves as many breaks as it found.
std::optional<BreakRepair> RepairBreaks(const std::vector<AnchorSession>& sessions,
                                        const std::vector<State>& state,
                                        const std::vector<LoopRecord>& loops, size_t q,
                                        const AnchorConfig& config, StageTimes* times);

}  // namespace bimslam::anchor
