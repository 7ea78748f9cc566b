// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// What `bimslam anchor` writes (README.md of this folder documents each file):
//   OUT/anchor.json        verdict per query session with the numbers behind it, anchors,
//                          hypotheses, stage times, what was derived for foreign sessions
//   OUT/loops.json         every loop candidate: indices, descriptor distance, yaw, fitness,
//                          accepted or rejected with the reason
//   OUT/posegraph.g2o      the multi-session graph (posegraph::SerializeMultiSessionG2o)
//   OUT/<query>/           each anchored session in the session-data layout, world frame "bim",
//                          with trajectory_bim.tum (every scan, placed by its odometry between
//                          keyframes); of a session anchored in parts, the keyframes and scans of
//                          its anchored pieces only
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "host_tools/anchor/anchoring.hpp"

namespace bimslam::anchor {

// anchor.json's content.
std::string AnchorSummaryJson(const std::vector<AnchorSession>& sessions,
                              const AnchorResult& result, const AnchorConfig& config);
std::string LoopsJson(const std::vector<AnchorSession>& sessions, const AnchorResult& result);

// Every scan of a session's trajectory placed in the world: the correction world-from-local of
// the keyframes around it, interpolated in time (before the first and after the last keyframe,
// theirs). Without a trajectory, the keyframes' world poses.
std::vector<io::StampedPose> WorldTrajectory(const AnchorSession& session,
                                             const std::vector<Eigen::Isometry3d>& world_poses);
// The same for a session anchored in parts: only keyframes with placed[k] count, and a scan is
// placed from a keyframe only when no failed stretch of the session's odometry lies between them
// (the correction is interpolated only between two such keyframes). Scans inside a stretch, or
// with no such keyframe on either side, are left out.
std::vector<io::StampedPose> WorldTrajectory(const AnchorSession& session,
                                             const std::vector<Eigen::Isometry3d>& world_poses,
                                             const std::vector<bool>& placed);

// Writes everything to `out`. Refuses (common::FileError) an existing non-empty folder unless
// overwrite. Returns the folders of the anchored sessions written.
std::vector<std::filesystem::path> WriteAnchorOutput(const std::filesystem::path& out,
                                                     const std::vector<AnchorSession>& sessions,
                                                     const AnchorResult& result,
                                                     const AnchorConfig& config, bool overwrite);

}  // namespace bimslam::anchor
