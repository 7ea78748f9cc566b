// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Loop registration: oriented normals, the normal-binned surfel map, and coarse-to-fine ICP with
// its fitness and information, on scans simulated by the project's Embree LiDAR simulator.
#include "algorithms/registration/registration.hpp"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include "algorithms/common/status.hpp"
#include "algorithms/simulation/lidar_simulator.hpp"
#include "tests/unit/odometry/odometry_scenes.hpp"

namespace bimslam::registration {
namespace {
namespace BIMSLAM_UNITY_ID {

using odometry::test::Pose;

common::PointCloud StaticScan(const simulation::Scene& scene, const Eigen::Isometry3d& T,
                              uint64_t seed, bool noisy) {
    return odometry::test::Scan(
        scene, [&](double) { return T; }, 0, seed,
        noisy ? simulation::NoiseModel{} : simulation::NoiseModel::Noiseless());
}

// A reference map of noiseless scans from `poses` (world frame).
SurfelPyramid ReferenceMap(const simulation::Scene& scene,
                           const std::vector<Eigen::Isometry3d>& poses,
                           const RegistrationConfig& config) {
    SurfelPyramid map(config);
    OrientedCloudConfig oc;
    oc.sample_voxel_size = 0.05;
    for (size_t i = 0; i < poses.size(); ++i) {
        map.Add(MakeOrientedCloud(StaticScan(scene, poses[i], 100 + i, false), oc), poses[i]);
    }
    map.Build();
    return map;
}

double TranslationError(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
    return (a.translation() - b.translation()).norm();
}
double RotationErrorDeg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
    return common::RotationAngle(a.inverse() * b) * 180 / M_PI;
}

TEST(OrientedCloud, NormalsAreTheRoomsAxesFacingTheSensor) {
    const simulation::Scene scene(odometry::test::Room({0, 0, 1.2}, {8, 6, 3.0}));
    const Eigen::Isometry3d T_world_lidar = Pose(0.5, -0.3, 0.5, 0.3);
    const OrientedCloud c = MakeOrientedCloud(StaticScan(scene, T_world_lidar, 1, true), {});
    ASSERT_GT(c.size(), 300u);
    // Every point lies on a wall, the floor or the ceiling: its normal is one of the room's six
    // half-axes (in the lidar frame, turned by the yaw), the one facing the sensor.
    const Eigen::Matrix3d R = T_world_lidar.linear();
    size_t off_axis = 0;  // more than 10 degrees from every axis
    for (size_t k = 0; k < c.size(); ++k) {
        EXPECT_LT(c.normals[k].dot(c.points[k]), 0.0f) << k;
        const Eigen::Vector3d n_world = R * c.normals[k].cast<double>();
        if (n_world.cwiseAbs().maxCoeff() < std::cos(10.0 * M_PI / 180)) ++off_axis;
    }
    // Range noise tilts a few (corners, grazing views): 2 % may be over 10 degrees.
    EXPECT_LT(off_axis, c.size() / 50);
}

TEST(SurfelMap, BothFacesOfAThinWallFitTheirOwnPlanes) {
    // A 0.15 m wall across a long room, scanned from both sides: every 0.5 m voxel along it
    // holds both faces, which a map without normal bins could not fit.
    common::TriangleMesh mesh = odometry::test::Room({0, 0, 1.2}, {12, 6, 3.0});
    odometry::test::Append(&mesh, simulation::BoxMesh({0.0, 0, 1.2}, {0.15, 4.0, 3.0}, 0.0));
    const simulation::Scene scene(mesh);
    SurfelMap map({.voxel_size = 0.5});
    for (const Eigen::Isometry3d& T : {Pose(-2.5, 0, 0.6, 0), Pose(2.5, 0, 0.6, 0)}) {
        map.Add(MakeOrientedCloud(StaticScan(scene, T, 3, false), {.sample_voxel_size = 0.05}), T);
    }
    map.Build();
    int faces = 0;
    for (const double x : {-0.075, 0.075}) {
        for (double y = -1.5; y <= 1.5; y += 0.5) {
            float d = 0;
            const Eigen::Vector3f n(x < 0 ? -1.f : 1.f, 0.f, 0.f);
            const Surfel* s = map.Find(Eigen::Vector3f(float(x), float(y), 1.0f), n, 0.9f, &d);
            if (s && std::abs(d) < 0.005f) ++faces;
        }
    }
    EXPECT_EQ(faces, 14);  // 7 places on each face
}

TEST(Registration, RecoversAKnownTransformFromAGuessAMetreAndFifteenDegreesOff) {
    const simulation::Scene scene(odometry::test::FurnishedRoom());
    const RegistrationConfig config;
    const SurfelPyramid map =
        ReferenceMap(scene, {Pose(-2, 0, 0.6, 0), Pose(2, 0.5, 0.6, 1.0)}, config);
    const Eigen::Isometry3d truth = Pose(0.7, -0.6, 0.45, 0.25, 0.02, -0.015);
    const OrientedCloud query = MakeOrientedCloud(StaticScan(scene, truth, 7, true), {});
    const Eigen::Isometry3d guess = Pose(0, 0, 0.6, 0);
    const RegistrationResult r = Register(query, map, guess, config);
    EXPECT_FALSE(r.failed);
    EXPECT_TRUE(r.converged);
    EXPECT_EQ(r.degenerate_directions, 0);
    EXPECT_LT(TranslationError(r.T_target_source, truth), 0.01);
    EXPECT_LT(RotationErrorDeg(r.T_target_source, truth), 0.1);
    // Not every surface the query sees was seen from the reference's two places (furniture
    // hides some): most, not all, points are inliers.
    EXPECT_GT(r.fitness.inlier_ratio, 0.6);
    EXPECT_LT(r.fitness.inlier_rmse, 0.02);
    // The information is symmetric positive definite and its covariance says millimetres.
    EXPECT_TRUE(r.information.isApprox(r.information.transpose()));
    const Eigen::SelfAdjointEigenSolver<common::Matrix6d> eig(r.information);
    EXPECT_GT(eig.eigenvalues().minCoeff(), 0.0);
    const common::Matrix6d cov = r.information.inverse();
    for (int i = 0; i < 3; ++i) {
        EXPECT_GT(std::sqrt(cov(i, i)), 1e-4);
        EXPECT_LT(std::sqrt(cov(i, i)), 0.02);
    }
}

TEST(Registration, ACorridorsAxisIsDegenerateWithoutInformation) {
    // 200 m: its ends lie beyond the 60 m the oriented cloud keeps.
    const simulation::Scene scene(odometry::test::Corridor(200.0));
    const RegistrationConfig config;
    const SurfelPyramid map =
        ReferenceMap(scene, {Pose(-3, 0, 0.5, 0), Pose(3, 0, 0.5, 0)}, config);
    const Eigen::Isometry3d truth = Pose(0.4, 0.1, 0.5, 0.05);
    const OrientedCloud query = MakeOrientedCloud(StaticScan(scene, truth, 9, true), {});
    const RegistrationResult r = Register(query, map, Pose(0, 0, 0.5, 0), config);
    ASSERT_FALSE(r.failed);
    EXPECT_EQ(r.degenerate_directions, 1);
    // The axis keeps the guess's x (0), the rest is recovered.
    EXPECT_NEAR(r.T_target_source.translation().x(), 0.0, 0.05);
    EXPECT_NEAR(r.T_target_source.translation().y(), 0.1, 0.01);
    EXPECT_LT(RotationErrorDeg(r.T_target_source, truth), 0.2);
    // No information along the corridor: along x in the query's frame, turned by the yaw.
    const Eigen::Vector3d axis = r.T_target_source.linear().transpose() * Eigen::Vector3d::UnitX();
    common::Vector6d v = common::Vector6d::Zero();
    v.head<3>() = axis;
    EXPECT_LT(v.dot(r.information * v), 1e-6 * r.information.trace());
}

TEST(Registration, AScanOfAnotherRoomHasALowInlierRatio) {
    const RegistrationConfig config;
    const simulation::Scene reference(odometry::test::FurnishedRoom());
    const SurfelPyramid map = ReferenceMap(reference, {Pose(0, 0, 0.6, 0)}, config);
    common::TriangleMesh other = odometry::test::Room({0, 0, 1.0}, {5, 4, 2.5});
    odometry::test::Append(&other, simulation::BoxMesh({1, 1, 0.5}, {1, 1, 1}, 0.3));
    const OrientedCloud query =
        MakeOrientedCloud(StaticScan(simulation::Scene(other), Pose(0, 0, 0.6, 0), 4, true), {});
    const RegistrationResult r = Register(query, map, Pose(0, 0, 0.6, 0), config);
    EXPECT_TRUE(r.failed || r.fitness.inlier_ratio < 0.5) << r.fitness.inlier_ratio;
}

TEST(RegistrationConfig, ValidateNamesTheField) {
    RegistrationConfig c;
    c.levels.clear();
    try {
        c.Validate();
        FAIL();
    } catch (const common::Error& e) {
        EXPECT_NE(std::string(e.what()).find("levels"), std::string::npos);
    }
    OrientedCloudConfig o;
    o.normal_voxel_size = 0.01;
    EXPECT_THROW(o.Validate(), common::Error);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::registration
