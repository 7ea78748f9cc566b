// Following one hypothesis (internal to host_tools/anchor, step 3 of anchoring.hpp): the pose
// graph from its loops, rounds of proximity registration from the estimate until the accepted
// loops stop changing, the loops the solution cannot explain dropped, and the free-space evidence
// at the end.
#pragma once

#include <Eigen/Geometry>
#include <functional>
#include <vector>

#include "host_tools/anchor/anchoring.hpp"
#include "host_tools/anchor/graph_state.hpp"
#include "host_tools/anchor/target.hpp"

namespace bimslam::anchor {

struct Evaluation {
    Hypothesis hypothesis;
    int clique = -1;  // the clique (place-recognition hypothesis) it started from
    State query;
    std::vector<LoopRecord> accepted;
    std::vector<LoopRecord> rejected;  // the last round's rejected proximity candidates
};

// Whether two poses differ by more than (m, deg).
bool Apart(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double m, double deg);

// Proximity loops of session q's keyframes placed at `world`: each keyframe j with wanted(j)
// whose nearest target keyframe (within the proximity radius and height) passes use_target is
// registered from its estimate (from AnchorConfig::proximity_first_level) and verified; one that
// moved farther than the gate from its estimate is not.
std::vector<LoopRecord> ProximityLoops(const std::vector<AnchorSession>& sessions,
                                       const Target& target,
                                       const std::vector<Eigen::Isometry3d>& world, size_t q,
                                       const std::function<bool(size_t)>& wanted,
                                       const std::function<bool(const TargetKeyframe&)>& use_target,
                                       const AnchorConfig& config, StageTimes* times);

// Follows a hypothesis whose place-recognition loops are seed_loops; the query's state starts at
// its odometry, placed by `anchor`; the other sessions stay where `state` has them.
Evaluation FollowHypothesis(const std::vector<AnchorSession>& sessions, std::vector<State> state,
                            size_t q, const Target& target, std::vector<LoopRecord> seed_loops,
                            const Eigen::Isometry3d& anchor, const AnchorConfig& config,
                            StageTimes* times);

}  // namespace bimslam::anchor
