// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/common/se3.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace bimslam::common {
namespace {
namespace BIMSLAM_UNITY_ID {

Vector6d RandomTwist(std::mt19937& rng, double max_angle) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Vector6d xi;
    for (int i = 0; i < 6; ++i) xi[i] = u(rng) * 5.0;
    Eigen::Vector3d phi = xi.tail<3>();
    xi.tail<3>() = phi.normalized() * std::abs(u(rng)) * max_angle;
    return xi;
}

TEST(Se3, ExpLogRoundTripAcrossAngles) {
    std::mt19937 rng(1);
    for (double max_angle : {1e-9, 1e-7, 1e-4, 0.5, 2.0, M_PI - 1e-3}) {
        for (int i = 0; i < 200; ++i) {
            const Vector6d xi = RandomTwist(rng, max_angle);
            const Vector6d back = LogSE3(ExpSE3(xi));
            EXPECT_LT((back - xi).norm(), 1e-9 * (1.0 + xi.norm())) << "angle " << max_angle;
        }
    }
}

TEST(Se3, ExpMatchesRodriguesAndEigenAngleAxis) {
    const Eigen::Vector3d axis = Eigen::Vector3d(1, -2, 0.5).normalized();
    for (double angle : {0.0, 1e-8, 0.3, 1.7, 3.1}) {
        const Eigen::Matrix3d expected = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
        EXPECT_LT((ExpSO3(angle * axis) - expected).norm(), 1e-12) << angle;
    }
}

TEST(Se3, LogNearPiIsAccurate) {
    const Eigen::Vector3d axis = Eigen::Vector3d(0.3, 0.4, -0.2).normalized();
    const double angle = M_PI - 1e-9;
    const Eigen::Vector3d phi = LogSO3(Eigen::AngleAxisd(angle, axis).toRotationMatrix());
    EXPECT_NEAR(phi.norm(), angle, 1e-8);
    EXPECT_LT((phi.normalized() - axis).norm(), 1e-6);
}

TEST(Se3, LeftJacobianInverse) {
    std::mt19937 rng(2);
    for (int i = 0; i < 100; ++i) {
        const Eigen::Vector3d phi = RandomTwist(rng, 3.0).tail<3>();
        const Eigen::Matrix3d prod = LeftJacobianSO3(phi) * LeftJacobianInverseSO3(phi);
        EXPECT_LT((prod - Eigen::Matrix3d::Identity()).norm(), 1e-9);
    }
}

TEST(Se3, ComposeInverseBetween) {
    std::mt19937 rng(3);
    for (int i = 0; i < 100; ++i) {
        const Eigen::Isometry3d a = ExpSE3(RandomTwist(rng, 3.0));
        const Eigen::Isometry3d b = ExpSE3(RandomTwist(rng, 3.0));
        EXPECT_LT((Compose(a, Inverse(a)).matrix() - Eigen::Matrix4d::Identity()).norm(), 1e-12);
        EXPECT_LT((Compose(a, Between(a, b)).matrix() - b.matrix()).norm(), 1e-12);
        EXPECT_TRUE(IsValidRigid(Compose(a, b)));
    }
}

TEST(Se3, InterpolateEndpointsMidpointAndExtrapolation) {
    const Eigen::Isometry3d T0 = FromQuaternionTranslation(
        Eigen::Quaterniond(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ())), {1, 2, 3});
    const Eigen::Isometry3d T1 = FromQuaternionTranslation(
        Eigen::Quaterniond(Eigen::AngleAxisd(1.0, Eigen::Vector3d::UnitZ())), {3, 2, 1});
    EXPECT_LT((Interpolate(T0, T1, 0.0).matrix() - T0.matrix()).norm(), 1e-12);
    EXPECT_LT((Interpolate(T0, T1, 1.0).matrix() - T1.matrix()).norm(), 1e-12);
    const Eigen::Isometry3d mid = Interpolate(T0, T1, 0.5);
    EXPECT_NEAR(RotationAngle(Between(T0, mid)), 0.4, 1e-12);
    EXPECT_LT((mid.translation() - Eigen::Vector3d(2, 2, 2)).norm(), 1e-12);
    // Constant-velocity extrapolation: one more step of the same motion.
    const Eigen::Isometry3d ext = Interpolate(T0, T1, 2.0);
    EXPECT_NEAR(RotationAngle(Between(T1, ext)), 0.8, 1e-12);
    // Slerp takes the short arc even when the quaternions have opposite signs.
    const Eigen::Quaterniond q(Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX()));
    const Eigen::Isometry3d A = FromQuaternionTranslation(q, {0, 0, 0});
    const Eigen::Isometry3d B =
        FromQuaternionTranslation(Eigen::Quaterniond(-q.w(), -q.x(), -q.y(), -q.z()), {0, 0, 0});
    EXPECT_NEAR(RotationAngle(Between(A, Interpolate(A, B, 0.5))), 0.0, 1e-12);
}

TEST(Se3, QuaternionTranslationRoundTrip) {
    const Eigen::Quaterniond q = Eigen::Quaterniond(0.5, -0.1, 0.7, 0.2).normalized();
    const Eigen::Isometry3d T = FromQuaternionTranslation(q, {4, 5, 6});
    EXPECT_NEAR(Rotation(T).angularDistance(q), 0.0, 1e-12);
    EXPECT_EQ(T.translation(), Eigen::Vector3d(4, 5, 6));
    // Unnormalised input is normalised, not rejected.
    const Eigen::Isometry3d T2 =
        FromQuaternionTranslation(Eigen::Quaterniond(2 * q.coeffs()), {0, 0, 0});
    EXPECT_TRUE(IsValidRigid(T2));
}

TEST(Se3, AdjointTransportsTwists) {
    // Exp(Ad(T) xi) = T Exp(xi) T^-1 (Barfoot eq. 7.47).
    std::mt19937 rng(4);
    for (int i = 0; i < 50; ++i) {
        const Eigen::Isometry3d T = ExpSE3(RandomTwist(rng, 2.0));
        const Vector6d xi = RandomTwist(rng, 1.0);
        const Eigen::Isometry3d lhs = ExpSE3(Adjoint(T) * xi);
        const Eigen::Isometry3d rhs = T * ExpSE3(xi) * Inverse(T);
        EXPECT_LT((lhs.matrix() - rhs.matrix()).norm(), 1e-9);
    }
}

TEST(Se3, IsValidRigidRejectsBadMatrices) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    EXPECT_TRUE(IsValidRigid(T));
    T.matrix()(0, 0) = std::nan("");
    EXPECT_FALSE(IsValidRigid(T));
    T = Eigen::Isometry3d::Identity();
    T.matrix()(0, 0) = -1.0;  // a reflection
    EXPECT_FALSE(IsValidRigid(T));
    T = Eigen::Isometry3d::Identity();
    T.matrix()(0, 1) = 0.01;
    EXPECT_FALSE(IsValidRigid(T));
}

// Roll, pitch and yaw about the fixed x, y and z axes, applied in that order (R = Rz Ry Rx): a
// yaw of 90 deg turns x into y, a pitch of 15 deg tips x down towards -z, and the three compose.
TEST(Se3, RotationFromRpyDegIsZYXAboutFixedAxes) {
    EXPECT_LT((RotationFromRpyDeg({0, 0, 90}) * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY())
                  .norm(),
              1e-15);
    const double p = 15.0 * M_PI / 180.0;
    EXPECT_LT((RotationFromRpyDeg({0, 15, 0}) * Eigen::Vector3d::UnitX() -
               Eigen::Vector3d(std::cos(p), 0, -std::sin(p)))
                  .norm(),
              1e-15);
    const Eigen::Matrix3d R = RotationFromRpyDeg({10, -20, 30});
    const Eigen::Matrix3d expected = RotationFromRpyDeg({0, 0, 30}) *
                                     RotationFromRpyDeg({0, -20, 0}) *
                                     RotationFromRpyDeg({10, 0, 0});
    EXPECT_LT((R - expected).norm(), 1e-15);
    const Eigen::Isometry3d T = PoseFromXyzRpyDeg({1, 2, 3}, {10, -20, 30});
    EXPECT_EQ(T.translation(), Eigen::Vector3d(1, 2, 3));
    EXPECT_EQ(T.linear(), R);
    EXPECT_TRUE(IsValidRigid(T));
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::common
