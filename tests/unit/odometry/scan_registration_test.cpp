// Point-to-plane registration with Ceres against the voxel map: exact poses recovered in a
// furnished room; a corridor's axis detected as degenerate and kept at the initial guess.
#include <gtest/gtest.h>

#include "algorithms/odometry/preprocess.hpp"
#include "algorithms/odometry/scan_registration.hpp"
#include "algorithms/odometry/voxel_map.hpp"
#include "tests/unit/odometry/odometry_scenes.hpp"

namespace bimslam::odometry {
namespace {

using test::Pose;

struct Registered {
    RegistrationResult result;
    double translation_error = 0, rotation_error_deg = 0;
};

// The map from a static scan at `map_pose`; a static scan at `truth` registered from `guess`
// (both in the map frame = the world).
Registered Register(const simulation::Scene& scene, const Eigen::Isometry3d& map_pose,
                    const Eigen::Isometry3d& truth, const Eigen::Isometry3d& guess) {
    Preprocessor pre;
    VoxelMap map;
    const ScanMotion still;
    const auto first = test::Scan(scene, [&](double) { return map_pose; }, 0, 1);
    pre.Run(first, still);
    std::vector<Eigen::Vector3f> world;
    for (const auto& p : pre.map_points()) world.push_back((map_pose * p.cast<double>()).cast<float>());
    map.Insert(world);
    const auto second = test::Scan(scene, [&](double) { return truth; }, 100'000'000, 2);
    pre.Run(second, still);
    ScanRegistration reg;
    Registered out;
    out.result = reg.Align(pre.registration_points(), map, guess,
                           common::Vector6d::Constant(0.05),
                           ScanRegistration::Clock::now() + std::chrono::seconds(10));
    const Eigen::Isometry3d err = truth.inverse() * out.result.T_map_lidar;
    out.translation_error = err.translation().norm();
    out.rotation_error_deg = common::RotationAngle(err) * 180 / M_PI;
    return out;
}

TEST(ScanRegistration, RecoversAKnownMotionInAFurnishedRoom) {
    const simulation::Scene scene(test::FurnishedRoom());
    const Eigen::Isometry3d map_pose = Pose(0, 0, 0.5, 0);
    const Eigen::Isometry3d truth = Pose(0.25, -0.12, 0.52, 0.08, 0.01, -0.015);
    const Registered r = Register(scene, map_pose, truth, map_pose);
    EXPECT_FALSE(r.result.failed);
    EXPECT_TRUE(r.result.converged);
    EXPECT_EQ(r.result.degenerate_directions, 0);
    EXPECT_GT(r.result.correspondences, 500);
    EXPECT_LT(r.translation_error, 0.01);
    EXPECT_LT(r.rotation_error_deg, 0.1);
}

}  // namespace
}  // namespace bimslam::odometry
