// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Internal to host_tools/bim: what every sample layout (sample_building.hpp) is assembled from.
// SampleBuilder appends walls, rooms, doors, windows, straight stairs with their slab openings and
// railings, and the slabs to a SampleLayout, naming each element the same way in every layout; the
// layouts (sample_office.cpp, sample_hall.cpp, sample_symmetric.cpp) only say where things go.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "host_tools/bim/sample_building.hpp"

namespace bimslam::bim {

// The corners of the rectangle [x0, x1] x [y0, y1], counter-clockwise from (x0, y0).
std::vector<Eigen::Vector2d> Rect(double x0, double y0, double x1, double y1);
// "6.0", "22.5": a coordinate to the decimetre, as partitions are named.
std::string Metres(double v);
// "0.03": room 3 of storey 0.
std::string RoomNumber(int storey, int index);

// A room of a plan: its kind and its IfcSpace.LongName.
struct RoomSpec {
    RoomKind kind;
    const char* name;
};

// A straight flight from the floor of `storey` to the floor of the storey above, in its stair room
// on both storeys. A side against a wall gets no railing and the slab opening is not widened there.
struct StairSpec {
    std::string name;
    int storey = 0;
    int room_bottom = -1, room_top = -1;
    Eigen::Vector2d foot = Eigen::Vector2d::Zero();        // the middle of the first riser
    Eigen::Vector2d direction = Eigen::Vector2d::UnitX();  // up the flight: +-x or +-y
    double width_m = 1.2;
    double riser_m = 0.2;  // the storey height must be a whole number of them
    double tread_m = 0.28;
    bool wall_left = false, wall_right = false;  // seen looking up the flight
};

class SampleBuilder {
public:
    SampleLayout out;

    // A wall of the storey's clear height (storey height - slab).
    int Wall(std::string name, int storey, Eigen::Vector2d a, Eigen::Vector2d b, double thickness,
             bool exterior);
    int Room(int storey, int index, RoomKind kind, std::string name,
             std::vector<Eigen::Vector2d> polygon);
    // A door in `wall` centred at `centre` (on its centreline) from room `from` (-1: outdoors) into
    // room `into`. Named "Door <into>-<n>" for the n-th door into the room, or "Door <into>-W" (N,
    // E, S: the side of the footprint) from outdoors.
    void Door(int storey, int wall, Eigen::Vector2d centre, double width, int leaves, int from,
              int into);
    // Windows along a room's edge [a, b] that lies on the inner face of exterior wall `wall`.
    void Windows(int room, int wall, Eigen::Vector2d a, Eigen::Vector2d b);
    // Windows on every edge of `room` that lies on the inner face of one of `walls` (exterior
    // wall indices), edge by edge in the polygon's order.
    void WindowsOnExteriorEdges(int room, const std::vector<int>& walls);
    // A column of the storey's clear height in `room`, named "Column <room>-<n>".
    void Column(int room, Eigen::Vector2d centre, double size, bool round);
    // The stair; the opening it needs in the slab of the storey above (the flight's footprint,
    // 0.2 m longer at the bottom for headroom and 0.1 m wider on its open sides), and a railing
    // on that opening's open sides (all but the top end and the sides against a wall), "<stair
    // name> well railing". Returns the opening, for Slabs().
    Eigen::AlignedBox2d Stair(const StairSpec& spec);
    // "<storey> slab" for every storey (over the whole footprint, with the openings of the stairs
    // arriving there), then "Roof slab" on top of the highest storey.
    void Slabs(const std::vector<std::vector<Eigen::AlignedBox2d>>& openings_per_storey);
};

// The storey's first stair room (RoomKind::kStair), -1 when it has none.
int StairRoom(const SampleLayout& layout, int storey);

// Furnishes the rooms `furnish` accepts (all when empty) by their kind, from the seed
// (sample_building_furniture.cpp). Pieces keep clear of the doors, the columns and the stairs.
void PlaceFurniture(SampleLayout& layout, uint64_t seed,
                    const std::function<bool(int room)>& furnish = {});
// Appends a piece to its room, named "<Kind> <room>-<n>" for the n-th of its kind there.
void AddFurniture(SampleLayout& layout, SampleFurniture piece);

// The layouts, each in its own file; options are valid.
SampleLayout OfficeLayout(const SampleBuildingOptions& options);
SampleLayout HallLayout(const SampleBuildingOptions& options);
SampleLayout SymmetricLayout(const SampleBuildingOptions& options);
SampleLayout WingLayout(const SampleBuildingOptions& options);

}  // namespace bimslam::bim
