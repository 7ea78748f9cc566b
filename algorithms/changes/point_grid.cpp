// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/changes/point_grid.hpp"

#include <algorithm>
#include <string>
#include <utility>

#include "algorithms/common/status.hpp"

namespace bimslam::changes {

PointGrid::PointGrid(std::span<const Eigen::Vector3f> points, float cell_m)
    : points_(points), cell_(cell_m) {
    if (!(cell_m > 0)) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            "PointGrid: cell size must be > 0, not " + std::to_string(cell_m));
    }
    // (key, index) pairs sort with the key next to its index: several times faster than sorting
    // indices by a key looked up elsewhere.
    std::vector<std::pair<uint64_t, uint32_t>> keyed(points.size());
    for (size_t i = 0; i < points.size(); ++i) {
        keyed[i] = {common::PackVoxel(common::VoxelOf(points[i] / cell_m)), uint32_t(i)};
    }
    std::sort(keyed.begin(), keyed.end());
    order_.resize(points.size());
    cell_of_point_.resize(points.size());
    for (size_t k = 0; k < keyed.size(); ++k) {
        const auto [kk, i] = keyed[k];
        if (keys_.empty() || keys_.back() != kk) {
            keys_.push_back(kk);
            begin_.push_back(uint32_t(k));
        }
        order_[k] = i;
        cell_of_point_[i] = uint32_t(keys_.size() - 1);
    }
    begin_.push_back(uint32_t(order_.size()));
}

size_t PointGrid::LowerBound(uint64_t key) const {
    return size_t(std::lower_bound(keys_.begin(), keys_.end(), key) - keys_.begin());
}

}  // namespace bimslam::changes
