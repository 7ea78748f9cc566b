// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Keyframe selection: the distance and angle rules, the keyframe's cloud and descriptor, and the
// odometry edge with the covariance accumulated over the scans in between.
#include "algorithms/keyframes/keyframe_selector.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "algorithms/common/status.hpp"

namespace bimslam::keyframes {
namespace {
namespace BIMSLAM_UNITY_ID {

struct Walker {
    KeyframeSelector selector;
    odometry::OdometryResult r;
    common::PointCloud cloud;
    explicit Walker(const KeyframeConfig& c = {}) : selector(c) {
        for (int i = 0; i < 2000; ++i) {  // a round room's wall, 4 m away, -1 to 2 m high
            const double a = 2 * M_PI * (i / 10) / 200;
            cloud.PushBack(Eigen::Vector3f(float(4 * std::cos(a)), float(4 * std::sin(a)),
                                           -1.f + 0.3f * float(i % 10)),
                           10.f, uint16_t(i % 32), uint32_t(i) * 50'000);
        }
    }
    // One scan that moved by `step` since the last, with the given per-scan covariance.
    bool Step(const Eigen::Isometry3d& step, double sigma = 0.01) {
        r.stamp_ns += 100'000'000;
        r.T_prev_lidar = step;
        r.T_odom_lidar = r.T_odom_lidar * step;
        r.covariance = common::Matrix6d::Identity() * sigma * sigma;
        cloud.stamp = common::SensorTime{r.stamp_ns};
        return selector.Add(r, cloud);
    }
};

Eigen::Isometry3d Forward(double x) { return Eigen::Isometry3d(Eigen::Translation3d(x, 0, 0)); }
Eigen::Isometry3d Yaw(double deg) {
    return Eigen::Isometry3d(Eigen::AngleAxisd(deg * M_PI / 180, Eigen::Vector3d::UnitZ()));
}

TEST(KeyframeSelector, FirstScanThenEveryMetre) {
    Walker w;
    EXPECT_TRUE(w.Step(Eigen::Isometry3d::Identity()));
    EXPECT_FALSE(w.selector.edge().has_value());
    int keyframes = 1;
    for (int k = 0; k < 50; ++k) keyframes += w.Step(Forward(0.3)) ? 1 : 0;  // 15 m
    EXPECT_EQ(keyframes, 1 + 12);  // every 4th scan: 1.2 m apart (0.9 m is not enough)
    EXPECT_EQ(w.selector.count(), size_t(keyframes));
}

TEST(KeyframeSelector, TurningOnTheSpotMakesKeyframesEveryTenDegrees) {
    Walker w;
    w.Step(Eigen::Isometry3d::Identity());
    int keyframes = 0;
    for (int k = 0; k < 36; ++k) keyframes += w.Step(Yaw(5.5)) ? 1 : 0;  // 198 degrees
    EXPECT_EQ(keyframes, 18);
}

TEST(KeyframeSelector, TheEdgeCarriesTheMotionAndTheAccumulatedCovariance) {
    Walker w;
    w.Step(Eigen::Isometry3d::Identity());
    for (int k = 0; k < 3; ++k) EXPECT_FALSE(w.Step(Forward(0.3), 0.01));
    ASSERT_TRUE(w.Step(Forward(0.3), 0.01));
    const io::SessionEdge& e = *w.selector.edge();
    EXPECT_EQ(e.from, 0u);
    EXPECT_EQ(e.to, 1u);
    EXPECT_NEAR(e.T_from_to.translation().x(), 1.2, 1e-12);
    // Four scans of 1 cm and 0.01 rad each, moving 0.3 m straight ahead: along x the variances
    // add (4 x 1e-4); sideways each scan's yaw error also swings the rest of the way (0.9, 0.6,
    // 0.3 and 0 m): 4e-4 + 1e-4 (0.81 + 0.36 + 0.09), correlated with the yaw by
    // 1e-4 (0.9 + 0.6 + 0.3) (Barfoot, eq. 7.300).
    const common::Matrix6d cov = e.information.inverse();
    EXPECT_NEAR(cov(0, 0), 4e-4, 1e-8);
    EXPECT_NEAR(cov(5, 5), 4e-4, 1e-8);
    EXPECT_NEAR(cov(1, 1), 5.26e-4, 1e-8);
    EXPECT_NEAR(std::abs(cov(1, 5)), 1.8e-4, 1e-8);
    EXPECT_TRUE((e.information - e.information.transpose()).cwiseAbs().maxCoeff() < 1e-6);

    const io::SessionKeyframe& kf = w.selector.keyframe();
    EXPECT_EQ(kf.stamp_ns, w.r.stamp_ns);
    EXPECT_TRUE(kf.T_odom_lidar->isApprox(w.r.T_odom_lidar));
    EXPECT_EQ(kf.cloud.size(), w.cloud.size());
    EXPECT_EQ(kf.cloud.time_offset_ns, w.cloud.time_offset_ns);
    EXPECT_EQ(kf.descriptor.rows(), 20);
    EXPECT_EQ(kf.descriptor.cols(), 60);
    EXPECT_GT(kf.descriptor.maxCoeff(), 0.f);
}

TEST(KeyframeSelector, AScanWithoutPointsNeverBecomesAKeyframe) {
    Walker w;
    const common::PointCloud full = w.cloud;
    w.cloud = common::PointCloud{};
    EXPECT_FALSE(w.Step(Eigen::Isometry3d::Identity())) << "not even the first";
    w.cloud = full;
    EXPECT_TRUE(w.Step(Forward(0.1)));
    w.cloud = common::PointCloud{};
    EXPECT_FALSE(w.Step(Forward(1.5))) << "far enough, but empty";
    w.cloud = full;
    ASSERT_TRUE(w.Step(Forward(0.1))) << "the next scan with points takes its place";
    EXPECT_NEAR(w.selector.edge()->T_from_to.translation().x(), 1.6, 1e-12);
    EXPECT_EQ(w.selector.count(), 2u);
}

TEST(KeyframeConfig, ValidateNamesTheField) {
    KeyframeConfig c;
    c.angle_deg = 0;
    try {
        KeyframeSelector s(c);
        FAIL();
    } catch (const common::Error& e) {
        EXPECT_NE(std::string(e.what()).find("angle_deg"), std::string::npos);
    }
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::keyframes
