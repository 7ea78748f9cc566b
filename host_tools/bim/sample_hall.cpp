// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The "hall" layout (sample_building.hpp): a second building unlike the office, so that what is
// tuned on one is tested on the other. 24 m x 20 m, three storeys 3.5 m apart (or
// SampleBuildingOptions::storeys, 2 to 8: a tall building for the rig's memory with a whole
// building's map), 0.4 m exterior and 0.2 m interior walls, 0.25 m slabs. Circulation runs along
// y: on the ground floor a central hall 7.8 m wide with four round columns, entered from the south
// (--exterior-doors); on the upper floors a 2.2 m corridor. North of it, on every storey, a stair
// hall with straight flights side by side (ground to first floor along the north wall, first to
// second floor in the middle, the other way, and so on), and on the upper floors rooms
// north-west and north-east of it that open from it.
// Rooms of other sizes and kinds than the office's (classroom, library, open offices with
// columns); every room has a door from the circulation.
#include "host_tools/bim/sample_builder.hpp"

namespace bimslam::bim {
namespace {

using Eigen::AlignedBox2d;
using Eigen::Vector2d;
using K = RoomKind;

constexpr double kHallLength = 24.0, kHallWidth = 20.0;
constexpr double kExt = 0.4, kInt = 0.2, kSlab = 0.25;
constexpr double kFloorToFloor = 3.5;
constexpr double kXMin = kExt, kXMax = kHallLength - kExt, kYMin = kExt, kYMax = kHallWidth - kExt;
// Wall centrelines: the stair hall between x = 8 and 16 north of y = 14 (the hall's walls on the
// ground floor run on along x = 8 and 16 to the south wall); the upper corridor's walls.
constexpr double kStairWest = 8.0, kStairEast = 16.0, kStairSouth = 14.0;
constexpr double kCorridorWest = 10.8, kCorridorEast = 13.2;
constexpr double kNorthDoorY = 15.2;  // doors from the stair hall, south of the flights

struct Side {
    std::vector<double> partitions;  // centrelines in y, south to north
    std::vector<RoomSpec> rooms;     // one more than partitions
};

struct HallStorey {
    const char* name;
    Side west, east;
    RoomSpec north_west, north_east;  // upper storeys: rooms beside the stair hall
    std::vector<Vector2d> columns;    // in the hall or the open office
};

// The ground floor and the two upper plans; with more storeys (SampleBuildingOptions::storeys)
// the two upper plans take turns upwards.
std::vector<HallStorey> Plans(int storeys) {
    static const char* const kNames[] = {"Ground Floor", "First Floor",  "Second Floor",
                                         "Third Floor",  "Fourth Floor", "Fifth Floor",
                                         "Sixth Floor",  "Seventh Floor"};
    std::vector<HallStorey> plans = {
        {"Ground Floor",
         {{6.0, 10.5},
          {{K::kOffice, "Office"}, {K::kMeeting, "Meeting room"}, {K::kClassroom, "Classroom"}}},
         {{4.0, 9.0}, {{K::kToilets, "Toilets"}, {K::kOffice, "Office"}, {K::kLibrary, "Library"}}},
         {},
         {},
         {{10.5, 4.5}, {13.5, 4.5}, {10.5, 9.5}, {13.5, 9.5}}},
        {"First Floor",
         {{9.0}, {{K::kOpenOffice, "Open office"}, {K::kMeeting, "Meeting room"}}},
         {{5.0, 9.5}, {{K::kOffice, "Office"}, {K::kOffice, "Office"}, {K::kKitchen, "Kitchen"}}},
         {K::kOffice, "Office"},
         {K::kStorage, "Archive"},
         {{3.9, 4.65}, {7.2, 4.65}}},
        {"Second Floor",
         {{4.5, 9.5}, {{K::kOffice, "Office"}, {K::kOffice, "Office"}, {K::kToilets, "Toilets"}}},
         {{7.0}, {{K::kOpenOffice, "Open office"}, {K::kClassroom, "Classroom"}}},
         {K::kMeeting, "Meeting room"},
         {K::kLibrary, "Library"},
         {{16.8, 3.65}, {20.1, 3.65}}},
    };
    plans.resize(size_t(storeys), plans.back());
    for (int s = 3; s < storeys; ++s) {
        plans[size_t(s)] = plans[size_t(1 + (s - 1) % 2)];
        plans[size_t(s)].name = kNames[s];
    }
    return plans;
}

void AddStorey(SampleBuilder& b, int s, const HallStorey& plan, const SampleBuildingOptions& o) {
    SampleLayout& L = b.out;
    const std::string& sn = L.storeys[s].name;
    const bool ground = s == 0;
    // The circulation's walls in x, and how far north the side rooms reach.
    const double cw = ground ? kStairWest : kCorridorWest;
    const double ce = ground ? kStairEast : kCorridorEast;
    const double circ_y1 = kStairSouth - kInt / 2;
    const double side_y1 = ground ? kYMax : circ_y1;

    const int south =
        b.Wall(sn + " exterior wall south", s, {0, kExt / 2}, {kHallLength, kExt / 2}, kExt, true);
    const int north = b.Wall(sn + " exterior wall north", s, {0, kHallWidth - kExt / 2},
                             {kHallLength, kHallWidth - kExt / 2}, kExt, true);
    const int west =
        b.Wall(sn + " exterior wall west", s, {kExt / 2, kYMin}, {kExt / 2, kYMax}, kExt, true);
    const int east = b.Wall(sn + " exterior wall east", s, {kHallLength - kExt / 2, kYMin},
                            {kHallLength - kExt / 2, kYMax}, kExt, true);
    const char* what = ground ? " hall wall " : " corridor wall ";
    const int circ_w =
        b.Wall(sn + what + "west", s, {cw, kYMin}, {cw, ground ? kYMax : circ_y1}, kInt, false);
    const int circ_e =
        b.Wall(sn + what + "east", s, {ce, kYMin}, {ce, ground ? kYMax : circ_y1}, kInt, false);
    const double cross_x0 = ground ? kStairWest + kInt / 2 : kXMin;
    const double cross_x1 = ground ? kStairEast - kInt / 2 : kXMax;
    const int cross = b.Wall(sn + " stair hall wall south", s, {cross_x0, kStairSouth},
                             {cross_x1, kStairSouth}, kInt, false);
    int stair_w = circ_w, stair_e = circ_e;  // the stair hall's side walls
    if (!ground) {
        stair_w = b.Wall(sn + " stair hall wall west", s, {kStairWest, kStairSouth + kInt / 2},
                         {kStairWest, kYMax}, kInt, false);
        stair_e = b.Wall(sn + " stair hall wall east", s, {kStairEast, kStairSouth + kInt / 2},
                         {kStairEast, kYMax}, kInt, false);
    }
    const double west_x1 = cw - kInt / 2, east_x0 = ce + kInt / 2;
    for (const double y : plan.west.partitions) {
        b.Wall(sn + " partition y=" + Metres(y), s, {kXMin, y}, {west_x1, y}, kInt, false);
    }
    for (const double y : plan.east.partitions) {
        b.Wall(sn + " partition y=" + Metres(y), s, {east_x0, y}, {kXMax, y}, kInt, false);
    }

    // Rooms: the circulation, the stair hall, the west side south to north, the east side, and
    // on the upper storeys the rooms north-west and north-east.
    int number = 0;
    const int circ =
        b.Room(s, number++, ground ? K::kHall : K::kCorridor, ground ? "Hall" : "Corridor",
               Rect(cw + kInt / 2, kYMin, ce - kInt / 2, circ_y1));
    const int stair =
        b.Room(s, number++, K::kStair, "Stair hall",
               Rect(kStairWest + kInt / 2, kStairSouth + kInt / 2, kStairEast - kInt / 2, kYMax));
    auto side = [&](const Side& plan_side, double x0, double x1, int wall) {
        double y0 = kYMin;
        for (size_t i = 0; i < plan_side.rooms.size(); ++i) {
            const bool last = i == plan_side.partitions.size();
            const double y1 = last ? side_y1 : plan_side.partitions[i] - kInt / 2;
            const int r = b.Room(s, number++, plan_side.rooms[i].kind, plan_side.rooms[i].name,
                                 Rect(x0, y0, x1, y1));
            // Doors where the room meets the circulation: one in the middle, or two 1.5 m from
            // the ends of a side longer than 8 m.
            const double a = y0, c = std::min(y1, circ_y1);
            const double x = L.walls[wall].start.x();
            if (c - a > 8.0) {
                b.Door(s, wall, {x, a + 1.5}, 1.0, 1, circ, r);
                b.Door(s, wall, {x, c - 1.5}, 1.0, 1, circ, r);
            } else {
                b.Door(s, wall, {x, 0.5 * (a + c)}, 1.0, 1, circ, r);
            }
            if (!last) y0 = plan_side.partitions[i] + kInt / 2;
        }
    };
    side(plan.west, kXMin, west_x1, circ_w);
    side(plan.east, east_x0, kXMax, circ_e);
    b.Door(s, cross, {0.5 * (kStairWest + kStairEast), kStairSouth}, 1.4, 2, circ, stair);
    if (!ground) {
        const double y0 = kStairSouth + kInt / 2;
        const int nw = b.Room(s, number++, plan.north_west.kind, plan.north_west.name,
                              Rect(kXMin, y0, kStairWest - kInt / 2, kYMax));
        const int ne = b.Room(s, number++, plan.north_east.kind, plan.north_east.name,
                              Rect(kStairEast + kInt / 2, y0, kXMax, kYMax));
        b.Door(s, stair_w, {kStairWest, kNorthDoorY}, 1.0, 1, stair, nw);
        b.Door(s, stair_e, {kStairEast, kNorthDoorY}, 1.0, 1, stair, ne);
    }
    if (ground && o.exterior_doors) {
        b.Door(s, south, {0.5 * (kStairWest + kStairEast), kExt / 2}, 1.8, 2, -1, circ);
    }

    // Windows in every room but the stair hall (its flights run along its north wall).
    for (int r = circ; r < int(L.rooms.size()); ++r) {
        if (r != stair) b.WindowsOnExteriorEdges(r, {south, north, west, east});
    }
    // Columns: round ones in the hall, square ones in the open offices.
    for (const Vector2d& c : plan.columns) {
        for (int r = circ; r < int(L.rooms.size()); ++r) {
            if (L.rooms[r].Contains(c)) b.Column(r, c, ground ? 0.5 : 0.4, ground);
        }
    }
}

}  // namespace

SampleLayout HallLayout(const SampleBuildingOptions& options) {
    SampleBuilder b;
    SampleLayout& L = b.out;
    L.layout = BuildingLayout::kHall;
    L.building_name = "Sample hall";
    const int storeys = options.storeys > 0 ? options.storeys : 3;
    L.summary = (storeys == 3 ? std::string("A three") : "A " + std::to_string(storeys)) +
                "-storey building around a central hall generated by bimslam";
    L.footprint_m = {kHallLength, kHallWidth};
    L.exterior_wall_m = kExt;
    L.interior_wall_m = kInt;
    L.slab_m = kSlab;
    const std::vector<HallStorey> plans = Plans(storeys);
    for (size_t s = 0; s < plans.size(); ++s) {
        L.storeys.push_back({plans[s].name, kFloorToFloor * double(s), kFloorToFloor});
    }
    for (size_t s = 0; s < plans.size(); ++s) AddStorey(b, int(s), plans[s], options);

    // Flights of 20 risers of 0.175 m and treads of 0.28 m (5.32 m long), side by side in the
    // stair hall, taking turns: from the ground floor (and every second storey above) along the
    // north wall up towards the east, from the first floor (and every second above) in the
    // middle up towards the west, so each arrives beside the next one's foot.
    std::vector<std::vector<AlignedBox2d>> wells(plans.size());
    for (int s = 0; s + 1 < storeys; ++s) {
        StairSpec f;
        f.name = std::string("Stair to ") + plans[size_t(s + 1)].name;
        f.storey = s;
        f.room_bottom = StairRoom(L, s);
        f.room_top = StairRoom(L, s + 1);
        f.riser_m = 0.175;
        if (s % 2 == 0) {
            f.foot = {9.0, kYMax - f.width_m / 2};
            f.direction = Vector2d::UnitX();
            f.wall_left = true;
        } else {
            f.foot = {14.7, 17.2};
            f.direction = -Vector2d::UnitX();
        }
        wells[size_t(s + 1)].push_back(b.Stair(f));
    }
    b.Slabs(wells);

    if (options.furniture) PlaceFurniture(L, options.seed);
    return L;
}

}  // namespace bimslam::bim
