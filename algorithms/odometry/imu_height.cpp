// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/odometry/imu_height.hpp"

#include <algorithm>
#include <cmath>

#include "algorithms/common/status.hpp"

namespace bimslam::odometry {
namespace {
void RequireField(bool ok, const char* field, double value, const char* rule) {
    common::Require(ok, "ImuHeightConfig", field, value, rule);
}
}  // namespace

void ImuHeightConfig::Validate() const {
    RequireField(accel_noise > 0 && accel_noise <= 10, "accel_noise", accel_noise,
                 "must be in (0, 10]");
    RequireField(bias_walk > 0 && bias_walk <= 1, "bias_walk", bias_walk, "must be in (0, 1]");
    RequireField(initial_bias_sigma > 0 && initial_bias_sigma <= 10, "initial_bias_sigma",
                 initial_bias_sigma, "must be in (0, 10]");
    RequireField(initial_velocity_sigma > 0 && initial_velocity_sigma <= 100,
                 "initial_velocity_sigma", initial_velocity_sigma, "must be in (0, 100]");
    RequireField(position_sigma > 0 && position_sigma <= 1, "position_sigma", position_sigma,
                 "must be in (0, 1]");
    RequireField(rest_velocity_sigma > 0 && rest_velocity_sigma <= 10, "rest_velocity_sigma",
                 rest_velocity_sigma, "must be in (0, 10]");
    RequireField(rest_bias_sigma > 0 && rest_bias_sigma <= 10, "rest_bias_sigma", rest_bias_sigma,
                 "must be in (0, 10]");
    RequireField(ready_velocity_sigma > 0 && ready_velocity_sigma <= 10, "ready_velocity_sigma",
                 ready_velocity_sigma, "must be in (0, 10]");
}

ImuHeight::ImuHeight(const ImuHeightConfig& config) : config_(config) { config_.Validate(); }

void ImuHeight::Reset(double h, const Eigen::Vector3d& up, bool at_rest, double bias) {
    x_ << h, 0, at_rest ? bias : 0.0;
    up_ = up.normalized();
    const double sp = config_.position_sigma;
    const double sv = at_rest ? config_.rest_velocity_sigma : config_.initial_velocity_sigma;
    const double sb = at_rest ? config_.rest_bias_sigma : config_.initial_bias_sigma;
    P_ = Eigen::Vector3d(sp * sp, sv * sv, sb * sb).asDiagonal();
    initialized_ = true;
}

bool ImuHeight::ready() const {
    return initialized_ && P_(1, 1) < config_.ready_velocity_sigma * config_.ready_velocity_sigma;
}

void ImuHeight::Propagate(const Eigen::Matrix3d& R_odom_lidar, const Eigen::Vector3d& f,
                          double dt) {
    if (!initialized_ || !(dt > 0)) return;
    const double a = up_.dot(R_odom_lidar * f) - kStandardGravity - bias();
    x_(0) += velocity() * dt + 0.5 * dt * dt * a;
    x_(1) += dt * a;
    // x' = F x: h' = h + v dt - b dt^2/2, v' = v - b dt.
    Eigen::Matrix3d F;
    F << 1, dt, -0.5 * dt * dt, 0, 1, -dt, 0, 0, 1;
    // White acceleration noise integrated over dt (q [dt^3/3 dt^2/2; dt^2/2 dt] on h and v), and
    // the bias's random walk.
    const double q = config_.accel_noise * config_.accel_noise;
    const double qb = config_.bias_walk * config_.bias_walk;
    Eigen::Matrix3d Q;
    Q << q * dt * dt * dt / 3, q * dt * dt / 2, 0, q * dt * dt / 2, q * dt, 0, 0, 0, qb * dt;
    P_ = F * P_ * F.transpose() + Q;
}

void ImuHeight::Update(double h, double variance) {
    if (!initialized_) return;
    const double r2 = std::max(config_.position_sigma * config_.position_sigma, variance);
    const Eigen::Vector3d PHt = P_.col(0);  // H = [1 0 0]
    const Eigen::Vector3d K = PHt / (P_(0, 0) + r2);
    x_ += K * (h - height());
    // Joseph form, kept symmetric: P = (I - K H) P (I - K H)^T + K r2 K^T.
    Eigen::Matrix3d A = Eigen::Matrix3d::Identity();
    A.col(0) -= K;
    P_ = A * P_ * A.transpose() + r2 * K * K.transpose();
}

}  // namespace bimslam::odometry
