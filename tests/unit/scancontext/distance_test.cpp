// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/scancontext/distance.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "tests/support/synthetic_scene.hpp"
#include "tests/unit/scancontext/test_clouds.hpp"

namespace bimslam::scancontext {
namespace {
namespace BIMSLAM_UNITY_ID {

using testing::AngleDiff;
using testing::Deg;

constexpr double kPi = std::numbers::pi;

TEST(DistanceTest, WrapShiftAndYawLieInTheHalfOpenInterval) {
    EXPECT_EQ(WrapShift(0, 60), 0);
    EXPECT_EQ(WrapShift(29, 60), 29);
    EXPECT_EQ(WrapShift(30, 60), 30);
    EXPECT_EQ(WrapShift(-30, 60), 30);
    EXPECT_EQ(WrapShift(31, 60), -29);
    EXPECT_EQ(WrapShift(-61, 60), -1);
    EXPECT_EQ(WrapShift(3, 7), 3);
    EXPECT_EQ(WrapShift(4, 7), -3);
    EXPECT_DOUBLE_EQ(ShiftToYaw(30, 60), kPi);
    EXPECT_DOUBLE_EQ(ShiftToYaw(-30, 60), kPi);
    EXPECT_DOUBLE_EQ(ShiftToYaw(-1, 60), -Deg(6.0));
}

TEST(DistanceTest, IdenticalDescriptorsAreAtZero) {
    const Descriptor a = testing::RandomDescriptor(20, 60, 1);
    const DistanceResult r = Distance(a, a);
    EXPECT_NEAR(r.distance, 0.0, 1e-6);
    EXPECT_EQ(r.shift, 0);
    EXPECT_EQ(r.yaw, 0.0);
}

TEST(DistanceTest, EmptyAndIncomparableDescriptorsNeverGiveNaN) {
    const Descriptor zero = Descriptor::Zero(20, 60);
    const Descriptor a = testing::RandomDescriptor(20, 60, 2);
    EXPECT_EQ(Distance(zero, zero).distance, kNoOverlapDistance);
    EXPECT_EQ(Distance(zero, a).distance, kNoOverlapDistance);
    EXPECT_EQ(Distance(a, zero, 1.0).distance, kNoOverlapDistance);
    EXPECT_EQ(ColumnShiftDistance(zero, zero, 5), kNoOverlapDistance);

    EXPECT_EQ(Distance(a, testing::RandomDescriptor(20, 61, 2)).distance, kIncomparableDistance);
    EXPECT_EQ(Distance(Descriptor(0, 0), Descriptor(0, 0)).distance, kIncomparableDistance);
    Descriptor bad = a;
    bad(3, 4) = std::numeric_limits<float>::quiet_NaN();
    EXPECT_EQ(Distance(a, bad).distance, kIncomparableDistance);
    EXPECT_EQ(ColumnShiftDistance(bad, a, 0), kIncomparableDistance);
    // A NaN search ratio is treated as 0, not propagated.
    EXPECT_NEAR(Distance(a, a, std::numeric_limits<double>::quiet_NaN()).distance, 0.0, 1e-6);
}

TEST(DistanceTest, ColumnShiftDistanceFollowsEquationFive) {
    // Two columns: (1, 0) vs (1, 1) -> cos 1/sqrt(2); (0, 2) vs (0, 3) -> cos 1.
    Descriptor a(2, 2), b(2, 2);
    a << 1, 0, 0, 2;
    b << 1, 0, 1, 3;
    EXPECT_NEAR(ColumnShiftDistance(a, b, 0), (1.0 - 1.0 / std::sqrt(2.0) + 0.0) / 2.0, 1e-7);
    // An empty column on one side leaves that pair out of the mean.
    Descriptor c(2, 2);
    c << 1, 0, 1, 0;
    EXPECT_NEAR(ColumnShiftDistance(a, c, 0), 1.0 - 1.0 / std::sqrt(2.0), 1e-7);
}

TEST(DistanceTest, ShiftedColumnsGiveSignedYaw) {
    const Descriptor a = testing::RandomDescriptor(20, 60, 4);
    for (int k : {-29, -7, -1, 1, 7, 29, 30}) {
        const DistanceResult r = Distance(a, testing::ShiftColumns(a, k));
        EXPECT_NEAR(r.distance, 0.0, 1e-6) << k;
        EXPECT_EQ(r.shift, WrapShift(k, 60)) << k;
        EXPECT_NEAR(r.yaw, ShiftToYaw(k, 60), 1e-12) << k;
        // Swapping the arguments negates the yaw (except at the half turn, which is +pi).
        const DistanceResult back = Distance(testing::ShiftColumns(a, k), a);
        EXPECT_NEAR(AngleDiff(back.yaw, -r.yaw), 0.0, 1e-12) << k;
    }
}

TEST(DistanceTest, WindowedSearchMatchesExhaustiveMinimumWhenRatioIsOne) {
    for (uint32_t seed = 0; seed < 5; ++seed) {
        const Descriptor a = testing::RandomDescriptor(20, 60, 10 + seed);
        const Descriptor b = testing::RandomDescriptor(20, 60, 20 + seed);
        double best = 10.0;
        for (int s = 0; s < 60; ++s) best = std::min(best, ColumnShiftDistance(a, b, s));
        const DistanceResult r = Distance(a, b, 1.0);
        EXPECT_DOUBLE_EQ(r.distance, best);
        EXPECT_DOUBLE_EQ(ColumnShiftDistance(a, b, r.shift), best);
        // The default window only looks at 7 shifts, so it can only be worse or equal.
        EXPECT_GE(Distance(a, b).distance, best);
        EXPECT_GE(r.distance, 0.0);
        EXPECT_LE(r.distance, 2.0);
    }
}

// Rotating a cloud by whole sectors: the descriptor's columns move exactly, distance ~ 0 and the
// yaw is the rotation. The points sit well inside their cells (test_clouds.hpp), so no point can
// change cell through rounding and the bound can be tight.
void ExpectRotationRecovered(const ScanContextConfig& config, const common::PointCloud& cloud,
                             double bound) {
    const Descriptor a = MakeDescriptor(cloud, config);
    ASSERT_GT((a.array() != 0.0f).count(), 50);
    for (int k : {-30, -29, -17, -5, -1, 1, 2, 7, 15, 23, 29, 30}) {
        const double theta = k * config.SectorAngle();
        const Descriptor b = MakeDescriptor(testing::RotateZ(cloud, theta), config);
        const DistanceResult r = Distance(a, b, config.search_ratio);
        EXPECT_LT(r.distance, bound) << "k = " << k;
        EXPECT_NEAR(AngleDiff(r.yaw, theta), 0.0, 1e-9) << "k = " << k;
        EXPECT_GT(r.yaw, -kPi);
        EXPECT_LE(r.yaw, kPi);
    }
}

TEST(DistanceTest, RotatedCellCentredCloudOutdoor) {
    const ScanContextConfig config = ScanContextConfig::Outdoor();
    for (uint32_t seed : {1u, 2u, 3u}) {
        ExpectRotationRecovered(config, testing::MakeCellCentredCloud(config, seed), 1e-5);
    }
}

TEST(DistanceTest, RotatedCellCentredCloudIndoor) {
    const ScanContextConfig config = ScanContextConfig::Indoor();
    for (uint32_t seed : {1u, 2u, 3u}) {
        ExpectRotationRecovered(config, testing::MakeCellCentredCloud(config, seed), 1e-5);
    }
}

// The same with ray-cast scenes. Columns at the centres of 0.6 degree steps keep every azimuth
// 0.3 degree from a sector edge, and range noise moves points along their rays only; a range can
// still land within float rounding (~1e-6 m) of a ring edge, which could move one point into the
// next ring and perturb one cell, hence the looser bound (measured: below 2e-8 for every k).
test::LidarModel CentredLidar() {
    test::LidarModel lidar;
    lidar.columns = 600;
    lidar.azimuth_offset_rad = Deg(0.3);
    lidar.range_noise_sigma = 0.01;
    return lidar;
}

TEST(DistanceTest, RotatedRoomScanIndoor) {
    for (uint32_t seed : {11u, 12u}) {
        const test::Place place = test::MakeRandomRoom(seed);
        const Eigen::Isometry3d T(Eigen::Translation3d(place.sensor));
        const common::PointCloud cloud = test::ScanScene(place.scene, T, CentredLidar(), seed);
        ExpectRotationRecovered(ScanContextConfig::Indoor(), cloud, 1e-3);
    }
}

TEST(DistanceTest, RotatedTownScanOutdoor) {
    for (uint32_t seed : {21u, 22u}) {
        const test::Place place = test::MakeRandomTown(seed);
        const Eigen::Isometry3d T(Eigen::Translation3d(place.sensor));
        const common::PointCloud cloud = test::ScanScene(place.scene, T, CentredLidar(), seed);
        ExpectRotationRecovered(ScanContextConfig::Outdoor(), cloud, 1e-3);
    }
}

// The convention in terms of poses: scanning the same spot with the sensor turned by psi
// (T_world_b = T_world_a * Rz(psi)) gives cloud_b = Rz(-psi) * cloud_a, so the yaw of
// Distance(a, b) is -psi, the yaw of T_b_a.
TEST(DistanceTest, YawIsThatOfTheRelativePoseBA) {
    const test::Place place = test::MakeRandomRoom(31);
    const test::LidarModel lidar = CentredLidar();
    const Eigen::Isometry3d T_world_a(Eigen::Translation3d(place.sensor));
    const ScanContextConfig config = ScanContextConfig::Indoor();
    const Descriptor a = MakeDescriptor(test::ScanScene(place.scene, T_world_a, lidar, 1), config);
    for (int k : {-12, 5, 20}) {
        const double psi = k * config.SectorAngle();
        const Eigen::Isometry3d T_world_b =
            T_world_a * Eigen::AngleAxisd(psi, Eigen::Vector3d::UnitZ());
        const Descriptor b =
            MakeDescriptor(test::ScanScene(place.scene, T_world_b, lidar, 2), config);
        const DistanceResult r = Distance(a, b);
        EXPECT_LT(r.distance, 0.02) << k;  // re-scanned with fresh noise
        EXPECT_NEAR(AngleDiff(r.yaw, -psi), 0.0, 1e-9) << k;
        const Eigen::Isometry3d T_b_a = T_world_b.inverse() * T_world_a;
        const double yaw_b_a = std::atan2(T_b_a.linear()(1, 0), T_b_a.linear()(0, 0));
        EXPECT_NEAR(AngleDiff(r.yaw, yaw_b_a), 0.0, 1e-9) << k;
    }
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::scancontext
