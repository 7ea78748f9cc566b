// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/bim/coverage_path.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <span>
#include <sstream>
#include <string>

#include "algorithms/common/polyline.hpp"
#include "algorithms/common/se3.hpp"
#include "algorithms/common/status.hpp"

namespace bimslam::bim {
namespace {
using common::StatusCode;
constexpr double kInf = std::numeric_limits<double>::infinity();

// A grid graph for the searches: the safe cells, 8-connected, and per cell the factor of the cost
// of stepping onto it: its length, more near walls, so that walks keep to the middle.
struct Lattice {
    int width = 0, height = 0;
    double resolution = 0;
    Eigen::Vector2d origin = Eigen::Vector2d::Zero();
    std::vector<uint8_t> traversable;
    std::vector<float> cost;

    Eigen::Vector2d Center(size_t i) const {
        return origin +
               resolution * Eigen::Vector2d(double(i % width) + 0.5, double(i / width) + 0.5);
    }

    // Dijkstra from `source`; stops early once every cell of `targets` is settled, when given.
    // With one target it is A*: the straight-line distance never overestimates (every step costs
    // at least its length), so the path is still the cheapest, and far fewer cells are settled.
    void Search(size_t source, std::vector<double>& dist, std::vector<size_t>& parent,
                std::span<const size_t> targets = {}) const {
        const bool astar = targets.size() == 1;
        const Eigen::Vector2d goal = astar ? Center(targets[0]) : Eigen::Vector2d::Zero();
        auto h = [&](size_t i) { return astar ? (Center(i) - goal).norm() : 0.0; };
        std::vector<uint8_t> wanted;
        size_t remaining = 0;
        if (!targets.empty()) {
            wanted.assign(traversable.size(), 0);
            for (const size_t t : targets) remaining += wanted[t] == 0 ? (wanted[t] = 1) : 0;
        }
        dist.assign(traversable.size(), kInf);
        parent.assign(traversable.size(), SIZE_MAX);
        using Item = std::pair<double, size_t>;
        std::priority_queue<Item, std::vector<Item>, std::greater<Item>> open;
        dist[source] = 0;
        open.push({h(source), source});
        const int dx[8] = {1, -1, 0, 0, 1, 1, -1, -1}, dy[8] = {0, 0, 1, -1, 1, -1, 1, -1};
        while (!open.empty()) {
            const auto [f, i] = open.top();
            open.pop();
            const double d = dist[i];
            if (f > d + h(i) + 1e-9) continue;  // stale entry
            if (!wanted.empty() && wanted[i] && --remaining == 0) return;
            const int x = int(i % width), y = int(i / width);
            for (int k = 0; k < 8; ++k) {
                const int nx = x + dx[k], ny = y + dy[k];
                if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
                const size_t j = size_t(ny) * width + nx;
                if (!traversable[j]) continue;
                const double nd = d + resolution * (k < 4 ? 1.0 : M_SQRT2) * cost[j];
                if (nd < dist[j]) {
                    dist[j] = nd;
                    parent[j] = i;
                    open.push({nd + h(j), j});
                }
            }
        }
    }
};

struct Planner {
    const OccupancyGrid& g;
    const PathConfig& c;
    Lattice fine;

    Planner(const OccupancyGrid& grid, const PathConfig& config) : g(grid), c(config) {
        fine.width = g.width;
        fine.height = g.height;
        fine.resolution = g.resolution;
        fine.origin = g.origin;
        fine.traversable.assign(g.cells.size(), 0);
        fine.cost.assign(g.cells.size(), 0.0f);
        for (size_t i = 0; i < g.cells.size(); ++i) {
            fine.traversable[i] = g.cells[i] == Cell::kFree && g.clearance[i] >= c.clearance_m;
            const double margin = std::max(0.0, double(g.clearance[i]) - c.clearance_m);
            fine.cost[i] = float(1.0 + 2.0 * std::exp(-margin / 0.25));
        }
    }
    bool Safe(const Eigen::Vector2d& p) const {
        int x, y;
        return g.ToCell(p, &x, &y) && fine.traversable[size_t(y) * g.width + x];
    }
    // Every point of the segment at half-cell steps is safe.
    bool Visible(const Eigen::Vector2d& a, const Eigen::Vector2d& b) const {
        const int steps = std::max(1, int(std::ceil((b - a).norm() / (0.5 * g.resolution))));
        for (int i = 0; i <= steps; ++i) {
            if (!Safe(a + (b - a) * (double(i) / steps))) return false;
        }
        return true;
    }
    // The fine lattice in blocks of k x k cells, for the distances between all viewpoints (the
    // tour's order needs them only roughly; the legs are then searched on the fine lattice). A
    // block is traversable when any of its cells is, at the cheapest of their costs: optimistic,
    // so a viewpoint the fine lattice reaches, the coarse one reaches too.
    Lattice Coarse(int k) const {
        Lattice out;
        out.width = (g.width + k - 1) / k;
        out.height = (g.height + k - 1) / k;
        out.resolution = g.resolution * k;
        out.origin = g.origin;
        out.traversable.assign(size_t(out.width) * out.height, 0);
        out.cost.assign(out.traversable.size(), std::numeric_limits<float>::max());
        for (size_t i = 0; i < g.cells.size(); ++i) {
            if (!fine.traversable[i]) continue;
            const size_t j =
                size_t(int(i / g.width) / k) * out.width + size_t(int(i % g.width) / k);
            out.traversable[j] = 1;
            out.cost[j] = std::min(out.cost[j], fine.cost[i]);
        }
        return out;
    }
    size_t ToCoarse(size_t i, int k, const Lattice& coarse) const {
        return size_t(int(i / g.width) / k) * coarse.width + size_t(int(i % g.width) / k);
    }
};

// Rooms: 4-connected components of the cells with more clearance than room_split_m.
std::vector<std::vector<size_t>> Rooms(const OccupancyGrid& g, const PathConfig& c) {
    const std::vector<int> label = LabelRegions(
        g, [&](size_t i) { return g.cells[i] == Cell::kFree && g.clearance[i] >= c.room_split_m; });
    std::vector<std::vector<size_t>> all;
    for (size_t i = 0; i < label.size(); ++i) {
        if (label[i] < 0) continue;
        if (size_t(label[i]) >= all.size()) all.resize(size_t(label[i]) + 1);
        all[size_t(label[i])].push_back(i);
    }
    const size_t min_cells = size_t(c.min_room_area_m2 / (g.resolution * g.resolution));
    std::vector<std::vector<size_t>> rooms;
    for (auto& room : all) {
        if (room.size() >= min_cells) rooms.push_back(std::move(room));
    }
    return rooms;
}

// Viewpoints of one room: its cell of most clearance, then farthest-point sampling until every
// candidate is within `spacing` of one. Candidates keep away from the walls (a metre, or 60 % of
// the room's most clearance in a narrow one), so viewpoints lie inside the room, not in corners,
// where farthest points over all its cells would go.
std::vector<size_t> Viewpoints(const OccupancyGrid& g, const std::vector<size_t>& room,
                               double spacing) {
    auto center = [&g](size_t i) { return g.Center(int(i % g.width), int(i / g.width)); };
    size_t first = room[0];
    for (size_t i : room) {
        if (g.clearance[i] > g.clearance[first]) first = i;
    }
    const float inner = std::min(1.0f, 0.6f * g.clearance[first]);
    std::vector<size_t> candidates;
    for (size_t i : room) {
        if (g.clearance[i] >= inner) candidates.push_back(i);
    }
    std::vector<size_t> views{first};
    std::vector<double> dist(candidates.size(), kInf);
    while (true) {
        size_t far = 0;
        for (size_t k = 0; k < candidates.size(); ++k) {
            dist[k] = std::min(dist[k], (center(candidates[k]) - center(views.back())).norm());
            if (dist[k] > dist[far]) far = k;
        }
        if (dist[far] <= spacing) return views;
        views.push_back(candidates[far]);
    }
}

// Closed tour through all points of a distance matrix: nearest neighbour from 0, then 2-opt.
std::vector<int> Tour(const std::vector<std::vector<double>>& d) {
    const int n = int(d.size());
    std::vector<int> tour{0};
    std::vector<bool> used(n, false);
    used[0] = true;
    for (int step = 1; step < n; ++step) {
        int best = -1;
        for (int j = 0; j < n; ++j) {
            if (!used[j] && (best < 0 || d[tour.back()][j] < d[tour.back()][best])) best = j;
        }
        used[best] = true;
        tour.push_back(best);
    }
    for (bool improved = true; improved && n > 3;) {
        improved = false;
        for (int i = 0; i < n - 1; ++i) {
            for (int k = i + 2; k < n; ++k) {
                const int a = tour[i], b = tour[i + 1], c = tour[k], e = tour[(k + 1) % n];
                if (a == e) continue;
                if (d[a][c] + d[b][e] < d[a][b] + d[c][e] - 1e-9) {
                    std::reverse(tour.begin() + i + 1, tour.begin() + k + 1);
                    improved = true;
                }
            }
        }
    }
    return tour;
}

// String pulling of one leg (viewpoint to viewpoint): from each corner, straight on to the last
// cell of the leg seen along a safe line before the first one that is not. Legs are pulled one
// by one so that the viewpoints stay corners: a room entered and left by the same door would
// otherwise be cut off.
std::vector<Eigen::Vector2d> Straighten(const Planner& p, const std::vector<Eigen::Vector2d>& leg) {
    std::vector<Eigen::Vector2d> out{leg[0]};
    size_t anchor = 0;
    while (anchor + 1 < leg.size()) {
        size_t next = anchor + 1;
        while (next + 1 < leg.size() && p.Visible(leg[anchor], leg[next + 1])) ++next;
        out.push_back(leg[next]);
        anchor = next;
    }
    return out;
}

// Chaikin corner cutting on a closed polyline; a cut that leaves the safe cells is not made, and
// pinned corners (the viewpoints) are kept: cutting them would shrink every visit to a dead end
// (a room entered and left by the same door) by a quarter of its leg a pass. The walk turns on
// the spot there, which a legged robot can; the timing slows the turn (max_yaw_rate_radps).
std::vector<Eigen::Vector2d> Smooth(const Planner& p, std::vector<Eigen::Vector2d> pts,
                                    std::vector<uint8_t> pinned, int passes) {
    for (int pass = 0; pass < passes && pts.size() >= 3; ++pass) {
        std::vector<Eigen::Vector2d> out;
        std::vector<uint8_t> out_pinned;
        const size_t n = pts.size();
        for (size_t i = 0; i < n; ++i) {
            const Eigen::Vector2d& a = pts[i];
            const Eigen::Vector2d& b = pts[(i + 1) % n];
            const Eigen::Vector2d q = 0.75 * a + 0.25 * b, r = 0.25 * a + 0.75 * b;
            const bool keep = pinned[i] || (!out.empty() && !p.Visible(out.back(), q)) ||
                              (out.empty() && !p.Visible(0.25 * pts[n - 1] + 0.75 * a, q));
            if (keep) {
                out.push_back(a);
                out_pinned.push_back(pinned[i]);
            }
            out.push_back(q);
            out.push_back(r);
            out_pinned.insert(out_pinned.end(), {0, 0});
        }
        pts = std::move(out);
        pinned = std::move(out_pinned);
    }
    return pts;
}

}  // namespace

void PathConfig::Validate() const {
    common::Require(clearance_m > 0 && clearance_m < 5, "PathConfig", "clearance_m", clearance_m,
                    "must be in (0, 5) m");
    common::Require(room_split_m >= clearance_m && room_split_m < 10, "PathConfig", "room_split_m",
                    room_split_m, "must be in [clearance_m, 10) m");
    common::Require(min_room_area_m2 >= 0, "PathConfig", "min_room_area_m2", min_room_area_m2,
                    "must be >= 0");
    common::Require(view_spacing_m > 0.5, "PathConfig", "view_spacing_m", view_spacing_m,
                    "must be > 0.5 m");
    common::Require(speed_mps > 0 && speed_mps < 10, "PathConfig", "speed_mps", speed_mps,
                    "must be in (0, 10) m/s");
    common::Require(max_yaw_rate_radps > 0.05 && max_yaw_rate_radps < 20, "PathConfig",
                    "max_yaw_rate_radps", max_yaw_rate_radps, "must be in (0.05, 20) rad/s");
    common::Require(sensor_height_m > 0 && sensor_height_m < 10, "PathConfig", "sensor_height_m",
                    sensor_height_m, "must be in (0, 10) m");
    common::Require(spacing_m > 0 && spacing_m <= 1, "PathConfig", "spacing_m", spacing_m,
                    "must be in (0, 1] m");
    common::Require(smoothing_passes >= 0 && smoothing_passes <= 10, "PathConfig",
                    "smoothing_passes", smoothing_passes, "must be in [0, 10]");
}

CoveragePath PlanCoveragePath(const OccupancyGrid& g, const PathConfig& c) {
    c.Validate();
    const Planner planner(g, c);
    const std::vector<std::vector<size_t>> rooms = Rooms(g, c);
    std::vector<size_t> views;
    std::vector<int> view_room;
    for (size_t r = 0; r < rooms.size(); ++r) {
        for (size_t v : Viewpoints(g, rooms[r], c.view_spacing_m)) {
            views.push_back(v);
            view_room.push_back(int(r));
        }
    }
    if (views.empty()) {
        throw common::Error(StatusCode::kInvalidArgument,
                            "storey '" + g.storey + "': no free space with " +
                                std::to_string(c.room_split_m) + " m of clearance for a walk");
    }
    // Start in the biggest room (usually the corridor every door opens onto).
    size_t biggest = 0;
    for (size_t r = 1; r < rooms.size(); ++r) {
        if (rooms[r].size() > rooms[biggest].size()) biggest = r;
    }
    const size_t start =
        size_t(std::find(view_room.begin(), view_room.end(), int(biggest)) - view_room.begin());
    std::swap(views[0], views[start]);
    std::swap(view_room[0], view_room[start]);

    // Geodesic distances between viewpoints; the unreachable ones are dropped.
    std::vector<double> dist;
    std::vector<size_t> parent;
    std::vector<std::vector<double>> d;
    planner.fine.Search(views[0], dist, parent);
    CoveragePath out;
    std::vector<size_t> kept;
    std::vector<int> kept_room;
    for (size_t k = 0; k < views.size(); ++k) {
        if (std::isfinite(dist[views[k]])) {
            kept.push_back(views[k]);
            kept_room.push_back(view_room[k]);
        } else {
            ++out.unreachable_viewpoints;
        }
    }
    // On 20 cm blocks, symmetric: each search needs to reach only the viewpoints after its own.
    const int block = std::max(1, int(std::lround(0.2 / g.resolution)));
    const Lattice coarse = planner.Coarse(block);
    std::vector<size_t> coarse_kept;
    for (const size_t v : kept) coarse_kept.push_back(planner.ToCoarse(v, block, coarse));
    d.assign(kept.size(), std::vector<double>(kept.size(), 0.0));
    for (size_t a = 0; a + 1 < kept.size(); ++a) {
        coarse.Search(coarse_kept[a], dist, parent, std::span(coarse_kept).subspan(a + 1));
        for (size_t b = a + 1; b < kept.size(); ++b) d[a][b] = d[b][a] = dist[coarse_kept[b]];
    }
    const std::vector<int> tour = Tour(d);
    out.rooms = int(rooms.size());

    // The cell paths between consecutive viewpoints, closed back to the start, each straightened
    // where it can be.
    std::vector<Eigen::Vector2d> line;
    std::vector<uint8_t> pinned;  // the viewpoints
    for (size_t k = 0; k < tour.size(); ++k) {
        const size_t from = kept[tour[k]], to = kept[tour[(k + 1) % tour.size()]];
        out.viewpoints.push_back(g.Center(int(from % g.width), int(from / g.width)));
        out.viewpoint_room.push_back(kept_room[tour[k]]);
        if (from == to) continue;
        planner.fine.Search(from, dist, parent, std::span(&to, 1));
        std::vector<Eigen::Vector2d> leg;
        for (size_t i = to; i != from; i = parent[i]) {
            leg.push_back(g.Center(int(i % g.width), int(i / g.width)));
        }
        leg.push_back(g.Center(int(from % g.width), int(from / g.width)));
        std::reverse(leg.begin(), leg.end());
        const std::vector<Eigen::Vector2d> straight = Straighten(planner, leg);
        line.insert(line.end(), straight.begin(),
                    straight.end() - 1);  // the next leg starts at its end
        pinned.push_back(1);
        pinned.resize(line.size(), 0);
    }
    if (line.empty()) {
        line.push_back(out.viewpoints[0]);
        pinned.push_back(1);
    }

    // Rounded at the corners, evenly sampled.
    line = Smooth(planner, line, pinned, c.smoothing_passes);
    out.points = common::ResamplePolyline(line, c.spacing_m, /*closed=*/true);

    // Heading along the walk, averaged over half a metre so that the body turns smoothly.
    const size_t n = out.points.size();
    std::vector<double> yaw(n, 0.0);  // unwrapped, so that averaging does not jump at +-pi
    for (size_t i = 0; i < n; ++i) {
        const Eigen::Vector2d t = out.points[(i + 1) % n] - out.points[(i + n - 1) % n];
        double a = t.norm() > 1e-9 ? std::atan2(t.y(), t.x()) : (i ? yaw[i - 1] : 0.0);
        if (i > 0) a = yaw[i - 1] + std::remainder(a - yaw[i - 1], 2 * M_PI);
        yaw[i] = a;
    }
    const int half = std::max(1, int(0.25 / c.spacing_m));
    double length = 0, time_s = 0, previous_yaw = 0;
    out.min_clearance_m = kInf;
    for (size_t i = 0; i < n; ++i) {
        double sum = 0;
        int count = 0;
        for (int k = -half; k <= half; ++k) {
            const long j = long(i) + k;
            if (j < 0 || j >= long(n)) continue;
            sum += yaw[size_t(j)];
            ++count;
        }
        const double heading = sum / count;
        if (i > 0) {
            const double step = (out.points[i] - out.points[i - 1]).norm();
            length += step;
            time_s += std::max(step / c.speed_mps,
                               std::abs(heading - previous_yaw) / c.max_yaw_rate_radps);
        }
        previous_yaw = heading;
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
        T.linear() = Eigen::AngleAxisd(heading, Eigen::Vector3d::UnitZ()).toRotationMatrix();
        T.translation() << out.points[i], g.floor_z + c.sensor_height_m;
        out.poses.push_back(io::StampedPose::FromIsometry(int64_t(std::llround(time_s * 1e9)), T));
        int x, y;
        if (g.ToCell(out.points[i], &x, &y)) {
            out.min_clearance_m =
                std::min(out.min_clearance_m, double(g.clearance[size_t(y) * g.width + x]));
        }
    }
    out.length_m = length;
    out.duration_s = time_s;
    return out;
}

std::vector<Eigen::Vector2d> PlanRoute(const OccupancyGrid& g, const PathConfig& c,
                                       const Eigen::Vector2d& from, const Eigen::Vector2d& to) {
    c.Validate();
    const Planner planner(g, c);
    auto cell = [&](const Eigen::Vector2d& p, const char* which) {
        int x, y;
        if (!g.ToCell(p, &x, &y) || !planner.fine.traversable[size_t(y) * g.width + x]) {
            std::ostringstream os;
            os << "storey '" << g.storey << "': the route's " << which << " (" << p.x() << ", "
               << p.y() << ") is not free space with " << c.clearance_m << " m of clearance";
            throw common::Error(StatusCode::kInvalidArgument, os.str());
        }
        return size_t(y) * g.width + x;
    };
    const size_t a = cell(from, "start"), b = cell(to, "end");
    std::vector<double> dist;
    std::vector<size_t> parent;
    planner.fine.Search(a, dist, parent, std::span(&b, 1));
    if (!std::isfinite(dist[b])) {
        std::ostringstream os;
        os << "storey '" << g.storey << "': no way with " << c.clearance_m
           << " m of clearance from (" << from.x() << ", " << from.y() << ") to (" << to.x() << ", "
           << to.y() << ")";
        throw common::Error(StatusCode::kInvalidArgument, os.str());
    }
    std::vector<Eigen::Vector2d> leg{to};
    for (size_t i = parent[b]; i != a && i != SIZE_MAX; i = parent[i]) {
        leg.push_back(g.Center(int(i % g.width), int(i / g.width)));
    }
    leg.push_back(from);
    std::reverse(leg.begin(), leg.end());
    return Straighten(planner, leg);
}

std::vector<io::StampedPose> SampleWalk(const std::vector<io::StampedPose>& walk, double rate_hz) {
    std::vector<io::StampedPose> out;
    if (walk.empty() || !(rate_hz > 0)) return out;
    const double step_ns = 1e9 / rate_hz;
    size_t j = 1;
    for (int64_t k = 0;; ++k) {
        const int64_t t = walk.front().stamp_ns + int64_t(std::llround(double(k) * step_ns));
        if (t > walk.back().stamp_ns) break;
        while (j + 1 < walk.size() && walk[j].stamp_ns < t) ++j;
        if (walk.size() == 1 || t <= walk[j - 1].stamp_ns) {
            out.push_back(io::StampedPose::FromIsometry(t, walk[j - 1].Pose()));
            continue;
        }
        const io::StampedPose& a = walk[j - 1];
        const io::StampedPose& b = walk[j];
        const double f =
            std::clamp(double(t - a.stamp_ns) / double(b.stamp_ns - a.stamp_ns), 0.0, 1.0);
        out.push_back(io::StampedPose::FromIsometry(t, common::Interpolate(a.Pose(), b.Pose(), f)));
    }
    return out;
}

io::Image PathImage(const OccupancyGrid& g, const CoveragePath& path) {
    const io::Image grey = GridImage(g);
    io::Image img(g.width, g.height, 3);
    for (size_t i = 0; i < grey.data.size(); ++i) {
        for (int k = 0; k < 3; ++k) img.data[3 * i + k] = grey.data[i];
    }
    auto paint = [&](const Eigen::Vector2d& p, uint8_t r, uint8_t gr, uint8_t b, int radius) {
        int x, y;
        if (!g.ToCell(p, &x, &y)) return;
        for (int dy = -radius; dy <= radius; ++dy) {
            for (int dx = -radius; dx <= radius; ++dx) {
                if (!g.Inside(x + dx, y + dy)) continue;
                uint8_t* px = img.At(x + dx, g.height - 1 - (y + dy));
                px[0] = r;
                px[1] = gr;
                px[2] = b;
            }
        }
    };
    for (size_t i = 0; i < path.points.size(); ++i) {
        const Eigen::Vector2d a = path.points[i], b = path.points[(i + 1) % path.points.size()];
        const int steps = std::max(1, int((b - a).norm() / (0.5 * g.resolution)));
        for (int s = 0; s <= steps; ++s) paint(a + (b - a) * (double(s) / steps), 220, 20, 20, 0);
    }
    for (const Eigen::Vector2d& v : path.viewpoints) paint(v, 20, 60, 230, 2);
    return img;
}

}  // namespace bimslam::bim
