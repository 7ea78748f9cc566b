// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/registration/removed_surfaces.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <unordered_map>
#include <utility>

#include "algorithms/common/voxel_hash.hpp"

namespace bimslam::registration {
namespace {

// The normal's nearest axis: a wall's two faces (opposite normals) share it.
int Axis(const Eigen::Vector3f& normal) {
    int axis = 0;
    normal.cwiseAbs().maxCoeff(&axis);
    return axis;
}

// A crossing's cell (common::PackVoxel of its 0.5 m voxel); cells of one axis only ever join.
uint64_t CellKey(const Crossing& c, double cell) {
    return common::PackVoxel(common::VoxelOf(c.at / static_cast<float>(cell)));
}

struct CellStats {
    std::vector<std::pair<size_t, const Crossing*>> crossings;  // (view, crossing)
    int component = -1;
};
using Cells = std::unordered_map<uint64_t, CellStats>;  // of one axis

// Labels the cells' connected groups (26 neighbours) from `first`; returns the next label.
int LabelComponents(Cells* cells, int first) {
    int n = first;
    for (auto& [key, stats] : *cells) {
        if (stats.component >= 0) continue;
        stats.component = n;
        std::vector<uint64_t> stack{key};
        while (!stack.empty()) {
            const Eigen::Vector3i c = common::UnpackVoxel(stack.back());
            stack.pop_back();
            for (int dx = -1; dx <= 1; ++dx) {
                for (int dy = -1; dy <= 1; ++dy) {
                    for (int dz = -1; dz <= 1; ++dz) {
                        auto it = cells->find(common::PackVoxel(c + Eigen::Vector3i(dx, dy, dz)));
                        if (it == cells->end() || it->second.component >= 0) continue;
                        it->second.component = n;
                        stack.push_back(it->first);
                    }
                }
            }
        }
        ++n;
    }
    return n;
}

// One connected group of cells of one axis as a surface: its crossings, views, the share of its
// rays that end on the map, and its area on its plane (its cells projected along its axis).
RemovedSurface Summarise(int axis,
                         const std::vector<std::pair<uint64_t, const CellStats*>>& group) {
    RemovedSurface s;
    s.axis = axis;
    std::set<std::pair<int, int>> projected;
    std::set<size_t> views;
    size_t on_map = 0;
    for (const auto& [key, stats] : group) {
        s.cells.push_back(key);
        const Eigen::Vector3i c = common::UnpackVoxel(key);
        projected.insert({c[(axis + 1) % 3], c[(axis + 2) % 3]});
        for (const auto& [view, crossing] : stats->crossings) {
            views.insert(view);
            s.center += crossing->at;
            on_map += crossing->lands_on_map;
            ++s.crossings;
        }
    }
    std::sort(s.cells.begin(), s.cells.end());
    s.center /= float(std::max<size_t>(1, s.crossings));
    s.views = views.size();
    s.on_map = s.crossings ? double(on_map) / double(s.crossings) : 0.0;
    s.area_m2 = double(projected.size());  // in cells; scaled by the caller
    return s;
}

}  // namespace

std::vector<RemovedSurface> FindRemovedSurfaces(const std::vector<const FreeSpaceResult*>& views,
                                                const RemovedSurfaceConfig& config) {
    std::array<Cells, 3> cells;  // per normal axis
    size_t total = 0;
    for (size_t v = 0; v < views.size(); ++v) {
        for (const Crossing& c : views[v]->crossings) {
            cells[Axis(c.normal)][CellKey(c, config.cell)].crossings.emplace_back(v, &c);
            ++total;
        }
    }
    std::vector<RemovedSurface> surfaces;
    int labels = 0;
    for (int axis = 0; axis < 3; ++axis) {
        const int first = labels;
        labels = LabelComponents(&cells[axis], first);
        std::vector<std::vector<std::pair<uint64_t, const CellStats*>>> groups(labels - first);
        for (const auto& [key, stats] : cells[axis]) {
            groups[stats.component - first].emplace_back(key, &stats);
        }
        for (const auto& group : groups) {
            RemovedSurface s = Summarise(axis, group);
            s.area_m2 *= config.cell * config.cell;
            if (s.views >= config.min_views && s.area_m2 <= config.max_area_m2 &&
                s.on_map >= config.min_on_map &&
                double(s.crossings) >= config.min_share * double(total)) {
                surfaces.push_back(std::move(s));
            }
        }
    }
    std::sort(
        surfaces.begin(), surfaces.end(),
        [](const RemovedSurface& a, const RemovedSurface& b) { return a.crossings > b.crossings; });
    if (surfaces.size() > config.max_surfaces) surfaces.resize(config.max_surfaces);
    return surfaces;
}

double UnexplainedRatio(const FreeSpaceResult& view, const std::vector<RemovedSurface>& removed,
                        const RemovedSurfaceConfig& config) {
    if (view.rays == 0) return 0.0;
    size_t explained = 0;
    for (const Crossing& c : view.crossings) {
        const uint64_t key = CellKey(c, config.cell);
        const int axis = Axis(c.normal);
        for (const RemovedSurface& s : removed) {
            if (s.axis == axis && std::binary_search(s.cells.begin(), s.cells.end(), key)) {
                ++explained;
                break;
            }
        }
    }
    return double(view.seen_through - explained) / double(view.rays);
}

double MedianUnexplained(const std::vector<const FreeSpaceResult*>& views,
                         const std::vector<RemovedSurface>& removed,
                         const RemovedSurfaceConfig& config) {
    std::vector<double> ratios;
    for (const FreeSpaceResult* v : views) {
        if (v->rays > 0) ratios.push_back(UnexplainedRatio(*v, removed, config));
    }
    if (ratios.empty()) return 0.0;
    std::nth_element(ratios.begin(), ratios.begin() + ratios.size() / 2, ratios.end());
    return ratios[ratios.size() / 2];
}

}  // namespace bimslam::registration
