// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/anchor/target.hpp"

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>

#include "algorithms/common/status.hpp"

namespace bimslam::anchor {

Target::Target(const std::vector<AnchorSession>& sessions,
               const std::vector<std::pair<size_t, std::vector<Eigen::Isometry3d>>>& members,
               const AnchorConfig& config)
    : map_(std::make_unique<registration::SurfelPyramid>(config.registration)),
      index_(config.descriptor) {
    for (const auto& [s, world] : members) {
        const AnchorSession& session = sessions.at(s);
        if (world.size() != session.keyframes() || session.clouds.size() != session.keyframes()) {
            throw common::Error(common::StatusCode::kInvalidArgument,
                                "Target: session " + session.name + " without clouds or poses");
        }
        sessions_.push_back(s);
        for (size_t k = 0; k < world.size(); ++k) {
            keyframes_.push_back({s, k, world[k]});
            const common::Status st = index_.Add(session.descriptors[k]);
            if (!st.ok()) {
                throw common::Error(common::StatusCode::kInvalidArgument,
                                    session.name + ": keyframe " + std::to_string(k) +
                                        " descriptor: " + st.message());
            }
        }
    }
    std::vector<Eigen::Vector3d> walked;
    for (const TargetKeyframe& k : keyframes_) walked.push_back(k.T_world_lidar.translation());
    walked_ = localization::WalkedSpace(walked, config.floating_radius_m, config.floating_height_m);
    // The map's levels on their own threads (each the same sums in the same order as one after
    // another: the same maps), while the descriptor index builds.
    tbb::parallel_invoke(
        [&] {
            tbb::parallel_for(size_t(0), map_->levels(), [&](size_t li) {
                registration::SurfelMap& level = map_->mutable_level(li);
                for (const auto& [s, world] : members) {
                    for (size_t k = 0; k < world.size(); ++k) {
                        level.Add(sessions[s].clouds[k], world[k]);
                    }
                }
                level.Build();
            });
        },
        [&] { index_.Build(); });
    MarkPorous(sessions, config);
}

// The free-space level's surfels that the members' own rays pass through are porous
// (registration::MarkPorous): a railing's bars, which the 0.5 m surfels make a wall, otherwise
// count as seen through wherever a query looks across a stairwell (issue 35: Office_A's Go1 climb,
// whose right loops by the stair saw through 26 % of their rays). The model's own rays are no
// label: whatever they pass through is not solid where the target's sessions saw it.
void Target::MarkPorous(const std::vector<AnchorSession>& sessions, const AnchorConfig& config) {
    registration::SurfelMap& level = map_->mutable_level(config.free_space_level);
    std::vector<registration::SurfelRays> rays(keyframes_.size());
    tbb::parallel_for(size_t(0), keyframes_.size(), [&](size_t i) {
        const TargetKeyframe& k = keyframes_[i];
        rays[i] = registration::RaysAtSurfels(sessions[k.session].clouds[k.index], level,
                                              k.T_world_lidar, config.free_space);
    });
    registration::MarkPorous(&level, rays, config.free_space);
}

bool Target::Contains(size_t session) const {
    return std::find(sessions_.begin(), sessions_.end(), session) != sessions_.end();
}

size_t Target::Nearest(const Eigen::Vector3d& p, double radius, double height) const {
    size_t best = kNone;
    double best_d2 = radius * radius;
    for (size_t i = 0; i < keyframes_.size(); ++i) {
        const Eigen::Vector3d d = keyframes_[i].T_world_lidar.translation() - p;
        if (std::abs(d.z()) > height) continue;
        const double d2 = d.head<2>().squaredNorm();
        if (d2 <= best_d2) {
            best_d2 = d2;
            best = i;
        }
    }
    return best;
}

}  // namespace bimslam::anchor
