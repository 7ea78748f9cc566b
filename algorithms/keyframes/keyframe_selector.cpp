// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/keyframes/keyframe_selector.hpp"

#include <cmath>

#include "algorithms/common/status.hpp"

namespace bimslam::keyframes {

void KeyframeConfig::Validate() const {
    using common::Require;
    Require(distance_m > 0 && std::isfinite(distance_m), "KeyframeConfig", "distance_m", distance_m,
            "must be > 0");
    Require(angle_deg > 0 && angle_deg <= 360, "KeyframeConfig", "angle_deg", angle_deg,
            "must be in (0, 360]");
    descriptor.Validate();
}

KeyframeSelector::KeyframeSelector(const KeyframeConfig& config)
    : config_(config), descriptor_builder_(config.descriptor) {
    config_.Validate();
}

bool KeyframeSelector::Add(const odometry::OdometryResult& scan,
                           const common::PointCloud& deskewed) {
    const Eigen::Isometry3d& T = scan.T_odom_lidar;
    if (count_ > 0) {
        // T_last_j = T_last_(j-1) * D_j, perturbed on the right:
        // Sigma_j = Ad(D_j^-1) Sigma_(j-1) Ad(D_j^-1)^T + Sigma_D (Barfoot, eq. 7.300).
        const common::Matrix6d A = common::Adjoint(scan.T_prev_lidar.inverse());
        covariance_ = A * covariance_ * A.transpose() + scan.covariance;
        const Eigen::Isometry3d T_last_current = common::Between(T_odom_last_, T);
        const bool far = T_last_current.translation().norm() >= config_.distance_m;
        const bool turned =
            common::RotationAngle(T_last_current) >= config_.angle_deg * M_PI / 180.0;
        if ((!far && !turned) || deskewed.size() < config_.min_points) return false;
        io::SessionEdge e;
        e.from = static_cast<uint32_t>(count_ - 1);
        e.to = static_cast<uint32_t>(count_);
        e.T_from_to = T_last_current;
        // Regularised so that a direction the odometry did not observe still inverts.
        const common::Matrix6d sym = 0.5 * (covariance_ + covariance_.transpose());
        e.information = (sym + 1e-9 * common::Matrix6d::Identity()).inverse();
        edge_ = e;
    } else {
        if (deskewed.size() < config_.min_points) return false;
        edge_.reset();
    }
    keyframe_.stamp_ns = scan.stamp_ns;
    keyframe_.T_world_lidar = T;
    keyframe_.T_odom_lidar = T;
    keyframe_.cloud.xyz = deskewed.xyz;
    keyframe_.cloud.intensity = deskewed.intensity;
    keyframe_.cloud.ring = deskewed.ring;
    keyframe_.cloud.time_offset_ns = deskewed.time_offset_ns;
    keyframe_.cloud.stamp = deskewed.stamp;
    keyframe_.cloud.frame = deskewed.frame;
    descriptor_builder_.Build(keyframe_.cloud, &keyframe_.descriptor);
    T_odom_last_ = T;
    covariance_.setZero();
    ++count_;
    return true;
}

}  // namespace bimslam::keyframes
