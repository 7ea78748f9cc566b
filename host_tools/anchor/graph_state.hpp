// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The sessions' state during anchoring and the pose graph built from it (internal to
// host_tools/anchor): where each session is, the graph of its odometry and the given loops,
// optimisation that reads the free sessions back, and graduated non-convexity's loop weights.
#pragma once

#include <Eigen/Geometry>
#include <vector>

#include "algorithms/posegraph/pose_graph.hpp"
#include "host_tools/anchor/anchoring.hpp"

namespace bimslam::anchor {

// Where a session is: its anchor and keyframe poses, and whether it may move.
struct State {
    Eigen::Isometry3d anchor = Eigen::Isometry3d::Identity();
    std::vector<Eigen::Isometry3d> poses;
    bool fixed = true;
    // Held by a prior on each keyframe at the session's own (world) poses: an earlier visit.
    bool held = false;
    std::vector<Eigen::Isometry3d> World() const;
};

// The graph of every session (fixed ones constant), the odometry edges of the free ones (their
// information times config.odometry_information_scale), a prior on each keyframe of the held
// ones (at AnchorSession::poses, config.earlier_sigma_*) and the loops (those to the reference,
// session 0, with the model's tolerance added: WithModelTolerance).
posegraph::PoseGraph BuildGraph(const std::vector<AnchorSession>& sessions,
                                const std::vector<State>& state,
                                const std::vector<LoopRecord>& loops, const AnchorConfig& config);

// A loop's information with the model's covariance added: (H^+ + Sigma)^-1, computed as
// (I + H Sigma)^-1 H so that directions the registration left unconstrained (H's null space)
// stay without information.
Eigen::Matrix<double, 6, 6> WithModelTolerance(const Eigen::Matrix<double, 6, 6>& information,
                                               double sigma_m, double sigma_deg);

// Optimises (config.graph unless graph_config) and reads the free sessions back; returns the
// largest keyframe move (m). The graph goes to *out when given.
double OptimizeStates(const std::vector<AnchorSession>& sessions, std::vector<State>* state,
                      const std::vector<LoopRecord>& loops, const AnchorConfig& config,
                      StageTimes* times, const std::vector<double>& weights = {},
                      const posegraph::PoseGraphConfig* graph_config = nullptr,
                      posegraph::PoseGraph* out = nullptr);

// GNC-TLS's weight of a residual r2 (squared, whitened) at the threshold c2 (the squared
// c-bar) and control parameter mu: Yang et al. 2020 (below), Prop. 4, Eq. (14): 1 for
// r2 <= mu / (mu + 1) c2, 0 for r2 >= (mu + 1) / mu c2, sqrt(c2 mu (mu + 1) / r2) - mu between.
double GncTlsWeight(double r2, double c2, double mu);
// The first mu, c2 / (2 max_r2 - c2) (ibid., Remark 5): the surrogate cost is convex over every
// residual, so no loop starts excluded. For max_r2 > c2.
double GncInitialMu(double max_r2, double c2);

// GNC with a truncated least squares cost (Yang, Antonante, Tzoumas, Carlone, "Graduated
// Non-Convexity for Robust Spatial Perception", RA-L 2020, Prop. 4): the loops' weights go from
// the convex surrogate (all in) to TLS (0 or 1) as mu grows; returns the final weights.
std::vector<double> GncWeights(const std::vector<AnchorSession>& sessions,
                               std::vector<State>* state, const std::vector<LoopRecord>& loops,
                               const AnchorConfig& config, StageTimes* times);

// The odometry edges whose relative pose in `poses` (a session's keyframes, solved) is off the
// measured one by more than max_m or max_deg (SessionResult::odometry_breaks). An edge marked in
// `height_unsure` (HeightUnsureEdges, pieces.hpp: the odometry said it did not know its height
// between the two keyframes) counts its offset in the horizontal only (the local frame's, which
// the IMU levels): on the held-out Office_A's Go1 climb the odometry's height fell 0.26 and
// 0.40 m over two such edges, the loops upstairs said so, and as breaks the repair dropped those
// 22 right loops (keyframes 34.7 cm RMSE, called anchored).
std::vector<SessionResult::OdometryBreak> OdometryBreaks(
    const std::vector<io::SessionEdge>& edges, const std::vector<Eigen::Isometry3d>& poses,
    double max_m, double max_deg, const std::vector<bool>& height_unsure = {});

// The same for session s's edges, unsure where its odometry_verdict.json says so.
std::vector<SessionResult::OdometryBreak> OdometryBreaks(
    const AnchorSession& s, const std::vector<Eigen::Isometry3d>& poses,
    const AnchorConfig& config);

}  // namespace bimslam::anchor
