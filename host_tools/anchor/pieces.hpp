// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// A query session whose odometry failed somewhere (issue 32, item 3; issue 31, item 5): the
// odometry's own verdict, written into the session by `bimslam odometry` / `bimslam map`
// (odometry_verdict.json: algorithms/odometry/trajectory_trust.hpp), names the stretches of scans
// whose registration failed. A keyframe's pose across such a stretch is only as good as the guess
// the failed scans kept, so anchoring splits the session there: each piece (a run of keyframes
// with no failed scan between any two of them) is anchored on its own, as a session of its own,
// and no odometry edge joins two pieces. Keyframes inside a stretch are in no piece and are never
// placed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "algorithms/io/session.hpp"

namespace bimslam::anchor {

struct AnchorSession;

// One stretch of scans whose registration failed, as odometry_verdict.json gives it.
struct OdometryStretch {
    size_t first_scan = 0, last_scan = 0;  // scan indices of the odometry run, inclusive
    double first_s = 0, last_s = 0;        // seconds since the run's first scan
    int64_t first_ns = 0, last_ns = 0;     // the scans' stamps (trajectory.tum's, times.txt's)
    size_t failed = 0;                     // failed scans in it
    std::vector<std::string> reasons;
    // "scans 120-131 (12.0-13.1 s: low overlap)"
    std::string Describe() const;
};

// The odometry's verdict on a session: "trusted", "untrusted", or empty when the session has no
// odometry_verdict.json (a rig's session, another tool's, or one written before the file was).
struct OdometryVerdict {
    std::string verdict;
    std::vector<OdometryStretch> stretches;  // empty unless untrusted
    // Where the odometry saw its height again while uncertain (odometry::kHeightAmbiguous): the
    // height may be off by whole stair risers from there on (the relocaliser reads it).
    std::vector<OdometryStretch> height_ambiguous;
    // Where the scans did not see the height for longer than the odometry allows
    // (odometry::TrajectoryTrust::kMaxHeightUnseenS): the accelerometers' height drifted there.
    std::vector<OdometryStretch> height_unseen;
};

inline constexpr const char* kOdometryVerdictFile = "odometry_verdict.json";

// Reads DIR/odometry_verdict.json; an empty verdict when there is none. Throws common::FileError
// naming the file for a malformed one (a missing field, a stretch whose stamps run backwards, an
// untrusted verdict without stretches).
OdometryVerdict ReadOdometryVerdict(const std::filesystem::path& dir);

// A run of keyframes [first, last] (inclusive).
struct KeyframeSpan {
    size_t first = 0, last = 0;
    size_t size() const { return last - first + 1; }
    bool operator==(const KeyframeSpan&) const = default;
};

struct SessionSplit {
    std::vector<KeyframeSpan> pieces;  // in order; keyframes inside a stretch are in none
    std::vector<size_t> inside;        // keyframes whose scan lies inside a stretch
};

// Whether some stretch overlaps the times [a_ns, b_ns] (inclusive at both ends).
bool StretchBetween(const std::vector<OdometryStretch>& stretches, int64_t a_ns, int64_t b_ns);

// Per odometry edge (from, to: indices into keyframes): whether the odometry said it did not
// know its height between the two keyframes, a height-unseen or height-ambiguous stretch of `v`
// overlapping the times from the one to the other. Such an edge's height may be off by whole
// stair risers (OdometryBreaks, graph_state.hpp). Empty when `v` has no such stretch.
std::vector<bool> HeightUnsureEdges(const std::vector<io::SessionEdge>& edges,
                                    const std::vector<io::SessionKeyframe>& keyframes,
                                    const OdometryVerdict& v);

// The pieces of a session whose keyframes' scans were taken at keyframe_ns (increasing): a
// keyframe whose stamp lies inside a stretch is in no piece; two consecutive keyframes are in one
// piece unless a stretch overlaps the times from the one to the other.
SessionSplit SplitAtStretches(const std::vector<int64_t>& keyframe_ns,
                              const std::vector<OdometryStretch>& stretches);

// The keyframes of `span` as a session of their own: poses, descriptors, clouds, distances along
// the path (from the span's first keyframe), the odometry edges with both ends inside (renumbered),
// and the scans of trajectory.tum between its first and last keyframe. Named NAME[first-last].
AnchorSession MakePiece(const AnchorSession& session, const KeyframeSpan& span);

}  // namespace bimslam::anchor
