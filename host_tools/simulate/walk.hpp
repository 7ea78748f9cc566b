// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The planar walk of a capture: the storey's coverage walk (bim/coverage_path.hpp) or the
// scenario's waypoints, joined by routes through the occupancy grid that keep the platform's
// clearance; from a start pose that may lie outside the building, in which case the first route
// is planned on a grid that reaches from the start (free space outdoors too) and enters through a
// door to the outside. A vehicle's whole walk is planned on such an outdoor grid, and its corners
// are rounded to its turning radius.
#pragma once

#include <string>
#include <vector>

#include "algorithms/simulation/body_trajectory.hpp"
#include "host_tools/bim/bim_model.hpp"
#include "host_tools/bim/coverage_path.hpp"
#include "host_tools/bim/occupancy_grid.hpp"
#include "host_tools/simulate/scenario.hpp"

namespace bimslam::simulate {

struct Walk {
    std::vector<Eigen::Vector2d> points;  // the planar path, start first
    size_t lap_begin = 0;  // points[lap_begin...] is the walk proper, after the way from the start
    double start_yaw = 0;  // radians
    double floor_z = 0;    // the storey's floor
    bool starts_outside = false;
    // The lap ends where it begins (a coverage walk, or waypoints whose last is their first): a
    // longer capture starts it over instead of turning back.
    bool closed = false;
    bim::OccupancyGrid grid;  // the storey's grid (inside), for clutter placement
    size_t waypoints = 0;     // viewpoints of the coverage walk, or waypoints
    // For the user: each added or moved object that cut free floor off the rest (a crate in a
    // doorway), with the area; the walk does not go there.
    std::vector<std::string> notes;
};

// The grid planner's settings for the scenario's platform: its clearance (0.3 m for a Go1, 0.35 m
// for a person, 1.2 m for a vehicle), speed and yaw rate.
bim::PathConfig PathConfigFor(const Scenario& scenario);

// The platform's body motion (its gait: the base's height, bob and sway).
simulation::GaitConfig GaitFor(Platform p);

// How high the platform's top stands above the floor: its sensor (the gait's base, the mount's
// height, the bob) and 0.15 m of rig and hand above it; 0 for a vehicle (it stays outdoors).
double HeadroomFor(const Scenario& scenario);

// The grid of the walk on `plan` (PlanningModel): the platform's headroom (HeadroomFor), and with
// edits.removed.walk_through a margin that reaches every element of the plan (an annex added
// outside the model) with the default margin to spare.
bim::GridConfig GridConfigFor(const bim::BimModel& plan, const Scenario& scenario);

// Throws common::Error naming what cannot be walked (a waypoint in a wall, a start outside with
// no door to the outside, a storey without free space).
Walk PlanWalk(const bim::BimModel& model, int storey, const Scenario& scenario);

// The way from `start`, outside the storey's walls, in through a door to `to` inside: planned on a
// grid of the storey that reaches the start and whose free space is what the start reaches.
// Throws common::Error saying that the storey needs a door to the outside when none leads in.
std::vector<Eigen::Vector2d> WayIn(const bim::BimModel& model, int storey,
                                   const bim::GridConfig& grid, const bim::PathConfig& pc,
                                   const Eigen::Vector2d& start, const Eigen::Vector2d& to);
// Whether `start` lies outside the free space of the storey's (inside) grid.
bool StartsOutside(const bim::OccupancyGrid& inside, const Eigen::Vector2d& start);

// The walk with its lap walked `laps` times: a closed walk starts over; an open one turns back and
// retraces its way.
std::vector<Eigen::Vector2d> RepeatWalk(const Walk& walk, size_t laps);

// The polyline with each corner replaced by a circular arc of `radius_m` (points every 0.5 m),
// tangent to both legs; the radius shrinks where a leg is too short for it (the arc takes at most
// half of each leg). The ends stay where they are.
std::vector<Eigen::Vector2d> RoundCorners(const std::vector<Eigen::Vector2d>& points,
                                          double radius_m);

}  // namespace bimslam::simulate
