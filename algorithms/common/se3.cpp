// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/common/se3.hpp"

#include <cmath>

namespace bimslam::common {
namespace {
// Below this angle the closed forms lose precision to cancellation; use Taylor series instead.
constexpr double kSmallAngle = 1e-6;
}  // namespace

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
    Eigen::Matrix3d S;
    S << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
    return S;
}

Eigen::Matrix3d ExpSO3(const Eigen::Vector3d& phi) {
    const double theta = phi.norm();
    const Eigen::Matrix3d S = Skew(phi);
    if (theta < kSmallAngle) {
        return Eigen::Matrix3d::Identity() + S + 0.5 * S * S;
    }
    // Rodrigues: R = I + sin(t)/t [phi]x + (1 - cos(t))/t^2 [phi]x^2.
    return Eigen::Matrix3d::Identity() + (std::sin(theta) / theta) * S +
           ((1.0 - std::cos(theta)) / (theta * theta)) * S * S;
}

Eigen::Vector3d LogSO3(const Eigen::Matrix3d& R) {
    // Through the quaternion (Eigen uses Shepperd's method), which stays accurate near 0 and pi
    // where the trace formula does not.
    Eigen::Quaterniond q(R);
    q.normalize();
    if (q.w() < 0.0) {
        q.coeffs() = -q.coeffs();
    }
    const double n = q.vec().norm();
    if (n < 1e-12) {
        return 2.0 * q.vec();
    }
    return (2.0 * std::atan2(n, q.w()) / n) * q.vec();
}

Eigen::Matrix3d LeftJacobianSO3(const Eigen::Vector3d& phi) {
    const double theta = phi.norm();
    const Eigen::Matrix3d S = Skew(phi);
    if (theta < kSmallAngle) {
        return Eigen::Matrix3d::Identity() + 0.5 * S + (1.0 / 6.0) * S * S;
    }
    const double t2 = theta * theta;
    return Eigen::Matrix3d::Identity() + ((1.0 - std::cos(theta)) / t2) * S +
           ((theta - std::sin(theta)) / (t2 * theta)) * S * S;
}

Eigen::Matrix3d LeftJacobianInverseSO3(const Eigen::Vector3d& phi) {
    const double theta = phi.norm();
    const Eigen::Matrix3d S = Skew(phi);
    if (theta < kSmallAngle) {
        return Eigen::Matrix3d::Identity() - 0.5 * S + (1.0 / 12.0) * S * S;
    }
    const double c =
        1.0 / (theta * theta) - (1.0 + std::cos(theta)) / (2.0 * theta * std::sin(theta));
    return Eigen::Matrix3d::Identity() - 0.5 * S + c * S * S;
}

Eigen::Isometry3d ExpSE3(const Vector6d& xi) {
    const Eigen::Vector3d rho = xi.head<3>();
    const Eigen::Vector3d phi = xi.tail<3>();
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = ExpSO3(phi);
    T.translation() = LeftJacobianSO3(phi) * rho;
    return T;
}

Vector6d LogSE3(const Eigen::Isometry3d& T) {
    const Eigen::Vector3d phi = LogSO3(T.linear());
    Vector6d xi;
    xi.head<3>() = LeftJacobianInverseSO3(phi) * T.translation();
    xi.tail<3>() = phi;
    return xi;
}

Eigen::Isometry3d Inverse(const Eigen::Isometry3d& T) {
    Eigen::Isometry3d inv = Eigen::Isometry3d::Identity();
    inv.linear() = T.linear().transpose();
    inv.translation() = -(inv.linear() * T.translation());
    return inv;
}

Eigen::Isometry3d Between(const Eigen::Isometry3d& T_world_a, const Eigen::Isometry3d& T_world_b) {
    return Inverse(T_world_a) * T_world_b;
}

Eigen::Isometry3d Interpolate(const Eigen::Isometry3d& T0, const Eigen::Isometry3d& T1,
                              double alpha) {
    // R0 Exp(alpha Log(R0^T R1)) is slerp along the shortest arc, and extrapolates correctly.
    const Eigen::Vector3d phi = LogSO3(T0.linear().transpose() * T1.linear());
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = T0.linear() * ExpSO3(alpha * phi);
    T.translation() = (1.0 - alpha) * T0.translation() + alpha * T1.translation();
    return T;
}

Eigen::Isometry3d FromQuaternionTranslation(const Eigen::Quaterniond& q, const Eigen::Vector3d& t) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = q.normalized().toRotationMatrix();
    T.translation() = t;
    return T;
}

Eigen::Quaterniond Rotation(const Eigen::Isometry3d& T) {
    return Eigen::Quaterniond(T.linear()).normalized();
}

Matrix6d Adjoint(const Eigen::Isometry3d& T) {
    Matrix6d Ad = Matrix6d::Zero();
    const Eigen::Matrix3d R = T.linear();
    Ad.topLeftCorner<3, 3>() = R;
    Ad.topRightCorner<3, 3>() = Skew(T.translation()) * R;
    Ad.bottomRightCorner<3, 3>() = R;
    return Ad;
}

Eigen::Isometry3d YawPose(double yaw) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    return T;
}

double Heading(const Eigen::Matrix3d& R) { return std::atan2(R(1, 0), R(0, 0)); }

Eigen::Matrix3d RotationFromRpyDeg(const Eigen::Vector3d& rpy_deg) {
    const Eigen::Vector3d r = rpy_deg * (M_PI / 180.0);
    return (Eigen::AngleAxisd(r.z(), Eigen::Vector3d::UnitZ()) *
            Eigen::AngleAxisd(r.y(), Eigen::Vector3d::UnitY()) *
            Eigen::AngleAxisd(r.x(), Eigen::Vector3d::UnitX()))
        .toRotationMatrix();
}

Eigen::Isometry3d PoseFromXyzRpyDeg(const Eigen::Vector3d& xyz, const Eigen::Vector3d& rpy_deg) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = RotationFromRpyDeg(rpy_deg);
    T.translation() = xyz;
    return T;
}

double RotationAngle(const Eigen::Isometry3d& T) { return LogSO3(T.linear()).norm(); }

bool IsValidRigid(const Eigen::Isometry3d& T, double tol) {
    if (!T.matrix().allFinite()) {
        return false;
    }
    const Eigen::Matrix3d R = T.linear();
    if ((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > tol) {
        return false;
    }
    return R.determinant() > 0.0 && T.matrix().row(3) == Eigen::RowVector4d(0, 0, 0, 1);
}

}  // namespace bimslam::common
