// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// SE(3) helpers on Eigen::Isometry3d.
//
// Conventions: a transform is named T_to_from (T_world_lidar maps lidar points into world).
// Tangent vectors are xi = [rho; phi] with the translation part first and the rotation vector
// second, T = Exp(xi) = [ Exp_SO3(phi)  J_l(phi) rho ; 0 1 ] (Barfoot, "State Estimation for
// Robotics", eq. 7.83 and 7.86). Covariances over poses use the same order.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace bimslam::common {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

// Skew-symmetric matrix [v]x with [v]x w = v x w.
Eigen::Matrix3d Skew(const Eigen::Vector3d& v);

// SO(3) exponential (Rodrigues) and logarithm; the log returns an angle in [0, pi].
Eigen::Matrix3d ExpSO3(const Eigen::Vector3d& phi);
Eigen::Vector3d LogSO3(const Eigen::Matrix3d& R);

// Left Jacobian of SO(3) and its inverse (Barfoot eq. 7.77, 7.79).
Eigen::Matrix3d LeftJacobianSO3(const Eigen::Vector3d& phi);
Eigen::Matrix3d LeftJacobianInverseSO3(const Eigen::Vector3d& phi);

// SE(3) exponential and logarithm; Log(Exp(xi)) == xi for |phi| < pi.
Eigen::Isometry3d ExpSE3(const Vector6d& xi);
Vector6d LogSE3(const Eigen::Isometry3d& T);

// a * b, and the inverse, re-orthonormalising nothing: both are exact for rigid transforms.
inline Eigen::Isometry3d Compose(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
    return a * b;
}
Eigen::Isometry3d Inverse(const Eigen::Isometry3d& T);

// Relative motion from a to b, both in the same world: T_a_b = a^-1 * b.
Eigen::Isometry3d Between(const Eigen::Isometry3d& T_world_a, const Eigen::Isometry3d& T_world_b);

// Interpolation at alpha in [0, 1] (extrapolates outside): rotation by slerp, translation
// linearly. This is what per-point deskewing and trajectory lookups use.
Eigen::Isometry3d Interpolate(const Eigen::Isometry3d& T0, const Eigen::Isometry3d& T1,
                              double alpha);

// Conversion to and from a unit quaternion plus a translation. The quaternion is normalised.
Eigen::Isometry3d FromQuaternionTranslation(const Eigen::Quaterniond& q, const Eigen::Vector3d& t);
Eigen::Quaterniond Rotation(const Eigen::Isometry3d& T);

// A rotation about z by `yaw` (rad), no translation: a Scan Context match's yaw as a pose.
Eigen::Isometry3d YawPose(double yaw);
// The heading of R (rad): the angle of its x axis in the x-y plane, atan2(R10, R00).
double Heading(const Eigen::Matrix3d& R);

// A mount or a pose from x y z (m) and roll pitch yaw (deg), rotation R = Rz(yaw) Ry(pitch)
// Rx(roll) (the fixed-axis x-y-z convention of ROS' RPY and of the rig's `mount` setting).
Eigen::Matrix3d RotationFromRpyDeg(const Eigen::Vector3d& rpy_deg);
Eigen::Isometry3d PoseFromXyzRpyDeg(const Eigen::Vector3d& xyz, const Eigen::Vector3d& rpy_deg);

// Adjoint of T, acting on [rho; phi]: Ad(T) = [R [t]x R ; 0 R].
Matrix6d Adjoint(const Eigen::Isometry3d& T);

// Rotation angle of T in radians, in [0, pi]; translation norm in metres.
double RotationAngle(const Eigen::Isometry3d& T);
inline double TranslationNorm(const Eigen::Isometry3d& T) { return T.translation().norm(); }

// True when the linear part is a rotation (orthonormal, det +1) within tol and all entries are
// finite.
bool IsValidRigid(const Eigen::Isometry3d& T, double tol = 1e-6);

}  // namespace bimslam::common
