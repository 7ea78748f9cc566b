// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Scenes and scans for the odometry tests: rooms and corridors as triangle meshes, scanned by
// the project's Embree simulator with the built-in OS1-32 (1024 x 10), rolling shutter included
// (each column from the pose at its own time), turned into point clouds as the driver does.
#pragma once

#include <Eigen/Geometry>
#include <functional>
#include <vector>

#include "algorithms/common/point_cloud.hpp"
#include "algorithms/common/triangle_mesh.hpp"
#include "algorithms/simulation/lidar_simulator.hpp"
#include "algorithms/simulation/primitive_meshes.hpp"

namespace bimslam::odometry::test {

inline void Append(common::TriangleMesh* mesh, const common::TriangleMesh& part) {
    const auto base = static_cast<uint32_t>(mesh->vertices.size());
    mesh->vertices.insert(mesh->vertices.end(), part.vertices.begin(), part.vertices.end());
    for (auto t : part.triangles)
        mesh->triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
}

// A closed box seen from inside (floor, ceiling, four walls) centred at `centre`.
inline common::TriangleMesh Room(const Eigen::Vector3d& centre, const Eigen::Vector3d& size) {
    return simulation::BoxMesh(centre, size, 0.0);
}

// A room with furniture-sized boxes along its walls: well constrained in every direction.
inline common::TriangleMesh FurnishedRoom() {
    common::TriangleMesh m = Room({0, 0, 1.2}, {14, 9, 3.0});
    Append(&m, simulation::BoxMesh({3, 3.5, 0.4}, {1.6, 0.8, 0.8}, 0.0));
    Append(&m, simulation::BoxMesh({-4, -3.6, 0.5}, {1.0, 1.0, 1.0}, 0.3));
    Append(&m, simulation::BoxMesh({-6.2, 2, 0.9}, {0.6, 2.0, 1.8}, 0.0));
    Append(&m, simulation::BoxMesh({5.5, -2.5, 0.75}, {0.5, 0.5, 1.5}, 0.0));
    Append(&m, simulation::BoxMesh({0.5, -1.5, 0.37}, {1.2, 0.7, 0.74}, 0.2));
    return m;
}

// A straight corridor, 2 m wide and 2.8 m high, `length` long along x, with nothing in it.
inline common::TriangleMesh Corridor(double length) {
    return Room({0, 0, 1.1}, {length, 2.0, 2.8});
}

// One scan; pose(t) is T_world_sensor at t seconds after the scan start.
inline common::PointCloud Scan(const simulation::Scene& scene,
                               const std::function<Eigen::Isometry3d(double)>& pose,
                               int64_t stamp_ns, uint64_t seed,
                               const simulation::NoiseModel& noise = {}) {
    static const simulation::LidarModel lidar = simulation::LidarModel::DefaultOs1_32(1024, 10.0);
    simulation::ScanImage image;
    simulation::SimulateScan(
        scene, lidar, [&](int v) { return pose(double(lidar.ColumnTimeOffsetNs(v)) * 1e-9); },
        noise, seed, &image);
    common::PointCloud cloud;
    cloud.stamp = common::SensorTime{stamp_ns};
    for (int v = 0; v < image.w; ++v) {
        for (int u = 0; u < image.h; ++u) {
            const uint32_t r = image.range_mm[image.Index(u, v)];
            if (r == 0) continue;
            const Eigen::Vector3d p = lidar.Origin(u, v) + 1e-3 * r * lidar.Direction(u, v);
            cloud.PushBack(p.cast<float>(), float(image.reflectivity[image.Index(u, v)]),
                           uint16_t(u), uint32_t(lidar.ColumnTimeOffsetNs(v)));
        }
    }
    return cloud;
}

inline Eigen::Isometry3d Pose(double x, double y, double z, double yaw, double pitch = 0,
                              double roll = 0) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                  Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                  Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                     .toRotationMatrix();
    T.translation() = Eigen::Vector3d(x, y, z);
    return T;
}

}  // namespace bimslam::odometry::test
