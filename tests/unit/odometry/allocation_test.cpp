// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The odometry's hot path after warm-up: the motion prior, preprocessing, the maps, edge features
// and keyframes allocate nothing, and neither does LidarOdometry::Process as a whole.
#include <gtest/gtest.h>

#include "algorithms/keyframes/keyframe_selector.hpp"
#include "algorithms/odometry/lidar_odometry.hpp"
#include "algorithms/odometry/motion_prior.hpp"
#include "tests/support/allocation_counter.hpp"
#include "tests/support/synthetic_scene.hpp"

namespace bimslam::odometry {
namespace {
namespace BIMSLAM_UNITY_ID {

TEST(HotPath, MotionPriorDoesNotAllocate) {
    MotionPrior prior;
    BodyMotionSample s;
    s.attitude = Eigen::Quaterniond::Identity();
    const size_t before = test::Allocations();
    for (int k = 0; k < 10000; ++k) {  // wraps the ring buffer twice
        s.t_ns = int64_t(k) * 10'000'000;
        s.v_xy = {1.0, 0.1};
        ASSERT_TRUE(prior.Add(s).ok());
        if (k > 10) {
            ASSERT_TRUE(prior.Between(s.t_ns - 95'000'000, s.t_ns).has_value());
        }
    }
    EXPECT_EQ(test::Allocations() - before, 0u);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::odometry

namespace bimslam::odometry {
namespace {
namespace BIMSLAM_UNITY_ID {

// Scans of a furnished room along a short walk (analytic ray casting, made before counting).
std::vector<common::PointCloud> RoomScans(int n) {
    test::Scene scene;
    scene.room = test::SceneBox{{-7, -4.5, -0.3}, {7, 4.5, 2.7}};
    scene.boxes.push_back({{2, 3, -0.3}, {3.6, 3.8, 0.5}});
    scene.boxes.push_back({{-4.5, -4.1, -0.3}, {-3.5, -3.1, 0.7}});
    scene.cylinders.push_back({{1.0, -1.5}, 0.25, -0.3, 2.7});
    test::LidarModel lidar;
    lidar.range_noise_sigma = 0.01;
    std::vector<common::PointCloud> scans;
    for (int k = 0; k < n; ++k) {
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
        T.translation() = Eigen::Vector3d(0.05 * k, 0.02 * k, 0.6);
        T.linear() = Eigen::AngleAxisd(0.02 * k, Eigen::Vector3d::UnitZ()).toRotationMatrix();
        scans.push_back(test::ScanScene(scene, T, lidar, uint32_t(k) + 1));
        scans.back().stamp = common::SensorTime{1'000'000'000 + int64_t(k) * 100'000'000};
    }
    return scans;
}

TEST(HotPath, PreprocessingTheMapAndKeyframesDoNotAllocateAfterWarmUp) {
    const auto scans = RoomScans(12);
    Preprocessor pre;
    VoxelMap map;
    EdgeExtractor edges;  // LOAM edges and their line map (edge_features, off by default)
    VoxelMap edge_map(EdgeMapConfig());
    size_t edge_points = 0;
    keyframes::KeyframeConfig kc;
    kc.distance_m = 0.1;  // a keyframe every other scan
    keyframes::KeyframeSelector selector(kc);
    OdometryResult r;
    std::vector<Eigen::Vector3f> world;
    world.reserve(300000);
    ScanMotion motion;
    size_t keyframes = 0;
    const auto step = [&](size_t k) {
        pre.Run(scans[k], motion);
        world.assign(pre.map_points().begin(), pre.map_points().end());
        map.Insert(world);
        map.Prune(Eigen::Vector3d::Zero());
        const auto e = edges.Run(pre.deskewed());
        edge_points += e.size();
        edge_map.Insert(e);
        edge_map.Prune(Eigen::Vector3d::Zero());
        r.stamp_ns = scans[k].stamp.ns;
        r.T_odom_lidar.translation() = Eigen::Vector3d(0.05 * double(k), 0, 0);
        keyframes += selector.Add(r, pre.deskewed()) ? 1 : 0;
    };
    for (size_t k = 0; k < 4; ++k) step(k);  // warm-up: buffers reach their sizes
    const size_t before = test::Allocations();
    for (size_t k = 4; k < scans.size(); ++k) step(k);
    EXPECT_EQ(test::Allocations() - before, 0u);
    EXPECT_GT(keyframes, 4u);
    EXPECT_GT(edge_points, 12u * 10u);
}

// LidarOdometry::Process as a whole allocates nothing after its first scans (the registration's
// solve is its own, on fixed-size matrices; the Ceres solve it replaced built its program,
// evaluator and linear solver on every call: up to 200 allocations a solve).
TEST(HotPath, LidarOdometryDoesNotAllocateAfterWarmUp) {
    const auto scans = RoomScans(30);
    // The budget is the largest Validate accepts: with the default 50 ms a slow run (qemu-user,
    // 8x slower; a loaded machine) spends it before registration starts, and the registration's
    // allocations, if any, would not be counted. The budget's own test is in lidar_odometry_test.
    LidarOdometryConfig config;
    config.budget_ms = 10'000;
    LidarOdometry lo(config);
    for (size_t k = 0; k < 5; ++k) lo.Process(scans[k]);
    size_t iterations = 0;
    const size_t before = test::Allocations();
    for (size_t k = 5; k < scans.size(); ++k) {
        const OdometryResult& r = lo.Process(scans[k]);
        iterations += size_t(r.registration.iterations);
        EXPECT_EQ(r.flags & kRegistrationFailed, 0u);
    }
    EXPECT_EQ(test::Allocations() - before, 0u);
    EXPECT_GT(iterations, 25u);  // every scan was registered, not cut short
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::odometry
