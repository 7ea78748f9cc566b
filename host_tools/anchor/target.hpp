// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// What query keyframes are registered to: the surfel maps of one or more sessions' keyframe
// clouds placed at their world poses (the BIM reference; later also anchored query sessions),
// their keyframes' world poses and a Scan Context index over their descriptors. Loops found
// against it are attached to the target keyframe they were registered at (place recognition)
// or the nearest one (proximity), so each loop is a factor between two keyframes.
#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <limits>
#include <memory>
#include <vector>

#include "algorithms/localization/walked_space.hpp"
#include "algorithms/registration/registration.hpp"
#include "algorithms/scancontext/candidate_index.hpp"
#include "host_tools/anchor/anchor_config.hpp"
#include "host_tools/anchor/anchor_session.hpp"

namespace bimslam::anchor {

struct TargetKeyframe {
    size_t session = 0, index = 0;  // into the sessions given to Anchor
    Eigen::Isometry3d T_world_lidar = Eigen::Isometry3d::Identity();
};

class Target {
public:
    static constexpr size_t kNone = std::numeric_limits<size_t>::max();

    // The keyframes of `members` (session index, world poses of its keyframes).
    Target(const std::vector<AnchorSession>& sessions,
           const std::vector<std::pair<size_t, std::vector<Eigen::Isometry3d>>>& members,
           const AnchorConfig& config);

    const registration::SurfelPyramid& map() const { return *map_; }
    const std::vector<TargetKeyframe>& keyframes() const { return keyframes_; }
    const scancontext::CandidateIndex& index() const { return index_; }
    bool Contains(size_t session) const;
    // The keyframe nearest to p within radius (horizontal) and height (vertical), or kNone.
    size_t Nearest(const Eigen::Vector3d& p, double radius, double height) const;
    // Where its keyframes stand (LoopRules::floating_radius_m and _height_m): what a placement
    // of a query floats over or under (Hypothesis::floating).
    const localization::WalkedSpace& walked() const { return walked_; }

private:
    void MarkPorous(const std::vector<AnchorSession>& sessions, const AnchorConfig& config);

    std::unique_ptr<registration::SurfelPyramid> map_;
    std::vector<TargetKeyframe> keyframes_;
    scancontext::CandidateIndex index_;
    localization::WalkedSpace walked_;
    std::vector<size_t> sessions_;
};

}  // namespace bimslam::anchor
