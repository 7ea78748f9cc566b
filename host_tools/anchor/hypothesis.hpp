// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Following one hypothesis (internal to host_tools/anchor, step 3 of anchoring.hpp): the pose
// graph from its loops, rounds of proximity registration from the estimate until the accepted
// loops stop changing, the loops the solution cannot explain dropped, and the free-space evidence
// at the end. hypothesis.cpp defines AnchoringProblem's FollowHypothesis and ProximityLoops;
// this header holds what they return.
#pragma once

#include <Eigen/Geometry>
#include <vector>

#include "host_tools/anchor/anchoring.hpp"
#include "host_tools/anchor/graph_state.hpp"

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

}  // namespace bimslam::anchor
