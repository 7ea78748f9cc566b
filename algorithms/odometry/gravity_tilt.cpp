// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/odometry/gravity_tilt.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "algorithms/common/status.hpp"
#include "algorithms/odometry/imu_height.hpp"

namespace bimslam::odometry {
namespace {
void RequireTiltField(bool ok, const char* field, double value, const char* rule) {
    common::Require(ok, "GravityTiltConfig", field, value, rule);
}

// 0 before lo, 1 after hi, linear between.
double TrapezoidRamp(double t, double lo, double hi) {
    return std::clamp((t - lo) / (hi - lo), 0.0, 1.0);
}

using Matrix7d = Eigen::Matrix<double, 7, 7>;
}  // namespace

void GravityTiltConfig::Validate() const {
    RequireTiltField(window_scans >= 2 && window_scans <= 1000, "window_scans", window_scans,
                     "must be in [2, 1000]");
    RequireTiltField(velocity_scans >= 1 && velocity_scans <= window_scans, "velocity_scans",
                     velocity_scans, "must be in [1, window_scans]");
    RequireTiltField(accel_noise > 0 && accel_noise <= 10, "accel_noise", accel_noise,
                     "must be in (0, 10]");
    RequireTiltField(position_sigma > 0 && position_sigma <= 1, "position_sigma", position_sigma,
                     "must be in (0, 1]");
    RequireTiltField(tilt_walk > 0 && tilt_walk <= 1, "tilt_walk", tilt_walk, "must be in (0, 1]");
    RequireTiltField(bias_walk > 0 && bias_walk <= 1, "bias_walk", bias_walk, "must be in (0, 1]");
    RequireTiltField(initial_bias_sigma > 0 && initial_bias_sigma <= 10, "initial_bias_sigma",
                     initial_bias_sigma, "must be in (0, 10]");
    RequireTiltField(start_sigma > 0 && start_sigma <= 1, "start_sigma", start_sigma,
                     "must be in (0, 1]");
    RequireTiltField(ready_sigma > 0 && ready_sigma <= 1, "ready_sigma", ready_sigma,
                     "must be in (0, 1]");
}

GravityTilt::GravityTilt(const GravityTiltConfig& config) : config_(config) { config_.Validate(); }

void GravityTilt::Reset(const Eigen::Vector3d& up, const Eigen::Matrix3d& R0, bool at_rest) {
    up_ = up.normalized();
    e1_ = up_.unitOrthogonal();
    e2_ = up_.cross(e1_);
    x_.setZero();
    P_.setZero();
    // The tilt now and at the start are one at the start: 3 deg, uninformed.
    const Eigen::Matrix2d tilt = Eigen::Matrix2d::Identity() * 0.05 * 0.05;
    P_.block<2, 2>(0, 0) = P_.block<2, 2>(0, 2) = P_.block<2, 2>(2, 0) = P_.block<2, 2>(2, 2) =
        tilt;
    P_.bottomRightCorner<3, 3>().diagonal().setConstant(config_.initial_bias_sigma *
                                                        config_.initial_bias_sigma);
    // The prior: up was the mean of g up_true + a + R0 b, so t + (R0 b) across up / g = 0, to
    // what the walk's own acceleration adds.
    const double s = at_rest ? 0.1 * config_.start_sigma : config_.start_sigma;
    Eigen::Matrix<double, 2, 7> H = Eigen::Matrix<double, 2, 7>::Zero();
    H(0, 0) = H(1, 1) = 1;
    H.block<1, 3>(0, 4) = e1_.transpose() * R0 / kStandardGravity;
    H.block<1, 3>(1, 4) = e2_.transpose() * R0 / kStandardGravity;
    const Eigen::Matrix2d S = H * P_ * H.transpose() + s * s * Eigen::Matrix2d::Identity();
    const Eigen::Matrix<double, 7, 2> K = P_ * H.transpose() * S.inverse();
    P_ = (Matrix7d::Identity() - K * H) * P_;
    steps_.clear();
    since_update_ = 0;
    updates_ = 0;
    initialized_ = true;
}

Eigen::Matrix3d GravityTilt::AddScan(int64_t stamp_ns, const Eigen::Vector3d& p,
                                     const Eigen::Vector3d& Rf_dt, const Eigen::Matrix3d& R_dt,
                                     double dt, bool ok) {
    if (!initialized_) return Eigen::Matrix3d::Identity();
    if (dt > 0) {
        P_.topLeftCorner<2, 2>().diagonal().array() += config_.tilt_walk * config_.tilt_walk * dt;
        P_.bottomRightCorner<3, 3>().diagonal().array() +=
            config_.bias_walk * config_.bias_walk * dt;
    }
    if (!ok) {
        steps_.clear();
        since_update_ = 0;
        return Eigen::Matrix3d::Identity();
    }
    steps_.push_back({stamp_ns, p, Rf_dt, R_dt, dt});
    const size_t need = size_t(config_.window_scans + config_.velocity_scans + 1);
    while (steps_.size() > need) steps_.pop_front();
    ++since_update_;
    if (steps_.size() < need || since_update_ < config_.window_scans) {
        return Eigen::Matrix3d::Identity();
    }
    since_update_ = 0;
    if (!Update() || !ready()) return Eigen::Matrix3d::Identity();
    // The pose is levelled back to the start's tilt, and the registrations go on from it: the
    // frame's tilt is the start's again (an error-state reset, its uncertainty kept). Only the
    // filter's news is ever applied, so a registration that follows the levelled pose does not
    // feed the correction back.
    const Eigen::Matrix3d C =
        Eigen::Quaterniond::FromTwoVectors(up_ + tilt(), up_ + start_tilt()).toRotationMatrix();
    x_.head<2>() = x_.segment<2>(2);
    return C;
}

bool GravityTilt::Update() {
    // Scans 0 .. m: the mean velocity at the window's start; N .. N + m at its end.
    const size_t m = size_t(config_.velocity_scans), last = steps_.size() - 1, bm = last - m;
    const auto t = [&](size_t i) { return double(steps_[i].stamp_ns) * 1e-9; };
    const double wa = t(m) - t(0), wb = t(last) - t(bm);
    if (!(wa > 0) || !(wb > 0)) return false;
    const Eigen::Vector3d va = (steps_[m].p - steps_[0].p) / wa;
    const Eigen::Vector3d vb = (steps_[last].p - steps_[bm].p) / wb;
    // Step i covers (t(i-1), t(i)]: its weight, the trapezoid's at its middle.
    Eigen::Vector3d y = -(vb - va);
    Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
    double T = 0, w2dt = 0;
    for (size_t i = 1; i <= last; ++i) {
        const double mid = 0.5 * (t(i - 1) + t(i));
        const double w = TrapezoidRamp(mid, t(0), t(m)) - TrapezoidRamp(mid, t(bm), t(last));
        y += w * steps_[i].Rf_dt;
        M += w * steps_[i].R_dt;
        T += w * steps_[i].dt;
        w2dt += w * w * steps_[i].dt;
    }
    if (!(T > 0)) return false;
    const double g = kStandardGravity;
    const Eigen::Vector3d z = y - g * T * up_;
    Eigen::Matrix<double, 3, 7> H = Eigen::Matrix<double, 3, 7>::Zero();
    H.col(0) = g * T * e1_;
    H.col(1) = g * T * e2_;
    H.rightCols<3>() = M;
    const double sp = config_.position_sigma;
    const double r = config_.accel_noise * config_.accel_noise * w2dt + 2 * sp * sp / (wa * wa) +
                     2 * sp * sp / (wb * wb);
    const Eigen::Matrix3d S = H * P_ * H.transpose() + r * Eigen::Matrix3d::Identity();
    const Eigen::Matrix<double, 7, 3> K = P_ * H.transpose() * S.inverse();
    x_ += K * (z - H * x_);
    P_ = (Matrix7d::Identity() - K * H) * P_;
    P_ = 0.5 * (P_ + P_.transpose());
    ++updates_;
    return true;
}

double GravityTilt::drift_sigma() const {
    // Of t - t0: P_tt + P_00 - 2 P_t0, the larger axis.
    const Eigen::Matrix2d d =
        P_.block<2, 2>(0, 0) + P_.block<2, 2>(2, 2) - P_.block<2, 2>(0, 2) - P_.block<2, 2>(2, 0);
    return std::sqrt(std::max(d(0, 0), d(1, 1)));
}

bool GravityTilt::ready() const {
    return initialized_ && updates_ > 0 && drift_sigma() < config_.ready_sigma;
}

}  // namespace bimslam::odometry
