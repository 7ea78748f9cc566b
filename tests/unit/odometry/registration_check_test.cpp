// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/odometry/registration_check.hpp"

#include <gtest/gtest.h>

#include "algorithms/common/status.hpp"

namespace bimslam::odometry {
namespace {
namespace BIMSLAM_UNITY_ID {

RegistrationResult Good() {
    RegistrationResult r;
    r.points = 1000;
    r.correspondences = 950;
    r.inliers = 920;
    r.rms = 0.01;
    return r;
}

TEST(RegistrationCheck, AScanThatFitsPasses) {
    const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
    EXPECT_EQ(JudgeRegistration(Good(), I, I, Eigen::Vector3d::Constant(0.05), {}), 0u);
}

TEST(RegistrationCheck, EachKindOfEvidenceFailsOnItsOwn) {
    const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
    const Eigen::Vector3d sigma = Eigen::Vector3d::Constant(0.05);
    RegistrationCheckConfig c;
    RegistrationResult r = Good();
    r.correspondences = 250;  // overlap 0.25
    r.inliers = 240;
    EXPECT_EQ(JudgeRegistration(r, I, I, sigma, c), uint32_t(kLowOverlap));
    r = Good();
    r.inliers = 450;  // 0.45 of the points, 0.47 of the matches: as scans left 8-27 deg off
    EXPECT_EQ(JudgeRegistration(r, I, I, sigma, c), uint32_t(kFewInliers));
    r.correspondences = 500;  // a door leaf in view: few matches, but those fit
    EXPECT_EQ(JudgeRegistration(r, I, I, sigma, c), 0u);
    r = Good();
    r.rms = 0.08;
    EXPECT_EQ(JudgeRegistration(r, I, I, sigma, c), uint32_t(kHighResidual));
    // Far from the prediction: only when asked for.
    Eigen::Isometry3d T = I;
    T.translation() = Eigen::Vector3d(0.5, 0, 0);  // 10 sigma
    EXPECT_EQ(JudgeRegistration(Good(), I, T, sigma, c), 0u);
    c.max_prediction_sigmas = 5;
    EXPECT_EQ(JudgeRegistration(Good(), I, T, sigma, c), uint32_t(kFarFromPrediction));
    c.enabled = false;
    r.inliers = 0;
    EXPECT_EQ(JudgeRegistration(r, I, T, sigma, c), 0u);
    EXPECT_EQ(CheckReasonText(kLowOverlap | kHighResidual),
              "low overlap with the map, high residual");
}

// Duplex_A's walk down from Level 2, its scan 1 against a map of one scan (`bimslam odometry
// --scans-csv`): 2364 points, 1200 matched, 943 within 0.1 m: "few inliers" (0.40 of the points,
// 0.79 of the matches). 699 of the matches were to planes through one ring (VoxelPlane::
// line_like), 239 of the 257 matches off their plane among them. Left out, 483 of the other 501
// fit (0.96); the overlap still counts them all (0.51).
TEST(RegistrationCheck, MatchesToLineLikePlanesAreNoEvidenceOfFit) {
    const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
    const Eigen::Vector3d sigma = Eigen::Vector3d::Constant(0.05);
    RegistrationResult r;
    r.points = 2364;
    r.correspondences = 1200;
    r.inliers = 943;
    r.rms = 0.019;
    EXPECT_EQ(JudgeRegistration(r, I, I, sigma, {}), uint32_t(kFewInliers)) << "all counted";
    r.unjudged = 699;
    r.inliers = 483;
    EXPECT_EQ(JudgeRegistration(r, I, I, sigma, {}), 0u);
    EXPECT_NEAR(RegistrationScore(r), 483.0 / 1665.0, 1e-12);
    // The other matches must still fit: 300 of 501 is a wrong minimum's share.
    r.inliers = 300;
    EXPECT_EQ(JudgeRegistration(r, I, I, sigma, {}), uint32_t(kFewInliers));
    // A scan matched mostly to such planes still overlaps the map.
    r.correspondences = 800;
    r.unjudged = 750;
    r.inliers = 50;
    EXPECT_EQ(JudgeRegistration(r, I, I, sigma, {}), 0u);
}

TEST(RegistrationCheck, AFailedRegistrationIsNotJudgedAgain) {
    RegistrationResult r;
    r.failed = true;  // kRegistrationFailed already says so
    const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
    EXPECT_EQ(JudgeRegistration(r, I, I, Eigen::Vector3d::Constant(0.05), {}), 0u);
}

TEST(RegistrationCheck, ConfigurationOutOfRangeIsRejected) {
    RegistrationCheckConfig c;
    c.min_inlier_ratio = 1.5;
    EXPECT_THROW(c.Validate(), common::Error);
    c = {};
    c.retry_headings = -1;
    EXPECT_THROW(c.Validate(), common::Error);
    c = {};
    EXPECT_NO_THROW(c.Validate());
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::odometry
