// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/changes/dbscan.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <limits>
#include <numeric>
#include <string>

#include "algorithms/changes/point_grid.hpp"
#include "algorithms/common/status.hpp"

namespace bimslam::changes {
namespace {

// Union-find over cells, with path halving and union by index (the smaller root wins, which
// keeps the labelling independent of the order unions happen in).
struct DisjointSets {
    std::vector<uint32_t> parent;
    explicit DisjointSets(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
    uint32_t Find(uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    }
    void Union(uint32_t a, uint32_t b) {
        a = Find(a), b = Find(b);
        if (a < b) parent[b] = a;
        if (b < a) parent[a] = b;
    }
};

}  // namespace

void DbscanConfig::Validate() const {
    if (!(eps_m > 0) || !std::isfinite(eps_m)) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            "dbscan.eps_m must be > 0, not " + std::to_string(eps_m));
    }
    if (min_points < 1) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            "dbscan.min_points must be >= 1, not " + std::to_string(min_points));
    }
}

DbscanResult Dbscan(std::span<const Eigen::Vector3f> points, const DbscanConfig& config) {
    config.Validate();
    DbscanResult out;
    out.labels.assign(points.size(), -1);
    if (points.empty()) return out;
    const float eps = float(config.eps_m);
    const float eps2 = eps * eps;
    const size_t min_points = size_t(config.min_points);
    const PointGrid grid(points, eps / std::sqrt(3.0f) * 0.999f);
    const size_t cells = grid.cell_count();
    constexpr int kReach = 2;  // ceil(sqrt(3)): cells within eps of a cell

    // 1. Core points.
    std::vector<uint8_t> core(points.size(), 0);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, cells, 256), [&](const auto& range) {
        for (size_t c = range.begin(); c < range.end(); ++c) {
            const auto members = grid.CellPoints(c);
            if (members.size() >= min_points) {
                for (const uint32_t i : members) core[i] = 1;
                continue;
            }
            for (const uint32_t i : members) {
                size_t n = 0;
                grid.ForEachCellNear(grid.CellIndex(c), kReach, [&](size_t d) {
                    if (n >= min_points) return;
                    for (const uint32_t j : grid.CellPoints(d)) {
                        if ((points[j] - points[i]).squaredNorm() <= eps2 && ++n >= min_points) {
                            break;
                        }
                    }
                });
                core[i] = n >= min_points;
            }
        }
    });
    std::vector<uint8_t> core_cell(cells, 0);
    for (size_t c = 0; c < cells; ++c) {
        for (const uint32_t i : grid.CellPoints(c)) core_cell[c] |= core[i];
    }

    // 2. Join core cells that have core points within eps of each other.
    DisjointSets sets(cells);
    for (size_t a = 0; a < cells; ++a) {
        if (!core_cell[a]) continue;
        grid.ForEachCellNear(grid.CellIndex(a), kReach, [&](size_t b) {
            if (b <= a || !core_cell[b] || sets.Find(uint32_t(a)) == sets.Find(uint32_t(b))) return;
            for (const uint32_t i : grid.CellPoints(a)) {
                if (!core[i]) continue;
                for (const uint32_t j : grid.CellPoints(b)) {
                    if (core[j] && (points[i] - points[j]).squaredNorm() <= eps2) {
                        sets.Union(uint32_t(a), uint32_t(b));
                        return;
                    }
                }
            }
        });
    }

    // Labels in the order of each cluster's first core point.
    std::vector<int32_t> label_of_root(cells, -1);
    for (size_t i = 0; i < points.size(); ++i) {
        if (!core[i]) continue;
        ++out.core_points;
        const uint32_t root = sets.Find(grid.CellOfPoint(uint32_t(i)));
        if (label_of_root[root] < 0) label_of_root[root] = out.clusters++;
        out.labels[i] = label_of_root[root];
    }

    // 3. Border points: the cluster of the nearest core point within eps.
    tbb::parallel_for(tbb::blocked_range<size_t>(0, points.size(), 4096), [&](const auto& range) {
        for (size_t i = range.begin(); i < range.end(); ++i) {
            if (core[i]) continue;
            float best = std::numeric_limits<float>::infinity();
            int32_t label = -1;
            grid.ForEachCellNear(
                grid.CellIndex(grid.CellOfPoint(uint32_t(i))), kReach, [&](size_t d) {
                    for (const uint32_t j : grid.CellPoints(d)) {
                        if (!core[j]) continue;
                        const float d2 = (points[j] - points[i]).squaredNorm();
                        if (d2 <= eps2 && (d2 < best || (d2 == best && out.labels[j] < label))) {
                            best = d2;
                            label = out.labels[j];
                        }
                    }
                });
            out.labels[i] = label;
        }
    });
    return out;
}

Eigen::AlignedBox3d ClusterBox(std::span<const Eigen::Vector3f> points,
                               std::span<const uint32_t> indices) {
    Eigen::AlignedBox3d box;
    for (const uint32_t i : indices) box.extend(points[i].cast<double>());
    return box;
}

}  // namespace bimslam::changes
