// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/common/point_cloud.hpp"

#include <gtest/gtest.h>

namespace bimslam::common {
namespace {
namespace BIMSLAM_UNITY_ID {

TEST(PointCloud, ChannelsFollowXyz) {
    PointCloud c;
    EXPECT_TRUE(c.empty());
    c.PushBack({1, 2, 3}, 0.5f, 7, 1000);
    c.PushBack({4, 5, 6}, 0.7f, 8, 2000);
    EXPECT_EQ(c.size(), 2u);
    EXPECT_TRUE(c.HasIntensity() && c.HasRing() && c.HasTime());
    EXPECT_TRUE(c.ChannelsConsistent());
    EXPECT_EQ(c.ring[1], 8);
    c.PushBack({7, 8, 9});  // xyz only: the other channels now disagree
    EXPECT_FALSE(c.ChannelsConsistent());
}

TEST(PointCloud, ResizeCreatesOnlyRequestedChannels) {
    PointCloud c;
    c.Resize(10, /*with_intensity=*/true, /*with_ring=*/false, /*with_time=*/false);
    EXPECT_EQ(c.size(), 10u);
    EXPECT_TRUE(c.HasIntensity());
    EXPECT_FALSE(c.HasRing());
    EXPECT_FALSE(c.HasTime());
    EXPECT_TRUE(c.ChannelsConsistent());
    c.Resize(4, false, false, false);  // a present channel follows the new size
    EXPECT_EQ(c.intensity.size(), 4u);
    c.Clear();
    EXPECT_TRUE(c.empty());
    EXPECT_FALSE(c.HasIntensity());
}

TEST(PointCloud, ReserveDoesNotReallocateOnPush) {
    PointCloud c;
    c.Reserve(100);
    const auto* before = c.xyz.data();
    for (int i = 0; i < 100; ++i) c.PushBack({0, 0, 0}, 0, 0, 0);
    EXPECT_EQ(before, c.xyz.data());
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::common
