// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The walk of a whole building (`storey: all`, `bimslam simulate --storey all`): every floor the
// stairs reach from the start storey, joined by walking the flights (bim/stairs.hpp).
//
// Coverage: the start storey's coverage walk, and from it, depth first, each floor a walkable
// flight leads to: the way to the flight's foot (or head), the flight, that floor's coverage walk
// (entered where it passes nearest the flight), and back by the same flight. The walk ends where it
// began. Waypoints (path.waypoint_storeys names the storey of each): consecutive waypoints are
// joined by A* over the 3D graph, whose nodes are the flights' ends and whose edges are the routes
// on each floor's grid (bim::PlanRoute, their length the cost) and the flights (their length in
// plan); the heuristic is the straight distance in 3D.
//
// On a flight the walk follows its walking line (StairFlight::Line) at a slower pace: a person at
// 1.6 steps a second (1.6 x the run per second), a Go1 at 0.25 m/s, its body pitched with the
// flight (simulation::PathPoint).
#pragma once

#include <filesystem>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "algorithms/io/trajectory.hpp"
#include "algorithms/simulation/body_trajectory.hpp"
#include "host_tools/bim/bim_model.hpp"
#include "host_tools/bim/building_graph.hpp"
#include "host_tools/simulate/scenario.hpp"

namespace bimslam::simulate {

inline constexpr double kGo1StairSpeedMps = 0.25;
inline constexpr double kPersonStairStepsPerS = 1.6;

struct BuildingWalk {
    std::vector<simulation::PathPoint> points;  // start first
    double start_yaw = 0;
    bim::BuildingGraph graph;
    std::vector<int> storeys;        // in the order the walk first enters them
    bool starts_outside = false;     // path.start outside the start storey: the walk goes in
    size_t flights_walked = 0;       // each way counted
    size_t waypoints = 0;            // viewpoints of the coverage walks, or waypoints
    std::vector<std::string> notes;  // what cannot be walked (graph.problems) and coverage notes
};

// Throws common::Error naming what cannot be walked (a waypoint's storey not reached, a vehicle).
BuildingWalk PlanBuildingWalk(const bim::BimModel& model, const Scenario& scenario);

// The walk walked `laps` times (it is closed for coverage; waypoints turn back).
std::vector<simulation::PathPoint> RepeatBuildingWalk(const BuildingWalk& walk, size_t laps,
                                                      bool closed);

// The storey whose floor lies under height z: the highest with elevation <= z + 0.1 m (the
// lowest storey when none).
int StoreyUnder(const bim::BimModel& model, double z);

// ground_truth_storeys.csv: per frame of `truth` (stamped in the sensor clock), the storey under
// the platform (StoreyUnder the floor's height there), that height, and whether it is on a flight.
void WriteStoreyTruth(const simulation::BodyTrajectory& trajectory, const bim::BimModel& model,
                      const std::vector<io::StampedPose>& truth, const std::filesystem::path& dir);

// Names in changes.json (world.hpp's WriteChanges) each added object's storey (the floor under
// its lowest point) and each removed or moved element's (its own).
void AddStoreys(const bim::BimModel& model, nlohmann::json& changes);

}  // namespace bimslam::simulate
