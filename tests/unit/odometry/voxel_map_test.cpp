// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/odometry/voxel_map.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "algorithms/common/status.hpp"

namespace bimslam::odometry {
namespace {
namespace BIMSLAM_UNITY_ID {

// Points along x at 0.1 m spacing on the ground (z = 0.3, mid-voxel) at y, with a millimetre's
// wobble in z: what one ring leaves in a voxel it crosses far out.
std::vector<Eigen::Vector3f> Ring(float y) {
    std::vector<Eigen::Vector3f> p;
    for (int k = 0; k < 6; ++k) p.emplace_back(0.05f + 0.1f * float(k), y, k % 2 ? 0.301f : 0.299f);
    return p;
}

// A line is no evidence of a plane: any plane through it fits it (voxel_map.hpp,
// min_judged_spread). Its plane still registers; a second ring in the voxel makes it judged.
TEST(VoxelMap, APlaneThroughOneRingIsLineLikeAndASecondRingMakesItTheGround) {
    VoxelMap map;
    const Eigen::Vector3f sensor(0.3f, -20.0f, 1.5f);  // the ground 20 m out
    const Eigen::Vector3f at(0.3f, 0.3f, 0.3f);
    map.Insert(Ring(0.30f), sensor);
    float d = 0;
    const VoxelPlane* line = map.FindPlane(at, &d);
    ASSERT_NE(line, nullptr) << "it registers";
    EXPECT_TRUE(line->line_like);

    map.Insert(Ring(0.48f), sensor);  // the next ring, 0.18 m on: a spread of 0.09 m across
    const VoxelPlane* ground = map.FindPlane(at, &d);
    ASSERT_NE(ground, nullptr);
    EXPECT_FALSE(ground->line_like);
    EXPECT_GT(std::abs(ground->normal.z()), 0.999f);
    EXPECT_NEAR(d, 0.0f, 0.005f);
}

// The version tells a copy of the map's planes whether it still holds (the registration's
// per-point neighbourhoods): new whenever planes may have changed, never shared by two maps.
TEST(VoxelMap, ItsVersionChangesWithItsPlanesAndNeverRepeats) {
    VoxelMap a, b;
    EXPECT_NE(a.version(), b.version());
    const uint64_t v0 = a.version();
    a.Insert(Ring(0.30f));
    const uint64_t v1 = a.version();
    EXPECT_NE(v1, v0);
    float d = 0;
    a.FindPlane(Eigen::Vector3f(0.3f, 0.3f, 0.3f), &d);
    a.Prune(Eigen::Vector3d(0.3, 0.3, 0.3), 10.0);  // the voxel is within 10 m: nothing dropped
    EXPECT_EQ(a.version(), v1) << "queries and a Prune that drops nothing keep it";
    a.Prune(Eigen::Vector3d(100, 0, 0), 10.0);  // drops the voxel
    EXPECT_EQ(a.voxels(), 0u);
    const uint64_t v2 = a.version();
    EXPECT_NE(v2, v1);
    a.Clear();
    EXPECT_NE(a.version(), v2);
    EXPECT_NE(a.version(), b.version());
}

TEST(VoxelMapConfig, ValidateNamesTheJudgedSpread) {
    VoxelMapConfig c;
    c.min_judged_spread = c.voxel_size;
    try {
        c.Validate();
        FAIL() << "no error";
    } catch (const common::Error& e) {
        EXPECT_NE(std::string(e.what()).find("min_judged_spread"), std::string::npos) << e.what();
    }
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::odometry
