// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Internal to host_tools/bim: storeys planned along a corridor in x, the plan of the office and of
// the symmetric building (sample_office.cpp, sample_symmetric.cpp). A rectangular footprint; per
// storey a corridor between two walls along x over the clear length, rooms south and north of it
// between partitions, a door from the corridor into every room, windows on the exterior walls,
// optionally a corner cut off by a slanted wall, columns in open offices, and entrances at the
// corridor's ends.
#pragma once

#include <vector>

#include "host_tools/bim/sample_builder.hpp"

namespace bimslam::bim {

// What differs between storeys: the partitions along the corridor and the rooms between them.
struct CorridorStorey {
    const char* name;
    std::vector<double> south_partitions;  // centrelines, west to east
    std::vector<RoomSpec> south_rooms;     // one more than partitions
    std::vector<double> north_partitions;
    std::vector<RoomSpec> north_rooms;
    // The north room (index into north_rooms, -1: none) with a corner cut off by a slanted wall,
    // its north-east corner when cut_east, else its north-west one.
    int cut_room = -1;
    bool cut_east = true;
};

struct Entrance {
    double width_m = 1.0;
    int leaves = 1;
};

struct CorridorPlan {
    double length = 30.0, width = 15.0;  // footprint
    double exterior_wall = 0.3, interior_wall = 0.15, slab = 0.2;
    double floor_to_floor = 3.2;
    double corridor_south_wall = 6.075, corridor_north_wall = 8.225;  // centrelines
    double cut_corner = 2.0;  // legs of the corner the slanted wall cuts off
    // Room doors. Office: one single door 1 m from the room's west end, a second one 1 m from
    // its east end in rooms longer than 8 m, the stair room's only door at its east end, where
    // the flight arrives. Centred: one door in the middle of the room's corridor side.
    bool centred_doors = false;
    double door_width = 1.0;
    int door_leaves = 1;
    // Columns in the open offices south of the corridor, on this x grid, alternately square
    // and round.
    std::vector<double> column_x;
    // Doors to the outside at the corridor's west and east ends (ground floor,
    // SampleBuildingOptions::exterior_doors).
    Entrance west_entrance, east_entrance;
    std::vector<CorridorStorey> storeys;
};

// Sets up b.out (footprint, walls, storeys) and adds every storey of the plan.
void BuildCorridorStoreys(SampleBuilder& b, const CorridorPlan& plan,
                          const SampleBuildingOptions& options);

// The office's stair in a two-storey plan, then the slabs: "Stair", a straight flight 1.2 m wide
// from the ground floor's stair room to the first floor's, along the south exterior wall (on its
// right) up towards the east from x = foot_x; the first floor's slab has its opening.
void AddSouthWallStair(SampleBuilder& b, const CorridorPlan& plan, double foot_x);

}  // namespace bimslam::bim
