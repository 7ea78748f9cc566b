// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// An indexed triangle mesh, the shape the BIM ingest, the ray caster and the change detector
// exchange.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

namespace bimslam::common {

struct TriangleMesh {
    // Metres. float keeps meshes compact and is what Embree consumes; models far from their origin
    // must be shifted to a local origin before they are stored here.
    std::vector<Eigen::Vector3f> vertices;
    // Counter-clockwise seen from outside; indices into vertices.
    std::vector<std::array<uint32_t, 3>> triangles;

    bool empty() const { return triangles.empty(); }
    // True when every index is below vertices.size().
    bool IndicesValid() const;
};

}  // namespace bimslam::common
