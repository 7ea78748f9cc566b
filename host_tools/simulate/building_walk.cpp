// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/simulate/building_walk.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <tuple>

#include "algorithms/common/status.hpp"
#include "algorithms/io/file_util.hpp"
#include "host_tools/bim/coverage_path.hpp"
#include "host_tools/simulate/simulate.hpp"
#include "host_tools/simulate/walk.hpp"
#include "host_tools/simulate/world.hpp"

namespace bimslam::simulate {
namespace {

using simulation::PathPoint;

// Appends the walk on the floors and flights, keeping track of where it is.
class Walker {
public:
    Walker(const bim::BimModel& model, const Scenario& s, BuildingWalk& w)
        : model_(model), s_(s), w_(w), pc_(PathConfigFor(s)) {}

    Eigen::Vector2d Here() const { return w_.points.back().p.head<2>(); }

    // Points on the floor of `storey`.
    void Floor(int storey, const std::vector<Eigen::Vector2d>& pts) {
        if (std::find(w_.storeys.begin(), w_.storeys.end(), storey) == w_.storeys.end()) {
            w_.storeys.push_back(storey);
        }
        const double z = w_.graph.grids[size_t(storey)].floor_z;
        for (const Eigen::Vector2d& p : pts) {
            const Eigen::Vector3d q(p.x(), p.y(), z);
            if (!w_.points.empty() && (w_.points.back().p - q).norm() < 1e-9) continue;
            w_.points.push_back({q, 0.0, 0.0, s_.speed.speed_mps});
        }
    }

    // The way from here to `to` on the storey's grid, keeping the clearance.
    void Route(int storey, const Eigen::Vector2d& to) {
        if ((Here() - to).norm() < 1e-6) return;
        Floor(storey, bim::PlanRoute(w_.graph.grids[size_t(storey)], pc_, Here(), to));
    }

    // The flight's walking line, up or down, at the stair pace with the body along its slope.
    void Flight(const bim::StairFlight& f, bool up) {
        std::vector<Eigen::Vector3d> line = f.Line();
        if (!up) std::reverse(line.begin(), line.end());
        const double climb = std::atan2(f.rise_m, std::max(f.run_m, 1e-3)) * (up ? 1.0 : -1.0);
        const double pace =
            s_.platform == Platform::kGo1 ? kGo1StairSpeedMps : kPersonStairStepsPerS * f.run_m;
        for (size_t k = 0; k < line.size(); ++k) {
            const bool end = k == 0 || k + 1 == line.size();  // standing on a floor
            PathPoint p{line[k], end ? 0.0 : climb, end ? 0.0 : 1.0,
                        end ? s_.speed.speed_mps : std::min(pace, s_.speed.speed_mps)};
            if (!w_.points.empty() && (w_.points.back().p - p.p).norm() < 1e-9) {
                w_.points.back() = p;
                continue;
            }
            w_.points.push_back(p);
        }
        ++w_.flights_walked;
    }

    // The storey's coverage walk (closed), computed once.
    const std::vector<Eigen::Vector2d>& Coverage(int storey) {
        auto it = coverage_.find(storey);
        if (it != coverage_.end()) return it->second;
        const bim::CoveragePath c = bim::PlanCoveragePath(w_.graph.grids[size_t(storey)], pc_);
        std::vector<Eigen::Vector2d> tour = c.points;
        tour.push_back(c.points.front());
        w_.waypoints += c.viewpoints.size();
        if (c.unreachable_viewpoints > 0) {
            w_.notes.push_back("storey '" + model_.storeys[size_t(storey)].name +
                               "': " + std::to_string(c.unreachable_viewpoints) +
                               " viewpoint(s) cannot be reached with the platform's clearance "
                               "and are left out");
        }
        return coverage_.emplace(storey, std::move(tour)).first->second;
    }

    // The storey's coverage walk entered at its point nearest to here (or at its start when the
    // walk has not begun), then each unvisited floor a flight leads to, depth first.
    void Visit(int storey, std::vector<bool>& visited) {
        visited[size_t(storey)] = true;
        const std::vector<Eigen::Vector2d>& tour = Coverage(storey);
        size_t k = 0;
        if (!w_.points.empty()) {
            for (size_t i = 1; i < tour.size(); ++i) {
                if ((tour[i] - Here()).norm() < (tour[k] - Here()).norm()) k = i;
            }
            Route(storey, tour[k]);
        }
        std::vector<Eigen::Vector2d> lap(tour.begin() + long(k), tour.end() - 1);
        lap.insert(lap.end(), tour.begin(), tour.begin() + long(k) + 1);
        Floor(storey, lap);
        const Eigen::Vector2d home = tour[k];
        for (const int fi : w_.graph.FlightsAt(storey)) {
            const bim::StairFlight& f = w_.graph.flights[size_t(fi)];
            const bool up = f.lower == storey;
            const int other = up ? f.upper : f.lower;
            if (visited[size_t(other)]) continue;
            const size_t mark = w_.points.size(), flights = w_.flights_walked;
            const size_t storeys = w_.storeys.size();
            try {
                Route(storey, up ? f.entry : f.exit);
                Flight(f, up);
                Visit(other, visited);
                Route(other, up ? f.exit : f.entry);
                Flight(f, !up);
                Route(storey, home);
            } catch (const common::Error& e) {
                // Keep the walk on the storeys it reached; say which flight and why.
                w_.points.resize(mark);
                w_.flights_walked = flights;
                w_.storeys.resize(storeys);
                visited[size_t(other)] = false;
                w_.notes.push_back(f.name + " is not walked: " + e.what());
            }
        }
    }

    // From here on storey `from` to `to` on storey `to_storey`: A* over the 3D graph (nodes: the
    // two ends and every walkable flight's foot and head; edges: routes on a floor, flights).
    void Join(int from, int to_storey, const Eigen::Vector2d& to) {
        struct Node {
            int storey;
            Eigen::Vector2d xy;
            int flight = -1;  // the flight whose end it is
        };
        std::vector<Node> nodes{{from, Here()}, {to_storey, to}};
        for (size_t i = 0; i < w_.graph.flights.size(); ++i) {
            const bim::StairFlight& f = w_.graph.flights[i];
            if (!f.Walkable()) continue;
            nodes.push_back({f.lower, f.entry, int(i)});
            nodes.push_back({f.upper, f.exit, int(i)});
        }
        auto z = [&](const Node& n) { return w_.graph.grids[size_t(n.storey)].floor_z; };
        auto heuristic = [&](size_t i) {
            return std::hypot((nodes[i].xy - to).norm(), z(nodes[i]) - z(nodes[1]));
        };
        const size_t n = nodes.size();
        std::vector<double> g(n, kInf);
        std::vector<size_t> parent(n, SIZE_MAX);
        std::vector<bool> closed(n, false);
        g[0] = 0;
        for (;;) {
            size_t best = SIZE_MAX;
            for (size_t i = 0; i < n; ++i) {
                if (!closed[i] && std::isfinite(g[i]) &&
                    (best == SIZE_MAX || g[i] + heuristic(i) < g[best] + heuristic(best))) {
                    best = i;
                }
            }
            if (best == SIZE_MAX || best == 1) break;
            closed[best] = true;
            for (size_t j = 0; j < n; ++j) {
                if (closed[j]) continue;
                const bool same_flight =
                    nodes[best].flight >= 0 && nodes[best].flight == nodes[j].flight;
                const double cost =
                    same_flight ? w_.graph.flights[size_t(nodes[j].flight)].LengthM()
                    : nodes[best].storey == nodes[j].storey
                        ? RouteLength(nodes[best].storey, nodes[best].xy, nodes[j].xy)
                        : kInf;
                if (g[best] + cost < g[j]) g[j] = g[best] + cost, parent[j] = best;
            }
        }
        if (!std::isfinite(g[1])) throw NoWay(from, to_storey, to);
        std::vector<size_t> chain;
        for (size_t i = 1; i != SIZE_MAX; i = parent[i]) chain.push_back(i);
        std::reverse(chain.begin(), chain.end());
        for (size_t k = 1; k < chain.size(); ++k) {
            const Node& a = nodes[chain[k - 1]];
            const Node& b = nodes[chain[k]];
            if (a.flight >= 0 && a.flight == b.flight) {
                Flight(w_.graph.flights[size_t(a.flight)],
                       b.storey == w_.graph.flights[size_t(a.flight)].upper);
            } else {
                Route(b.storey, b.xy);
            }
        }
    }

private:
    static constexpr double kInf = std::numeric_limits<double>::infinity();

    // Why Join found no way to `to`: the waypoint itself where the platform cannot stand (in an
    // added object, too near a wall), no way on its own storey, or none over the stairs.
    common::Error NoWay(int from, int to_storey, const Eigen::Vector2d& to) const {
        std::ostringstream os;
        os << "no way from storey '" << model_.storeys[size_t(from)].name << "' to the waypoint ("
           << to.x() << ", " << to.y() << ") on storey '" << model_.storeys[size_t(to_storey)].name
           << "': ";
        try {
            bim::PlanRoute(w_.graph.grids[size_t(to_storey)], pc_, to, to);
            os << (from == to_storey ? "no route on the storey keeps the platform's "
                                     : "no flight of stairs and route keep the platform's ")
               << pc_.clearance_m << " m of clearance";
        } catch (const common::Error&) {
            os << "it is not free space with the platform's " << pc_.clearance_m
               << " m of clearance (in an added object, or too near a wall?)";
        }
        return common::Error(common::StatusCode::kInvalidArgument, os.str());
    }

    // The length of the way on the storey's grid (infinite where there is none), computed once.
    double RouteLength(int storey, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
        if ((a - b).norm() < 1e-6) return 0.0;
        const auto key = std::make_tuple(storey, a.x(), a.y(), b.x(), b.y());
        if (auto it = lengths_.find(key); it != lengths_.end()) return it->second;
        double len = kInf;
        try {
            const std::vector<Eigen::Vector2d> r =
                bim::PlanRoute(w_.graph.grids[size_t(storey)], pc_, a, b);
            len = 0;
            for (size_t k = 1; k < r.size(); ++k) len += (r[k] - r[k - 1]).norm();
        } catch (const common::Error&) {
        }
        return lengths_[key] = len;
    }

    std::map<std::tuple<int, double, double, double, double>, double> lengths_;
    const bim::BimModel& model_;
    const Scenario& s_;
    BuildingWalk& w_;
    bim::PathConfig pc_;
    std::map<int, std::vector<Eigen::Vector2d>> coverage_;
};

// The storeys' grids with the scenario's added objects and moved elements on them.
void AddObstacles(const bim::BimModel& model, const Scenario& s, bim::BuildingGraph& g) {
    const std::vector<Obstacle> obstacles = WalkObstacles(model, s.edits);
    for (const int storey : g.floors) {
        for (const Obstacle& o : obstacles) bim::AddObstacle(g.grids[size_t(storey)], o.mesh);
    }
}

// The waypoints in order, each on its storey (path.waypoint_storeys), joined over the stairs.
void WalkWaypoints(const bim::BimModel& model, const Scenario& s, BuildingWalk& w, Walker& walker) {
    int here = w.graph.start;
    for (size_t i = 0; i < s.path.waypoints.size(); ++i) {
        const int storey = s.path.waypoint_storeys.empty()
                               ? w.graph.start
                               : bim::FindStorey(model, s.path.waypoint_storeys[i]);
        if (!w.graph.Reaches(storey)) {
            std::string why;
            for (const std::string& p : w.graph.problems) why += "; " + p;
            throw common::Error(common::StatusCode::kInvalidArgument,
                                "path.waypoints[" + std::to_string(i) + "] lies on storey '" +
                                    model.storeys[size_t(storey)].name +
                                    "', which the stairs do not reach" + why);
        }
        if (w.points.empty()) {
            walker.Floor(storey, {s.path.waypoints[i]});
        } else {
            walker.Join(here, storey, s.path.waypoints[i]);
        }
        here = storey;
    }
    w.waypoints = s.path.waypoints.size();
}

}  // namespace

int StoreyUnder(const bim::BimModel& model, double z) {
    int best = 0;
    for (size_t i = 0; i < model.storeys.size(); ++i) {
        if (model.storeys[i].elevation_m <= z + 0.1) best = int(i);
    }
    return best;
}

BuildingWalk PlanBuildingWalk(const bim::BimModel& model_in, const Scenario& s) {
    // With edits.removed.walk_through the removed elements are not in the way, and the added
    // objects are on the grid before its free space is found (PlanningModel).
    const std::optional<bim::BimModel> opened =
        s.edits.removed.walk_through ? std::optional(PlanningModel(model_in, s.edits))
                                     : std::nullopt;
    const bim::BimModel& model = opened ? *opened : model_in;
    if (s.platform == Platform::kVehicle) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            "storey: all walks the building's storeys and stairs; a vehicle "
                            "cannot (platform: go1 or handheld)");
    }
    BuildingWalk w;
    const bool go1 = s.platform == Platform::kGo1;
    w.graph = bim::BuildBuildingGraph(model, GridConfigFor(model, s),
                                      go1 ? bim::StairLimits::Go1() : bim::StairLimits{},
                                      PathConfigFor(s).clearance_m, bim::DefaultWalkStorey(model));
    w.notes = w.graph.problems;
    AddObstacles(model_in, s, w.graph);
    Walker walker(model, s, w);
    const int start = w.graph.start;
    const bool outside =
        s.path.start && StartsOutside(w.graph.grids[size_t(start)], s.path.start->xy);
    if (s.path.start) {
        w.start_yaw = s.path.start->yaw_deg * M_PI / 180.0;
        w.starts_outside = outside;
        // From outside: the way in through a door to where the walk proper begins (the start
        // storey's coverage, or the first waypoint), on a grid that reaches the start.
        const Eigen::Vector2d in = s.path.mode == PathMode::kCoverage || s.path.waypoints.empty()
                                       ? walker.Coverage(start).front()
                                       : s.path.waypoints.front();
        // The walk's own grid rules (its headroom: not under a porch roof lower than the rig).
        walker.Floor(start, outside ? WayIn(model, start, GridConfigFor(model, s), PathConfigFor(s),
                                            s.path.start->xy, in)
                                    : std::vector<Eigen::Vector2d>{s.path.start->xy});
    }
    if (s.path.mode == PathMode::kCoverage) {
        std::vector<bool> visited(model.storeys.size(), false);
        walker.Visit(start, visited);
    } else {
        WalkWaypoints(model, s, w, walker);
    }
    if (!s.path.start && w.points.size() > 1) {
        const Eigen::Vector2d d = (w.points[1].p - w.points[0].p).head<2>();
        w.start_yaw = std::atan2(d.y(), d.x());
    }
    if (s.path.start && !outside && s.path.mode == PathMode::kCoverage) {
        walker.Route(start, s.path.start->xy);  // closed: back at the start
    }
    return w;
}

std::vector<simulation::PathPoint> RepeatBuildingWalk(const BuildingWalk& walk, size_t laps,
                                                      bool closed) {
    std::vector<simulation::PathPoint> out = walk.points;
    std::vector<simulation::PathPoint> lap = walk.points;
    for (size_t k = 1; k < laps; ++k) {
        if (!closed) std::reverse(lap.begin(), lap.end());
        for (simulation::PathPoint p : lap) {
            if (!closed) p.climb_rad = -p.climb_rad;  // walked the other way
            if ((out.back().p - p.p).norm() < 1e-9) continue;
            out.push_back(p);
        }
    }
    return out;
}

// Per frame of a building walk: the storey under the platform and whether it is on a flight
// (ground_truth_storeys.csv).
void WriteStoreyTruth(const simulation::BodyTrajectory& trajectory, const bim::BimModel& model,
                      const std::vector<io::StampedPose>& truth, const std::filesystem::path& dir) {
    std::string text = "stamp_ns,storey,floor_z_m,on_flight\n";
    for (const io::StampedPose& pose : truth) {
        const double t = double(pose.stamp_ns - kSensorBootNs) * 1e-9;
        const double z = trajectory.FloorZAt(t);
        char line[64];
        std::snprintf(line, sizeof line, ",%.3f,%d\n", z, trajectory.FlightAt(t) > 0.5 ? 1 : 0);
        text += std::to_string(pose.stamp_ns) + "," +
                model.storeys[size_t(StoreyUnder(model, z))].name + line;
    }
    io::WriteFileAtomic(dir / "ground_truth_storeys.csv", text);
}

// Each added object's storey (the floor under its lowest point) and each removed or moved
// element's (its own), for a building walk's changes.json.
void AddStoreys(const bim::BimModel& model, nlohmann::json& changes) {
    for (nlohmann::json& a : changes["added"]) {
        a["storey"] = model.storeys[size_t(StoreyUnder(model, a["box_min"][2].get<double>()))].name;
    }
    for (const char* key : {"removed", "moved"}) {
        for (nlohmann::json& e : changes[key]) {
            for (const bim::BimElement& el : model.elements) {
                if (el.global_id != e["global_id"].get<std::string>()) continue;
                e["storey"] = el.storey >= 0 ? model.storeys[size_t(el.storey)].name : "";
                break;
            }
        }
    }
}

}  // namespace bimslam::simulate
