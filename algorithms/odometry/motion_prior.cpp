// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/odometry/motion_prior.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "algorithms/common/status.hpp"

namespace bimslam::odometry {
using common::Require;
namespace {
using common::StatusCode;

void Require(bool ok, const char* field, double value, const char* rule) {
    common::Require(ok, "MotionPriorConfig", field, value, rule);
}

// Roll and pitch of a body attitude (ZYX Euler angles, yaw dropped).
Eigen::Matrix3d RollPitch(const std::optional<Eigen::Quaterniond>& q) {
    if (!q) return Eigen::Matrix3d::Identity();
    const Eigen::Matrix3d R = q->normalized().toRotationMatrix();
    const double pitch = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
    const double roll = std::atan2(R(2, 1), R(2, 2));
    return (Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
            Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
        .toRotationMatrix();
}

bool Finite(const BodyMotionSample& s) {
    return s.v_xy.allFinite() && std::isfinite(s.yaw_rate) &&
           (!s.attitude || s.attitude->coeffs().allFinite());
}
}  // namespace

void MotionPriorConfig::Validate() const {
    Require(velocity_sigma >= 0 && std::isfinite(velocity_sigma), "velocity_sigma", velocity_sigma,
            "must be >= 0");
    Require(velocity_scale_sigma >= 0 && velocity_scale_sigma < 1, "velocity_scale_sigma",
            velocity_scale_sigma, "must be in [0, 1)");
    Require(yaw_rate_sigma >= 0 && std::isfinite(yaw_rate_sigma), "yaw_rate_sigma", yaw_rate_sigma,
            "must be >= 0");
    Require(attitude_sigma >= 0 && std::isfinite(attitude_sigma), "attitude_sigma", attitude_sigma,
            "must be >= 0");
    Require(vertical_sigma >= 0 && std::isfinite(vertical_sigma), "vertical_sigma", vertical_sigma,
            "must be >= 0");
    Require(invalid_velocity_sigma > 0 && std::isfinite(invalid_velocity_sigma),
            "invalid_velocity_sigma", invalid_velocity_sigma, "must be > 0");
    Require(invalid_yaw_rate_sigma > 0 && std::isfinite(invalid_yaw_rate_sigma),
            "invalid_yaw_rate_sigma", invalid_yaw_rate_sigma, "must be > 0");
    Require(max_gap_s > 0 && std::isfinite(max_gap_s), "max_gap_s", max_gap_s, "must be > 0");
    Require(capacity >= 2, "capacity", double(capacity), "must be >= 2");
}

MotionPrior::MotionPrior(const MotionPriorConfig& config) : config_(config) {
    config_.Validate();
    buffer_.resize(config_.capacity);
}

common::Status MotionPrior::Add(const BodyMotionSample& s) {
    if (!Finite(s)) return {StatusCode::kInvalidArgument, "non-finite body motion sample"};
    if (count_ > 0 && s.t_ns <= At(count_ - 1).t_ns) {
        return {StatusCode::kInvalidArgument, "body motion sample out of time order"};
    }
    if (count_ == buffer_.size()) {
        buffer_[head_] = s;  // overwrite the oldest
        head_ = (head_ + 1) % buffer_.size();
    } else {
        buffer_[(head_ + count_) % buffer_.size()] = s;
        ++count_;
    }
    return common::Status::Ok();
}

int64_t MotionPrior::begin_ns() const { return count_ ? At(0).t_ns : 0; }
int64_t MotionPrior::end_ns() const { return count_ ? At(count_ - 1).t_ns : 0; }

std::optional<MotionPrior::Relative> MotionPrior::Between(int64_t a_ns, int64_t b_ns) const {
    if (count_ < 2 || a_ns > b_ns || a_ns < begin_ns() || b_ns > end_ns()) return std::nullopt;
    // The interval holding a: the last sample at or before it.
    size_t lo = 0, hi = count_ - 1;
    while (hi - lo > 1) {
        const size_t mid = (lo + hi) / 2;
        (At(mid).t_ns <= a_ns ? lo : hi) = mid;
    }
    // Planar state relative to a, and its covariance (x, y, yaw).
    double x = 0, y = 0, yaw = 0, seconds = 0;
    Eigen::Matrix3d P = Eigen::Matrix3d::Zero();
    const double scale2 = config_.velocity_scale_sigma * config_.velocity_scale_sigma;
    Eigen::Vector2d last_v = Eigen::Vector2d::Zero();
    double last_w = 0;
    for (size_t k = lo; k + 1 < count_ && At(k).t_ns < b_ns; ++k) {
        const BodyMotionSample& s0 = At(k);
        const BodyMotionSample& s1 = At(k + 1);
        const int64_t t0 = std::max(s0.t_ns, a_ns), t1 = std::min(s1.t_ns, b_ns);
        if (t1 <= t0) continue;
        const double dt = 1e-9 * double(t1 - t0);
        const bool gap = 1e-9 * double(s1.t_ns - s0.t_ns) > config_.max_gap_s;
        // Trapezoid over the interval when both ends are valid; else hold the last valid value
        // with the noise of invalid data.
        const bool v_ok = !gap && s0.velocity_valid && s1.velocity_valid;
        const bool w_ok = !gap && s0.yaw_rate_valid && s1.yaw_rate_valid;
        const Eigen::Vector2d v = v_ok ? Eigen::Vector2d(0.5 * (s0.v_xy + s1.v_xy)) : last_v;
        const double w = w_ok ? 0.5 * (s0.yaw_rate + s1.yaw_rate) : last_w;
        if (v_ok) last_v = v;
        if (w_ok) last_w = w;
        const double sv = v_ok ? config_.velocity_sigma : config_.invalid_velocity_sigma;
        const double sw = w_ok ? config_.yaw_rate_sigma : config_.invalid_yaw_rate_sigma;

        // Midpoint rule: the displacement of the interval in the frame of a.
        const double yaw_mid = yaw + 0.5 * w * dt;
        const double c = std::cos(yaw_mid), sn = std::sin(yaw_mid);
        const Eigen::Vector2d d(dt * (c * v.x() - sn * v.y()), dt * (sn * v.x() + c * v.y()));
        // Jacobian of (x, y, yaw) after the step with respect to before (the yaw rotates d).
        Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
        F(0, 2) = -d.y();
        F(1, 2) = d.x();
        // Input noise: velocity white noise (variance sv^2 dt per axis, a random walk in time)
        // plus the scale error (variance s^2 |d| x 1 m, a random walk in distance), yaw rate
        // white noise; rotated from the body into frame a.
        const double var_v = sv * sv * dt + scale2 * d.norm();
        Eigen::Matrix2d Rb;
        Rb << c, -sn, sn, c;
        Eigen::Matrix3d Q = Eigen::Matrix3d::Zero();
        Q.topLeftCorner<2, 2>() = Rb * (var_v * Eigen::Matrix2d::Identity()) * Rb.transpose();
        Q(2, 2) = sw * sw * dt;
        P = F * P * F.transpose() + Q;
        x += d.x();
        y += d.y();
        yaw += w * dt;
        seconds += dt;
    }
    // Roll and pitch at a and b from the attitude of the nearest samples before them.
    size_t kb = lo;
    while (kb + 1 < count_ && At(kb + 1).t_ns <= b_ns) ++kb;
    const bool attitude = At(lo).attitude.has_value() && At(kb).attitude.has_value();
    const Eigen::Matrix3d Ra = RollPitch(At(lo).attitude), Rb = RollPitch(At(kb).attitude);

    Relative r;
    // Body frame at a: R_a = Ra (roll/pitch, yaw 0); at b: Rz(yaw) Rb. T_a_b = R_a^T T_b.
    Eigen::Isometry3d T_b = Eigen::Isometry3d::Identity();
    T_b.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix() * Rb;
    T_b.translation() = Eigen::Vector3d(x, y, 0);
    Eigen::Isometry3d T_a = Eigen::Isometry3d::Identity();
    T_a.linear() = Ra;
    r.T_a_b = common::Inverse(T_a) * T_b;
    // Covariance over [x y z rx ry rz] in frame a (small-angle: the planar block maps onto
    // x, y, rz; roll and pitch are two independent absolute attitude readings).
    const int idx[3] = {0, 1, 5};
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) r.covariance(idx[i], idx[j]) = P(i, j);
    }
    r.covariance(2, 2) = config_.vertical_sigma * config_.vertical_sigma * seconds;
    const double att = attitude ? config_.attitude_sigma : 0.1;  // unknown: a 0.1 rad guess
    r.covariance(3, 3) = r.covariance(4, 4) = 2 * att * att;
    return r;
}

}  // namespace bimslam::odometry
