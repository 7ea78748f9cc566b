// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// A session to compare with the model: what `bimslam anchor` writes (specs/session-data.md with
// frames.world = "bim": optimized_poses.txt holds every keyframe's T_bim_lidar), read and checked.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "algorithms/changes/aligned_map.hpp"
#include "algorithms/changes/pose_refinement.hpp"
#include "algorithms/io/session.hpp"

namespace bimslam::change_detection {

struct SessionInput {
    SessionInput() = default;
    SessionInput(const SessionInput&) = delete;  // keyframes point into session
    SessionInput(SessionInput&&) = default;

    std::filesystem::path dir;
    io::Session session;
    // Views into session.keyframes, with the poses moved by -origin_m (the model's local origin,
    // bim::BimModel::origin_m), so that they are in the frame of the model's mesh.
    std::vector<changes::MapKeyframe> keyframes;
    // The session's odometry and loop edges (singlesession_posegraph.g2o), which hold the
    // keyframes together when change detection refines their poses.
    std::vector<changes::KeyframeEdge> edges;
    size_t points = 0;
};

// Throws common::FileError (kInvalidArgument) naming the session when it is not one, its world
// frame is not "bim" (it has not been anchored: run `bimslam anchor` first) or it has no keyframes
// or no points, and what io::ReadSession throws for a damaged one. load_clouds = false checks all
// that but the points, quickly (before the model is loaded).
SessionInput LoadAnchoredSession(const std::filesystem::path& dir, const Eigen::Vector3d& origin_m,
                                 bool load_clouds = true);

}  // namespace bimslam::change_detection
