// LiDAR odometry: one scan in, its pose in the odometry frame out, in bounded time. No thread and
// no I/O of its own: the rig's odometry module and `bimslam odometry` run this same code.
//
// Per scan (README.md, "LiDAR odometry"):
// 1. Prediction of the motion since the previous scan: constant velocity by default; the Go1's
//    body motion (MotionPrior, moved into the lidar frame by T_base_lidar) replaces it when
//    present; the Ouster IMU's integrated gyro replaces its rotation when present.
// 2. Preprocessing: range crop, self-filter, deskew with that motion (the gyro's rotation inside
//    the scan when present), voxel downsampling (Preprocessor).
// 3. Registration of the downsampled scan to the local map from the prediction (ScanRegistration,
//    Ceres), with degenerate directions kept at the prediction. When the motion it implies
//    differs from the one the scan was deskewed with, the scan is deskewed again with it and
//    registered once more.
// 4. The map gets the scan's fine points at the estimated pose and forgets what lies far behind.
//
// Time. The whole call is budgeted (budget_ms): registration stops at its share of the budget
// with its best estimate and the kOverBudget flag. Frames: `lidar` is the Ouster sensor frame of
// the points and of the IMU; `odom` is the lidar frame of the first scan. Time stamps: one clock
// for scans, IMU and body motion (the sensor's; the caller converts the Go1's).
//
// Allocation: none per scan after the first, except inside ceres::Solve, which builds its
// evaluator on every call (measured in tests/unit/odometry/allocation_test.cpp).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <chrono>
#include <cstdint>
#include <optional>
#include <vector>

#include "algorithms/common/point_cloud.hpp"
#include "algorithms/common/se3.hpp"
#include "algorithms/odometry/edge_features.hpp"
#include "algorithms/odometry/motion_prior.hpp"
#include "algorithms/odometry/preprocess.hpp"
#include "algorithms/odometry/scan_registration.hpp"
#include "algorithms/odometry/voxel_map.hpp"

namespace bimslam::odometry {

// An IMU sample in the lidar frame and the scans' clock.
struct ImuMeasurement {
    int64_t t_ns = 0;
    Eigen::Vector3d gyro = Eigen::Vector3d::Zero();   // rad/s
    Eigen::Vector3d accel = Eigen::Vector3d::Zero();  // m/s^2
};

// The edge map of LOAM's edge features: lines in 0.6 m voxels.
inline VoxelMapConfig EdgeMapConfig() {
    VoxelMapConfig c;
    c.fit_lines = true;
    c.min_plane_points = 4;
    c.min_point_spacing = 0.04;
    c.max_plane_thickness = 0.05;
    c.max_voxels = 10000;
    return c;
}

struct LidarOdometryConfig {
    PreprocessConfig preprocess;
    VoxelMapConfig map;
    RegistrationConfig registration;
    // LOAM edge features (edge_features.hpp) registered point-to-line to an edge map, on top of
    // the point-to-plane registration. Off: measured on the project's captures, they took
    // 1.25-1.6x the time for 4 % less error, and failed once without the IMU (README.md).
    bool edge_features = false;
    EdgeFeatureConfig edges;
    VoxelMapConfig edge_map = EdgeMapConfig();
    MotionPriorConfig body_prior;
    double budget_ms = 50.0;         // per scan, 10 Hz
    double map_update_share = 0.15;  // of the budget kept for the map update
    // The lidar on the Go1's body (for the body-motion prior): 5 cm ahead, 28 cm above.
    Eigen::Isometry3d T_base_lidar = Eigen::Isometry3d(Eigen::Translation3d(0.05, 0.0, 0.28));
    bool use_imu = true;
    bool use_body_motion = true;
    size_t imu_capacity = 2048;   // samples (20 s at the Ouster's 100 Hz)
    double max_imu_gap_s = 0.05;  // longer gaps: the gyro does not cover the interval
    // Standard deviation of the constant-velocity prediction per scan [m m m rad rad rad]: the
    // fallback along degenerate directions when there is no body motion.
    common::Vector6d constant_velocity_sigma =
        (common::Vector6d() << 0.05, 0.05, 0.05, 0.02, 0.02, 0.02).finished();
    double imu_rotation_sigma = 0.003;  // rad per scan, the gyro's rotation
    // Scans the constant velocity is averaged over. One scan's motion is noisy, and a velocity
    // that is wrong deskews the next scan wrongly, whose pose is then wrong the other way: with
    // one scan this can ring (measured on hand-held captures); averaging over a few damps it.
    int velocity_window = 4;
    // A scan is deskewed again with its estimated motion when that differs from the predicted
    // one by more than this over the sweep (metres of translation + 10 m x radians of rotation:
    // the displacement of a point 10 m away).
    double redeskew_threshold = 0.02;

    void Validate() const;
};

enum OdometryFlag : uint32_t {
    kFirstScan = 1u << 0,
    kOverBudget = 1u << 1,          // the best estimate when the budget ran out
    kDegenerate = 1u << 2,          // some directions came from the prediction
    kRegistrationFailed = 1u << 3,  // too few correspondences: the prediction
    kNotConverged = 1u << 4,
    kBodyPriorUsed = 1u << 5,
    kImuUsed = 1u << 6,
    kTooFewPoints = 1u << 7,   // the scan kept fewer points than registration needs
    kDeskewedAgain = 1u << 8,  // deskewed and registered a second time (step 3b)
};

struct OdometryResult {
    int64_t stamp_ns = 0;  // the scan's start
    Eigen::Isometry3d T_odom_lidar = Eigen::Isometry3d::Identity();
    Eigen::Isometry3d T_prev_lidar = Eigen::Isometry3d::Identity();  // motion since the last scan
    // Covariance of that motion, [rho; phi] as a right perturbation (lidar frame).
    common::Matrix6d covariance = common::Matrix6d::Identity() * 1e-4;
    uint32_t flags = 0;
    PreprocessStats preprocess;
    RegistrationResult registration;
    size_t map_voxels = 0;
    size_t map_points = 0;
    size_t edge_points = 0;  // with edge_features: LOAM edge points of this scan
    double preprocess_ms = 0, register_ms = 0, map_ms = 0, total_ms = 0;
};

class LidarOdometry {
public:
    using Clock = std::chrono::steady_clock;

    explicit LidarOdometry(const LidarOdometryConfig& config = {});

    // Inputs between scans, in time order. Out of order or non-finite samples are dropped and
    // counted (the hot path never throws).
    void AddImu(const ImuMeasurement& imu);
    void AddBodyMotion(const BodyMotionSample& sample);

    // One scan (lidar frame, time offsets from scan.stamp): its pose. Scans must come in time
    // order; a scan not after the previous one is ignored (kTooFewPoints, pose unchanged).
    const OdometryResult& Process(const common::PointCloud& scan);

    // The last scan's kept points, deskewed into its lidar frame at its start (the keyframe
    // cloud), valid until the next Process().
    const common::PointCloud& deskewed() const { return preprocessor_.deskewed(); }
    const VoxelMap& map() const { return map_; }
    const LidarOdometryConfig& config() const { return config_; }
    uint64_t dropped_inputs() const { return dropped_inputs_; }
    size_t scans() const { return scans_; }

private:
    // Rotation of the lidar at t1 in the lidar at t0 from the gyro; false when the buffer does
    // not cover [t0, t1].
    bool IntegrateGyro(int64_t t0_ns, int64_t t1_ns, Eigen::Quaterniond* q) const;
    // The motion during a scan: constant velocity `twist`, the gyro's rotation when it covers it.
    ScanMotion MotionFor(const common::Vector6d& twist, double duration, int64_t stamp) const;
    const ImuMeasurement& Imu(size_t i) const { return imu_[(imu_head_ + i) % imu_.size()]; }

    LidarOdometryConfig config_;
    Preprocessor preprocessor_;
    VoxelMap map_;
    ScanRegistration registration_;
    MotionPrior body_prior_;
    std::optional<EdgeExtractor> edge_extractor_;  // with edge_features
    std::optional<VoxelMap> edge_map_;
    std::span<const Eigen::Vector3f> edges_;  // of the last preprocessing
    std::vector<ImuMeasurement> imu_;         // ring buffer
    size_t imu_head_ = 0, imu_count_ = 0;
    std::vector<Eigen::Vector3f> world_points_;  // scratch: map points at the estimated pose

    OdometryResult result_;
    bool initialized_ = false;
    int64_t last_stamp_ns_ = 0;
    // The constant-velocity model: the twist per second (lidar frame) over the last
    // velocity_window scans, from the poses kept here.
    common::Vector6d velocity_ = common::Vector6d::Zero();
    struct PastPose {
        int64_t stamp_ns;
        Eigen::Isometry3d T_odom_lidar;
    };
    std::vector<PastPose> past_;  // ring of velocity_window + 1
    size_t past_count_ = 0;
    uint64_t dropped_inputs_ = 0;
    size_t scans_ = 0;
};

}  // namespace bimslam::odometry
