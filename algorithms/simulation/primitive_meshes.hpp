// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Box and vertical cylinder meshes: the solids scenario edits add to a simulated world
// (host_tools/simulate) and the shapes the tests build their scenes from. Here rather than in
// host_tools/simulate so that the odometry's and registration's scene tests need only this
// library, which a firmware-only build (the aarch64 cross-build) can build for its tests.
#pragma once

#include <Eigen/Core>

#include "algorithms/common/triangle_mesh.hpp"

namespace bimslam::simulation {

// A box of `size` (x, y, z extents) centred at `center`, turned by `yaw_rad` about the vertical;
// 8 vertices, 12 triangles facing outwards.
common::TriangleMesh BoxMesh(const Eigen::Vector3d& center, const Eigen::Vector3d& size,
                             double yaw_rad);
// A closed vertical cylinder standing on `base`: `segments` sides, a bottom and a top cap, all
// facing outwards.
common::TriangleMesh CylinderMesh(const Eigen::Vector3d& base, double radius, double height,
                                  int segments = 24);

}  // namespace bimslam::simulation
