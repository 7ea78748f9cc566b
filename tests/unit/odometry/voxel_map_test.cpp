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

// Two rings' points across the voxel at (0, 0, 0), at y0 and y0 + 0.17, on a floor at height z.
std::vector<Eigen::Vector3f> Patch(float y0, float z) {
    std::vector<Eigen::Vector3f> p = Ring(y0), second = Ring(y0 + 0.17f);
    p.insert(p.end(), second.begin(), second.end());
    for (Eigen::Vector3f& q : p) q.z() += z - 0.3f;
    return p;
}

// A point's error from the pose's rotation grows with its range, so a voxel first seen from beyond
// 10 m and seen again from under half that range starts again from the nearer view
// (voxel_map.hpp): a floor seen 3 cm too high from 40 m, then where it is from 25 m (not near
// enough: the two views mix) and from 10 m (the far view goes).
TEST(VoxelMap, AVoxelSeenFromUnderHalfItsRangeStartsAgainFromTheNearerView) {
    VoxelMap map;
    const Eigen::Vector3f at(0.3f, 0.3f, 0.3f);
    float d = 0;
    map.Insert(Patch(0.05f, 0.33f), Eigen::Vector3f(0.3f, -40.0f, 1.5f));
    ASSERT_NE(map.FindPlane(at, &d), nullptr);
    EXPECT_NEAR(d, -0.03f, 0.002f);
    map.Insert(Patch(0.38f, 0.30f), Eigen::Vector3f(0.3f, -25.0f, 1.5f));
    EXPECT_EQ(map.points(), 24u) << "both views";
    ASSERT_NE(map.FindPlane(at, &d), nullptr);
    EXPECT_GT(std::abs(d), 0.005f) << "a plane through both";
    map.Insert(Patch(0.38f, 0.30f), Eigen::Vector3f(0.3f, -10.0f, 1.5f));
    EXPECT_EQ(map.points(), 12u) << "the near view's alone";
    ASSERT_NE(map.FindPlane(at, &d), nullptr);
    EXPECT_NEAR(d, 0.0f, 0.002f);

    VoxelMap unseen;  // points without a viewpoint have no range: never started again
    unseen.Insert(Patch(0.05f, 0.33f));
    unseen.Insert(Patch(0.38f, 0.30f), Eigen::Vector3f(0.3f, -1.0f, 1.5f));
    EXPECT_EQ(unseen.points(), 24u);

    VoxelMap close;  // first seen from within 10 m: the range noise is its error, it stays
    close.Insert(Patch(0.05f, 0.33f), Eigen::Vector3f(0.3f, -8.0f, 1.5f));
    close.Insert(Patch(0.38f, 0.30f), Eigen::Vector3f(0.3f, -1.0f, 1.5f));
    EXPECT_EQ(close.points(), 24u);
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

// A pruned map answers as one built from the voxels it kept: Prune takes each voxel out of the
// hash table (linear probing's deletion: the entries probed past it moved back) and moves the
// last voxel into its place. A floor of 40 x 40 cells, each patch at its own height so that each
// cell's plane is told from its neighbours', in a table of 4096 slots, pruned round a sensor
// that walks across it; after each round every cell's centre is asked of both maps.
TEST(VoxelMap, APrunedMapAnswersAsOneBuiltFromWhatItKept) {
    VoxelMapConfig config;
    config.max_voxels = 2000;
    const float size = float(config.voxel_size), inv = float(1.0 / config.voxel_size);
    const auto patch = [&](int x, int y) {  // 3 x 3 points, 0.18 m apart
        const float z = (0.2f + 0.05f * float((7 * x + 3 * y) % 11)) * size;
        std::vector<Eigen::Vector3f> p;
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                p.emplace_back((float(x) + 0.2f + 0.3f * float(i)) * size,
                               (float(y) + 0.2f + 0.3f * float(j)) * size, z);
            }
        }
        return p;
    };
    VoxelMap pruned(config);
    std::vector<bool> alive(40 * 40, true);
    for (int x = 0; x < 40; ++x) {
        for (int y = 0; y < 40; ++y) pruned.Insert(patch(x, y));
    }
    ASSERT_EQ(pruned.voxels(), 1600u);
    for (int round = 0; round < 6; ++round) {
        const Eigen::Vector3d sensor(double(2 * round + 10) * size, 20.0 * size, 0.0);
        const double radius = 14.0 * size;
        pruned.Prune(sensor, radius);
        // Prune's own test, in its arithmetic: the voxel's centre (key + 0.5) within the radius.
        const Eigen::Vector3f c = ((sensor.cast<float>() * inv).array() - 0.5f).matrix();
        const float r2 = float(radius * radius) * inv * inv;
        VoxelMap kept(config);
        for (int x = 0; x < 40; ++x) {
            for (int y = 0; y < 40; ++y) {
                const Eigen::Vector3f key(float(x), float(y), 0.0f);
                alive[size_t(40 * x + y)] =
                    alive[size_t(40 * x + y)] && (key - c).squaredNorm() <= r2;
                if (alive[size_t(40 * x + y)]) kept.Insert(patch(x, y));
            }
        }
        ASSERT_EQ(pruned.voxels(), kept.voxels()) << "round " << round;
        ASSERT_EQ(pruned.points(), kept.points());
        ASSERT_GT(kept.voxels(), 100u);
        ASSERT_LT(kept.voxels(), 1600u);
        for (int x = 0; x < 40; ++x) {
            for (int y = 0; y < 40; ++y) {
                const Eigen::Vector3f at = patch(x, y)[4];
                float da = 0, db = 0;
                const VoxelPlane* a = pruned.FindPlane(at, &da);
                const VoxelPlane* b = kept.FindPlane(at, &db);
                ASSERT_EQ(a == nullptr, b == nullptr)
                    << "round " << round << " cell " << x << " " << y;
                if (!a) continue;
                EXPECT_EQ(a->normal, b->normal);
                EXPECT_EQ(a->offset, b->offset);
                EXPECT_EQ(da, db);
            }
        }
    }
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
