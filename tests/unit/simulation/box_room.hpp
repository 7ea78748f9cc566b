// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// A closed axis-aligned box room as a triangle mesh (each wall its own element id) and the exact
// analytic cast of a ray from inside it, for the simulation's tests and the LiDAR adapter's
// round trip (tests/unit/bim/lidar_from_metadata_test.cpp).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "algorithms/common/triangle_mesh.hpp"

namespace bimslam::test {

struct BoxRoom {
    // Wall w = 2 * axis + side (side 0: the lo plane, 1: the hi plane) has element id kIdBase + w.
    static constexpr uint32_t kIdBase = 100;

    Eigen::Vector3d lo, hi;
    common::TriangleMesh mesh;
    std::vector<uint32_t> ids;  // per triangle

    BoxRoom(const Eigen::Vector3d& lo_, const Eigen::Vector3d& hi_) : lo(lo_), hi(hi_) {
        for (int k = 0; k < 3; ++k) {
            const int a = (k + 1) % 3, b = (k + 2) % 3;  // e_a x e_b = e_k
            for (int side = 0; side < 2; ++side) {
                const auto base = static_cast<uint32_t>(mesh.vertices.size());
                for (int c = 0; c < 4; ++c) {  // corners (0,0) (1,0) (1,1) (0,1) in (a, b)
                    Eigen::Vector3d p;
                    p[k] = side ? hi[k] : lo[k];
                    p[a] = (c == 1 || c == 2) ? hi[a] : lo[a];
                    p[b] = (c >= 2) ? hi[b] : lo[b];
                    mesh.vertices.push_back(p.cast<float>());
                }
                // Counter-clockwise seen from inside: normal +e_k on the lo plane, -e_k on hi.
                if (side == 0) {
                    mesh.triangles.push_back({base, base + 1, base + 2});
                    mesh.triangles.push_back({base, base + 2, base + 3});
                } else {
                    mesh.triangles.push_back({base, base + 2, base + 1});
                    mesh.triangles.push_back({base, base + 3, base + 2});
                }
                ids.insert(ids.end(), 2, kIdBase + static_cast<uint32_t>(2 * k + side));
            }
        }
    }

    struct Exit {
        double t = 0;       // distance along the unit direction to the wall
        int wall = -1;      // 2 * axis + side
        double margin = 0;  // distance further along the ray to the next wall's plane
    };
    // Where the ray from `o` (inside) along the unit `d` leaves the room: the smallest positive
    // plane distance over the three axes.
    Exit Cast(const Eigen::Vector3d& o, const Eigen::Vector3d& d) const {
        double t[3];
        int wall[3];
        for (int k = 0; k < 3; ++k) {
            t[k] = std::numeric_limits<double>::infinity();
            wall[k] = -1;
            if (d[k] > 0) t[k] = (hi[k] - o[k]) / d[k], wall[k] = 2 * k + 1;
            if (d[k] < 0) t[k] = (lo[k] - o[k]) / d[k], wall[k] = 2 * k;
        }
        int order[3] = {0, 1, 2};
        std::sort(order, order + 3, [&](int i, int j) { return t[i] < t[j]; });
        return {t[order[0]], wall[order[0]], t[order[1]] - t[order[0]]};
    }

    // Distance from p to the nearest wall plane, and whether p is within the box (to tol).
    double DistanceToWalls(const Eigen::Vector3d& p) const {
        double best = std::numeric_limits<double>::infinity();
        for (int k = 0; k < 3; ++k) {
            best = std::min({best, std::abs(p[k] - lo[k]), std::abs(p[k] - hi[k])});
        }
        return best;
    }
    bool Contains(const Eigen::Vector3d& p, double tol) const {
        return (p.array() >= lo.array() - tol).all() && (p.array() <= hi.array() + tol).all();
    }
};

}  // namespace bimslam::test
