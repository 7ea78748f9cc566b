// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Where the model's walks went, to judge a placement by the walk's heights (issue 31, item 5):
// the reference walks every storey its stairs reach, so a query keyframe that a placement puts
// over or under all of them (reference keyframes near it horizontally, none at its height) stands
// a storey off, above the top storey or below the lowest. Counted per hypothesis offline
// (host_tools/anchor, Hypothesis::floating) and per clique live (relocalizer.cpp), and compared
// by LoopRules::HeightsPrefer.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace bimslam::localization {

class WalkedSpace {
public:
    // `walked`: the positions (model frame) of the walks' keyframes. A position floats when some
    // lie within `radius` horizontally and none of those within `height` vertically.
    WalkedSpace(const std::vector<Eigen::Vector3d>& walked, double radius, double height);
    WalkedSpace() = default;  // no walks: nothing floats

    bool Floats(const Eigen::Vector3d& p) const;
    // How many of `positions` (odometry frame) float when placed by T (model from odometry).
    size_t Floating(const std::vector<Eigen::Vector3d>& positions,
                    const Eigen::Isometry3d& T) const;

private:
    int64_t Key(int64_t i, int64_t j) const { return (i << 32) ^ (j & 0xffffffff); }

    double radius_ = 1, height_ = 1;
    // Grid cells of radius_ (x, y): a position's neighbours lie in its cell and the 8 around it.
    std::unordered_map<int64_t, std::vector<Eigen::Vector3d>> cells_;
};

}  // namespace bimslam::localization
