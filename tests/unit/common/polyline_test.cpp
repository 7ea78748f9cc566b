// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Polyline resampling: spacing along the length across corners, open and closed.
#include "algorithms/common/polyline.hpp"

#include <gtest/gtest.h>

namespace bimslam::common {
namespace {
namespace BIMSLAM_UNITY_ID {

TEST(ResamplePolyline, OpenKeepsTheSpacingAcrossCornersAndEndsAtTheLastPoint) {
    // An L: 1 m along x, then 0.55 m along y.
    const std::vector<Eigen::Vector2d> l = {{0, 0}, {1, 0}, {1, 0.55}};
    const auto out = ResamplePolyline(l, 0.25, /*closed=*/false);
    ASSERT_EQ(out.size(), 8u);  // 0, .25, .5, .75, 1 (the corner), 1.25, 1.5 m, then the end
    EXPECT_TRUE(out[4].isApprox(Eigen::Vector2d(1, 0)));
    EXPECT_TRUE(out[5].isApprox(Eigen::Vector2d(1, 0.25)));
    EXPECT_TRUE(out.back().isApprox(Eigen::Vector2d(1, 0.55)));
}

TEST(ResamplePolyline, ClosedWalksBackToTheStartAndAppendsNothing) {
    const std::vector<Eigen::Vector2d> square = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    const auto out = ResamplePolyline(square, 0.3, /*closed=*/true);
    // 4 m of perimeter: points at 0, 0.3, ..., 3.9 m.
    ASSERT_EQ(out.size(), 14u);
    EXPECT_TRUE(out[4].isApprox(Eigen::Vector2d(1, 0.2)));
    EXPECT_TRUE(out.back().isApprox(Eigen::Vector2d(0, 0.1)));
}

TEST(ResamplePolyline, RepeatedPointsAreSkipped) {
    const std::vector<Eigen::Vector2d> p = {{0, 0}, {0, 0}, {0.5, 0}, {0.5, 0}};
    const auto out = ResamplePolyline(p, 0.2, /*closed=*/false);
    ASSERT_EQ(out.size(), 4u);  // 0, 0.2, 0.4, then the end at 0.5
    for (const auto& q : out) EXPECT_TRUE(q.allFinite());
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::common
