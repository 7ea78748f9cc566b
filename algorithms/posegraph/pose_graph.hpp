// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// A multi-session pose graph with anchor nodes (Kim, Kaess, Fletcher, Leonard, Bachrach, Roy,
// Teller, "Multiple relative pose graphs for robust cooperative mapping", ICRA 2010; the
// LT-mapper line of work), solved with Ceres.
//
// Each session s has its keyframe poses x_s,k in its own frame (T_local_lidar) and an anchor
// Delta_s (T_world_local) that places that frame in the shared world; a keyframe's world pose is
// Delta_s * x_s,k.
//
// Factors:
//   odometry  between x_s,i and x_s,j of one session: Log(z^-1 x_s,i^-1 x_s,j), z = T_i_j measured,
//             with a Cauchy loss (odometry_loss_scale);
//   loop      between keyframe i of session a and j of session b, the BIM-SLAM paper's eq. 2:
//             Log(c^-1 (Delta_a x_a,i)^-1 (Delta_b x_b,j)), c = T_ai_bj measured (the pose of b's
//             keyframe in a's), with a robust loss;
//   prior     on one keyframe's world pose: Log(z^-1 Delta_s x_s,k), z = T_world_lidar where an
//             earlier anchoring put it, quadratic (an earlier visit held by its own uncertainty,
//             as LT-mapper holds its earlier sessions);
// each whitened by the square root of its information matrix. Both residuals are right
// perturbations of the second pose ("where b's keyframe is, seen from a's"), the frame in which
// registration (algorithms/registration) states its information; a test builds a pair with a
// known transform and checks the residual is zero, because getting this direction wrong is a known
// failure of implementations in the field.
//
// The residual is [t_err; 2 vec(q_err)] of T_err = z^-1 (...): the SE(3) logarithm to first order
// (Ceres' pose_graph_3d example), exact at zero, where it matters.
//
// Fixed sessions (the BIM reference). The paper holds S_GT with priors of variance 1e-100; here its
// anchor and poses are constant parameter blocks, which is the limit of that prior and keeps the
// problem well conditioned (a 1e-100 variance is a 1e100 weight). Gauge of the other sessions:
// their first keyframe is held at its odometry pose, so the anchor alone carries where the session
// lies in the world; without that, Delta_s and every x_s,k could move together freely.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "algorithms/common/se3.hpp"

namespace bimslam::posegraph {

struct OdometryFactor {
    size_t session = 0;
    size_t from = 0, to = 0;
    Eigen::Isometry3d T_from_to = Eigen::Isometry3d::Identity();
    common::Matrix6d information = common::Matrix6d::Identity();  // over [rho; phi]
};

struct LoopFactor {
    size_t session_a = 0, index_a = 0;
    size_t session_b = 0, index_b = 0;
    Eigen::Isometry3d T_a_b = Eigen::Isometry3d::Identity();      // c: b's keyframe in a's
    common::Matrix6d information = common::Matrix6d::Identity();  // over [rho; phi] of b
};

// A keyframe's world pose held where it was estimated before, with that estimate's information.
struct PriorFactor {
    size_t session = 0, index = 0;
    Eigen::Isometry3d T_world_lidar = Eigen::Isometry3d::Identity();  // z
    common::Matrix6d information = common::Matrix6d::Identity();      // over [rho; phi]
};

struct PoseGraphConfig {
    // Cauchy loss on the whitened loop residual, in standard deviations: a loop whose residual is
    // this many sigmas counts half as much as a quadratic would let it.
    double loop_loss_scale = 3.0;
    // Off for graduated non-convexity, which weighs the loops itself.
    bool robust_loops = true;
    // Cauchy loss on odometry edges too, in standard deviations; 0: none. An odometry that
    // loses track for a moment (a doorway, a jolt) makes one edge tens of sigmas wrong; without
    // a robust loss that edge outvotes the loops on both sides of it.
    double odometry_loss_scale = 3.0;
    // The robust losses' scales are multiplied by these in turn, each solve starting where the
    // last ended: a wide Cauchy is nearly quadratic, so a residual tens of sigmas off still
    // pulls (a loop that proximity found after a broken odometry edge) instead of sitting in the
    // flat tail where the loss ignores it; then the scale narrows to its value (graduated
    // non-convexity, as Black and Rangarajan 1996).
    std::vector<double> annealing = {16.0, 4.0, 1.0};
    int max_iterations = 100;
    int threads = 2;
    void Validate() const;
};

struct OptimizeSummary {
    bool converged = false;
    int iterations = 0;
    double initial_cost = 0, final_cost = 0;
    double seconds = 0;
    std::string message;  // Ceres' own, when it did not converge
};

class PoseGraph {
public:
    // A session with its keyframe poses (its own frame) and the anchor's initial value. A fixed
    // session never moves; any other holds its first pose.
    size_t AddSession(std::vector<Eigen::Isometry3d> poses, const Eigen::Isometry3d& anchor,
                      bool fixed);
    void AddOdometry(const OdometryFactor& f);  // throws common::Error for a bad index
    size_t AddLoop(const LoopFactor& f);        // the loop's index
    void AddPrior(const PriorFactor& f);        // throws common::Error for a bad index

    // Optimises with the loops whose weight is > 0 (all when `loop_weights` is empty; a weight
    // scales the loop's information, as graduated non-convexity needs).
    OptimizeSummary Optimize(const PoseGraphConfig& config,
                             const std::vector<double>& loop_weights = {});

    size_t sessions() const { return sessions_.size(); }
    size_t keyframes(size_t s) const { return sessions_.at(s).poses.size(); }
    const std::vector<LoopFactor>& loops() const { return loops_; }
    const std::vector<OdometryFactor>& odometry() const { return odometry_; }
    const std::vector<PriorFactor>& priors() const { return priors_; }
    bool fixed(size_t s) const { return sessions_.at(s).fixed; }

    const Eigen::Isometry3d& anchor(size_t s) const { return sessions_.at(s).anchor; }
    void SetAnchor(size_t s, const Eigen::Isometry3d& T_world_local);
    const Eigen::Isometry3d& pose(size_t s, size_t k) const { return sessions_.at(s).poses.at(k); }
    Eigen::Isometry3d WorldPose(size_t s, size_t k) const { return anchor(s) * pose(s, k); }
    // Resets a session's poses (e.g. to its odometry, before trying another hypothesis).
    void SetPoses(size_t s, std::vector<Eigen::Isometry3d> poses);

    // The whitened residual of a loop at the current estimate ([rho; phi], unit covariance) and
    // its squared norm (chi-square with 6 degrees of freedom when the loop is right).
    common::Vector6d LoopResidual(size_t loop) const;
    double LoopChi2(size_t loop) const { return LoopResidual(loop).squaredNorm(); }

private:
    struct Session {
        std::vector<Eigen::Isometry3d> poses;
        Eigen::Isometry3d anchor = Eigen::Isometry3d::Identity();
        bool fixed = false;
    };
    std::vector<Session> sessions_;
    std::vector<OdometryFactor> odometry_;
    std::vector<LoopFactor> loops_;
    std::vector<PriorFactor> priors_;
};

// The residual both factors use: [t; 2 vec(q)] of z^-1 * T_a^-1 * T_b, whitened by sqrt_info.
// Exposed for tests (the known-transform pair must give zero).
common::Vector6d RelativePoseResidual(const Eigen::Isometry3d& z, const Eigen::Isometry3d& T_a,
                                      const Eigen::Isometry3d& T_b);

// The square root of a symmetric positive semi-definite information matrix: S with S^T S = I
// (zero rows along null directions, so degenerate loops constrain only what they measured).
common::Matrix6d SqrtInformation(const common::Matrix6d& information);

// A multi-session g2o file (LT-mapper's convention): vertex ids session * 1000000 + keyframe,
// holding world poses; EDGE_SE3:QUAT for odometry and loops (information over [x y z rx ry rz],
// upper triangle); FIX for the vertices of fixed sessions.
std::string SerializeMultiSessionG2o(const PoseGraph& graph);

}  // namespace bimslam::posegraph
