// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/simulate/walk.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <optional>
#include <sstream>

#include "algorithms/common/status.hpp"
#include "host_tools/bim/coverage_path.hpp"
#include "host_tools/bim/reference_walk.hpp"
#include "host_tools/simulate/world.hpp"

namespace bimslam::simulate {
namespace {

// A turning radius of a small car at town speed: its corners at 3 m/s take about 1.8 m/s^2.
constexpr double kVehicleTurnRadiusM = 5.0;

void Append(std::vector<Eigen::Vector2d>& walk, const std::vector<Eigen::Vector2d>& leg) {
    for (const Eigen::Vector2d& p : leg) {
        if (walk.empty() || (walk.back() - p).norm() > 1e-9) walk.push_back(p);
    }
}

// Less floor than this cut off by an object is not worth a note (a corner behind a cabinet).
constexpr double kCutOffNoteM2 = 1.0;

// Free cells outside the largest free region: what the walk cannot reach.
size_t CutOffCells(const bim::OccupancyGrid& g) {
    const std::vector<int> label =
        bim::LabelRegions(g, [&](size_t i) { return g.cells[i] == bim::Cell::kFree; });
    std::vector<size_t> size;
    for (const int l : label) {
        if (l < 0) continue;
        if (size_t(l) >= size.size()) size.resize(size_t(l) + 1, 0);
        ++size[size_t(l)];
    }
    size_t total = 0, largest = 0;
    for (const size_t n : size) total += n, largest = std::max(largest, n);
    return total - largest;
}

bool IsFree(const bim::OccupancyGrid& g, const Eigen::Vector2d& p) {
    int x, y;
    return g.ToCell(p, &x, &y) && g.cells[size_t(y) * g.width + x] == bim::Cell::kFree;
}

// A grid that reaches every point of `reach` (with 3 m to spare), whose free space is what `seed`
// reaches: outdoors, and indoors only through a door to the outside.
bim::OccupancyGrid OutdoorGrid(const bim::BimModel& model, int storey, bim::GridConfig config,
                               const std::vector<Eigen::Vector2d>& reach,
                               const Eigen::Vector2d& seed) {
    const Eigen::AlignedBox3d b = model.Bounds();
    const Eigen::Vector2d lo = b.min().head<2>(), hi = b.max().head<2>();
    double margin = 0.0;
    for (const Eigen::Vector2d& p : reach) {
        margin = std::max({margin, lo.x() - p.x(), p.x() - hi.x(), lo.y() - p.y(), p.y() - hi.y()});
    }
    config.margin_m = margin + 3.0;
    config.seed = seed;
    return bim::BuildOccupancyGrid(model, storey, config);
}

// What the scenario adds or moves is in the way too: a walk through the added cabinet put the
// sensor inside it for 0.7 s (every point within the odometry's minimum range). Returns a note for
// each object that cuts free floor off the rest.
std::vector<std::string> PutObstacles(bim::OccupancyGrid& grid,
                                      const std::vector<Obstacle>& obstacles,
                                      double object_height_m) {
    std::vector<std::string> notes;
    size_t cut_off = 0;
    for (const Obstacle& o : obstacles) {
        if (bim::AddObstacle(grid, o.mesh, object_height_m) == 0) continue;
        const size_t now = CutOffCells(grid);
        if (now > cut_off + size_t(kCutOffNoteM2 / (grid.resolution * grid.resolution))) {
            std::ostringstream os;
            os << std::fixed << std::setprecision(1) << o.edit << " cuts "
               << double(now - cut_off) * grid.resolution * grid.resolution
               << " m2 of free floor off the rest: the walk does not go there";
            notes.push_back(os.str());
        }
        cut_off = now;
    }
    return notes;
}

// A walk that starts inside covers the enclosed region it starts in: the storey's largest, or
// another of kMinWalkedRegionM2 or more (Duplex_A's second dwelling), whose grid then replaces
// `grid`. Returns the region (GridConfig::region).
int RegionOfStart(const bim::BimModel& model, int storey, const bim::GridConfig& gc,
                  const Eigen::Vector2d& start, bim::OccupancyGrid& grid) {
    if (IsFree(grid, start)) return gc.region;
    const std::vector<double> areas = grid.region_areas_m2;
    for (int r = 0; r < int(areas.size()) && r < bim::kMaxWalkedRegions; ++r) {
        if (r == gc.region || areas[size_t(r)] < bim::kMinWalkedRegionM2) continue;
        bim::GridConfig other = gc;
        other.region = r;
        bim::OccupancyGrid g = bim::BuildOccupancyGrid(model, storey, other);
        if (IsFree(g, start)) {
            grid = std::move(g);
            return r;
        }
    }
    return gc.region;  // outside, or in a wall: said where the walk is planned
}

}  // namespace

simulation::GaitConfig GaitFor(Platform p) {
    switch (p) {
        case Platform::kGo1:
            return simulation::GaitConfig::Go1Trot();
        case Platform::kHandheld:
            return simulation::GaitConfig::Handheld();
        case Platform::kVehicle:
            return simulation::GaitConfig::Vehicle();
    }
    return simulation::GaitConfig::Go1Trot();
}

double HeadroomFor(const Scenario& s) {
    if (s.platform == Platform::kVehicle) return 0;
    const simulation::GaitConfig g = GaitFor(s.platform);
    return g.base_height_m + std::max(0.0, s.sensor.mount_xyz.z()) + g.bounce_m + 0.15;
}

bim::GridConfig GridConfigFor(const bim::BimModel& plan, const Scenario& s) {
    bim::GridConfig gc;
    gc.headroom_m = HeadroomFor(s);
    if (!s.edits.removed.walk_through) return gc;
    // The grid spans the structure's footprint and the margin: widen the margin so that it
    // reaches every element of the planning model (an annex added outside) with the usual margin
    // to spare.
    Eigen::AlignedBox2d structure, all;
    for (const bim::BimElement& e : plan.elements) {
        for (uint32_t t = e.first_triangle; t < e.first_triangle + e.triangle_count; ++t) {
            for (const uint32_t k : plan.mesh.triangles[t]) {
                const Eigen::Vector2d p = plan.mesh.vertices[k].head<2>().cast<double>();
                all.extend(p);
                if (e.role == bim::ElementRole::kStructure) structure.extend(p);
            }
        }
    }
    if (structure.isEmpty()) return gc;
    gc.margin_m += std::max(
        {0.0, (structure.min() - all.min()).maxCoeff(), (all.max() - structure.max()).maxCoeff()});
    return gc;
}

std::vector<Eigen::Vector2d> WayIn(const bim::BimModel& model, int storey,
                                   const bim::GridConfig& grid, const bim::PathConfig& pc,
                                   const Eigen::Vector2d& start, const Eigen::Vector2d& to) {
    try {
        const bim::OccupancyGrid g = OutdoorGrid(model, storey, grid, {start}, start);
        return bim::PlanRoute(g, pc, start, to);
    } catch (const common::Error& e) {
        std::ostringstream os;
        os << "path.start (" << start.x() << ", " << start.y()
           << ") is outside the building and no way leads in (" << e.what()
           << "). The storey needs a door to the outside; the sample building has them "
              "with `bimslam bim sample --exterior-doors`";
        throw common::Error(common::StatusCode::kInvalidArgument, os.str());
    }
}

bool StartsOutside(const bim::OccupancyGrid& inside, const Eigen::Vector2d& start) {
    return !IsFree(inside, start);
}

bim::PathConfig PathConfigFor(const Scenario& s) {
    bim::PathConfig c;
    // Half the platform's width plus room: a Go1 is 0.3 m wide, a person a little wider, a car
    // 1.8 m.
    switch (s.platform) {
        case Platform::kGo1:
            c.clearance_m = 0.3;
            break;
        case Platform::kHandheld:
            c.clearance_m = 0.35;
            break;
        case Platform::kVehicle:
            c.clearance_m = 1.2;
            c.room_split_m = c.clearance_m;  // (rooms matter to a coverage walk only)
            break;
    }
    c.speed_mps = s.speed.speed_mps;
    c.max_yaw_rate_radps = s.speed.max_yaw_rate_deg_s * M_PI / 180.0;
    return c;
}

Walk PlanWalk(const bim::BimModel& model_in, int storey, const Scenario& s) {
    // With edits.removed.walk_through the removed elements are not in the way, and the added
    // objects are on the grid before its free space is found (PlanningModel).
    const std::optional<bim::BimModel> opened =
        s.edits.removed.walk_through ? std::optional(PlanningModel(model_in, s.edits))
                                     : std::nullopt;
    const bim::BimModel& model = opened ? *opened : model_in;
    Walk w;
    bim::GridConfig gc = GridConfigFor(model, s);
    w.grid = bim::BuildOccupancyGrid(model, storey, gc);
    if (s.path.start && s.platform != Platform::kVehicle) {
        gc.region = RegionOfStart(model, storey, gc, s.path.start->xy, w.grid);
    }
    const std::vector<Obstacle> obstacles = WalkObstacles(model_in, s.edits);
    if (!opened) {
        w.notes = PutObstacles(w.grid, obstacles, gc.object_height_m);
    } else {
        // They are on it already; what they cut off is told on the grid without them, when it
        // has enclosed floor (not where a demolished facade left the walls open).
        try {
            bim::OccupancyGrid bare = bim::BuildOccupancyGrid(
                PlanningModel(model_in, s.edits, /*with_objects=*/false), storey, gc);
            w.notes = PutObstacles(bare, obstacles, gc.object_height_m);
        } catch (const common::Error&) {
        }
    }
    w.floor_z = w.grid.floor_z;
    const bim::PathConfig pc = PathConfigFor(s);
    const bool vehicle = s.platform == Platform::kVehicle;

    // A vehicle's waypoints and start lie outdoors: its routes are planned on a grid that reaches
    // them all. A walk's lie inside: the storey's grid.
    std::vector<Eigen::Vector2d> reach = s.path.waypoints;
    if (s.path.start) reach.push_back(s.path.start->xy);
    const bim::OccupancyGrid outdoor =
        vehicle ? OutdoorGrid(model, storey, gc, reach, reach.back()) : bim::OccupancyGrid{};
    const bim::OccupancyGrid& route_grid = vehicle ? outdoor : w.grid;

    // The walk proper.
    std::vector<Eigen::Vector2d> walk;
    if (s.path.mode == PathMode::kCoverage) {
        const bim::CoveragePath coverage = bim::PlanCoveragePath(w.grid, pc);
        walk = coverage.points;
        walk.push_back(coverage.points.front());  // closed: back where it began
        w.waypoints = coverage.viewpoints.size();
        w.closed = true;
        if (coverage.unreachable_viewpoints > 0) {
            w.notes.push_back(std::to_string(coverage.unreachable_viewpoints) +
                              " viewpoint(s) of the coverage walk cannot be reached with the "
                              "platform's clearance and are left out: what they would see may "
                              "go unseen");
        }
    } else {
        walk.push_back(s.path.waypoints.front());
        for (size_t k = 1; k < s.path.waypoints.size(); ++k) {
            Append(walk,
                   bim::PlanRoute(route_grid, pc, s.path.waypoints[k - 1], s.path.waypoints[k]));
        }
        w.waypoints = s.path.waypoints.size();
        w.closed = s.path.waypoints.size() > 2 &&
                   (s.path.waypoints.front() - s.path.waypoints.back()).norm() < 1e-6;
    }

    // From the start to the walk's first point.
    if (s.path.start) {
        const Eigen::Vector2d start = s.path.start->xy;
        w.starts_outside = StartsOutside(w.grid, start);
        std::vector<Eigen::Vector2d> leg;
        if (!w.starts_outside || vehicle) {
            leg = bim::PlanRoute(route_grid, pc, start, walk.front());
        } else {
            leg = WayIn(model, storey, gc, pc, start, walk.front());
        }
        std::vector<Eigen::Vector2d> joined;
        Append(joined, leg);
        w.lap_begin = joined.size() - 1;  // the leg ends where the lap begins
        Append(joined, walk);
        walk = std::move(joined);
        w.start_yaw = s.path.start->yaw_deg * M_PI / 180.0;
    } else if (walk.size() > 1) {
        const Eigen::Vector2d d = walk[1] - walk[0];
        w.start_yaw = std::atan2(d.y(), d.x());
    }
    if (vehicle) {
        // A car cannot turn on the spot: the corners become arcs. The lap's first point moves
        // with them; the rounded lap begins at the arc nearest to it.
        const Eigen::Vector2d lap_start = walk[w.lap_begin];
        walk = RoundCorners(walk, kVehicleTurnRadiusM);
        if (w.lap_begin > 0) {
            size_t best = 0;
            for (size_t i = 1; i < walk.size(); ++i) {
                if ((walk[i] - lap_start).norm() < (walk[best] - lap_start).norm()) best = i;
            }
            w.lap_begin = best;
        }
        for (const Eigen::Vector2d& p : walk) {
            if (!IsFree(route_grid, p)) {
                std::ostringstream os;
                os << "path.waypoints: the vehicle's rounded corner at (" << p.x() << ", " << p.y()
                   << ") leaves the free space; give its turn (radius " << kVehicleTurnRadiusM
                   << " m) more room";
                throw common::Error(common::StatusCode::kInvalidArgument, os.str());
            }
        }
    }
    w.points = std::move(walk);
    return w;
}

std::vector<Eigen::Vector2d> RepeatWalk(const Walk& walk, size_t laps) {
    std::vector<Eigen::Vector2d> out = walk.points;
    std::vector<Eigen::Vector2d> lap(walk.points.begin() + long(walk.lap_begin), walk.points.end());
    for (size_t k = 1; k < laps; ++k) {
        if (!walk.closed) std::reverse(lap.begin(), lap.end());
        Append(out, lap);
    }
    return out;
}

std::vector<Eigen::Vector2d> RoundCorners(const std::vector<Eigen::Vector2d>& points,
                                          double radius_m) {
    if (points.size() < 3) return points;
    constexpr double kStepM = 0.5;
    std::vector<Eigen::Vector2d> out{points.front()};
    for (size_t i = 1; i + 1 < points.size(); ++i) {
        const Eigen::Vector2d a = points[i - 1], b = points[i], c = points[i + 1];
        const double la = (b - a).norm(), lc = (c - b).norm();
        if (la < 1e-9 || lc < 1e-9) continue;
        const Eigen::Vector2d u = (b - a) / la, v = (c - b) / lc;
        // The turn angle theta; the arc of radius r meets the legs d = r tan(theta/2) from the
        // corner.
        const double cross = u.x() * v.y() - u.y() * v.x();
        const double theta = std::atan2(std::abs(cross), u.dot(v));
        if (theta < 1e-3) {
            out.push_back(b);
            continue;
        }
        const double d = std::min(radius_m * std::tan(theta / 2), 0.5 * std::min(la, lc));
        const double r = d / std::tan(theta / 2);
        const Eigen::Vector2d p0 = b - d * u;
        const Eigen::Vector2d left(-u.y(), u.x());
        const double side = cross > 0 ? 1.0 : -1.0;  // turning left: the centre is on the left
        const Eigen::Vector2d centre = p0 + side * r * left;
        const int steps = std::max(1, int(std::ceil(r * theta / kStepM)));
        for (int k = 0; k <= steps; ++k) {
            const double phi = side * theta * k / steps;
            const Eigen::Vector2d offset = p0 - centre;
            out.push_back(centre +
                          Eigen::Vector2d(std::cos(phi) * offset.x() - std::sin(phi) * offset.y(),
                                          std::sin(phi) * offset.x() + std::cos(phi) * offset.y()));
        }
    }
    out.push_back(points.back());
    return out;
}

}  // namespace bimslam::simulate
