// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// LOAM edge features: found on the edges of a room and its furniture, per ring by the driver's
// ring index, never by elevation; and the edge map's lines.
#include "algorithms/odometry/edge_features.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "algorithms/common/status.hpp"
#include "algorithms/odometry/voxel_map.hpp"
#include "tests/unit/odometry/odometry_scenes.hpp"

namespace bimslam::odometry {
namespace {
namespace BIMSLAM_UNITY_ID {

using test::Pose;

// Distance from p to the nearest of the 12 edges of the axis-aligned box [lo, hi].
double DistanceToBoxEdges(const Eigen::Vector3d& p, const Eigen::Vector3d& lo,
                          const Eigen::Vector3d& hi) {
    double best = 1e9;
    for (int axis = 0; axis < 3; ++axis) {  // edges parallel to `axis`
        const int a = (axis + 1) % 3, b = (axis + 2) % 3;
        for (const double ca : {lo(a), hi(a)}) {
            for (const double cb : {lo(b), hi(b)}) {
                best = std::min(best, std::hypot(p(a) - ca, p(b) - cb));
            }
        }
    }
    return best;
}

const Eigen::Vector3d kCentre(0, 0, 1.2), kSize(14, 9, 3.0);

TEST(EdgeExtractor, FindsTheEdgesOfARoom) {
    const simulation::Scene scene(test::Room(kCentre, kSize));
    const Eigen::Isometry3d pose = Pose(1.0, -0.5, 0.6, 0.3);
    const common::PointCloud scan = test::Scan(
        scene, [&](double) { return pose; }, 0, 3);
    EdgeExtractor extractor;
    const auto edges = extractor.Run(scan);
    ASSERT_GT(edges.size(), 20u);
    const Eigen::Vector3d lo = kCentre - kSize / 2, hi = kCentre + kSize / 2;
    size_t near = 0;
    for (const Eigen::Vector3f& e : edges) {
        near += DistanceToBoxEdges(pose * e.cast<double>(), lo, hi) < 0.25 ? 1 : 0;
    }
    EXPECT_GT(double(near), 0.9 * double(edges.size())) << near << " of " << edges.size();
    EXPECT_LE(edges.size(), extractor.config().max_edges);
}

// The rings of an OS1 are offset in azimuth and unevenly spaced: two beams may look alike in
// elevation. Here the scan's points are relabelled so that two pairs of rings swap labels; the
// features are found per label, so the same points come out (as a set).
TEST(EdgeExtractor, UsesTheRingIndexNotTheElevation) {
    const simulation::Scene scene(test::Room(kCentre, kSize));
    common::PointCloud scan = test::Scan(
        scene, [](double) { return Pose(0.5, 0.5, 0.6, 0.1); }, 0, 4);
    EdgeExtractor extractor;
    auto sorted = [](std::span<const Eigen::Vector3f> s) {
        std::vector<std::array<float, 3>> v;
        for (const auto& p : s) v.push_back({p.x(), p.y(), p.z()});
        std::sort(v.begin(), v.end());
        return v;
    };
    const auto before = sorted(extractor.Run(scan));
    for (uint16_t& r : scan.ring) r = uint16_t(r == 3 ? 20 : r == 20 ? 3 : r);
    EXPECT_EQ(sorted(extractor.Run(scan)), before);
    // Every ring labelled alike (what a guess from a coarse elevation bin could do): the ring
    // walks zig-zag between beams, and the features are not the room's edges any more.
    for (uint16_t& r : scan.ring) r = 0;
    const auto merged = extractor.Run(scan);
    const Eigen::Vector3d lo = kCentre - kSize / 2, hi = kCentre + kSize / 2;
    size_t near = 0;
    for (const Eigen::Vector3f& e : merged) {
        near += DistanceToBoxEdges(Pose(0.5, 0.5, 0.6, 0.1) * e.cast<double>(), lo, hi) < 0.25;
    }
    EXPECT_LT(double(near), 0.5 * double(merged.size()));
}

TEST(EdgeExtractor, NoRingsNoEdgesAndAGapIsNoEdge) {
    EdgeExtractor extractor;
    common::PointCloud cloud;
    // A straight wall along one ring with a gap of 10 columns: the gap's ends are not edges.
    for (int v = 0; v < 200; ++v) {
        if (v >= 100 && v < 110) continue;
        cloud.PushBack(Eigen::Vector3f(5.f, -2.f + 0.02f * float(v), 0.f), 1.f, 0,
                       uint32_t(v) * 97656u);
    }
    EXPECT_TRUE(extractor.Run(cloud).empty());
    common::PointCloud no_rings;
    no_rings.xyz = cloud.xyz;
    EXPECT_TRUE(extractor.Run(no_rings).empty());
}

TEST(EdgeFeatureConfig, ValidateNamesTheField) {
    EdgeFeatureConfig c;
    c.sectors = 0;
    try {
        c.Validate();
        FAIL();
    } catch (const common::Error& e) {
        EXPECT_NE(std::string(e.what()).find("sectors"), std::string::npos);
    }
}

TEST(VoxelMap, FitsLinesWhenAskedAndFindsTheNearest) {
    VoxelMapConfig config;
    config.fit_lines = true;
    config.min_plane_points = 4;
    config.min_point_spacing = 0.02;
    VoxelMap map(config);
    std::vector<Eigen::Vector3f> line;
    for (int k = 0; k < 30; ++k) line.emplace_back(1.1f, 2.1f, 0.02f * float(k));
    map.Insert(line);
    float d = 0;
    const VoxelLine* found = map.FindLine(Eigen::Vector3f(1.2f, 2.1f, 0.3f), &d);
    ASSERT_NE(found, nullptr);
    EXPECT_NEAR(d, 0.1f, 1e-4);
    EXPECT_NEAR(std::abs(found->direction.z()), 1.f, 1e-4);
    // A plane's points are no line.
    VoxelMap planes(config);
    std::vector<Eigen::Vector3f> wall;
    for (int i = 0; i < 6; ++i) {
        for (int k = 0; k < 6; ++k) wall.emplace_back(3.1f, 0.1f * float(i), 0.1f * float(k));
    }
    planes.Insert(wall);
    EXPECT_EQ(planes.FindLine(Eigen::Vector3f(3.1f, 0.25f, 0.25f), &d), nullptr);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::odometry
