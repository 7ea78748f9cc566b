// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Storeys along a corridor in x (sample_corridor.hpp): the office's plan with its dimensions as
// parameters, so the symmetric building is the same generator with other numbers.
#include "host_tools/bim/sample_corridor.hpp"

#include <string>

namespace bimslam::bim {
namespace {

using Eigen::AlignedBox2d;
using Eigen::Vector2d;

// The plan's derived lines: clear interior faces and the corridor's faces.
struct Lines {
    double x_min, x_max, y_min, y_max;
    double south_rooms_y_max, corridor_y_min, corridor_y_max, north_rooms_y_min;

    explicit Lines(const CorridorPlan& p)
        : x_min(p.exterior_wall),
          x_max(p.length - p.exterior_wall),
          y_min(p.exterior_wall),
          y_max(p.width - p.exterior_wall),
          south_rooms_y_max(p.corridor_south_wall - p.interior_wall / 2),
          corridor_y_min(p.corridor_south_wall + p.interior_wall / 2),
          corridor_y_max(p.corridor_north_wall - p.interior_wall / 2),
          north_rooms_y_min(p.corridor_north_wall + p.interior_wall / 2) {}
};

// Spans [a, b] of the rooms between partitions (centrelines) across the clear length.
std::vector<std::pair<double, double>> Spans(const CorridorPlan& p, const Lines& l,
                                             const std::vector<double>& partitions) {
    std::vector<std::pair<double, double>> spans;
    double a = l.x_min;
    for (const double c : partitions) {
        spans.emplace_back(a, c - p.interior_wall / 2);
        a = c + p.interior_wall / 2;
    }
    spans.emplace_back(a, l.x_max);
    return spans;
}

void AddStorey(SampleBuilder& b, int s, const CorridorPlan& p, const CorridorStorey& plan,
               const SampleBuildingOptions& options) {
    SampleLayout& L = b.out;
    const Lines l(p);
    const double ext = p.exterior_wall, in = p.interior_wall;
    const std::string& sn = L.storeys[s].name;
    // Exterior walls: south and north over the full length, west and east between them.
    const int south =
        b.Wall(sn + " exterior wall south", s, {0, ext / 2}, {p.length, ext / 2}, ext, true);
    const int north = b.Wall(sn + " exterior wall north", s, {0, p.width - ext / 2},
                             {p.length, p.width - ext / 2}, ext, true);
    const int west =
        b.Wall(sn + " exterior wall west", s, {ext / 2, l.y_min}, {ext / 2, l.y_max}, ext, true);
    const int east = b.Wall(sn + " exterior wall east", s, {p.length - ext / 2, l.y_min},
                            {p.length - ext / 2, l.y_max}, ext, true);
    const int corridor_s = b.Wall(sn + " corridor wall south", s, {l.x_min, p.corridor_south_wall},
                                  {l.x_max, p.corridor_south_wall}, in, false);
    const int corridor_n = b.Wall(sn + " corridor wall north", s, {l.x_min, p.corridor_north_wall},
                                  {l.x_max, p.corridor_north_wall}, in, false);
    for (const double c : plan.south_partitions) {
        b.Wall(sn + " partition x=" + Metres(c), s, {c, l.y_min}, {c, l.south_rooms_y_max}, in,
               false);
    }
    for (const double c : plan.north_partitions) {
        b.Wall(sn + " partition x=" + Metres(c), s, {c, l.north_rooms_y_min}, {c, l.y_max}, in,
               false);
    }

    // Rooms: the corridor, then the south side west to east, then the north side.
    int number = 0;
    const int corridor = b.Room(s, number++, RoomKind::kCorridor, "Corridor",
                                Rect(l.x_min, l.corridor_y_min, l.x_max, l.corridor_y_max));
    std::vector<int> south_rooms, north_rooms;
    const auto south_spans = Spans(p, l, plan.south_partitions);
    for (size_t i = 0; i < south_spans.size(); ++i) {
        const auto [x0, x1] = south_spans[i];
        south_rooms.push_back(b.Room(s, number++, plan.south_rooms[i].kind,
                                     plan.south_rooms[i].name,
                                     Rect(x0, l.y_min, x1, l.south_rooms_y_max)));
    }
    const auto north_spans = Spans(p, l, plan.north_partitions);
    for (size_t i = 0; i < north_spans.size(); ++i) {
        const auto [x0, x1] = north_spans[i];
        std::vector<Vector2d> poly = Rect(x0, l.north_rooms_y_min, x1, l.y_max);
        if (int(i) == plan.cut_room) {
            // The slanted wall: its room-side face runs from p to q, cutting the corner off.
            const Vector2d corner = plan.cut_east ? Vector2d(x1, l.y_max) : Vector2d(x0, l.y_max);
            const double sx = plan.cut_east ? 1.0 : -1.0;
            const Vector2d pa = corner - Vector2d(0, p.cut_corner);
            const Vector2d q = corner - Vector2d(sx * p.cut_corner, 0);
            if (plan.cut_east) {
                poly = {{x0, l.north_rooms_y_min}, {x1, l.north_rooms_y_min}, pa, q, {x0, l.y_max}};
            } else {
                poly = {{x0, l.north_rooms_y_min}, {x1, l.north_rooms_y_min}, {x1, l.y_max}, q, pa};
            }
            // Centreline half a thickness towards the corner, ends buried 0.2 m in the exterior
            // walls so the corner is closed (the triangle behind it is a closed shaft).
            const Vector2d n = Vector2d(sx, 1.0).normalized();
            const Vector2d d = (q - pa).normalized();
            b.Wall(sn + " slanted wall", s, pa + n * (in / 2) - 0.2 * d, q + n * (in / 2) + 0.2 * d,
                   in, false);
        }
        north_rooms.push_back(
            b.Room(s, number++, plan.north_rooms[i].kind, plan.north_rooms[i].name, poly));
    }

    // A door from the corridor into every room (CorridorPlan says where).
    auto room_doors = [&](const std::vector<int>& rooms, int wall, double wall_y) {
        for (const int r : rooms) {
            const AlignedBox2d box = L.rooms[r].Bounds();
            const double x0 = box.min().x(), x1 = box.max().x();
            const double w = p.door_width;
            if (p.centred_doors) {
                b.Door(s, wall, {0.5 * (x0 + x1), wall_y}, w, p.door_leaves, corridor, r);
                continue;
            }
            const bool stair = L.rooms[r].kind == RoomKind::kStair;
            if (!stair) b.Door(s, wall, {x0 + 1.0, wall_y}, w, p.door_leaves, corridor, r);
            if (stair || x1 - x0 > 8.0) {
                b.Door(s, wall, {x1 - 1.0, wall_y}, w, p.door_leaves, corridor, r);
            }
        }
    };
    room_doors(south_rooms, corridor_s, p.corridor_south_wall);
    room_doors(north_rooms, corridor_n, p.corridor_north_wall);
    const double corridor_y = 0.5 * (l.corridor_y_min + l.corridor_y_max);
    const bool entrances = options.exterior_doors && s == 0;
    if (entrances) {
        b.Door(s, west, {ext / 2, corridor_y}, p.west_entrance.width_m, p.west_entrance.leaves, -1,
               corridor);
        b.Door(s, east, {p.length - ext / 2, corridor_y}, p.east_entrance.width_m,
               p.east_entrance.leaves, -1, corridor);
    }

    // Windows on every room edge lying on an exterior wall's inner face; the stair room only on
    // its east side (its flight runs along the south wall), the corridor's ends unless doors.
    for (int r = corridor; r < int(L.rooms.size()); ++r) {
        if (r == corridor && entrances) continue;
        const bool stair = L.rooms[r].kind == RoomKind::kStair;
        b.WindowsOnExteriorEdges(
            r, stair ? std::vector<int>{east} : std::vector<int>{south, north, west, east});
    }

    // Columns in the open offices south of the corridor, on the plan's grid.
    for (const int r : south_rooms) {
        if (L.rooms[r].kind != RoomKind::kOpenOffice) continue;
        const double y = 0.5 * (l.y_min + l.south_rooms_y_max);
        for (size_t k = 0; k < p.column_x.size(); ++k) {
            b.Column(r, {p.column_x[k], y}, 0.4, k % 2 == 1);
        }
    }
}

}  // namespace

void BuildCorridorStoreys(SampleBuilder& b, const CorridorPlan& plan,
                          const SampleBuildingOptions& options) {
    SampleLayout& L = b.out;
    L.footprint_m = {plan.length, plan.width};
    L.exterior_wall_m = plan.exterior_wall;
    L.interior_wall_m = plan.interior_wall;
    L.slab_m = plan.slab;
    for (size_t s = 0; s < plan.storeys.size(); ++s) {
        L.storeys.push_back(
            {plan.storeys[s].name, plan.floor_to_floor * double(s), plan.floor_to_floor});
    }
    for (size_t s = 0; s < plan.storeys.size(); ++s) {
        AddStorey(b, int(s), plan, plan.storeys[s], options);
    }
}

void AddSouthWallStair(SampleBuilder& b, const CorridorPlan& plan, double foot_x) {
    StairSpec stair;
    stair.name = "Stair";
    stair.storey = 0;
    stair.room_bottom = StairRoom(b.out, 0);
    stair.room_top = StairRoom(b.out, 1);
    stair.width_m = 1.2;
    stair.foot = {foot_x, plan.exterior_wall + stair.width_m / 2};
    stair.direction = Eigen::Vector2d::UnitX();
    stair.wall_right = true;
    const Eigen::AlignedBox2d well = b.Stair(stair);
    b.Slabs({{}, {well}});
}

}  // namespace bimslam::bim
