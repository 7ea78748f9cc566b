// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/changes/voxel_mesh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <tuple>

#include "algorithms/common/status.hpp"
#include "algorithms/common/voxel_hash.hpp"

namespace bimslam::changes {
namespace {

bool Less(const Eigen::Vector3i& a, const Eigen::Vector3i& b) {
    return std::tie(a.x(), a.y(), a.z()) < std::tie(b.x(), b.y(), b.z());
}

}  // namespace

double VoxelSolid::volume_m3() const {
    return double(voxels.size()) * double(voxel_m) * double(voxel_m) * double(voxel_m);
}

Eigen::Vector3d VoxelSolid::box_min() const {
    if (voxels.empty()) return Eigen::Vector3d::Zero();
    Eigen::Vector3i lo = voxels.front();
    for (const auto& v : voxels) lo = lo.cwiseMin(v);
    return lo.cast<double>() * double(voxel_m);
}

Eigen::Vector3d VoxelSolid::box_max() const {
    if (voxels.empty()) return Eigen::Vector3d::Zero();
    Eigen::Vector3i hi = voxels.front();
    for (const auto& v : voxels) hi = hi.cwiseMax(v);
    return (hi.cast<double>() + Eigen::Vector3d::Ones()) * double(voxel_m);
}

Eigen::Vector3d VoxelSolid::centroid() const {
    if (voxels.empty()) return Eigen::Vector3d::Zero();
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (const auto& v : voxels) sum += v.cast<double>();
    return (sum / double(voxels.size()) + Eigen::Vector3d::Constant(0.5)) * double(voxel_m);
}

VoxelSolid MakeVoxelSolid(std::span<const Eigen::Vector3f> points, float voxel_m, float base_z) {
    if (!(voxel_m > 0) || !std::isfinite(base_z)) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            "voxel solid: voxel size must be > 0 and the base finite, not " +
                                std::to_string(voxel_m) + " and " + std::to_string(base_z));
    }
    // Per (x, y) column its highest voxel.
    std::map<std::pair<int, int>, int> top;
    for (const Eigen::Vector3f& p : points) {
        const Eigen::Vector3i v = common::VoxelOf(p / voxel_m);
        const auto [it, fresh] = top.try_emplace({v.x(), v.y()}, v.z());
        if (!fresh) it->second = std::max(it->second, v.z());
    }
    // Closing: dilate by one column (a new column takes the highest of its neighbours), then
    // erode: keep a dilated column only when all its 8 neighbours are in the dilation.
    std::map<std::pair<int, int>, int> dilated = top;
    for (const auto& [xy, z] : top) {
        for (int dx = -1; dx <= 1; ++dx) {
            for (int dy = -1; dy <= 1; ++dy) {
                const auto [it, fresh] = dilated.try_emplace({xy.first + dx, xy.second + dy}, z);
                if (!fresh) it->second = std::max(it->second, z);
            }
        }
    }
    std::map<std::pair<int, int>, int> closed;
    for (const auto& [xy, z] : dilated) {
        bool inner = true;
        for (int dx = -1; dx <= 1 && inner; ++dx) {
            for (int dy = -1; dy <= 1 && inner; ++dy) {
                inner = dilated.count({xy.first + dx, xy.second + dy}) > 0;
            }
        }
        const auto original = top.find(xy);
        if (original != top.end()) {
            closed.emplace(xy, original->second);
        } else if (inner) {
            closed.emplace(xy, z);
        }
    }
    VoxelSolid solid;
    solid.voxel_m = voxel_m;
    const int base = int(std::floor(base_z / voxel_m + 0.5f));
    for (const auto& [xy, z] : closed) {
        for (int k = std::min(base, z); k <= z; ++k)
            solid.voxels.emplace_back(xy.first, xy.second, k);
    }
    std::sort(solid.voxels.begin(), solid.voxels.end(), Less);
    return solid;
}

common::TriangleMesh VoxelSurface(const VoxelSolid& solid) {
    common::VoxelHash occupied(solid.voxels.size() + 16);
    for (const auto& v : solid.voxels) occupied.FindOrInsert(common::PackVoxel(v), 1);
    common::TriangleMesh mesh;
    common::VoxelHash corner_index(4 * solid.voxels.size() + 16);
    const auto corner = [&](const Eigen::Vector3i& c) {
        bool fresh = false;
        const uint32_t i =
            corner_index.FindOrInsert(common::PackVoxel(c), uint32_t(mesh.vertices.size()), &fresh);
        if (fresh) mesh.vertices.push_back(c.cast<float>() * solid.voxel_m);
        return i;
    };
    // Face k of a voxel: axis a = k / 2, side s = k % 2 (0: the low face, normal -e_a). The quad's
    // corners (in the two other axes b, c, with e_a x e_b = e_c) go counter-clockwise seen along
    // the outward normal.
    for (const auto& v : solid.voxels) {
        for (int a = 0; a < 3; ++a) {
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            for (int s = 0; s < 2; ++s) {
                Eigen::Vector3i n = v;
                n[a] += s ? 1 : -1;
                if (occupied.Find(common::PackVoxel(n)) != common::VoxelHash::kAbsent) continue;
                std::array<Eigen::Vector3i, 4> q;
                for (int k = 0; k < 4; ++k) {
                    q[k] = v;
                    q[k][a] += s;
                }
                // (0,0), (1,0), (1,1), (0,1) in (b, c): counter-clockwise about +e_a.
                q[1][b] += 1;
                q[2][b] += 1;
                q[2][c] += 1;
                q[3][c] += 1;
                const uint32_t i0 = corner(q[0]), i1 = corner(q[1]), i2 = corner(q[2]),
                               i3 = corner(q[3]);
                if (s == 1) {
                    mesh.triangles.push_back({i0, i1, i2});
                    mesh.triangles.push_back({i0, i2, i3});
                } else {
                    mesh.triangles.push_back({i0, i2, i1});
                    mesh.triangles.push_back({i0, i3, i2});
                }
            }
        }
    }
    return mesh;
}

PlanRectangle SmallestPlanRectangle(std::span<const Eigen::Vector3f> points) {
    PlanRectangle best;
    if (points.empty()) return best;
    double best_perimeter = std::numeric_limits<double>::infinity();
    constexpr int kSteps = 180;  // 0.5 deg over a quarter turn: the rectangle repeats after it
    for (int k = 0; k < kSteps; ++k) {
        const double a = 0.5 * M_PI * k / kSteps;
        const Eigen::Vector2d u(std::cos(a), std::sin(a)), v(-u.y(), u.x());
        double u0 = std::numeric_limits<double>::infinity(), u1 = -u0, v0 = u0, v1 = -u0;
        for (const Eigen::Vector3f& p : points) {
            const Eigen::Vector2d q = p.head<2>().cast<double>();
            u0 = std::min(u0, u.dot(q));
            u1 = std::max(u1, u.dot(q));
            v0 = std::min(v0, v.dot(q));
            v1 = std::max(v1, v.dot(q));
        }
        const double du = u1 - u0, dv = v1 - v0;
        if (du + dv >= best_perimeter) continue;
        best_perimeter = du + dv;
        // The long side's direction: u, or v a quarter turn on.
        const double yaw = (du >= dv ? a : a + 0.5 * M_PI) * 180 / M_PI;
        best = {std::max(du, dv), std::min(du, dv), std::fmod(yaw, 180.0),
                0.5 * (u0 + u1) * u + 0.5 * (v0 + v1) * v};
    }
    return best;
}

}  // namespace bimslam::changes
