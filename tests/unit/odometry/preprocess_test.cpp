// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Preprocessing (crop, self-filter, deskew, voxel filters) and the bounded voxel map.
#include "algorithms/odometry/preprocess.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "algorithms/common/se3.hpp"
#include "algorithms/common/status.hpp"
#include "algorithms/odometry/voxel_map.hpp"

namespace bimslam::odometry {
namespace {
namespace BIMSLAM_UNITY_ID {

common::PointCloud Cloud(const std::vector<Eigen::Vector3f>& points, uint32_t dt_ns = 0) {
    common::PointCloud c;
    for (size_t i = 0; i < points.size(); ++i) c.PushBack(points[i], 1.f, 0, uint32_t(i) * dt_ns);
    return c;
}

TEST(Preprocessor, CropsSelfFiltersAndCountsEveryDrop) {
    PreprocessConfig config;
    config.min_range = 1.0;
    config.max_range = 20.0;
    Preprocessor pre(config);
    const auto cloud = Cloud({{0, 0, 0},          // no return
                              {0.5, 0, 0},        // too close
                              {30, 0, 0},         // too far
                              {0.1, 0.1, -0.3},   // too close as well
                              {0.3, 0.0, -0.9},   // too close (0.95 m)
                              {-0.4, 0.2, -0.2},  // too close (0.49 m)
                              {5, 1, 0},          // kept
                              {NAN, 0, 0},        // not finite
                              {2, 3, 1}});        // kept
    const PreprocessStats& s = pre.Run(cloud, ScanMotion());
    EXPECT_EQ(s.input, 9u);
    EXPECT_EQ(s.zero_range, 1u);
    EXPECT_EQ(s.non_finite, 1u);
    EXPECT_EQ(s.cropped, 5u);
    EXPECT_EQ(s.kept, 2u);
    EXPECT_EQ(pre.deskewed().size(), 2u);

    // A point 1.2 m away inside a box drawn around it is the rig itself.
    config.self_box_min = {1.0, -0.5, -0.5};
    config.self_box_max = {1.5, 0.5, 0.5};
    Preprocessor boxed(config);
    EXPECT_EQ(boxed.Run(Cloud({{1.2, 0, 0}, {5, 0, 0}}), ScanMotion()).self, 1u);
}

TEST(Preprocessor, DeskewMovesEachPointByTheMotionAtItsTime) {
    PreprocessConfig config;
    config.self_box_min = Eigen::Vector3d::Ones();  // no self box
    config.self_box_max = Eigen::Vector3d::Zero();
    Preprocessor pre(config);
    // 2 m/s forward and 1 rad/s of yaw; a point at time tau is moved by T_start_tau.
    common::Vector6d xi;
    xi << 2, 0, 0, 0, 0, 1;
    ScanMotion motion;
    motion.SetConstantVelocity(xi, 0.1);
    const auto cloud = Cloud({{5, 0, 0}, {5, 0, 0}, {5, 0, 0}}, 50'000'000);  // 0, 50, 100 ms
    pre.Run(cloud, motion);
    ASSERT_EQ(pre.deskewed().size(), 3u);
    for (int i = 0; i < 3; ++i) {
        const Eigen::Vector3d expected = common::ExpSE3(xi * (0.05 * i)) * Eigen::Vector3d(5, 0, 0);
        EXPECT_LT((pre.deskewed().xyz[size_t(i)].cast<double>() - expected).norm(), 1e-3) << i;
    }
    // Without deskew nothing moves.
    config.deskew = false;
    Preprocessor raw(config);
    raw.Run(cloud, motion);
    EXPECT_EQ(raw.deskewed().xyz[2], Eigen::Vector3f(5, 0, 0));
}

// A deskew round (lidar_odometry.cpp, DeskewAgain) moves the points the filters chose to where
// the new motion puts them: the same points as a Run with that motion when no point crosses a
// voxel's border, round after round. Points each alone in voxels of 2 and 4 m, 1 m from every
// border; the motions move them by at most 0.4 m.
TEST(Preprocessor, DeskewingAgainMovesTheChosenPointsAsARunWithTheNewMotionWould) {
    PreprocessConfig config;
    config.self_box_min = Eigen::Vector3d::Ones();  // no self box
    config.self_box_max = Eigen::Vector3d::Zero();
    config.map_voxel = config.max_map_voxel = 2.0;
    config.registration_voxel = config.max_registration_voxel = 4.0;
    config.target_map_points = config.target_registration_points = 0;
    common::PointCloud scan;  // 8 columns of 2 points, 12.5 ms apart
    for (int i = 0; i < 16; ++i) {
        const Eigen::Vector3f p(11.0f, 8.0f * float(i % 4) + 1.0f, 8.0f * float(i / 4) - 15.0f);
        scan.PushBack(p, 1.f, 0, uint32_t(i / 2) * 12'500'000u);
    }
    const auto motion = [](double vx, double vy, double wy, double wz) {
        common::Vector6d xi;
        xi << vx, vy, 0, 0, wy, wz;
        ScanMotion m;
        m.SetConstantVelocity(xi, 0.0875);
        return m;
    };
    const ScanMotion a = motion(1.0, 0, 0, 0.1), b = motion(1.1, 0.05, 0.02, 0.12),
                     c = motion(0.9, -0.1, -0.03, 0.05);
    const auto expect_same = [](std::span<const Eigen::Vector3f> got,
                                std::span<const Eigen::Vector3f> want, const char* what) {
        ASSERT_EQ(got.size(), want.size()) << what;
        for (size_t i = 0; i < got.size(); ++i)
            EXPECT_LT((got[i] - want[i]).norm(), 1e-5f) << what << " " << i;
    };
    Preprocessor pre(config);
    pre.Run(scan, a);
    ASSERT_EQ(pre.map_points().size(), 16u);
    ASSERT_EQ(pre.registration_points().size(), 16u);
    for (const ScanMotion* m : {&b, &c}) {  // two rounds
        pre.Redeskew(*m);
        Preprocessor fresh(config);
        fresh.Run(scan, *m);
        expect_same(pre.deskewed().xyz, fresh.deskewed().xyz, "kept");
        expect_same(pre.map_points(), fresh.map_points(), "map");
        expect_same(pre.registration_points(), fresh.registration_points(), "registration");
    }
    // A scan Run did not deskew stays as it is.
    config.deskew = false;
    Preprocessor raw(config);
    raw.Run(scan, a);
    raw.Redeskew(b);
    expect_same(raw.deskewed().xyz, scan.xyz, "not deskewed");
}

TEST(ScanMotion, InterpolatesBetweenKnotsAndClamps) {
    common::Vector6d xi;
    xi << 1, 0.5, 0, 0.2, 0, 0.8;
    ScanMotion m;
    m.SetConstantVelocity(xi, 0.1);
    for (double tau : {0.0, 0.013, 0.05, 0.0999}) {
        const Eigen::Isometry3d d = common::Between(common::ExpSE3(xi * tau), m.At(tau));
        EXPECT_LT(d.translation().norm(), 1e-5) << tau;
        EXPECT_LT(common::RotationAngle(d), 1e-5) << tau;
    }
    EXPECT_TRUE(m.At(0.5).isApprox(m.End()));
    EXPECT_TRUE(m.At(-1).isApprox(Eigen::Isometry3d::Identity()));
}

TEST(ScanMotion, TheTranslationAlongAnAxisIsReplacedAndTheRestKept) {
    common::Vector6d xi;
    xi << 1, 0.5, 0.2, 0, 0, 0.8;
    ScanMotion m;
    m.SetConstantVelocity(xi, 0.1);
    const ScanMotion before = m;
    const Eigen::Vector3d up = Eigen::Vector3d(0.1, 0, 1).normalized();
    std::array<double, ScanMotion::kKnots> d{};
    for (int k = 0; k < ScanMotion::kKnots; ++k) d[size_t(k)] = 0.03 * std::sin(k);
    m.SetTranslationAlong(up, d);
    for (int k = 0; k < ScanMotion::kKnots; ++k) {
        const double tau = m.KnotTime(k);
        const Eigen::Vector3d t = m.At(tau).translation(), t0 = before.At(tau).translation();
        EXPECT_NEAR(up.dot(t), d[size_t(k)], 1e-12) << k;
        EXPECT_LT(((t - up * up.dot(t)) - (t0 - up * up.dot(t0))).norm(), 1e-12) << k;
        EXPECT_TRUE(m.At(tau).linear().isApprox(before.At(tau).linear())) << "rotation kept";
    }
}

TEST(Preprocessor, VoxelFiltersKeepOnePointPerVoxelAndTheCap) {
    PreprocessConfig config;
    config.map_voxel = 0.1;
    config.registration_voxel = 0.5;
    config.max_registration_points = 100;
    config.target_map_points = 0;  // fixed sizes: the filters themselves are under test
    config.target_registration_points = 0;
    Preprocessor pre(config);
    std::vector<Eigen::Vector3f> grid;  // a 10 x 10 m wall sampled every 2 cm
    for (int i = 0; i < 500; ++i) {
        for (int j = 0; j < 500; ++j) grid.emplace_back(4.0f, -5 + 0.02f * i, -5 + 0.02f * j);
    }
    const PreprocessStats& s = pre.Run(Cloud(grid), ScanMotion());
    EXPECT_NEAR(double(s.map_points), 100.0 * 100.0, 300.0);  // one per 10 cm cell
    EXPECT_EQ(s.registration_points, 100u);                   // 400 cells, capped at 100
}

TEST(PreprocessConfig, ValidateNamesTheField) {
    PreprocessConfig c;
    c.registration_voxel = 0.05;  // finer than the map's
    try {
        c.Validate();
        FAIL();
    } catch (const common::Error& e) {
        EXPECT_NE(std::string(e.what()).find("registration_voxel"), std::string::npos);
    }
}

// A plane z = 0 sampled densely, seen from (0, 0, 1).
std::vector<Eigen::Vector3f> Floor(double half, double step, double z = 0) {
    std::vector<Eigen::Vector3f> p;
    for (double x = -half; x <= half; x += step) {
        for (double y = -half; y <= half; y += step) p.emplace_back(x, y, z);
    }
    return p;
}

TEST(VoxelMap, FitsPlanesAndFindsTheNearest) {
    VoxelMap map;
    map.Insert(Floor(3, 0.05));
    float d = 0;
    const VoxelPlane* plane = map.FindPlane({0.3f, -0.7f, 0.04f}, &d);
    ASSERT_NE(plane, nullptr);
    EXPECT_NEAR(std::abs(plane->normal.z()), 1.0, 1e-4);
    EXPECT_NEAR(std::abs(d), 0.04, 1e-4);
    // Far from anything: no plane.
    EXPECT_EQ(map.FindPlane({0, 0, 5}, &d), nullptr);
    // Each voxel keeps at most max_points_per_voxel points, spaced by min_point_spacing.
    EXPECT_LE(map.points(), map.voxels() * size_t(map.config().max_points_per_voxel));
}

TEST(VoxelMap, ACornerOffersNoPlane) {
    VoxelMapConfig config;
    config.voxel_size = 1.0;
    VoxelMap map(config);
    std::vector<Eigen::Vector3f> corner;
    for (int k = 0; k < 100; ++k) {  // the two faces' points in a scattered order
        const int i = k % 10, j = (k / 10 + 3 * k) % 10;
        corner.emplace_back(0.05f + 0.1f * i, 0.05f + 0.1f * j, 0.05f);  // floor
        corner.emplace_back(0.05f, 0.05f + 0.1f * j, 0.05f + 0.1f * i);  // wall
    }
    map.Insert(corner);
    float d = 0;
    EXPECT_EQ(map.FindPlane({0.5f, 0.5f, 0.5f}, &d), nullptr);
}

TEST(VoxelMap, StaysBoundedAndDropsWhatLiesFarBehind) {
    VoxelMapConfig config;
    config.max_voxels = 2000;
    config.max_distance = 20.0;
    VoxelMap map(config);
    // Walk 200 m along x over a floor, inserting a 10 x 10 m patch every metre.
    for (int x = 0; x < 200; ++x) {
        auto patch = Floor(5, 0.1);
        for (auto& p : patch) p.x() += float(x);
        map.Insert(patch);
        map.Prune({double(x), 0, 1});
        ASSERT_LE(map.voxels(), config.max_voxels);
    }
    float d = 0;
    EXPECT_NE(map.FindPlane({199.f, 0.f, 0.02f}, &d), nullptr);
    EXPECT_EQ(map.FindPlane({100.f, 0.f, 0.02f}, &d), nullptr) << "99 m behind: dropped";
    map.Clear();
    EXPECT_EQ(map.voxels(), 0u);
    EXPECT_EQ(map.points(), 0u);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::odometry
