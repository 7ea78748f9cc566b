// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The lidar's height from the accelerometers between scans: where the scans do not see the
// height, the prediction along gravity is what the accelerometers measured, not a vertical
// velocity carried on from before (issue 31, item 4).
//
// Why. A switchback stair between close walls leaves the height unobserved for seconds: the
// floor and the ceiling are outside an OS1's +-22.5 deg beyond the walls. The registration keeps
// its initial guess along such a direction (Zhang et al., ICRA 2016), and a constant-velocity guess
// kept climbing through the landing: Office_A's flight ended 33 cm high, and the run was trusted.
//
// Why the height only. Along gravity a tilt error of the pose leaks gravity in at second order
// (g (1 - cos e)); across it at first order (g sin e: a corridor's stop walked with the pose
// 0.65 deg off drifted 65 cm in 2.5 s). And one filter over the three axes learnt from scans that
// saw x and y only: the registration's weak direction comes out a few degrees off vertical, so an
// "observed" horizontal direction has a small vertical share, and the filter, sure of x and unsure
// of z, explained its horizontal innovations as height (a 2.4 m shaft: 0.2 m/s^2 of false bias,
// 3 m off). A filter of the height alone learns only from scans that saw the height.
//
// Model. A Kalman filter of x = [h v b] along up (the accelerometers' mean direction at the
// start, opposite gravity): the height, the vertical velocity and the accelerometers' vertical
// bias with gravity's residual. Between scans, each IMU sample held over its interval: a = up . (R
// f) - g - b, with f the specific force (lidar frame), R the lidar's rotation (the previous pose
// and the gyro since), g the standard gravity; h += v dt + a dt^2 / 2, v += a dt; white
// acceleration noise and a bias random walk. At a scan that saw the height: its height, sigma the
// larger of position_sigma and the registration's. At one that did not: the scan's height is
// taken with no information (the pose is the pose; the filter's variance grows on).
#pragma once

#include <Eigen/Core>

namespace bimslam::odometry {

inline constexpr double kStandardGravity = 9.80665;  // m/s^2 (the filter's g)

struct ImuHeightConfig {
    double accel_noise = 0.03;            // m/s^2/sqrt(Hz): the specific force's white noise
    double bias_walk = 0.01;              // m/s^2/sqrt(s)
    double initial_bias_sigma = 0.3;      // m/s^2: gravity's residual and the bias
    double initial_velocity_sigma = 1.0;  // m/s: a start in motion
    double position_sigma = 0.01;         // m: a registered scan's height where it saw it
    // The filter predicts once its vertical velocity is known to this (1 sigma, m/s): before,
    // it is the start's unknown one.
    double ready_velocity_sigma = 0.05;
    // A start at rest (the rig's, as the accelerometers and the gyro show it): the velocity is
    // zero to rest_velocity_sigma, and the bias along up is the mean specific force's size less
    // the standard gravity, to rest_bias_sigma (what the sensor's bias changes as it tilts).
    double rest_velocity_sigma = 0.02;  // m/s
    double rest_bias_sigma = 0.03;      // m/s^2

    // Throws common::Error naming the field and value when out of range.
    void Validate() const;
};

class ImuHeight {
public:
    explicit ImuHeight(const ImuHeightConfig& config = {});

    // Starts at height h (along `up`, a unit vector against gravity in the odometry frame), its
    // velocity unknown; or, `at_rest`, still, with the accelerometers' vertical bias `bias`.
    void Reset(double h, const Eigen::Vector3d& up, bool at_rest = false, double bias = 0);
    bool initialized() const { return initialized_; }
    // Whether its vertical velocity is known to ready_velocity_sigma.
    bool ready() const;

    // One accelerometer sample `f` (lidar frame, m/s^2) held for dt seconds, the lidar at
    // rotation R (odometry frame).
    void Propagate(const Eigen::Matrix3d& R_odom_lidar, const Eigen::Vector3d& f, double dt);
    // A scan that saw the height: its height h, with the registration's variance there.
    void Update(double h, double variance = 0);
    // A scan that did not see the height: it kept the prediction (or the constant velocity's);
    // the filter's height becomes it, with no information.
    void Hold(double h) { x_(0) = h; }

    double height() const { return x_(0); }
    double velocity() const { return x_(1); }
    double bias() const { return x_(2); }
    const Eigen::Matrix3d& covariance() const { return P_; }
    const Eigen::Vector3d& up() const { return up_; }

private:
    ImuHeightConfig config_;
    bool initialized_ = false;
    Eigen::Vector3d x_ = Eigen::Vector3d::Zero();
    Eigen::Matrix3d P_ = Eigen::Matrix3d::Identity();
    Eigen::Vector3d up_ = Eigen::Vector3d::UnitZ();
};

}  // namespace bimslam::odometry
