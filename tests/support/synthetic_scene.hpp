// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Synthetic scenes and LiDAR scans for tests and benchmarks: ray casting against axis-aligned
// boxes, vertical cylinders, a room seen from inside and a ground plane. Everything is
// deterministic in the seed. Meant to be simple and obviously right, not fast (no acceleration
// structure).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <vector>

#include "algorithms/common/point_cloud.hpp"

namespace bimslam::test {

// A solid axis-aligned box, hit from outside.
struct SceneBox {
    Eigen::Vector3d lo = Eigen::Vector3d::Zero();
    Eigen::Vector3d hi = Eigen::Vector3d::Ones();
};

// A solid vertical cylinder (pillar, tree trunk) with flat caps.
struct SceneCylinder {
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    double radius = 0.2;
    double z_lo = 0.0;
    double z_hi = 3.0;
};

struct Scene {
    std::optional<SceneBox> room;    // walls, floor and ceiling seen from inside
    std::optional<double> ground_z;  // an infinite horizontal ground plane at this height
    std::vector<SceneBox> boxes;
    std::vector<SceneCylinder> cylinders;

    // Distance along the unit direction `dir` from `origin` to the first surface, or nullopt when
    // nothing is hit closer than max_range.
    std::optional<double> Cast(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
                               double max_range) const;
};

// A spinning multi-beam LiDAR: `beams` elevations evenly spaced between the lowest and highest,
// `columns` azimuths evenly spaced from azimuth_offset_rad, counter-clockwise, in the lidar frame.
struct LidarModel {
    int beams = 32;
    int columns = 1024;
    double lowest_elevation_deg = -22.5;
    double highest_elevation_deg = 22.5;
    double azimuth_offset_rad = 0.0;
    double max_range = 120.0;
    double range_noise_sigma = 0.0;  // metres, Gaussian along the ray
    bool misses_as_origin = false;   // emit (0, 0, 0) for rays without a return, as Ouster does
};

// The points the LiDAR at T_world_lidar sees, in the lidar frame, with ring (beam index, 0 = top
// beam) and per-column time offsets over a 100 ms sweep.
common::PointCloud ScanScene(const Scene& scene, const Eigen::Isometry3d& T_world_lidar,
                             const LidarModel& lidar, uint32_t seed);

// A scene with a sensor position in it that keeps at least `clearance` metres (horizontally) from
// every object, so the sensor may be displaced by less than that and stay in free space.
struct Place {
    Scene scene;
    Eigen::Vector3d sensor = Eigen::Vector3d::Zero();
    double clearance = 0.0;
};

// A furnished box room (4-14 m x 3-10 m, 2.4-4 m high) with boxes (furniture), pillars and
// sometimes a partition wall; the sensor 0.4-1.2 m above the floor, clearance 0.6 m.
Place MakeRandomRoom(uint32_t seed);

// Buildings (boxes up to 25 m high) and trees (cylinders) on a ground plane at z = 0 within
// +/-70 m; the sensor 1.8 m above the ground, clearance 2 m.
Place MakeRandomTown(uint32_t seed);

}  // namespace bimslam::test
