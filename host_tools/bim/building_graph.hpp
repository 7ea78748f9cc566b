// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The walkable 3D graph of a building: the storeys a person stands in ("floors"), each with its
// occupancy grid, joined by the stair and ramp flights (stairs.hpp) that a platform can climb and
// whose bottom and top stand in the free space of their storeys.
//
// Floors: bim::DefaultWalkStorey's rule (2 m or more to the next storey; the last counts) and
// something people use on them (a door, a space, a stair, a railing or furniture). A flight joins
// two floors when its rise, pitch and width are within the platform's StairLimits and a standing
// cell with the walk's clearance lies off its first riser on the lower floor and off its last on
// the upper one. The stairwell (the flight's levels under the upper floor) is marked occupied in
// the upper grid, so no walk on that storey crosses the hole. What cannot be walked is said in
// `problems`, naming the storeys and the reason; the reach counts from the start storey.
#pragma once

#include <string>
#include <vector>

#include "host_tools/bim/bim_model.hpp"
#include "host_tools/bim/occupancy_grid.hpp"
#include "host_tools/bim/stairs.hpp"

namespace bimslam::bim {

struct BuildingGraph {
    std::vector<int> floors;            // storeys one stands in, lowest first
    std::vector<OccupancyGrid> grids;   // per model storey; empty (width 0) when not a floor
    std::vector<StairFlight> flights;   // all of them; Walkable() ones join floors
    int start = -1;                     // the storey the reach is counted from
    std::vector<int> reached;           // floors reached from `start`, lowest first
    std::vector<std::string> problems;  // each names the storeys and the reason

    bool Reaches(int storey) const;
    bool AllReached() const { return reached.size() == floors.size(); }
    // Flights joining `storey` to another floor, walkable ones only.
    std::vector<int> FlightsAt(int storey) const;
};

// Throws common::Error when the model has no storey with free space.
BuildingGraph BuildBuildingGraph(const BimModel& model, const GridConfig& grid,
                                 const StairLimits& limits, double clearance_m, int start_storey);

}  // namespace bimslam::bim
