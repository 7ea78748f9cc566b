// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Anchoring sessions whose odometry failed in places (internal to host_tools/anchor; pieces.hpp
// says why): the queries split into pieces that the anchoring treats as sessions of their own, and
// its result gathered back into one SessionResult per query with its pieces.
#pragma once

#include <vector>

#include "host_tools/anchor/anchoring.hpp"
#include "host_tools/anchor/pieces.hpp"

namespace bimslam::anchor {

// Where each session of SplitQueries::sessions came from: the input session and its keyframes.
struct PieceOrigin {
    size_t session = 0;
    KeyframeSpan span;
};

struct SplitQueries {
    // The reference, then each query whole (odometry trusted or not judged) or its pieces.
    std::vector<AnchorSession> sessions;
    std::vector<PieceOrigin> origin;   // per entry of sessions
    std::vector<SessionSplit> splits;  // per input session (empty for whole ones)
};

// Copies of the input sessions with every query that has failed stretches replaced by its pieces.
SplitQueries SplitAtUntrustedOdometry(const std::vector<AnchorSession>& sessions);

// The result of anchoring parts.sessions gathered back to the input sessions: a whole query's
// result as it is; a split query's from its pieces (CombinePieces; world_poses and placed for the
// keyframes of its anchored pieces; the counts summed); loops renumbered to the input sessions
// and their keyframes.
AnchorResult MergePieces(const std::vector<AnchorSession>& sessions, const SplitQueries& parts,
                         AnchorResult anchored);

}  // namespace bimslam::anchor
