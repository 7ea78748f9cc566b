// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The tracked pose (localization::FuseWithPrediction): a registration moves the prediction as far
// as it measured, not along a direction its information leaves unconstrained.
#include <gtest/gtest.h>

#include <cmath>

#include "algorithms/common/se3.hpp"
#include "algorithms/localization/relocalizer.hpp"

namespace bimslam::localization {
namespace {
namespace BIMSLAM_UNITY_ID {

// A prediction turned and placed in the model, and a registration that ends 2 cm across and
// 11 cm up from it (the model's axes), with 1 cm and 0.05 deg of standard deviation per axis.
struct Case {
    Eigen::Isometry3d predicted = Eigen::Isometry3d::Identity();
    registration::RegistrationResult r;
    Case() {
        predicted.linear() = common::ExpSO3(Eigen::Vector3d(0.05, -0.03, 1.2));
        predicted.translation() = Eigen::Vector3d(2.0, 7.5, 1.3);
        r.T_target_source = predicted;
        r.T_target_source.translation() += Eigen::Vector3d(0.02, 0.0, 0.11);
        common::Vector6d info;
        const double rad = 0.05 * M_PI / 180;
        info << 1e4, 1e4, 1e4, 1 / (rad * rad), 1 / (rad * rad), 1 / (rad * rad);
        r.information = info.asDiagonal();
    }
};

TEST(TrackFusion, AWellConstrainedRegistrationIsTakenAlmostWhole) {
    const Case c;
    const Eigen::Isometry3d found = FuseWithPrediction(c.predicted, c.r, 0.1, 0.1, 1.0);
    // 1 cm against the prediction's 10 cm: 99 % of the step.
    const Eigen::Vector3d d = found.translation() - c.predicted.translation();
    EXPECT_NEAR(d.x(), 0.02 * 0.99, 2e-4);
    EXPECT_NEAR(d.z(), 0.11 * 0.99, 2e-4);
    EXPECT_LT(common::RotationAngle(c.predicted.inverse() * found), 1e-6);
}

TEST(TrackFusion, AHeightTheRegistrationCouldNotConstrainStaysThePredictions) {
    Case c;
    // Degenerate along the model's vertical (registration.hpp: zero information there), in the
    // lidar's axes of the right perturbation.
    const Eigen::Vector3d up = c.predicted.linear().transpose() * Eigen::Vector3d::UnitZ();
    const Eigen::Matrix3d keep = Eigen::Matrix3d::Identity() - up * up.transpose();
    c.r.information.topLeftCorner<3, 3>() = keep * c.r.information.topLeftCorner<3, 3>() * keep;
    const Eigen::Isometry3d found = FuseWithPrediction(c.predicted, c.r, 0.1, 0.1, 1.0);
    const Eigen::Vector3d d = found.translation() - c.predicted.translation();
    EXPECT_NEAR(d.x(), 0.02 * 0.99, 2e-4);  // what it measured, as before
    EXPECT_NEAR(d.z(), 0.0, 1e-4);          // 11 cm that nothing measured: none of it
}

// A contradiction 1 m up (the held-out Office_A's climb, localization README) is cleared only by
// a registration that measured the height; one degenerate there measured nothing of it. One
// across is cleared by a registration that measured across, whatever it knew of the height.
TEST(TrackFusion, OnlyARegistrationThatMeasuredTheContradictedDirectionClearsIt) {
    Case c;
    const Eigen::Vector3d up = Eigen::Vector3d::UnitZ(), across = Eigen::Vector3d::UnitX();
    EXPECT_TRUE(MeasuredAlong(c.r, c.predicted, up, 0.1, 0.1));
    EXPECT_TRUE(MeasuredAlong(c.r, c.predicted, across, 0.1, 0.1));
    const Eigen::Vector3d up_lidar = c.predicted.linear().transpose() * up;
    const Eigen::Matrix3d keep = Eigen::Matrix3d::Identity() - up_lidar * up_lidar.transpose();
    c.r.information.topLeftCorner<3, 3>() = keep * c.r.information.topLeftCorner<3, 3>() * keep;
    EXPECT_FALSE(MeasuredAlong(c.r, c.predicted, up, 0.1, 0.1));
    EXPECT_TRUE(MeasuredAlong(c.r, c.predicted, across, 0.1, 0.1));
    // Off in rotation only (no direction): any agreeing registration clears it.
    EXPECT_TRUE(MeasuredAlong(c.r, c.predicted, Eigen::Vector3d::Zero(), 0.1, 0.1));
    // Measured, but less well than the prediction knows the height (sigma 20 cm against 10).
    c.r.information.topLeftCorner<3, 3>() += 25.0 * up_lidar * up_lidar.transpose();
    EXPECT_FALSE(MeasuredAlong(c.r, c.predicted, up, 0.1, 0.1));
    EXPECT_TRUE(MeasuredAlong(c.r, c.predicted, up, 0.1, 0.3));
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::localization
