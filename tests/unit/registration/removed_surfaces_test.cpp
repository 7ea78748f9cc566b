// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// FindRemovedSurfaces on hand-made crossings and on CheckFreeSpace over a hand-built map: a
// partition that several keyframes see through onto the walls behind it is explained; crossings
// spread over many surfaces, or rays that end where the map has nothing, are not. And porosity:
// a railing that the map's own rays pass between its bars is no surface to see through, a solid
// wall stays one.
#include "algorithms/registration/removed_surfaces.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "algorithms/common/status.hpp"
#include "algorithms/registration/free_space.hpp"
#include "algorithms/registration/surfel_map.hpp"

namespace bimslam::registration {
namespace {

// A view whose `rays` rays include one crossing per given point, on a plane of normal `normal`.
FreeSpaceResult View(size_t rays, const std::vector<Eigen::Vector3f>& at,
                     const Eigen::Vector3f& normal, bool lands_on_map = true) {
    FreeSpaceResult v;
    v.rays = rays;
    v.seen_through = at.size();
    for (const Eigen::Vector3f& p : at) v.crossings.push_back({p, normal, lands_on_map});
    return v;
}

// n crossings on the plane x = 2.5 (a partition 3.5 m long, 2.5 m high), spread along it.
std::vector<Eigen::Vector3f> OnPartition(size_t n, float shift) {
    std::vector<Eigen::Vector3f> out;
    for (size_t i = 0; i < n; ++i) {
        out.emplace_back(2.5f, -4.0f + 3.4f * float(i % 7) / 6.0f + shift,
                         0.2f + 2.2f * float(i % 5) / 4.0f);
    }
    return out;
}

std::vector<const FreeSpaceResult*> Pointers(const std::vector<FreeSpaceResult>& views) {
    std::vector<const FreeSpaceResult*> out;
    for (const auto& v : views) out.push_back(&v);
    return out;
}

TEST(RemovedSurfaces, OnePartitionSeenThroughFromSeveralKeyframesIsExplained) {
    std::vector<FreeSpaceResult> views;
    // Five keyframes each see 20 % of their rays through the partition (from either side: its
    // two faces share its cells), and 1 % through other surfaces far apart.
    for (int k = 0; k < 5; ++k) {
        FreeSpaceResult v = View(300, OnPartition(60, 0.05f * float(k)),
                                 Eigen::Vector3f(k % 2 ? 1.0f : -1.0f, 0, 0));
        for (int j = 0; j < 3; ++j) {
            v.crossings.push_back({Eigen::Vector3f(10.0f * float(k), 20.0f + 7.0f * float(j), 1),
                                   Eigen::Vector3f(0, 1, 0), true});
            ++v.seen_through;
        }
        views.push_back(v);
    }
    const RemovedSurfaceConfig config;
    const auto removed = FindRemovedSurfaces(Pointers(views), config);
    ASSERT_EQ(removed.size(), 1u);
    EXPECT_EQ(removed[0].axis, 0);
    EXPECT_EQ(removed[0].views, 5u);
    EXPECT_EQ(removed[0].crossings, 300u);
    EXPECT_NEAR(removed[0].center.x(), 2.5f, 0.01f);
    EXPECT_GT(removed[0].area_m2, 5.0);
    EXPECT_LE(removed[0].area_m2, config.max_area_m2);
    EXPECT_NEAR(MedianUnexplained(Pointers(views), {}, config), 63.0 / 300.0, 1e-9);
    EXPECT_NEAR(MedianUnexplained(Pointers(views), removed, config), 3.0 / 300.0, 1e-9);
}

TEST(RemovedSurfaces, EveryBoundMatters) {
    const RemovedSurfaceConfig config;
    const Eigen::Vector3f nx(1, 0, 0);
    // Seen from two keyframes only: no evidence that it is gone rather than misplaced.
    std::vector<FreeSpaceResult> two{View(300, OnPartition(60, 0), nx),
                                     View(300, OnPartition(60, 0.1f), nx)};
    EXPECT_TRUE(FindRemovedSurfaces(Pointers(two), config).empty());
    // The rays end where the map has nothing: the building beyond is not where the map has it.
    std::vector<FreeSpaceResult> nowhere;
    for (int k = 0; k < 4; ++k) nowhere.push_back(View(300, OnPartition(60, 0), nx, false));
    EXPECT_TRUE(FindRemovedSurfaces(Pointers(nowhere), config).empty());
    // A whole storey's facade (40 m x 3 m): no single element.
    std::vector<FreeSpaceResult> facade;
    for (int k = 0; k < 4; ++k) {
        std::vector<Eigen::Vector3f> at;
        for (int i = 0; i < 200; ++i) {
            at.emplace_back(2.5f, 0.2f * float(i), 0.3f + 2.4f * float(i % 4) / 3.0f);
        }
        facade.push_back(View(300, at, nx));
    }
    EXPECT_TRUE(FindRemovedSurfaces(Pointers(facade), config).empty());
    // Crossings spread over many small surfaces (a wrong placement): each under min_share.
    std::vector<FreeSpaceResult> spread;
    for (int k = 0; k < 4; ++k) {
        std::vector<Eigen::Vector3f> at;
        for (int i = 0; i < 40; ++i) at.emplace_back(3.0f * float(i), 1.5f * float(i % 3), 1.0f);
        spread.push_back(View(300, at, Eigen::Vector3f(0, 1, 0)));
    }
    EXPECT_TRUE(FindRemovedSurfaces(Pointers(spread), config).empty());
    EXPECT_NEAR(MedianUnexplained(Pointers(spread), {}, config), 40.0 / 300.0, 1e-9);
}

// CheckFreeSpace's crossings on a map of two parallel walls: a partition at x = 2.2 and a wall
// at x = 5.0 behind it. A query whose points lie on the far wall sees through the partition onto
// the map; one whose points lie between the two, 1 m short of the far wall, ends on nothing.
SurfelMap TwoWalls() {
    OrientedCloud walls;
    for (float x : {2.2f, 5.0f}) {
        for (float y = -3.0f; y <= 3.0f; y += 0.05f) {
            for (float z = -2.0f; z <= 2.0f; z += 0.05f) {
                walls.points.emplace_back(x, y, z);
                walls.normals.emplace_back(-1.0f, 0.0f, 0.0f);
            }
        }
    }
    SurfelMap map({.voxel_size = 0.5});
    map.Add(walls, Eigen::Isometry3d::Identity());
    map.Build();
    return map;
}

OrientedCloud PointsAt(float x) {
    OrientedCloud q;
    for (float y = -2.0f; y <= 2.0f; y += 0.1f) {
        for (float z = -1.0f; z <= 1.0f; z += 0.1f) {
            q.points.emplace_back(x, y, z);
            q.normals.emplace_back(-1.0f, 0.0f, 0.0f);
        }
    }
    return q;
}

TEST(RemovedSurfaces, CheckFreeSpaceSaysWhereTheRaysEnd) {
    const SurfelMap map = TwoWalls();
    const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
    const FreeSpaceResult beyond = CheckFreeSpace(PointsAt(5.0f), map, I, FreeSpaceConfig{});
    ASSERT_GT(beyond.seen_through, 100u);
    ASSERT_EQ(beyond.crossings.size(), beyond.seen_through);
    size_t on_map = 0;
    for (const Crossing& c : beyond.crossings) {
        EXPECT_NEAR(c.at.x(), 2.2f, 0.05f);
        EXPECT_NEAR(c.normal.x(), -1.0f, 0.05f);
        on_map += c.lands_on_map;
    }
    EXPECT_GT(double(on_map), 0.8 * double(beyond.crossings.size()));
    const FreeSpaceResult short_of = CheckFreeSpace(PointsAt(4.0f), map, I, FreeSpaceConfig{});
    ASSERT_GT(short_of.seen_through, 100u);
    for (const Crossing& c : short_of.crossings) EXPECT_FALSE(c.lands_on_map);
}

// A scan from the origin of a railing at x = 2.2 (bars 5 cm wide every 25 cm, 1 m high) in front
// of a solid wall at x = 5: each ray ends on the first of the two it meets.
OrientedCloud RailingScan() {
    OrientedCloud scan;
    for (float b = -0.6f; b <= 0.6f; b += 0.01f) {        // azimuth, rad
        for (float e = -0.3f; e <= 0.15f; e += 0.015f) {  // elevation: up to 0.66 m at the rail
            const Eigen::Vector3f dir(std::cos(e) * std::cos(b), std::cos(e) * std::sin(b),
                                      std::sin(e));
            const Eigen::Vector3f at_rail = dir * (2.2f / dir.x());
            const float phase = std::fmod(at_rail.y() + 10.0f, 0.25f);
            const bool bar = at_rail.z() > -1.0f && at_rail.z() < 1.0f && phase < 0.05f;
            scan.points.push_back(bar ? at_rail : Eigen::Vector3f(dir * (5.0f / dir.x())));
            scan.normals.emplace_back(-1.0f, 0.0f, 0.0f);
        }
    }
    return scan;
}

TEST(FreeSpace, ARailingTheMapsOwnRaysPassThroughIsPorousAndTheWallBehindItStaysSolid) {
    const OrientedCloud scan = RailingScan();
    const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
    SurfelMap map({.voxel_size = 0.5});
    map.Add(scan, I);
    map.Build();
    const FreeSpaceConfig config;
    // Before: the scan that made the map sees through its railing wherever it saw the wall.
    const FreeSpaceResult before = CheckFreeSpace(scan, map, I, config);
    ASSERT_GT(before.ratio(), 0.3) << before.seen_through << " of " << before.rays;
    for (const Crossing& c : before.crossings) EXPECT_NEAR(c.at.x(), 2.2f, 0.05f);

    const size_t marked = MarkPorous(&map, {RaysAtSurfels(scan, map, I, config)}, config);
    size_t rail = 0, porous_rail = 0, porous_wall = 0;
    for (const Surfel& s : map.surfels()) {
        const bool on_rail = std::abs(s.centroid.x() - 2.2f) < 0.1f;
        rail += on_rail;
        porous_rail += on_rail && s.porous;
        porous_wall += !on_rail && s.porous;
    }
    EXPECT_GT(rail, 3u);
    EXPECT_EQ(porous_rail, rail);
    EXPECT_EQ(porous_wall, 0u);
    EXPECT_EQ(marked, rail);
    EXPECT_EQ(CheckFreeSpace(scan, map, I, config).seen_through, 0u);
    // A query that sees 2 m beyond the wall (a wrong placement, or the wall gone) still sees
    // through the wall, and only the wall.
    OrientedCloud beyond;
    for (const Eigen::Vector3f& p : scan.points) beyond.points.push_back(p * (7.0f / p.x()));
    beyond.normals = scan.normals;
    const FreeSpaceResult through_wall = CheckFreeSpace(beyond, map, I, config);
    EXPECT_GT(through_wall.ratio(), 0.5);
    for (const Crossing& c : through_wall.crossings) EXPECT_NEAR(c.at.x(), 5.0f, 0.05f);
}

// MarkPorous's two bounds: two rays at least, and at least half of those that reach the surfel.
TEST(FreeSpace, ASurfelIsPorousWhenTwoRaysAndHalfOfThoseReachingItPassIt) {
    SurfelMap map = TwoWalls();
    ASSERT_GT(map.size(), 3u);
    const FreeSpaceConfig config;  // porous_crossings 2, porous_share 0.5
    // Surfel 0 crossed once, 1 twice by the rays of two clouds, 2 twice but stopping three.
    EXPECT_EQ(MarkPorous(&map, {{{0, 1}, {}}, {{1, 2, 2}, {2, 2, 2}}}, config), 1u);
    EXPECT_FALSE(map.surfels()[0].porous);
    EXPECT_TRUE(map.surfels()[1].porous);
    EXPECT_FALSE(map.surfels()[2].porous);
    // Surfel 0 crossed twice and stopping one: two thirds pass.
    EXPECT_EQ(MarkPorous(&map, {{{0}, {0}}, {{0}, {}}}, config), 1u);
    EXPECT_TRUE(map.surfels()[0].porous);
    EXPECT_THROW(map.MarkPorous({uint32_t(map.size())}), common::Error);
}

}  // namespace
}  // namespace bimslam::registration
