// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/changes/voxel_mesh.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <random>

#include "algorithms/changes/aligned_map.hpp"
#include "tests/unit/changes/change_scene.hpp"

namespace bimslam::changes {
namespace {
namespace BIMSLAM_UNITY_ID {

// Every directed edge (a, b) has its reverse (b, a) as often: a closed, consistently oriented
// surface (watertight).
void ExpectWatertight(const common::TriangleMesh& m) {
    std::map<std::pair<uint32_t, uint32_t>, int> edges;
    for (const auto& t : m.triangles) {
        for (int k = 0; k < 3; ++k) ++edges[{t[k], t[(k + 1) % 3]}];
    }
    for (const auto& [e, n] : edges) {
        const auto it = edges.find({e.second, e.first});
        ASSERT_TRUE(it != edges.end()) << e.first << " " << e.second;
        EXPECT_EQ(it->second, n);
    }
}

// Volume by the divergence theorem: positive for outward faces.
double SignedVolume(const common::TriangleMesh& m) {
    double v = 0;
    for (const auto& t : m.triangles) {
        v += m.vertices[t[0]].cast<double>().dot(
                 m.vertices[t[1]].cast<double>().cross(m.vertices[t[2]].cast<double>())) /
             6.0;
    }
    return v;
}

TEST(VoxelMesh, ExposedFacesOnlyClosedAndOutward) {
    VoxelSolid solid;
    solid.voxel_m = 0.1f;
    solid.voxels = {{0, 0, 0}, {0, 0, 1}, {1, 0, 0}, {3, 3, 3}};  // an L and a lone voxel
    const common::TriangleMesh m = VoxelSurface(solid);
    // The L: 3 cubes with 2 shared faces -> 18 - 4 = 14 faces; the lone one 6.
    EXPECT_EQ(m.triangles.size(), 2u * 20u);
    ExpectWatertight(m);
    EXPECT_NEAR(SignedVolume(m), solid.volume_m3(), 1e-9);
    EXPECT_NEAR(solid.volume_m3(), 4e-3, 1e-9);
    EXPECT_NEAR((solid.box_min() - Eigen::Vector3d(0, 0, 0)).norm(), 0, 1e-6);
    EXPECT_NEAR((solid.box_max() - Eigen::Vector3d(0.4, 0.4, 0.4)).norm(), 0, 1e-6);
}

TEST(VoxelMesh, ASolidFromPointsOnTopAndSidesOfABoxIsFilledDownToTheFloor) {
    // Points on the top (z = 0.6) and one side of a 0.8 x 0.5 x 0.6 box, none near the floor, and
    // a hole of a missing beam in the top.
    std::vector<Eigen::Vector3f> p;
    for (float x = 0.01f; x < 0.8f; x += 0.03f) {
        for (float y = 0.01f; y < 0.5f; y += 0.03f) {
            if (y < 0.2f || y > 0.25f) p.emplace_back(x, y, 0.599f);
        }
        for (float z = 0.15f; z < 0.6f; z += 0.03f) p.emplace_back(x, 0.001f, z);
    }
    const VoxelSolid solid = MakeVoxelSolid(p, 0.05f, 0.0f);
    EXPECT_NEAR(solid.volume_m3(), 0.8 * 0.5 * 0.6, 1e-6);
    const common::TriangleMesh m = VoxelSurface(solid);
    ExpectWatertight(m);
    EXPECT_NEAR(SignedVolume(m), solid.volume_m3(), 1e-6);
    EXPECT_NEAR(solid.box_min().z(), 0.0, 1e-6);
}

// A 1.2 x 0.5 m top seen at any turn keeps its sides, where its axis-aligned box grows with the
// turn; the long side's direction is the turn's.
TEST(VoxelMesh, TheSmallestPlanRectangleKeepsAnObjectsSidesWhateverItsTurn) {
    for (const double yaw_deg : {0.0, 15.0, 37.0, 90.0, 128.0}) {
        const double a = yaw_deg * M_PI / 180;
        const Eigen::Matrix2d R = Eigen::Rotation2Dd(a).toRotationMatrix();
        std::vector<Eigen::Vector3f> p;
        for (double x = -0.6; x <= 0.6 + 1e-9; x += 0.025) {
            for (double y = -0.25; y <= 0.25 + 1e-9; y += 0.025) {
                const Eigen::Vector2d q = R * Eigen::Vector2d(x, y) + Eigen::Vector2d(3, -2);
                p.emplace_back(float(q.x()), float(q.y()), 0.7f);
            }
        }
        const PlanRectangle r = SmallestPlanRectangle(p);
        EXPECT_NEAR(r.long_m, 1.2, 0.005) << yaw_deg;
        EXPECT_NEAR(r.short_m, 0.5, 0.005) << yaw_deg;
        const double turn = std::fmod(r.yaw_deg - yaw_deg + 360.0, 180.0);
        EXPECT_LE(std::min(turn, 180.0 - turn), 0.5) << yaw_deg << " measured " << r.yaw_deg;
        EXPECT_LT((r.center - Eigen::Vector2d(3, -2)).norm(), 0.005) << yaw_deg;
        Eigen::AlignedBox2d box;
        for (const auto& v : p) box.extend(v.head<2>().cast<double>());
        if (yaw_deg == 15.0) {
            EXPECT_GT(box.sizes().minCoeff(), 0.5 + 0.25) << "the box grows";
        }
    }
    EXPECT_EQ(SmallestPlanRectangle({}).long_m, 0.0);
    // A 0.6 m crate seen from a corner, turned 20 deg: two faces, an L in plan. The smallest
    // area would be the diagonal's rectangle (0.85 x 0.42 m); the perimeter's is the crate's.
    const Eigen::Matrix2d R = Eigen::Rotation2Dd(20 * M_PI / 180).toRotationMatrix();
    std::vector<Eigen::Vector3f> corner;
    for (double t = 0; t <= 0.6 + 1e-9; t += 0.025) {
        for (const Eigen::Vector2d& q : {Eigen::Vector2d(t, 0), Eigen::Vector2d(0, t)}) {
            const Eigen::Vector2d p = R * q;
            corner.emplace_back(float(p.x()), float(p.y()), 0.3f);
        }
    }
    const PlanRectangle c = SmallestPlanRectangle(corner);
    EXPECT_NEAR(c.long_m, 0.6, 0.005);
    EXPECT_NEAR(c.short_m, 0.6, 0.005);
    // Its centre is the crate's, where the L's axis-aligned box puts it 5 cm off.
    const Eigen::Vector2d crate = R * Eigen::Vector2d(0.3, 0.3);
    EXPECT_LT((c.center - crate).norm(), 0.01);
    Eigen::AlignedBox2d l;
    for (const auto& v : corner) l.extend(v.head<2>().cast<double>());
    EXPECT_GT((l.center() - crate).norm(), 0.04);
}

TEST(AlignedMap, MergesKeyframesCountingTheKeyframesThatSawEachVoxel) {
    common::PointCloud a, b;
    a.PushBack({2.0f, 0.01f, 0.01f});
    a.PushBack({2.02f, 0.02f, 0.02f});  // same voxel, same keyframe
    a.PushBack({50.0f, 0, 0});          // beyond max range
    b.PushBack({1.01f, 0.01f, 0.01f});  // at x = 2 in the world: the same voxel
    Eigen::Isometry3d Tb = Eigen::Isometry3d::Identity();
    Tb.translation().x() = 1.0;
    const std::vector<MapKeyframe> kf = {{&a, Eigen::Isometry3d::Identity()}, {&b, Tb}};
    const AlignedMap map = BuildAlignedMap(kf, AlignedMapConfig{});
    ASSERT_EQ(map.size(), 1u);
    EXPECT_EQ(map.points[0], 3u);
    EXPECT_EQ(map.keyframes[0], 2u);
    EXPECT_EQ(map.first_keyframe[0], 0u);
    EXPECT_EQ(map.cropped_points, 1u);
    EXPECT_NEAR(map.xyz[0].x(), (2.0 + 2.02 + 2.01) / 3, 1e-5);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::changes
