// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/bim/building_graph.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "algorithms/common/status.hpp"

namespace bimslam::bim {
namespace {

std::string Point(const Eigen::Vector2d& p) {
    std::ostringstream os;
    os.setf(std::ios::fixed);
    os.precision(2);
    os << "(" << p.x() << ", " << p.y() << ")";
    return os.str();
}

constexpr const char* kNotJoined =
    "with the walk's clearance (a grid's free space is its storey's largest enclosed region: the "
    "flight stands in another part of the building, not joined to it inside, or too tight a place)";

// Where the walk stands off a flight's end: the cell free with the clearance nearest to p (which
// lies `standing_m` off the riser along dir), within `reach`, and not on the flight's side of the
// riser (dir points away from the flight). False when there is none.
bool StandingCell(const OccupancyGrid& g, const Eigen::Vector2d& riser, const Eigen::Vector2d& p,
                  const Eigen::Vector2d& dir, double reach, double clearance, Eigen::Vector2d* at,
                  Eigen::Vector2i* cell) {
    int cx, cy;
    if (!g.ToCell(p, &cx, &cy) && !g.ToCell(riser, &cx, &cy)) return false;
    const int r = int(std::ceil(reach / g.resolution));
    double best = reach + 1e-9;
    bool found = false;
    for (int y = std::max(0, cy - r); y <= std::min(g.height - 1, cy + r); ++y) {
        for (int x = std::max(0, cx - r); x <= std::min(g.width - 1, cx + r); ++x) {
            const size_t i = size_t(y) * size_t(g.width) + size_t(x);
            if (g.cells[i] != Cell::kFree || g.clearance[i] < clearance) continue;
            const Eigen::Vector2d q = g.Center(x, y);
            if ((q - riser).dot(dir) < 0.5 * clearance) continue;  // on the flight's side
            const double d = (q - p).norm();
            if (d < best) best = d, *at = q, *cell = {x, y}, found = true;
        }
    }
    return found;
}

// A lid over the stairwell in the upper storey's grid: the flight's levels below the upper floor
// become occupied there, so no walk on that storey crosses the hole.
void CloseStairwell(OccupancyGrid& upper, const StairFlight& f) {
    common::TriangleMesh lid;
    const float z = float(upper.floor_z + 0.5);
    for (const StairLevel& l : f.levels) {
        if (l.centre.z() > f.upper_z - 0.05) continue;
        const Eigen::Vector2d c = l.centre.head<2>();
        const double r = 0.5 * std::min(l.depth_m, l.width_m);
        const auto base = uint32_t(lid.vertices.size());
        for (int k = 0; k < 4; ++k) {
            const Eigen::Vector2d q =
                c + r * Eigen::Vector2d(k == 0 || k == 3 ? -1 : 1, k < 2 ? -1 : 1);
            lid.vertices.emplace_back(float(q.x()), float(q.y()), z);
        }
        lid.triangles.push_back({base, base + 1, base + 2});
        lid.triangles.push_back({base, base + 2, base + 3});
    }
    AddObstacle(upper, lid);
}

// Storeys one stands in: 2 m or more to the next (the last counts), and something people use on
// it: a door, a space, a stair, a railing or furniture (FZK-Haus's attic has only its stairwell's
// railing; the Roof levels of Duplex_A and Office_A have walls, slabs and windows, and are no
// floors).
std::vector<int> FloorStoreys(const BimModel& m) {
    std::vector<int> out;
    for (size_t s = 0; s < m.storeys.size(); ++s) {
        const bool high =
            s + 1 == m.storeys.size() ||
            m.storeys[s + 1].elevation_m - m.storeys[s].elevation_m >= kMinWalkStoreyHeight;
        const bool used = std::any_of(m.elements.begin(), m.elements.end(), [&](const auto& e) {
            return e.storey == int(s) &&
                   (e.ifc_class.starts_with("IfcDoor") || e.ifc_class == "IfcSpace" ||
                    IsStairOrRampClass(e.ifc_class) || e.ifc_class == "IfcRailing" ||
                    e.ifc_class.starts_with("IfcFurni"));
        });
        if (high && used) out.push_back(int(s));
    }
    return out;
}

void Reach(BuildingGraph& g) {
    std::vector<int> stack{g.start};
    std::vector<bool> seen(g.grids.size(), false);
    seen[size_t(g.start)] = true;
    while (!stack.empty()) {
        const int s = stack.back();
        stack.pop_back();
        for (const int fi : g.FlightsAt(s)) {
            const StairFlight& f = g.flights[size_t(fi)];
            const int other = f.lower == s ? f.upper : f.lower;
            if (!seen[size_t(other)]) seen[size_t(other)] = true, stack.push_back(other);
        }
    }
    for (const int s : g.floors) {
        if (seen[size_t(s)]) g.reached.push_back(s);
    }
}

// Joins each flight to its storeys' grids, or says why it cannot.
void JoinFlight(const BimModel& m, BuildingGraph& g, double clearance, const StairLimits& lim,
                StairFlight& f) {
    if (!f.Walkable()) return;
    const Eigen::Vector2d u0 = f.UpAtFoot(), u1 = f.UpAtHead();
    const Eigen::Vector2d foot = f.entry, head = f.exit;  // the first and last risers
    if (!StandingCell(g.grids[size_t(f.lower)], foot, foot - u0 * lim.standing_m, -u0, 1.5,
                      clearance, &f.entry, &f.entry_cell)) {
        f.problem = "its foot at " + Point(foot) +
                    " does not stand in the free space the walk covers on storey '" +
                    m.storeys[size_t(f.lower)].name + "' " + kNotJoined;
        return;
    }
    if (!StandingCell(g.grids[size_t(f.upper)], head, head + u1 * lim.standing_m, u1, 1.5,
                      clearance, &f.exit, &f.exit_cell)) {
        f.problem = "its head at " + Point(head) +
                    " does not stand in the free space the walk covers on storey '" +
                    m.storeys[size_t(f.upper)].name + "' " + kNotJoined;
    }
}

std::string FlightStoreys(const BimModel& m, const StairFlight& f) {
    if (f.lower < 0 || f.upper < 0) return "";
    return " from '" + m.storeys[size_t(f.lower)].name + "' to '" +
           m.storeys[size_t(f.upper)].name + "'";
}

// The storeys' grids; a floor whose grid cannot be built is no floor (said in problems).
void BuildGrids(const BimModel& m, const GridConfig& config, BuildingGraph& g) {
    g.grids.assign(m.storeys.size(), OccupancyGrid{});
    std::vector<int> floors;
    for (const int s : FloorStoreys(m)) {
        try {
            g.grids[size_t(s)] = BuildOccupancyGrid(m, s, config);
            floors.push_back(s);
        } catch (const common::Error& e) {
            g.problems.push_back("storey '" + m.storeys[size_t(s)].name +
                                 "' has no floor to walk: " + e.what());
        }
    }
    g.floors = std::move(floors);
}

// Stairs in the file without geometry to walk: failed conversions and stair classes counted in
// the file of which no element has geometry.
void StairsWithoutGeometry(const BimModel& m, BuildingGraph& g) {
    for (const FailedElement& f : m.failed) {
        if (IsStairOrRampClass(f.ifc_class)) {
            g.problems.push_back(f.ifc_class + " (" + f.global_id +
                                 ") has no flight geometry: " + f.reason);
        }
    }
    size_t counted = 0;
    for (const auto& [cls, n] : m.class_counts) counted += IsStairOrRampClass(cls) ? n : 0;
    const bool any = std::any_of(m.elements.begin(), m.elements.end(), [](const BimElement& e) {
        return IsStairOrRampClass(e.ifc_class);
    });
    if (counted > 0 && !any) {
        g.problems.push_back("the model's " + std::to_string(counted) +
                             " stair and ramp elements have no geometry: no flight to walk");
    }
}

// Each floor not reached, with the reasons: the flights to it that cannot be walked.
void SayUnreached(const BimModel& m, BuildingGraph& g) {
    for (const int s : g.floors) {
        if (g.Reaches(s)) continue;
        std::string why;
        for (const StairFlight& f : g.flights) {
            if ((f.lower == s || f.upper == s) && !f.Walkable()) {
                why += (why.empty() ? "" : "; ") + f.name + ": " + f.problem;
            }
        }
        if (why.empty()) {
            why = g.flights.empty() ? "the model has no stair or ramp with geometry"
                                    : "no walkable stair joins it to the storeys reached";
        }
        g.problems.push_back("storey '" + m.storeys[size_t(s)].name + "' is not reached from '" +
                             m.storeys[size_t(g.start)].name + "': " + why);
    }
}

}  // namespace

bool BuildingGraph::Reaches(int storey) const {
    return std::find(reached.begin(), reached.end(), storey) != reached.end();
}

std::vector<int> BuildingGraph::FlightsAt(int storey) const {
    std::vector<int> out;
    for (size_t i = 0; i < flights.size(); ++i) {
        const StairFlight& f = flights[i];
        if (f.Walkable() && (f.lower == storey || f.upper == storey)) out.push_back(int(i));
    }
    return out;
}

BuildingGraph BuildBuildingGraph(const BimModel& m, const GridConfig& config,
                                 const StairLimits& limits, double clearance_m, int start_storey) {
    limits.Validate();
    BuildingGraph g;
    BuildGrids(m, config, g);
    if (g.floors.empty()) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            m.file + ": no storey has free floor to walk");
    }
    g.start = std::find(g.floors.begin(), g.floors.end(), start_storey) != g.floors.end()
                  ? start_storey
                  : g.floors.front();
    StairsWithoutGeometry(m, g);
    g.flights = FindStairFlights(m);
    for (StairFlight& f : g.flights) {
        CheckStairLimits(limits, f);
        for (const int s : {f.lower, f.upper}) {
            if (f.Walkable() && g.grids[size_t(s)].width == 0) {
                f.problem = "storey '" + m.storeys[size_t(s)].name + "' has no floor to walk";
            }
        }
        if (f.Walkable()) CloseStairwell(g.grids[size_t(f.upper)], f);
    }
    for (StairFlight& f : g.flights) {
        JoinFlight(m, g, clearance_m, limits, f);
        if (!f.Walkable()) {
            g.problems.push_back(f.name + FlightStoreys(m, f) + " cannot be walked: " + f.problem);
        }
    }
    Reach(g);
    SayUnreached(m, g);
    return g;
}

}  // namespace bimslam::bim
