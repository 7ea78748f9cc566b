// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/simulation/primitive_meshes.hpp"

#include <Eigen/Geometry>
#include <cmath>

namespace bimslam::simulation {

common::TriangleMesh BoxMesh(const Eigen::Vector3d& center, const Eigen::Vector3d& size,
                             double yaw_rad) {
    common::TriangleMesh m;
    const Eigen::Matrix3d R =
        Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    for (int i = 0; i < 8; ++i) {
        const Eigen::Vector3d s((i & 1) ? 0.5 : -0.5, (i & 2) ? 0.5 : -0.5, (i & 4) ? 0.5 : -0.5);
        m.vertices.push_back((center + R * s.cwiseProduct(size)).cast<float>());
    }
    // Corner i has bits x=1, y=2, z=4; faces counter-clockwise seen from outside.
    m.triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                   {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
    return m;
}

common::TriangleMesh CylinderMesh(const Eigen::Vector3d& base, double radius, double height,
                                  int segments) {
    common::TriangleMesh m;
    for (int k = 0; k < segments; ++k) {
        const double a = 2 * M_PI * k / segments;
        const Eigen::Vector3d d(radius * std::cos(a), radius * std::sin(a), 0);
        m.vertices.push_back((base + d).cast<float>());
        m.vertices.push_back((base + d + Eigen::Vector3d(0, 0, height)).cast<float>());
    }
    const uint32_t bottom = uint32_t(m.vertices.size()), top = bottom + 1;
    m.vertices.push_back(base.cast<float>());
    m.vertices.push_back((base + Eigen::Vector3d(0, 0, height)).cast<float>());
    for (int k = 0; k < segments; ++k) {
        const uint32_t a = uint32_t(2 * k), b = uint32_t(2 * ((k + 1) % segments));
        m.triangles.push_back({a, b, b + 1});
        m.triangles.push_back({a, b + 1, a + 1});
        m.triangles.push_back({bottom, b, a});
        m.triangles.push_back({top, a + 1, b + 1});
    }
    return m;
}

}  // namespace bimslam::simulation
