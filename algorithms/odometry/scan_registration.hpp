// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Scan-to-map registration: point-to-plane ICP against the VoxelMap's planes, solved by damped
// Gauss-Newton on the normal equations (12 unknowns; Ceres did it until stop 57: README.md,
// "Gauss-Newton without Ceres");
// optionally LOAM edge points point-to-line against an edge map (edge_features.hpp).
//
// Why point-to-plane, and edges off by default: measured on the project's 3-minute captures
// (README.md, "Why point-to-plane ..."), adding LOAM edges took 1.25-1.6x the time per scan and
// lowered the error by 4 % (0.4 mm); without the IMU, on a hand-held walk, it diverged once.
// The planes of 0.6 m voxels already give every wall, floor and ceiling point a correspondence.
//
// Unknowns. A perturbation delta = [rho; phi] of the initial guess T0 on the right (the lidar
// frame at the scan start): R = R0 Exp(phi), t = t0 + R0 rho; and a correction xi = [rho_x;
// phi_x] of the motion during the sweep the points were deskewed with (continuous time, as
// CT-ICP, Dellenbach et al., ICRA 2022, with the end pose written relative to the start). A
// point q_i deskewed to the scan start with the predicted motion, taken at the fraction alpha_i
// of the sweep, lies at
//   L_i = Exp(alpha_i phi_x) q_i + alpha_i rho_x      (the corrected deskew)
// and each correspondence (plane n_i . x = d_i) gives r_i = sqrt(w_i) (n_i . (R L_i + t) - d_i).
// Exact Jacobians: dr/drho = sqrt(w) n^T R0, dr/dphi = sqrt(w) (L x R^T n)^T J_r(phi) (Barfoot,
// "State Estimation for Robotics", eq. 7.77; J_r(phi) = J_l(-phi)); dr/drho_x = alpha sqrt(w)
// n^T R, dr/dphi_x = alpha sqrt(w) (q x E^T R^T n)^T J_r(alpha phi_x) with E = Exp(alpha
// phi_x), J_r taken as I (phi_x is a correction of a few degrees at most: only the convergence
// rate depends on it, not the solution). Exp(alpha phi_x) is evaluated to second order
// (I + [a]x + [a]x^2 / 2, a = alpha phi_x): its error, |a|^3 / 6, is 0.07 mm at 10 m for 2 deg.
// Why the correction: a scan deskewed with a motion that is wrong keeps the error in its shape,
// and no rigid pose fits it. Without the IMU the constant-velocity prediction cannot follow a
// Go1's trot (1.5 deg of roll at 2 Hz, 19 deg/s at its peak, lags a tenth of a second, so a
// sweep's rotation is off by up to 2 deg, 35 cm at 10 m); estimating the sweep's motion with the
// pose is what lets the scan fit (README.md, "LiDAR only"). The correction has a prior: zero
// with correction_sigma (over the sweep), so that it stays put where the scene cannot see it.
//
// Robust loss: Cauchy, applied by iteratively reweighted least squares: each outer iteration
// finds correspondences at the current pose and sets w_i = 1 / (1 + (r_i / c)^2); one Gauss-Newton
// step then solves the weighted problem. c is annealed from coarse to fine (graduated
// non-convexity, as in Yang et al., "GNC", RA-L 2020). Correspondences farther than the
// correspondence distance are not made at all; the caller adapts that distance to how good its
// predictions have been (KISS-ICP's adaptive threshold, lidar_odometry.hpp).
//
// Degeneracy (Zhang, Kaess, Singh, "On Degeneracy of Optimization-based State Estimation
// Problems", ICRA 2016): the information about delta with the correction marginalised out (the
// Schur complement of the normal equations H = J^T W J plus the correction's prior), with
// rotation scaled by the mean range so that both halves are in metres, divided by the weight
// sum: a direction whose share of the constraints is below degenerate_ratio (a long corridor's
// axis) takes its value from the initial guess (the motion prior) instead of the scan:
// delta <- (I - V_d V_d^T) delta, and the correction follows (its conditional optimum).
#pragma once

#include <Eigen/Cholesky>
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
    // The clock of the time budget (the deadline): wall time, or this thread's CPU time, so that
    // on a machine shared with other work (offline replay, CI) what the budget cuts is the
    // odometry's own work, not the time other processes took (LidarOdometry uses it too).
    bool cpu_time_budget = false;
    int max_iterations = 20;                   // outer: correspondences found again
    double max_correspondence_distance = 0.5;  // m
    // The Cauchy scale is annealed (graduated non-convexity): it starts at cauchy_scale_initial,
    // so that a prediction a few decimetres off still pulls every point, or at how far the
    // predictions have been off when that is less (AlignInput::prediction_error: the IMU's), and
    // is divided by cauchy_anneal each outer iteration down to cauchy_scale, where the points of
    // a surface the map holds a little askew stop pulling. Half the range noise (1 cm) and
    // sqrt(2) a step, against 2 cm and 2 before: on the tuning buildings' stair walks with the
    // IMU, three runs each, APE 0.67 -> 0.52 cm on average and the worst 2.31 -> 0.85 cm; the
    // finer scale alone or the slower steps alone did not (README.md, "A finer kernel, annealed
    // slowly").
    double cauchy_scale = 0.005;        // m
    double cauchy_scale_initial = 0.1;  // m
    double cauchy_anneal = 1.41421356;  // > 1: the kernel halves every two outer iterations
    // The scan's evidence (its degenerate directions, axis_share, rms and covariance) is weighed
    // at this scale, or the last kernel's when wider: the one degenerate_ratio and the odometry's
    // height_seen_share were set at. Weighed at the finer kernel, the few corner voxels whose
    // "plane" runs across two walls (their points on it, so weighted fully, while a wall's own
    // points sit a range noise off it) carried 5 times their share: a 2.4 m shaft's height
    // counted as seen from them and followed their noise 19.5 cm off (lidar_odometry_test.cpp,
    // AStopInAShaft...).
    double evidence_scale = 0.02;  // m
    int min_correspondences = 60;
    // Converged when an outer iteration moves the pose less than this. 1 mm and 1e-4 rad took
    // 11 outer iterations per LiDAR-only registration, one in ten stopped by max_iterations:
    // the last ones moved the pose by a millimetre back and forth as correspondences changed.
    // 3 mm and 3e-4 rad (1 mm at 3 m) took 26-38 % fewer, for the same or lower APE
    // (odometry README, "Time per scan").
    double converged_translation = 3e-3;  // m
    double converged_rotation = 3e-4;     // rad
    double degenerate_ratio = 0.01;
    // A correspondence whose point lies within this of its plane at the solution is an inlier
    // (RegistrationResult::inliers: the evidence registration_check.hpp judges a scan by).
    double inlier_distance = 0.1;  // m
    // Estimate the correction of the sweep's motion (header); off: a rigid scan.
    bool motion_correction = true;

    void Validate() const;
};

// What one registration is given besides the map.
struct AlignInput {
    std::span<const Eigen::Vector3f> points;  // lidar frame at the scan start (deskewed)
    std::span<const float> alpha;             // per point, its fraction of the sweep; empty: 0
    Eigen::Isometry3d T0 = Eigen::Isometry3d::Identity();
    // The initial guess's standard deviations [m, m, m, rad, rad, rad] (the covariance along
    // degenerate directions).
    common::Vector6d prior_sigma = common::Vector6d::Constant(0.05);
    // The prior of the motion correction over the sweep [m, m, m, rad, rad, rad]; zero: none
    // estimated.
    common::Vector6d correction_sigma = common::Vector6d::Zero();
    double max_correspondence_distance = 0;  // m; 0: the configuration's
    // How far T0 may be off (m, a point's displacement at the scene's extent, as LidarOdometry's
    // adaptive threshold measures its predictions); when positive the kernel starts at no more
    // than this. 0: unknown.
    double prediction_error = 0;
    // Keep T0's rotation and estimate the translation only (the gyro's rotation when the scan
    // contradicts it: LidarOdometryConfig::imu_rotation_gate).
    bool fix_rotation = false;
    std::span<const Eigen::Vector3f> edges;  // LOAM edge points (alpha 0), with edge_map
    const VoxelMap* edge_map = nullptr;
    // A direction (unit, T0's lidar frame; zero: none) whose evidence is measured (axis_share):
    // the constraints of surfaces that face it (their normals within 60 deg of it or of its
    // opposite). Walls whose normals noise tilts a few degrees constrain it in the normal
    // equations, by noise; a floor, a tread or a ceiling constrains it in fact.
    Eigen::Vector3d axis = Eigen::Vector3d::Zero();
    // When axis_share is under this, T0 is kept along the axis, as along a weak direction (the
    // height predicted from the accelerometers in a stairwell: imu_height.hpp); 0: never.
    double hold_axis_below = 0;
};

struct RegistrationResult {
    Eigen::Isometry3d T_map_lidar = Eigen::Isometry3d::Identity();
    // Covariance of the right perturbation [rho; phi] of T_map_lidar: s^2 H^-1 with the residual
    // variance s^2, and prior_sigma^2 along degenerate directions.
    common::Matrix6d covariance = common::Matrix6d::Identity();
    int iterations = 0;
    int correspondences = 0;
    int points = 0;  // scan points registered (in.points), the denominator of the ratios
    // Judged correspondences within inlier_distance of their plane at the solution.
    int inliers = 0;
    // Correspondences on line-like planes (VoxelPlane::line_like): registered, but left out of
    // the inliers' counts (registration_check.hpp). Included in `correspondences`.
    int unjudged = 0;
    double rms = 0;  // m, of the weighted residuals at the end
    int degenerate_directions = 0;
    // AlignInput::axis's evidence: the weights' share of the correspondences on surfaces that
    // face it, each weighted by its normal's cos^2 to it (0 when no axis was given).
    double axis_share = 0;
    bool axis_held = false;      // T0 kept along AlignInput::axis (hold_axis_below)
    double min_eigen_ratio = 0;  // smallest constraint share over the 6 directions
    bool converged = false;
    bool over_budget = false;  // stopped by the deadline; the best estimate so far
    bool failed = false;       // too few correspondences: T_map_lidar is the initial guess
    // The correction xi of the sweep's motion (header): a point at fraction alpha of the sweep
    // belongs at CorrectPoint(q, alpha, correction) in the lidar frame at the scan start.
    common::Vector6d correction = common::Vector6d::Zero();
};

// Exp(alpha phi) q + alpha rho to second order in alpha phi (header).
inline Eigen::Vector3f CorrectPoint(const Eigen::Vector3f& q, float alpha,
                                    const Eigen::Vector3f& rho, const Eigen::Vector3f& phi) {
    const Eigen::Vector3f a = alpha * phi;
    const Eigen::Vector3f aq = a.cross(q);
    return q + aq + 0.5f * a.cross(aq) + alpha * rho;
}

// Now on the budget's clock: steady_clock, or the calling thread's CPU time expressed as a
// steady_clock time point (only ever compared with others of the same clock).
std::chrono::steady_clock::time_point BudgetNow(bool cpu_time);

class ScanRegistration {
public:
    using Clock = std::chrono::steady_clock;

    // max_points: scan points plus twice the edge points registered at most.
    explicit ScanRegistration(const RegistrationConfig& config = {}, size_t max_points = 8192);
    ~ScanRegistration();

    // Registers in.points to `map` starting from in.T0, with the motion correction when
    // in.correction_sigma is not zero. Returns at the deadline with what it has. With edges and
    // an edge_map (fit_lines), LOAM's edge points join in: point-to-line, as two point-to-plane
    // residuals on planes through the line, orthogonal to each other.
    const RegistrationResult& Align(const AlignInput& in, const VoxelMap& map,
                                    Clock::time_point deadline);
    // A rigid scan (no correction), the configuration's correspondence distance.
    const RegistrationResult& Align(std::span<const Eigen::Vector3f> points, const VoxelMap& map,
                                    const Eigen::Isometry3d& T0,
                                    const common::Vector6d& prior_sigma, Clock::time_point deadline,
                                    std::span<const Eigen::Vector3f> edges = {},
                                    const VoxelMap* edge_map = nullptr);

    const RegistrationConfig& config() const { return config_; }

private:
    struct Correspondence {
        Eigen::Vector3d p;  // lidar frame at the scan start, as deskewed (q)
        Eigen::Vector3d n;  // map frame
        double d = 0;
        double sqrt_w = 1;
        double distance = 0;  // m, to its plane (or line) when associated: what sqrt_w came from
        double alpha = 0;
        bool judged = true;  // false on a line-like plane (VoxelPlane::line_like)
    };
    using Matrix12d = Eigen::Matrix<double, 12, 12>;
    using Vector12d = Eigen::Matrix<double, 12, 1>;
    // J^T W J and J^T W r over [delta; xi] of the first n correspondences at (delta, xi).
    void NormalEquations(const Eigen::Isometry3d& T0, const common::Vector6d& delta,
                         const common::Vector6d& xi, int n, bool correcting, Matrix12d* H,
                         Vector12d* g) const;
    // One damped Gauss-Newton step of (delta, xi) on the first n correspondences.
    void Step(const Eigen::Isometry3d& T0, int n, bool correcting, bool fix_rotation,
              const common::Vector6d& prior_k, common::Vector6d* delta, common::Vector6d* xi) const;
    int Associate(const AlignInput& in, const VoxelMap& map, const Eigen::Isometry3d& T,
                  const common::Vector6d& xi, double max_distance, double cauchy_scale);
    // The first n correspondences' weights found again from their distances at another scale.
    void Reweigh(int n, double cauchy_scale);
    // Where the scan's evidence along in.axis is under in.hold_axis_below, the solution `scaled`
    // (and its covariance, scaled units) kept at T0 along it.
    void HoldAxis(const AlignInput& in, common::Vector6d* scaled, common::Matrix6d* cov);

    // Align's steps. What one Align solves: with the sweep's correction or not, the
    // correspondences' reach, the correction's prior (Step's prior_k).
    struct Solve {
        bool correcting = false;
        double max_distance = 0;
        common::Vector6d prior_k = common::Vector6d::Zero();
    };
    // The fit at the solution: mean range (>= 1 m), weights, weighted squared residuals, the
    // weights on surfaces facing in.axis, inliers.
    struct Residuals {
        double mean_range = 0, weight_sum = 0, weighted_sq = 0, axis_sum = 0;
        int inliers = 0, unjudged = 0;
    };
    // The normal equations at the solution, rotations scaled to metres of mean range (x = S x'):
    // S the information on delta with the correction marginalised out, and the correction's
    // blocks to move it with delta.
    struct Information {
        common::Vector6d scale;
        common::Matrix6d S, Hdx;
        Eigen::LDLT<common::Matrix6d> Hxx_ldlt;
    };
    // Gauss-Newton iterations from in.T0 (delta, xi from zero); the correspondences of the
    // solution, or -1 when the first association found too few (result_.failed); last_kernel:
    // the Cauchy scale their weights were found at.
    int Iterate(const AlignInput& in, const VoxelMap& map, Clock::time_point deadline,
                const Solve& solve, common::Vector6d* delta, common::Vector6d* xi,
                double* last_kernel);
    Residuals Measure(const AlignInput& in, const common::Vector6d& delta,
                      const common::Vector6d& xi, int n) const;
    Information InformationAt(const Eigen::Isometry3d& T0, const common::Vector6d& delta,
                              const common::Vector6d& xi, int n, const Solve& solve,
                              double mean_range) const;
    // The solution `scaled` (scaled units) kept at T0 along the directions the scan did not
    // measure (fused with the guess along weak rotations), and its covariance (scaled units);
    // sets min_eigen_ratio, axis_share and degenerate_directions.
    common::Matrix6d KeepMeasured(const AlignInput& in, const Information& info,
                                  const Residuals& res, common::Vector6d* scaled);

    RegistrationConfig config_;
    std::vector<Correspondence> corr_;
    // Per scan point, the voxel it fell in at the last outer iteration and that voxel's
    // neighbourhood of planes (VoxelMap::ForNeighbourPlanes, copied: kMaxNeighbourPlanes a point,
    // at neighbour_planes_[k * kMaxNeighbourPlanes]). The map does not change during an Align, and
    // a point moves by millimetres between iterations, so most of the 7 hash lookups a point
    // makes per iteration (VoxelMap::Slot, the largest cost of a scan with the IMU) are made once;
    // the choice among the planes is made again each iteration, as FindPlane makes it.
    static constexpr size_t kMaxNeighbourPlanes = 14;  // 7 voxels, each with its back twin
    std::vector<Eigen::Vector3i> neighbour_key_;
    std::vector<uint8_t> neighbour_count_;
    std::vector<VoxelPlane> neighbour_planes_;
    // Points whose entries hold the map of version neighbours_version_ (VoxelMap::version): kept
    // from one Align to the next while the map is unchanged (a scan's deskew rounds and other
    // headings register against the map its predecessor left).
    size_t neighbours_cached_ = 0;
    uint64_t neighbours_version_ = 0;
    RegistrationResult result_;
};

// T0 * [rho; phi] as the registration applies it: R0 Exp(phi), t0 + R0 rho.
Eigen::Isometry3d ApplyPerturbation(const Eigen::Isometry3d& T0, const common::Vector6d& delta);

}  // namespace bimslam::odometry
