// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The accelerometers' height filter of the odometry (imu_height.hpp): what it integrates, what it
// removes (gravity, its bias), and that it learns only from scans that saw the height.
#include "algorithms/odometry/imu_height.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "algorithms/common/status.hpp"

namespace bimslam::odometry {
namespace {
namespace BIMSLAM_UNITY_ID {

const Eigen::Vector3d kRest(0, 0, 9.80665);  // the specific force at rest, level
constexpr double kDt = 0.01;                 // 100 Hz

// A sensor tilted by 10 deg about x and 5 deg about y: gravity is not on its z axis.
Eigen::Matrix3d Tilted() {
    return (Eigen::AngleAxisd(0.17, Eigen::Vector3d::UnitX()) *
            Eigen::AngleAxisd(0.09, Eigen::Vector3d::UnitY()))
        .toRotationMatrix();
}

TEST(ImuHeight, IntegratesAVerticalAccelerationWithGravityRemoved) {
    ImuHeight f;
    const Eigen::Matrix3d R = Tilted();
    f.Reset(3.0, Eigen::Vector3d::UnitZ());
    const Eigen::Vector3d a(0.5, -0.2, 0.3);  // world acceleration: only its 0.3 up counts
    for (int i = 0; i < 200; ++i) f.Propagate(R, R.transpose() * (a + kRest), kDt);
    EXPECT_NEAR(f.height(), 3.0 + 0.5 * 0.3 * 4.0, 1e-9);  // 2 s
    EXPECT_NEAR(f.velocity(), 2.0 * 0.3, 1e-9);
}

TEST(ImuHeight, LearnsItsBiasFromScansThatSawTheHeightAndThenHoldsIt) {
    ImuHeight f;
    const Eigen::Matrix3d R = Tilted();
    const Eigen::Vector3d bias(0.05, -0.04, 0.2);  // lidar frame, as a real accelerometer's
    f.Reset(0.0, Eigen::Vector3d::UnitZ());
    EXPECT_FALSE(f.ready()) << "its velocity is not known yet";
    // 10 s at rest, every scan (10 Hz) seeing the height.
    for (int scan = 0; scan < 100; ++scan) {
        for (int i = 0; i < 10; ++i) f.Propagate(R, R.transpose() * kRest + bias, kDt);
        f.Update(0.0);
    }
    EXPECT_TRUE(f.ready());
    EXPECT_NEAR(f.bias(), (R * bias).z(), 0.01);
    // Then 3 s of scans that do not see the height (a stairwell's walls): they hold what the
    // filter predicted, and the filter's bias keeps it still.
    for (int scan = 0; scan < 30; ++scan) {
        for (int i = 0; i < 10; ++i) f.Propagate(R, R.transpose() * kRest + bias, kDt);
        f.Hold(f.height());
    }
    EXPECT_LT(std::abs(f.height()), 0.02) << "unlearnt, the bias moves it 0.9 m in 3 s";
}

TEST(ImuHeight, AScanThatDidNotSeeTheHeightTeachesItNothing) {
    ImuHeight f;
    f.Reset(0.0, Eigen::Vector3d::UnitZ());
    for (int i = 0; i < 10; ++i) f.Propagate(Eigen::Matrix3d::Identity(), kRest, kDt);
    const Eigen::Matrix3d before = f.covariance();
    f.Hold(1.0);  // the pose, 1 m off the filter's height: taken, with no information
    EXPECT_EQ(f.height(), 1.0);
    EXPECT_EQ(f.velocity(), 0.0);
    EXPECT_EQ(f.bias(), 0.0);
    EXPECT_EQ(f.covariance(), before);
    f.Update(0.0);  // one that saw it: pulls the height back, and the velocity and bias with it
    EXPECT_LT(f.height(), 0.5);
    EXPECT_LT(f.covariance()(0, 0), before(0, 0));
}

TEST(ImuHeight, AnInvalidConfigurationIsNamed) {
    ImuHeightConfig c;
    c.position_sigma = 0;
    try {
        ImuHeight f(c);
        FAIL() << "accepted";
    } catch (const common::Error& e) {
        EXPECT_NE(std::string(e.what()).find("position_sigma"), std::string::npos) << e.what();
    }
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::odometry
