// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Dead reckoning from a legged robot's body motion (the Go1's velocity, yaw rate and IMU
// attitude, decoded from CAN): the motion prior that LiDAR odometry uses as its initial guess,
// for deskewing, and along directions a scan leaves unconstrained (long corridors).
//
// Model. Translation is integrated in the horizontal plane from the body velocity (vx, vy) and
// the yaw integrated from the yaw rate; roll and pitch come from the IMU attitude when present
// (gravity makes them observable; yaw is not, so it is never taken from the IMU). Errors grow as a
// random walk: white noise on velocity and yaw rate plus a velocity scale error, so the
// covariance grows with time and with distance (leg odometry slips and mis-scales, a yaw gyro
// drifts). The covariance of a relative motion is propagated in (x, y, yaw) with the unicycle
// Jacobians (Thrun, Burgard, Fox, "Probabilistic Robotics", sec. 5.4), then embedded in 6-D.
//
// Samples are kept in a ring buffer allocated at construction: Add and the queries never
// allocate, so this runs on the rig's hot path.
#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "algorithms/common/se3.hpp"
#include "algorithms/common/status.hpp"

namespace bimslam::odometry {

struct BodyMotionSample {
    int64_t t_ns = 0;  // one clock for every sample (e.g. the Go1 bridge's, unwrapped)
    Eigen::Vector2d v_xy = Eigen::Vector2d::Zero();  // m/s, body frame: x forward, y left
    double yaw_rate = 0.0;                           // rad/s about the body z axis
    bool velocity_valid = true;
    bool yaw_rate_valid = true;
    // Body orientation in a gravity-aligned frame (from the IMU); only roll and pitch are used.
    std::optional<Eigen::Quaterniond> attitude;
};

struct MotionPriorConfig {
    double velocity_sigma = 0.05;        // m/s, white noise on vx and vy
    double velocity_scale_sigma = 0.05;  // relative: leg odometry's scale error (5 %)
    double yaw_rate_sigma = 0.02;        // rad/s, white noise on the yaw rate
    double attitude_sigma = 0.02;        // rad, roll and pitch from the IMU
    double vertical_sigma = 0.05;        // m per sqrt(s): z is not measured (planar model)
    // Missing or invalid data: the last valid value is held with this much noise instead.
    double invalid_velocity_sigma = 1.0;  // m/s
    double invalid_yaw_rate_sigma = 1.0;  // rad/s
    double max_gap_s = 0.25;              // longer gaps between samples count as invalid data
    size_t capacity = 4096;               // samples kept (about 40 s at the Go1's 100 Hz)

    // Throws common::Error naming the field and value when out of range.
    void Validate() const;
};

class MotionPrior {
public:
    explicit MotionPrior(const MotionPriorConfig& config = {});

    // Appends a sample; time must increase. kInvalidArgument for a sample out of order or with
    // non-finite values (nothing stored). The oldest sample is dropped when the buffer is full.
    common::Status Add(const BodyMotionSample& sample);

    struct Relative {
        Eigen::Isometry3d T_a_b = Eigen::Isometry3d::Identity();  // body at b in body at a
        common::Matrix6d covariance = common::Matrix6d::Zero();   // [x y z rx ry rz], frame a
    };
    // The motion from time a to time b (a <= b, both within [begin_ns, end_ns]), interpolated
    // inside sample intervals; nullopt outside the buffered span.
    std::optional<Relative> Between(int64_t a_ns, int64_t b_ns) const;

    size_t size() const { return count_; }
    int64_t begin_ns() const;
    int64_t end_ns() const;
    const MotionPriorConfig& config() const { return config_; }

private:
    const BodyMotionSample& At(size_t i) const { return buffer_[(head_ + i) % buffer_.size()]; }
    MotionPriorConfig config_;
    std::vector<BodyMotionSample> buffer_;
    size_t head_ = 0;  // index of the oldest sample
    size_t count_ = 0;
};

}  // namespace bimslam::odometry
