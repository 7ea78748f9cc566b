// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Sessions placed in the BIM frame with the simulator's ground truth: what `bimslam anchor` will
// write, made exactly, for developing and testing change detection before anchoring exists (and
// for separating its errors from anchoring's later).
//
// A capture's ground_truth.tum holds T_bim_sensor at column 0 of every lidar frame, stamped in the
// sensor clock; a session's keyframe stamp (times.txt) is the start of its scan in the same clock,
// and the project's lidar frame is the Ouster sensor frame. So each keyframe's T_bim_lidar is the
// ground-truth pose with exactly its stamp: the lookup is exact, and a stamp without a pose is an
// error, never interpolated.
#pragma once

#include <filesystem>

namespace bimslam::test {

struct GroundTruthPlacement {
    size_t keyframes = 0;
    size_t scans = 0;
};

// Writes `out` (refused when it exists) as a copy of the odometry session `session` with
// frames.world = "bim", optimized_poses.txt = the ground truth at each keyframe's stamp,
// odom_poses.txt = the session's own poses, and trajectory.tum = the ground truth at every scan.
// Throws common::Error naming the stamp and the file when the ground truth has no pose at it, and
// what the session and TUM readers throw.
GroundTruthPlacement PlaceSessionOnGroundTruth(const std::filesystem::path& session,
                                               const std::filesystem::path& ground_truth_tum,
                                               const std::filesystem::path& out);

}  // namespace bimslam::test
