// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Scenes, sensors and comparisons shared by the simulation's unit tests.
#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "algorithms/simulation/lidar_simulator.hpp"
#include "tests/unit/simulation/box_room.hpp"

namespace bimslam::simulation::fixtures {

using test::BoxRoom;

inline Eigen::Isometry3d Pose(double x, double y, double z, double yaw_deg = 0,
                              double pitch_deg = 0, double roll_deg = 0) {
    constexpr double kDeg = M_PI / 180;
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(x, y, z);
    T.linear() = (Eigen::AngleAxisd(yaw_deg * kDeg, Eigen::Vector3d::UnitZ()) *
                  Eigen::AngleAxisd(pitch_deg * kDeg, Eigen::Vector3d::UnitY()) *
                  Eigen::AngleAxisd(roll_deg * kDeg, Eigen::Vector3d::UnitX()))
                     .toRotationMatrix();
    return T;
}

// A sensor with the given beam altitudes, no azimuth offsets, no beam origin offset and an
// identity lidar_to_sensor_transform: pixel (u, v) looks from the sensor origin at azimuth
// -v 360 / W degrees and elevation altitude[u].
inline LidarModel SimpleModel(std::vector<double> altitudes_deg, int columns) {
    LidarModel m;
    m.beam_azimuth_deg.assign(altitudes_deg.size(), 0.0);
    m.beam_altitude_deg = std::move(altitudes_deg);
    m.columns = columns;
    m.beam_origin_mm = 0;
    m.Validate();
    return m;
}

inline std::vector<double> Linspace(double a, double b, int n) {
    std::vector<double> out;
    for (int i = 0; i < n; ++i) out.push_back(n == 1 ? a : a + (b - a) * i / (n - 1));
    return out;
}

// Appends the rectangle a, b, c, a + c - b (counter-clockwise as given) as two triangles.
inline void AddQuad(common::TriangleMesh* m, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                    const Eigen::Vector3d& c) {
    const auto base = static_cast<uint32_t>(m->vertices.size());
    for (const Eigen::Vector3d& p : {a, b, c, Eigen::Vector3d(a + c - b)}) {
        m->vertices.push_back(p.cast<float>());
    }
    m->triangles.push_back({base, base + 1, base + 2});
    m->triangles.push_back({base, base + 2, base + 3});
}

// A wall facing the sensor at the origin: the plane x = distance, |y|, |z| <= half.
inline common::TriangleMesh WallAt(double distance, double half) {
    common::TriangleMesh m;
    AddQuad(&m, {distance, -half, -half}, {distance, -half, half}, {distance, half, half});
    return m;
}

// A floor: the plane z = height, |x|, |y| <= half.
inline common::TriangleMesh FloorAt(double height, double half) {
    common::TriangleMesh m;
    AddQuad(&m, {-half, -half, height}, {half, -half, height}, {half, half, height});
    return m;
}

// The room with a few boxes of furniture in it, for the determinism tests.
inline common::TriangleMesh FurnishedRoom() {
    BoxRoom room({-3, -2, -1.2}, {5, 4, 1.8});
    common::TriangleMesh m = room.mesh;
    for (int i = 0; i < 6; ++i) {
        const BoxRoom box(Eigen::Vector3d(-2.5 + 1.2 * i, i % 2 ? 2.5 : -1.5, -1.2),
                          Eigen::Vector3d(-1.9 + 1.2 * i, i % 2 ? 3.4 : -0.8, -0.4 + 0.3 * i));
        const auto base = static_cast<uint32_t>(m.vertices.size());
        m.vertices.insert(m.vertices.end(), box.mesh.vertices.begin(), box.mesh.vertices.end());
        for (auto t : box.mesh.triangles)
            m.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    }
    return m;
}

inline bool SameImage(const ScanImage& a, const ScanImage& b) {
    return a.h == b.h && a.w == b.w && a.range_mm == b.range_mm && a.signal == b.signal &&
           a.reflectivity == b.reflectivity && a.element_id == b.element_id;
}

inline NoiseModel Exact() {
    NoiseModel n = NoiseModel::Noiseless();
    n.range_resolution_mm = 1;
    return n;
}

}  // namespace bimslam::simulation::fixtures
