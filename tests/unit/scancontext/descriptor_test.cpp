// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/scancontext/descriptor.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "algorithms/common/status.hpp"
#include "tests/unit/scancontext/test_clouds.hpp"

namespace bimslam::scancontext {
namespace {
namespace BIMSLAM_UNITY_ID {

using testing::Deg;

Eigen::Vector3f Polar(double range, double azimuth_deg, double z) {
    const double a = Deg(azimuth_deg);
    return Eigen::Vector3f(static_cast<float>(range * std::cos(a)),
                           static_cast<float>(range * std::sin(a)), static_cast<float>(z));
}

TEST(DescriptorTest, EmptyCloudGivesZeroDescriptorOfConfiguredShape) {
    for (const ScanContextConfig& config :
         {ScanContextConfig::Outdoor(), ScanContextConfig::Indoor()}) {
        DescriptorStats stats;
        stats.used = 99;
        const Descriptor d = MakeDescriptor(common::PointCloud{}, config, &stats);
        EXPECT_EQ(d.rows(), 20);
        EXPECT_EQ(d.cols(), 60);
        EXPECT_TRUE(d.isZero());
        EXPECT_EQ(stats.used, 0u);
        EXPECT_EQ(stats.non_finite + stats.beyond_range + stats.on_axis, 0u);
    }
}

TEST(DescriptorTest, OutdoorCellIsMaxHeightPlusOffsetCountingSectorsCounterClockwise) {
    const ScanContextConfig config = ScanContextConfig::Outdoor();  // 4 m rings, 6 deg sectors
    common::PointCloud cloud;
    cloud.PushBack(Polar(10.0, 100.0, 1.0));        // ring 2, sector 16
    cloud.PushBack(Polar(11.0, 101.0, 3.0));        // same cell, higher
    cloud.PushBack(Polar(10.5, 99.0, -1.0));        // same cell, lower
    cloud.PushBack(Polar(1.0, -10.0, 0.5));         // azimuth 350 deg: ring 0, sector 58
    cloud.PushBack(Polar(1.0, 3.0, -3.0));          // ring 0, sector 0; below -lidar_height
    cloud.PushBack(Eigen::Vector3f(80, 0, 7));      // r == max_radius: last ring, sector 0
    cloud.PushBack(Eigen::Vector3f(80.01f, 0, 7));  // beyond max_radius
    cloud.PushBack(Eigen::Vector3f(0, 0, 0));       // origin (Ouster: no return)
    cloud.PushBack(Eigen::Vector3f(0, 0, 4));       // on the axis: no azimuth
    DescriptorStats stats;
    const Descriptor d = MakeDescriptor(cloud, config, &stats);
    EXPECT_FLOAT_EQ(d(2, 16), 5.0f);
    EXPECT_FLOAT_EQ(d(0, 58), 2.5f);
    EXPECT_FLOAT_EQ(d(0, 0), -1.0f);  // kept negative, as the reference implementation does
    EXPECT_FLOAT_EQ(d(19, 0), 9.0f);
    EXPECT_EQ((d.array() != 0.0f).count(), 4);
    EXPECT_EQ(stats.used, 6u);
    EXPECT_EQ(stats.beyond_range, 1u);
    EXPECT_EQ(stats.on_axis, 2u);
    EXPECT_EQ(stats.non_finite, 0u);
}

TEST(DescriptorTest, NonFinitePointsAreSkippedAndCounted) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    common::PointCloud cloud;
    cloud.PushBack(Eigen::Vector3f(nan, 1, 1));
    cloud.PushBack(Eigen::Vector3f(1, inf, 1));
    cloud.PushBack(Eigen::Vector3f(1, 1, -inf));
    cloud.PushBack(Eigen::Vector3f(nan, nan, nan));
    cloud.PushBack(Polar(5.0, 30.0, 1.0));
    for (const ScanContextConfig& config :
         {ScanContextConfig::Outdoor(), ScanContextConfig::Indoor()}) {
        DescriptorStats stats;
        const Descriptor d = MakeDescriptor(cloud, config, &stats);
        EXPECT_TRUE(d.allFinite());
        EXPECT_EQ(stats.non_finite, 4u);
        EXPECT_EQ(stats.used, 1u);
    }
}

TEST(DescriptorTest, IndoorCellIsZSpanOfOccupiedCellsByTheZSpanRule) {
    ScanContextConfig config = ScanContextConfig::Indoor();  // 0.5 m rings, >= 3 pts, >= 0.3 m
    config.indoor_rule = IndoorCellRule::kZSpan;
    common::PointCloud cloud;
    // Cell (4, 5): two points spanning 1 m -> too few points.
    cloud.PushBack(Polar(2.2, 33.0, 0.0));
    cloud.PushBack(Polar(2.3, 34.0, 1.0));
    // Cell (6, 20): three points spanning 0.2 m (a floor or table top) -> flat, empty.
    cloud.PushBack(Polar(3.1, 121.0, 0.1));
    cloud.PushBack(Polar(3.2, 122.0, 0.2));
    cloud.PushBack(Polar(3.3, 123.0, 0.3));
    // Cell (10, 40): four points spanning 2.2 m (a wall) -> 2.2.
    cloud.PushBack(Polar(5.1, 241.0, -0.7));
    cloud.PushBack(Polar(5.2, 242.0, 0.3));
    cloud.PushBack(Polar(5.3, 243.0, 1.5));
    cloud.PushBack(Polar(5.4, 244.0, 0.9));
    // Cell (19, 59): exactly 3 points spanning 0.5 m.
    cloud.PushBack(Polar(9.7, 355.0, 2.5));
    cloud.PushBack(Polar(9.8, 356.0, 2.0));
    cloud.PushBack(Polar(9.9, 357.0, 2.2));
    cloud.PushBack(Polar(10.5, 357.0, 2.2));  // beyond 10 m
    DescriptorStats stats;
    const Descriptor d = MakeDescriptor(cloud, config, &stats);
    EXPECT_FLOAT_EQ(d(10, 40), 2.2f);
    EXPECT_FLOAT_EQ(d(19, 59), 0.5f);
    EXPECT_EQ((d.array() != 0.0f).count(), 2);
    EXPECT_EQ(stats.used, 12u);
    EXPECT_EQ(stats.beyond_range, 1u);
}

// z_stack (the default): a cell's tallest stack of points with no gap over 0.3 m. A cell that
// holds a floor and a ceiling and nothing between, as every cell of an open room does from a few
// metres out, holds 0.3 m, the mark of space seen, as a cell of floor alone does; a wall standing
// on the floor is its height either way; two returns are too few to mark a cell.
TEST(DescriptorTest, IndoorCellIsItsTallestStackSoThatFloorAndCeilingAloneOnlyMarkIt) {
    const ScanContextConfig config = ScanContextConfig::Indoor();
    EXPECT_EQ(config.indoor_rule, IndoorCellRule::kZStack);
    common::PointCloud cloud;
    // Cell (10, 40): floor (-1.4 m) and ceiling (+1.3 m), three returns each.
    for (const double z : {-1.42, -1.40, -1.38, 1.28, 1.30, 1.32}) {
        cloud.PushBack(Polar(5.2, 242.0, z));
    }
    // Cell (12, 10): a wall from the floor to the ceiling, a return every 0.2 m.
    for (double z = -1.4; z <= 1.31; z += 0.2) cloud.PushBack(Polar(6.2, 62.0, z));
    // Cell (14, 30): a desk (floor to 0.75 m above it) under the ceiling.
    for (const double z : {-1.4, -1.2, -1.0, -0.8, -0.65, 1.3, 1.31}) {
        cloud.PushBack(Polar(7.2, 182.0, z));
    }
    // Cell (4, 5): floor alone, three returns; cell (6, 20): two returns, a metre apart.
    for (const double z : {-1.41, -1.40, -1.39}) cloud.PushBack(Polar(2.2, 33.0, z));
    cloud.PushBack(Polar(3.1, 121.0, -1.4));
    cloud.PushBack(Polar(3.2, 122.0, -0.4));
    const Descriptor stacked = MakeDescriptor(cloud, config);
    EXPECT_FLOAT_EQ(stacked(10, 40), 0.3f);
    EXPECT_NEAR(stacked(12, 10), 2.6f, 1e-5);
    EXPECT_NEAR(stacked(14, 30), 0.75f, 1e-5);
    EXPECT_FLOAT_EQ(stacked(4, 5), 0.3f);
    EXPECT_EQ(stacked(6, 20), 0.0f);
    EXPECT_EQ((stacked.array() != 0.0f).count(), 4);

    // The older rule gives all three the room's height, or nearly.
    ScanContextConfig span = config;
    span.indoor_rule = IndoorCellRule::kZSpan;
    const Descriptor spanned = MakeDescriptor(cloud, span);
    EXPECT_NEAR(spanned(10, 40), 2.74f, 1e-5);
    EXPECT_NEAR(spanned(14, 30), 2.71f, 1e-5);
    EXPECT_EQ(ToString(IndoorCellRule::kZStack), "z_stack");
    EXPECT_EQ(ParseIndoorCellRule("z_span"), IndoorCellRule::kZSpan);
    EXPECT_FALSE(ParseIndoorCellRule("span"));
}

TEST(DescriptorTest, BuilderReusesItsOutputWithoutReallocating) {
    DescriptorBuilder builder(ScanContextConfig::Indoor());
    const common::PointCloud a = testing::MakeCellCentredCloud(builder.config(), 1);
    const common::PointCloud b = testing::MakeCellCentredCloud(builder.config(), 2);
    Descriptor out;
    builder.Build(a, &out);
    const Descriptor first = out;
    const float* storage = out.data();
    builder.Build(b, &out);
    EXPECT_EQ(out.data(), storage);
    EXPECT_FALSE(out.isApprox(first));
    builder.Build(a, &out);
    EXPECT_EQ(out, first);
    // The span overload sees the same points.
    Descriptor from_span;
    builder.Build(std::span<const Eigen::Vector3f>(a.xyz), &from_span);
    EXPECT_EQ(from_span, first);
}

TEST(DescriptorTest, InvalidConfigThrows) {
    ScanContextConfig config;
    config.num_rings = 0;
    EXPECT_THROW(DescriptorBuilder{config}, common::Error);
    EXPECT_THROW(MakeDescriptor(common::PointCloud{}, config), common::Error);
}

TEST(DescriptorTest, RingKeyIsRowMeansAndSectorKeyIsColumnMeans) {
    Descriptor d(2, 3);
    d << 1, 2, 3,  //
        4, 0, 8;
    const Eigen::VectorXf ring = RingKey(d);
    const Eigen::VectorXf sector = SectorKey(d);
    ASSERT_EQ(ring.size(), 2);
    ASSERT_EQ(sector.size(), 3);
    EXPECT_FLOAT_EQ(ring[0], 2.0f);
    EXPECT_FLOAT_EQ(ring[1], 4.0f);
    EXPECT_FLOAT_EQ(sector[0], 2.5f);
    EXPECT_FLOAT_EQ(sector[1], 1.0f);
    EXPECT_FLOAT_EQ(sector[2], 5.5f);
}

TEST(DescriptorTest, RingKeyIsRotationInvariantAndSectorKeyShifts) {
    const Descriptor a = testing::RandomDescriptor(20, 60, 3);
    const Descriptor b = testing::ShiftColumns(a, 13);
    EXPECT_TRUE(RingKey(a).isApprox(RingKey(b), 1e-6f));
    const Eigen::VectorXf ka = SectorKey(a), kb = SectorKey(b);
    for (int j = 0; j < 60; ++j) EXPECT_FLOAT_EQ(kb[(j + 13) % 60], ka[j]);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::scancontext
