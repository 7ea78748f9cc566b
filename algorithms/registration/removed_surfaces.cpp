// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/registration/removed_surfaces.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <unordered_map>
#include <utility>

namespace bimslam::registration {
namespace {

constexpr long long kBias = 1 << 19;  // 20 bits per index: +-262 km in 0.5 m cells

// The normal's nearest axis: a wall's two faces (opposite normals) share it.
int Axis(const Eigen::Vector3f& normal) {
    int axis = 0;
    normal.cwiseAbs().maxCoeff(&axis);
    return axis;
}

Eigen::Vector3i CellOf(const Eigen::Vector3f& x, double cell) {
    return (x / static_cast<float>(cell)).array().floor().cast<int>();
}

long long Key(const Eigen::Vector3i& c, int axis) {
    return ((c.x() + kBias) << 42) | ((c.y() + kBias) << 22) | ((c.z() + kBias) << 2) | axis;
}

long long KeyOf(const Crossing& c, double cell) { return Key(CellOf(c.at, cell), Axis(c.normal)); }

struct CellStats {
    std::vector<std::pair<size_t, const Crossing*>> crossings;  // (view, crossing)
    int component = -1;
};

// Labels the cells' connected groups (26 neighbours, one axis); returns their number.
int LabelComponents(std::unordered_map<long long, CellStats>* cells) {
    int n = 0;
    for (auto& [key, stats] : *cells) {
        if (stats.component >= 0) continue;
        stats.component = n;
        std::vector<long long> stack{key};
        while (!stack.empty()) {
            const long long k = stack.back();
            stack.pop_back();
            const int axis = int(k & 3);
            const Eigen::Vector3i c(int((k >> 42) - kBias), int(((k >> 22) & 0xFFFFF) - kBias),
                                    int(((k >> 2) & 0xFFFFF) - kBias));
            for (int dx = -1; dx <= 1; ++dx) {
                for (int dy = -1; dy <= 1; ++dy) {
                    for (int dz = -1; dz <= 1; ++dz) {
                        auto it = cells->find(Key(c + Eigen::Vector3i(dx, dy, dz), axis));
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

// One connected group of cells as a surface: its crossings, views, the share of its rays that
// end on the map, and its area on its plane (its cells projected along its axis).
RemovedSurface Summarise(const std::vector<std::pair<long long, const CellStats*>>& group) {
    RemovedSurface s;
    std::set<size_t> views;
    std::set<std::pair<int, int>> projected;
    size_t on_map = 0;
    for (const auto& [key, stats] : group) {
        s.axis = int(key & 3);
        s.cells.push_back(key);
        const long long a = (key >> 42) - kBias, b = ((key >> 22) & 0xFFFFF) - kBias,
                        c = ((key >> 2) & 0xFFFFF) - kBias;
        projected.insert(s.axis == 0   ? std::make_pair(int(b), int(c))
                         : s.axis == 1 ? std::make_pair(int(a), int(c))
                                       : std::make_pair(int(a), int(b)));
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
    std::unordered_map<long long, CellStats> cells;
    size_t total = 0;
    for (size_t v = 0; v < views.size(); ++v) {
        for (const Crossing& c : views[v]->crossings) {
            cells[KeyOf(c, config.cell)].crossings.emplace_back(v, &c);
            ++total;
        }
    }
    const int n = LabelComponents(&cells);
    std::vector<std::vector<std::pair<long long, const CellStats*>>> groups(n);
    for (const auto& [key, stats] : cells) groups[stats.component].emplace_back(key, &stats);
    std::vector<RemovedSurface> surfaces;
    for (const auto& group : groups) {
        RemovedSurface s = Summarise(group);
        s.area_m2 *= config.cell * config.cell;
        if (s.views >= config.min_views && s.area_m2 <= config.max_area_m2 &&
            s.on_map >= config.min_on_map &&
            double(s.crossings) >= config.min_share * double(total)) {
            surfaces.push_back(std::move(s));
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
        const long long key = KeyOf(c, config.cell);
        for (const RemovedSurface& s : removed) {
            if (std::binary_search(s.cells.begin(), s.cells.end(), key)) {
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
