// Scan-to-map registration: point-to-plane ICP against the VoxelMap's planes, solved with Ceres;
// optionally LOAM edge points point-to-line against an edge map (edge_features.hpp).
//
// Why point-to-plane, and edges off by default: measured on the project's 3-minute captures
// (README.md, "Why point-to-plane ..."), adding LOAM edges took 1.25-1.6x the time per scan and
// lowered the error by 4 % (0.4 mm); without the IMU, on a hand-held walk, it diverged once.
// The planes of 0.6 m voxels already give every wall, floor and ceiling point a correspondence.
//
// The unknown is a perturbation delta = [rho; phi] of the initial guess T0 on the right
// (the lidar frame): R = R0 Exp(phi), t = t0 + R0 rho. Each correspondence i (scan point p_i,
// plane n_i . x = d_i) gives the residual r_i = sqrt(w_i) (n_i . (R p_i + t) - d_i) with the
// exact Jacobian dr/drho = sqrt(w_i) n_i^T R0, dr/dphi = sqrt(w_i) (p_i x R^T n_i)^T J_r(phi)
// (Barfoot, "State Estimation for Robotics", eq. 7.77; J_r(phi) = J_l(-phi)).
//
// Robust loss: Cauchy, applied by iteratively reweighted least squares: each outer iteration
// finds correspondences at the current pose and sets w_i = 1 / (1 + (r_i / c)^2); Ceres then
// solves the weighted problem. c is annealed from coarse to fine (graduated non-convexity, as in
// Yang et al., "GNC", RA-L 2020). Correspondences farther than max_correspondence_distance are not
// made at all.
//
// Degeneracy (Zhang, Kaess, Singh, "On Degeneracy of Optimization-based State Estimation
// Problems", ICRA 2016): the eigenvalues of the normal equations H = J^T W J, with rotation
// scaled by the mean range so that both halves are in metres, divided by the weight sum: a
// direction whose share of the constraints is below degenerate_ratio (a long corridor's axis)
// takes its value from the initial guess (the motion prior) instead of the scan:
// delta <- (I - V_d V_d^T) delta.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <chrono>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "algorithms/common/se3.hpp"
#include "algorithms/odometry/voxel_map.hpp"

namespace bimslam::odometry {

struct RegistrationConfig {
    int max_iterations = 20;                   // outer: correspondences found again
    int max_solver_iterations = 4;             // Ceres iterations per outer iteration
    double max_correspondence_distance = 0.5;  // m
    // The Cauchy scale is annealed: it starts at cauchy_scale_initial, so that a prediction a
    // few decimetres off still pulls every point, and halves each outer iteration down to
    // cauchy_scale, near the range noise, where outliers (people, clutter) stop counting.
    double cauchy_scale = 0.02;         // m
    double cauchy_scale_initial = 0.1;  // m
    int min_correspondences = 60;
    // Converged when an outer iteration moves the pose less than this.
    double converged_translation = 1e-3;  // m
    double converged_rotation = 1e-4;     // rad
    double degenerate_ratio = 0.01;

    void Validate() const;
};

struct RegistrationResult {
    Eigen::Isometry3d T_map_lidar = Eigen::Isometry3d::Identity();
    // Covariance of the right perturbation [rho; phi] of T_map_lidar: s^2 H^-1 with the residual
    // variance s^2, and prior_sigma^2 along degenerate directions.
    common::Matrix6d covariance = common::Matrix6d::Identity();
    int iterations = 0;
    int correspondences = 0;
    double rms = 0;  // m, of the weighted residuals at the end
    int degenerate_directions = 0;
    double min_eigen_ratio = 0;  // smallest constraint share over the 6 directions
    bool converged = false;
    bool over_budget = false;  // stopped by the deadline; the best estimate so far
    bool failed = false;       // too few correspondences: T_map_lidar is the initial guess
};

class ScanRegistration {
public:
    using Clock = std::chrono::steady_clock;

    // max_points: scan points plus twice the edge points registered at most.
    explicit ScanRegistration(const RegistrationConfig& config = {}, size_t max_points = 8192);
    ~ScanRegistration();

    // Registers `points` (lidar frame) to `map` starting from T0. Returns at the deadline with
    // what it has. prior_sigma: the initial guess's standard deviations [m, m, m, rad, rad, rad]
    // (the covariance along degenerate directions).
    // With `edges` and an `edge_map` (fit_lines), LOAM's edge points join in: point-to-line,
    // as two point-to-plane residuals on planes through the line, orthogonal to each other.
    const RegistrationResult& Align(std::span<const Eigen::Vector3f> points, const VoxelMap& map,
                                    const Eigen::Isometry3d& T0,
                                    const common::Vector6d& prior_sigma, Clock::time_point deadline,
                                    std::span<const Eigen::Vector3f> edges = {},
                                    const VoxelMap* edge_map = nullptr);

    const RegistrationConfig& config() const { return config_; }

private:
    struct Correspondence {
        Eigen::Vector3d p;  // lidar frame
        Eigen::Vector3d n;  // map frame
        double d = 0;
        double sqrt_w = 1;
    };
    class Cost;
    int Associate(std::span<const Eigen::Vector3f> points, const VoxelMap& map,
                  std::span<const Eigen::Vector3f> edges, const VoxelMap* edge_map,
                  const Eigen::Isometry3d& T, double cauchy_scale);

    RegistrationConfig config_;
    std::vector<Correspondence> corr_;
    RegistrationResult result_;
};

// T0 * [rho; phi] as the registration applies it: R0 Exp(phi), t0 + R0 rho.
Eigen::Isometry3d ApplyPerturbation(const Eigen::Isometry3d& T0, const common::Vector6d& delta);

}  // namespace bimslam::odometry
