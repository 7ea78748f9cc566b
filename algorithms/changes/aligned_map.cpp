// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/changes/aligned_map.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "algorithms/common/status.hpp"
#include "algorithms/common/voxel_hash.hpp"

namespace bimslam::changes {
namespace {

// Interleaves the low 21 bits of x, y, z (Morton order).
uint64_t Spread(uint64_t v) {
    v &= 0x1fffff;
    v = (v | v << 32) & 0x1f00000000ffffull;
    v = (v | v << 16) & 0x1f0000ff0000ffull;
    v = (v | v << 8) & 0x100f00f00f00f00full;
    v = (v | v << 4) & 0x10c30c30c30c30c3ull;
    v = (v | v << 2) & 0x1249249249249249ull;
    return v;
}

// Sums are taken relative to the voxel's corner, so float keeps 0.1 mm for any number of points.
struct Accumulator {
    Eigen::Vector3f sum = Eigen::Vector3f::Zero();
    uint32_t points = 0;
    uint32_t last_keyframe = 0;
    uint32_t first_keyframe = 0;
    uint16_t keyframes = 0;
    uint64_t key = 0;  // PackVoxel
};

uint64_t Morton(const Eigen::Vector3i& v) {
    constexpr int64_t kOffset = 1 << 20;
    return Spread(uint64_t(v.x() + kOffset)) << 2 | Spread(uint64_t(v.y() + kOffset)) << 1 |
           Spread(uint64_t(v.z() + kOffset));
}

}  // namespace

std::vector<uint32_t> MortonOrder(std::span<const Eigen::Vector3f> points, float voxel_m) {
    std::vector<std::pair<uint64_t, uint32_t>> keyed(points.size());
    for (size_t i = 0; i < points.size(); ++i) {
        keyed[i] = {Morton(common::VoxelOf(points[i] / voxel_m)), uint32_t(i)};
    }
    std::sort(keyed.begin(), keyed.end());
    std::vector<uint32_t> order(points.size());
    for (size_t i = 0; i < keyed.size(); ++i) order[i] = keyed[i].second;
    return order;
}

void AlignedMapConfig::Validate() const {
    if (!(voxel_m > 0) || !std::isfinite(voxel_m)) {
        common::ThrowInvalid("map.voxel_m must be > 0, not " + std::to_string(voxel_m));
    }
    if (!(min_range_m >= 0) || !(max_range_m > min_range_m) || !std::isfinite(max_range_m)) {
        common::ThrowInvalid("map: need 0 <= min_range_m < max_range_m, not " +
                             std::to_string(min_range_m) + " and " + std::to_string(max_range_m));
    }
}

AlignedMap BuildAlignedMap(std::span<const MapKeyframe> keyframes, const AlignedMapConfig& config) {
    config.Validate();
    size_t total = 0;
    for (size_t k = 0; k < keyframes.size(); ++k) {
        if (!keyframes[k].cloud)
            common::ThrowInvalid("keyframe " + std::to_string(k) + " has no cloud");
        if (!keyframes[k].T_world_lidar.matrix().allFinite()) {
            common::ThrowInvalid("keyframe " + std::to_string(k) + " has a non-finite pose");
        }
        total += keyframes[k].cloud->size();
    }
    AlignedMap map;
    map.input_points = total;
    const float voxel = float(config.voxel_m);
    const double min2 = config.min_range_m * config.min_range_m;
    const double max2 = config.max_range_m * config.max_range_m;
    common::VoxelHash index(total / 8 + 16);
    std::vector<Accumulator> acc;
    for (size_t k = 0; k < keyframes.size(); ++k) {
        const Eigen::Isometry3d& T = keyframes[k].T_world_lidar;
        for (const Eigen::Vector3f& p : keyframes[k].cloud->xyz) {
            const double r2 = p.cast<double>().squaredNorm();
            if (!p.allFinite() || r2 < min2 || r2 > max2) {
                ++map.cropped_points;
                continue;
            }
            const Eigen::Vector3d w = T * p.cast<double>();
            const Eigen::Vector3i v = common::VoxelOf(w.cast<float>() / voxel);
            bool fresh = false;
            const uint64_t key = common::PackVoxel(v);
            const uint32_t slot = index.FindOrInsert(key, uint32_t(acc.size()), &fresh);
            if (fresh) {
                Accumulator a;
                a.first_keyframe = a.last_keyframe = uint32_t(k);
                a.keyframes = 1;
                a.key = key;
                acc.push_back(a);
            }
            Accumulator& a = acc[slot];
            a.sum += (w - v.cast<double>() * double(voxel)).cast<float>();
            ++a.points;
            if (a.last_keyframe != uint32_t(k)) {
                a.last_keyframe = uint32_t(k);
                if (a.keyframes < UINT16_MAX) ++a.keyframes;
            }
        }
    }
    std::vector<std::pair<uint64_t, uint32_t>> order(acc.size());
    for (size_t i = 0; i < acc.size(); ++i)
        order[i] = {Morton(common::UnpackVoxel(acc[i].key)), uint32_t(i)};
    std::sort(order.begin(), order.end());
    map.xyz.resize(acc.size());
    map.points.resize(acc.size());
    map.keyframes.resize(acc.size());
    map.first_keyframe.resize(acc.size());
    for (size_t i = 0; i < order.size(); ++i) {
        const Accumulator& a = acc[order[i].second];
        const Eigen::Vector3d corner = common::UnpackVoxel(a.key).cast<double>() * double(voxel);
        map.xyz[i] = (corner + (a.sum / float(a.points)).cast<double>()).cast<float>();
        map.points[i] = a.points;
        map.keyframes[i] = a.keyframes;
        map.first_keyframe[i] = a.first_keyframe;
    }
    return map;
}

}  // namespace bimslam::changes
