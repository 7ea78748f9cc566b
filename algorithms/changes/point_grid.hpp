// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Points binned into cubic cells, for fixed-radius neighbour searches (DBSCAN, region growing,
// normals). The cells are sorted by their packed key (x, then y, then z), so the cells of one
// (x, y) column are contiguous and a neighbourhood of reach r is (2r + 1)^2 binary searches, one
// per column, each followed by a short scan: no hash table, O(n log n) to build.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "algorithms/common/voxel_hash.hpp"

namespace bimslam::changes {

class PointGrid {
public:
    // Keeps a view of `points`: they must outlive the grid and stay unchanged.
    PointGrid(std::span<const Eigen::Vector3f> points, float cell_m);

    float cell_m() const { return cell_; }
    size_t cell_count() const { return keys_.size(); }
    std::span<const Eigen::Vector3f> points() const { return points_; }

    // The points of cell c (indices into points()).
    std::span<const uint32_t> CellPoints(size_t c) const {
        return {order_.data() + begin_[c], begin_[c + 1] - begin_[c]};
    }
    Eigen::Vector3i CellIndex(size_t c) const { return common::UnpackVoxel(keys_[c]); }
    // The cell holding point i.
    uint32_t CellOfPoint(uint32_t i) const { return cell_of_point_[i]; }

    // Calls f(cell) for every non-empty cell whose index differs from `center` by at most
    // `reach` in each axis.
    template <class F>
    void ForEachCellNear(const Eigen::Vector3i& center, int reach, F&& f) const {
        for (int dx = -reach; dx <= reach; ++dx) {
            for (int dy = -reach; dy <= reach; ++dy) {
                const Eigen::Vector3i column(center.x() + dx, center.y() + dy, center.z());
                const uint64_t lo = common::PackVoxel(column - Eigen::Vector3i(0, 0, reach));
                const uint64_t hi = common::PackVoxel(column + Eigen::Vector3i(0, 0, reach));
                for (size_t c = LowerBound(lo); c < keys_.size() && keys_[c] <= hi; ++c) f(c);
            }
        }
    }
    // Calls f(j) for every point j within `radius` of p (p itself included when it is a point of
    // the grid). radius may exceed the cell size.
    template <class F>
    void ForEachPointWithin(const Eigen::Vector3f& p, float radius, F&& f) const {
        const int reach = int(std::ceil(radius / cell_));
        const float r2 = radius * radius;
        ForEachCellNear(common::VoxelOf(p / cell_), reach, [&](size_t c) {
            for (const uint32_t j : CellPoints(c)) {
                if ((points_[j] - p).squaredNorm() <= r2) f(j);
            }
        });
    }

private:
    size_t LowerBound(uint64_t key) const;

    std::span<const Eigen::Vector3f> points_;
    float cell_;
    std::vector<uint64_t> keys_;   // sorted, unique
    std::vector<uint32_t> begin_;  // cell c holds order_[begin_[c], begin_[c + 1])
    std::vector<uint32_t> order_;  // point indices by cell
    std::vector<uint32_t> cell_of_point_;
};

}  // namespace bimslam::changes
