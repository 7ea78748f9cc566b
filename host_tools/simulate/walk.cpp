#include "host_tools/simulate/walk.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "algorithms/common/status.hpp"
#include "host_tools/bim/coverage_path.hpp"

namespace bimslam::simulate {
namespace {

// A person needs a little more room than a Go1 (0.3 m wide).
bim::PathConfig PathConfigFor(const Scenario& s) {
    bim::PathConfig c;
    c.clearance_m = s.platform == Platform::kGo1 ? 0.3 : 0.35;
    c.speed_mps = s.speed.speed_mps;
    c.max_yaw_rate_radps = s.speed.max_yaw_rate_deg_s * M_PI / 180.0;
    return c;
}

void Append(std::vector<Eigen::Vector2d>& walk, const std::vector<Eigen::Vector2d>& leg) {
    for (const Eigen::Vector2d& p : leg) {
        if (walk.empty() || (walk.back() - p).norm() > 1e-9) walk.push_back(p);
    }
}

}  // namespace

Walk PlanWalk(const bim::BimModel& model, int storey, const Scenario& s) {
    Walk w;
    bim::GridConfig gc;
    w.grid = bim::BuildOccupancyGrid(model, storey, gc);
    w.floor_z = w.grid.floor_z;
    const bim::PathConfig pc = PathConfigFor(s);

    // The walk proper, inside.
    std::vector<Eigen::Vector2d> walk;
    if (s.path.mode == PathMode::kCoverage) {
        const bim::CoveragePath coverage = bim::PlanCoveragePath(w.grid, pc);
        walk = coverage.points;
        walk.push_back(coverage.points.front());  // closed: back where it began
        w.waypoints = coverage.viewpoints.size();
    } else {
        walk.push_back(s.path.waypoints.front());
        for (size_t k = 1; k < s.path.waypoints.size(); ++k) {
            Append(walk, bim::PlanRoute(w.grid, pc, s.path.waypoints[k - 1], s.path.waypoints[k]));
        }
        w.waypoints = s.path.waypoints.size();
    }

    // From the start to the walk's first point.
    if (s.path.start) {
        const Eigen::Vector2d start = s.path.start->xy;
        int x, y;
        w.starts_outside = !w.grid.ToCell(start, &x, &y) ||
                           w.grid.cells[size_t(y) * w.grid.width + x] != bim::Cell::kFree;
        std::vector<Eigen::Vector2d> leg;
        if (!w.starts_outside) {
            leg = bim::PlanRoute(w.grid, pc, start, walk.front());
        } else {
            // A grid that reaches the start, whose free space is what the start reaches.
            bim::GridConfig outdoor = gc;
            const Eigen::AlignedBox3d b = model.Bounds();
            const Eigen::Vector2d lo = b.min().head<2>(), hi = b.max().head<2>();
            const double reach = std::max({lo.x() - start.x(), start.x() - hi.x(),
                                           lo.y() - start.y(), start.y() - hi.y(), 0.0});
            outdoor.margin_m = reach + 3.0;
            outdoor.seed = start;
            const bim::OccupancyGrid g = bim::BuildOccupancyGrid(model, storey, outdoor);
            try {
                leg = bim::PlanRoute(g, pc, start, walk.front());
            } catch (const common::Error& e) {
                std::ostringstream os;
                os << "path.start (" << start.x() << ", " << start.y()
                   << ") is outside the building and no way leads in (" << e.what()
                   << "). The storey needs a door to the outside; the sample building has them "
                      "with `bimslam bim sample --exterior-doors`";
                throw common::Error(common::StatusCode::kInvalidArgument, os.str());
            }
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
    w.points = std::move(walk);
    return w;
}

std::vector<Eigen::Vector2d> RepeatWalk(const Walk& walk, PathMode mode, size_t laps) {
    std::vector<Eigen::Vector2d> out = walk.points;
    std::vector<Eigen::Vector2d> lap(walk.points.begin() + long(walk.lap_begin), walk.points.end());
    for (size_t k = 1; k < laps; ++k) {
        if (mode == PathMode::kWaypoints) std::reverse(lap.begin(), lap.end());
        Append(out, lap);
    }
    return out;
}

}  // namespace bimslam::simulate
