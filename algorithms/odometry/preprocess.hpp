// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Scan preprocessing for LiDAR odometry: range crop, the rig's self-filter box, per-point deskew
// and voxel downsampling. Everything is sized at construction; Run() never allocates once the
// scan size has been seen (the rig's hot path, DESIGN.md "Conventions").
//
// Deskew. A spinning LiDAR sees each column from where the sensor was at that column's time, so
// a scan taken while moving is smeared by the motion during the ~100 ms sweep. Each point p taken
// at offset tau from the scan start is moved into the lidar frame at the scan start:
//   p_start = T_start_tau * p,
// where ScanMotion gives T_start_tau: by default constant velocity (the twist of the motion
// estimated between scans, T_start_tau = Exp(tau * xi)), with the rotation replaced by the
// integrated gyro of the Ouster IMU when it covers the scan (LIO-SAM and FAST-LIO do the same).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "algorithms/common/point_cloud.hpp"
#include "algorithms/common/se3.hpp"

namespace bimslam::odometry {

// The motion of the lidar during one scan: T_start_tau for tau in [0, duration], as poses at
// evenly spaced knots, interpolated linearly (translation) and by slerp (rotation) in between.
class ScanMotion {
public:
    static constexpr int kKnots = 17;

    // No motion.
    ScanMotion() { SetConstantVelocity(common::Vector6d::Zero(), 0.1); }
    // Constant velocity: xi = [v; omega] (m/s, rad/s) in the lidar frame at the scan start.
    void SetConstantVelocity(const common::Vector6d& xi_per_s, double duration_s);
    // Replaces the rotation at each knot (the translation stays): q_start_tau[k] for tau_k =
    // k * duration / (kKnots - 1).
    void SetRotations(const std::array<Eigen::Quaterniond, kKnots>& q_start_tau);
    // Replaces the translation's component along the unit vector `axis` (the start frame) at
    // each knot by d[k]; the rest of the translation stays.
    void SetTranslationAlong(const Eigen::Vector3d& axis, const std::array<double, kKnots>& d);

    double duration_s() const { return duration_s_; }
    double KnotTime(int k) const { return duration_s_ * k / (kKnots - 1); }
    // T_start_tau; tau outside [0, duration] is clamped.
    Eigen::Isometry3d At(double tau_s) const;
    // The whole-scan motion T_start_end.
    Eigen::Isometry3d End() const { return At(duration_s_); }

private:
    double duration_s_ = 0.1;
    std::array<Eigen::Quaterniond, kKnots> q_;
    std::array<Eigen::Vector3d, kKnots> t_;
};

struct PreprocessConfig {
    double min_range = 0.5;    // m: closer returns are the rig itself or noise
    double max_range = 100.0;  // m
    // The rig's self-filter: points inside this box of the lidar frame are dropped. The default
    // holds a Go1's trunk and legs under a lidar mounted 5 cm ahead of the trunk's centre and
    // 28 cm above it (the trunk is 0.65 x 0.28 m). Empty when any min > max. LidarOdometry sets
    // it from the box in the base frame and the mount when given one (LidarOdometryConfig).
    Eigen::Vector3d self_box_min = {-0.45, -0.25, -0.65};
    Eigen::Vector3d self_box_max = {0.35, 0.25, -0.10};
    bool deskew = true;
    // Two resolutions, as KISS-ICP (Vizzo et al., RA-L 2023): a fine one for the map, a coarse one
    // for registration. These are the finest sizes. A dense sensor (128 beams) or a large scene
    // (outdoors, ranges to 100 m) gives many more points at the same voxel size, so each size
    // adapts from scan to scan to keep its count near a target (a count well under the target
    // keeps the finest size): v <- v * sqrt(count / target), because points on surfaces scale with
    // 1 / v^2. A 32-beam sensor indoors stays at the finest sizes. A map count over twice its
    // target (the first scans of a 128-beam sensor, a step outdoors) is filtered again at once at
    // v * sqrt(count / target) rather than over the next scans: a 128-beam scan at the finest size
    // gave ~50 000 map points and 24-33 ms scans before the damped adaptation caught up.
    double map_voxel = 0.10;           // m
    double registration_voxel = 0.35;  // m
    size_t target_map_points = 20000;  // 0: fixed sizes
    size_t target_registration_points = 2500;
    double max_map_voxel = 0.5;           // m, the coarsest the adaptation goes
    double max_registration_voxel = 1.5;  // m
    // A hard cap after the voxel filter: every k-th point is kept (the adaptation's first scans).
    size_t max_registration_points = 4000;
    size_t max_points = 262144;  // input points per scan the buffers are sized for

    // Throws common::Error naming the field and value when out of range.
    void Validate() const;
};

struct PreprocessStats {
    size_t input = 0;
    size_t zero_range = 0;  // no return
    size_t cropped = 0;     // outside [min_range, max_range]
    size_t self = 0;        // inside the self-filter box
    size_t non_finite = 0;
    size_t kept = 0;        // deskewed points (the keyframe cloud)
    size_t map_points = 0;  // after the map voxel filter
    size_t registration_points = 0;
    double map_voxel = 0, registration_voxel = 0;  // m, the sizes this scan used
    // Of the kept points: the 90th percentile of the range (m), the scene's extent.
    double range_p90 = 0;
};

class Preprocessor {
public:
    explicit Preprocessor(const PreprocessConfig& config = {});

    // Crops, deskews (to the lidar frame at the scan start) and downsamples `scan` (lidar frame,
    // time offsets from its stamp; without offsets no deskew is possible and none is done).
    const PreprocessStats& Run(const common::PointCloud& scan, const ScanMotion& motion);

    // The results of the last Run(), valid until the next one.
    const common::PointCloud& deskewed() const { return deskewed_; }  // every kept point
    std::span<const Eigen::Vector3f> map_points() const { return map_points_; }
    std::span<const Eigen::Vector3f> registration_points() const { return registration_points_; }
    // Per map and registration point, its time in the sweep as a fraction of the scan's duration
    // (0 at the start, 1 at the last point; all 0 without per-point time): what the registration's
    // motion correction (scan_registration.hpp) scales with.
    std::span<const float> map_alpha() const { return map_alpha_; }
    std::span<const float> registration_alpha() const { return registration_alpha_; }
    // The scan's duration the fractions are of (s): its largest time offset.
    double duration_s() const { return duration_s_; }
    const PreprocessConfig& config() const { return config_; }
    // Back to the finest voxel sizes (the odometry starts again).
    void ResetVoxels();
    // Moves the last Run()'s kept points and map points by a correction xi = [rho; phi] of the
    // sweep's motion: a point at fraction alpha goes to Exp(alpha phi) q + alpha rho (to second
    // order, scan_registration.hpp CorrectPoint), so the keyframe cloud and the map get it where
    // the registration found it belongs.
    void ApplyCorrection(const common::Vector6d& xi);
    // Deskews the last Run()'s points again with `motion` instead of the motion Run() used (the
    // odometry's deskew rounds with the gyro, lidar_odometry.hpp max_redeskew_move): every kept,
    // map and registration point moves to where `motion` puts it, for about a fifth of Run()'s
    // cost: one pose per distinct time offset and a transform per point, no crop, no voxel
    // filter. Which points the filters chose stays, so the caller keeps the moves well under a
    // voxel; the next scan's voxel sizes are not adapted again. No-op when Run() did not deskew.
    void Redeskew(const ScanMotion& motion);

private:
    // Run's steps. The scan's points kept (finite, in range, not the rig's own body), deskewed
    // with `motion`, each with its fraction of the sweep and its pose's entry; the range's 90th
    // percentile.
    void KeepAndDeskew(const common::PointCloud& scan, const ScanMotion& motion);
    // The map points: one a voxel of the kept points, filtered again at once at a coarser voxel
    // when over twice the target (PreprocessConfig::target_map_points).
    void FilterMapPoints();
    // The registration points: one a voxel of the map points, capped; returns how many the
    // filter found before the cap (what the next scan's voxel adapts to).
    size_t FilterRegistrationPoints();
    // First point per voxel of `in` into `out` (with its alpha and pose entry), using the
    // preallocated table; `ring`: each point's ring, or empty; *expected: the last output count
    // of this filter, in and out.
    void VoxelFilter(std::span<const Eigen::Vector3f> in, std::span<const float> in_alpha,
                     std::span<const uint32_t> in_pose, std::span<const uint16_t> ring,
                     double voxel, std::vector<Eigen::Vector3f>* out, std::vector<float>* out_alpha,
                     std::vector<uint32_t>* out_pose, size_t* expected);
    // The next scan's voxel size from this scan's count (header of PreprocessConfig).
    static double Adapt(double voxel, size_t count, size_t target, double finest, double coarsest);

    PreprocessConfig config_;
    PreprocessStats stats_;
    common::PointCloud deskewed_;
    std::vector<float> alpha_;  // of deskewed_
    std::vector<Eigen::Vector3f> map_points_;
    std::vector<Eigen::Vector3f> registration_points_;
    std::vector<float> map_alpha_, registration_alpha_;
    std::vector<Eigen::Vector3f> refilter_points_;  // scratch for a second map filter
    std::vector<float> refilter_alpha_;
    // The poses that deskewed the last Run()'s points, one per distinct time offset in the order
    // met (points come column by column), and each kept, map and registration point's entry:
    // what Redeskew moves them by.
    struct SweepPose {
        uint32_t tau_ns = 0;
        Eigen::Matrix3f R = Eigen::Matrix3f::Identity();
        Eigen::Vector3f t = Eigen::Vector3f::Zero();
    };
    std::vector<SweepPose> poses_, moves_;  // moves_: Redeskew's scratch
    std::vector<uint32_t> pose_, map_pose_, registration_pose_, refilter_pose_;
    std::vector<float> range_sample_;  // scratch for the range percentile
    double duration_s_ = 0;
    double map_voxel_ = 0, registration_voxel_ = 0;  // the current (adapted) sizes
    // The voxel filters' open-addressing table (VoxelHash::kEmpty when free, emptied again after
    // each filter through used_), and the last output count of each filter, which sizes the part
    // of the table the next one uses.
    std::vector<uint64_t> table_;
    std::vector<uint32_t> used_;
    // Each ring's last key in VoxelFilter (rings by their low bits: 256 covers every Ouster).
    static constexpr size_t kRingKeys = 256;
    std::array<uint64_t, kRingKeys> ring_keys_{};
    size_t expected_map_ = 0, expected_registration_ = 0;
};

}  // namespace bimslam::odometry
