// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/changes/extension.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

namespace bimslam::changes {
namespace {

uint64_t CellKey(int64_t x, int64_t y) {
    return (uint64_t(uint32_t(int32_t(x))) << 32) | uint64_t(uint32_t(int32_t(y)));
}

}  // namespace

std::vector<uint8_t> AboveLocalGround(std::span<const Eigen::Vector3f> xyz,
                                      std::span<const uint32_t> points, float cell_m,
                                      float clearance_m) {
    const auto cell = [&](const Eigen::Vector3f& p) {
        return std::pair<int64_t, int64_t>(int64_t(std::floor(p.x() / cell_m)),
                                           int64_t(std::floor(p.y() / cell_m)));
    };
    std::unordered_map<uint64_t, float> lowest;
    lowest.reserve(points.size() / 8 + 1);
    for (const uint32_t i : points) {
        const auto [cx, cy] = cell(xyz[i]);
        const auto [it, fresh] = lowest.try_emplace(CellKey(cx, cy), xyz[i].z());
        if (!fresh) it->second = std::min(it->second, xyz[i].z());
    }
    std::vector<uint8_t> above(points.size(), 0);
    for (size_t k = 0; k < points.size(); ++k) {
        const Eigen::Vector3f& p = xyz[points[k]];
        const auto [cx, cy] = cell(p);
        float ground = std::numeric_limits<float>::infinity();
        for (int64_t dx = -1; dx <= 1; ++dx) {
            for (int64_t dy = -1; dy <= 1; ++dy) {
                const auto it = lowest.find(CellKey(cx + dx, cy + dy));
                if (it != lowest.end()) ground = std::min(ground, it->second);
            }
        }
        above[k] = p.z() > ground + clearance_m;
    }
    return above;
}

}  // namespace bimslam::changes
