// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// bim_pose_t's covariance (localization::LiveCovariance): the fixing registration's information
// inverted, carried by the adjoint to a later base pose, with the odometry's drift added; a
// degenerate direction is unconstrained, not certain.
#include <gtest/gtest.h>

#include <cmath>

#include "algorithms/common/se3.hpp"
#include "algorithms/localization/relocalizer.hpp"

namespace bimslam::localization {
namespace {
namespace BIMSLAM_UNITY_ID {

common::Matrix6d Diagonal(double t, double r) {
    common::Vector6d d;
    d << t, t, t, r, r, r;
    return d.asDiagonal();
}

TEST(LiveCovariance, AtTheFixItIsTheInverseOfTheInformation) {
    RelocalizerConfig c;
    const common::Matrix6d info = Diagonal(1e6, 4e6);  // 1 mm, 0.5 mrad
    const common::Matrix6d C = LiveCovariance(info, Eigen::Isometry3d::Identity(), 0, c);
    EXPECT_TRUE(C.isApprox(info.inverse(), 1e-9)) << C;
}

TEST(LiveCovariance, TheDriftGrowsWithTheDistanceAndARotationsLeverArmAddsTranslation) {
    RelocalizerConfig c;
    const common::Matrix6d info = Diagonal(1e6, 1e6);
    const common::Matrix6d at = LiveCovariance(info, Eigen::Isometry3d::Identity(), 0, c);
    const common::Matrix6d far = LiveCovariance(info, Eigen::Isometry3d::Identity(), 2.0, c);
    const double drift = c.drift_per_m * 2.0;
    EXPECT_NEAR(far(0, 0) - at(0, 0), drift * drift, 1e-12);
    const double drift_r = c.drift_deg_per_m * M_PI / 180 * 2.0;
    EXPECT_NEAR(far(5, 5) - at(5, 5), drift_r * drift_r, 1e-12);
    // The base 3 m ahead (x) of the fix's lidar: the yaw's uncertainty moves it sideways (y) by
    // 3 m per rad, and not along x.
    Eigen::Isometry3d ahead = Eigen::Isometry3d::Identity();
    ahead.translation() = Eigen::Vector3d(3, 0, 0);
    const common::Matrix6d moved = LiveCovariance(info, ahead, 0, c);
    EXPECT_NEAR(moved(1, 1), 1e-6 + 9 * 1e-6, 1e-12);
    EXPECT_NEAR(moved(0, 0), 1e-6, 1e-12);
    EXPECT_TRUE(moved.isApprox(moved.transpose(), 1e-12));
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<common::Matrix6d>(moved).eigenvalues().minCoeff(), 0);
}

TEST(LiveCovariance, ADegenerateDirectionIsUnconstrained) {
    RelocalizerConfig c;
    common::Matrix6d info = Diagonal(1e6, 1e6);
    info(0, 0) = 0;  // a corridor's axis (registration.hpp: zero information)
    const common::Matrix6d C = LiveCovariance(info, Eigen::Isometry3d::Identity(), 0, c);
    EXPECT_NEAR(C(0, 0), kUnconstrainedVariance, 1e-6);
    EXPECT_NEAR(C(1, 1), 1e-6, 1e-12);
    const common::Matrix6d none =
        LiveCovariance(common::Matrix6d::Zero(), Eigen::Isometry3d::Identity(), 0, c);
    EXPECT_TRUE(none.diagonal().isApproxToConstant(kUnconstrainedVariance, 1e-9)) << none;
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::localization
