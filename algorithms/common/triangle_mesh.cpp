// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/common/triangle_mesh.hpp"

namespace bimslam::common {

bool TriangleMesh::IndicesValid() const {
    const size_t n = vertices.size();
    for (const auto& t : triangles) {
        if (t[0] >= n || t[1] >= n || t[2] >= n) return false;
    }
    return true;
}

}  // namespace bimslam::common
