// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/live/plan_view.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace bimslam::live {

PlanView::PlanView(const localization::RigMap& map) : map_(map), plans_(map.storeys.size()) {
    if (map.levels.empty()) return;
    // The finest level: the plan's detail (0.25 m on the default pyramid).
    const registration::SurfelMap* finest = &map.levels.front();
    for (const registration::SurfelMap& l : map.levels) {
        if (l.config().voxel_size < finest->config().voxel_size) finest = &l;
    }
    for (size_t s = 0; s < map.storeys.size(); ++s) {
        Plan& p = plans_[s];
        const double floor = map.storeys[s].elevation_m;
        bool any = false;
        for (const registration::Surfel& f : finest->surfels()) {
            const double z = f.centroid.z() - floor;
            if (std::abs(f.normal.z()) > 0.3 || z < 0.3 || z > 2.0) continue;
            const Eigen::Vector2d c(f.centroid.x(), f.centroid.y());
            p.walls.push_back(c);
            p.min = any ? p.min.cwiseMin(c) : c;
            p.max = any ? p.max.cwiseMax(c) : c;
            any = true;
        }
    }
}

std::string PlanView::Render(const LiveState& st, int width) const {
    char line[256];
    const std::string storey = st.storey >= 0 && size_t(st.storey) < map_.storeys.size()
                                   ? map_.storeys[st.storey].name
                                   : "-";
    std::string out;
    if (st.position) {
        std::snprintf(line, sizeof line,
                      "%.1f s  %s on '%s'%s%s at (%.2f, %.2f, %.2f) m, heading %.0f deg\n", st.t_s,
                      st.state.c_str(), storey.c_str(), st.space.empty() ? "" : " in ",
                      st.space.c_str(), st.position->x(), st.position->y(), st.position->z(),
                      st.yaw * 180 / M_PI);
    } else {
        std::snprintf(line, sizeof line, "%.1f s  %s (%d consistent loops, %d hypotheses)\n",
                      st.t_s, st.state.c_str(), st.consistent_loops, st.hypotheses);
    }
    out += line;
    const int s = st.storey >= 0 ? st.storey : 0;
    if (plans_.empty() || plans_[size_t(s)].walls.empty()) return out + "(no plan)\n";
    const Plan& p = plans_[size_t(s)];
    const Eigen::Vector2d span = (p.max - p.min).cwiseMax(1e-3);
    const int w = std::max(10, width);
    const double cell = span.x() / (w - 1);  // metres per column; rows are two columns tall
    const int h = std::max(3, int(std::ceil(span.y() / (2 * cell))) + 1);
    std::vector<std::string> grid(size_t(h), std::string(size_t(w), ' '));
    const auto put = [&](const Eigen::Vector2d& q, char c, bool over) {
        const int col = int(std::lround((q.x() - p.min.x()) / cell));
        const int row = h - 1 - int(std::lround((q.y() - p.min.y()) / (2 * cell)));
        if (col < 0 || col >= w || row < 0 || row >= h) return;
        char& g = grid[size_t(row)][size_t(col)];
        if (over || g == ' ') g = c;
    };
    for (const Eigen::Vector2d& q : p.walls) put(q, '#', true);
    for (const Eigen::Vector3d& q : st.walk) {
        const int on = localization::StoreyAt(map_.storeys, q.z());
        if (on == s) put(q.head<2>(), '.', false);
    }
    if (st.position) {
        // The heading's nearest of the four arrows (x right, y up on the plan).
        const char* arrows = ">^<v";
        const int k = int(std::lround(st.yaw / (M_PI / 2))) & 3;
        put(st.position->head<2>(), arrows[k], true);
    }
    for (const std::string& r : grid) out += r + "\n";
    return out;
}

}  // namespace bimslam::live
