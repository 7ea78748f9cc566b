// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The "hall" sample building (sample_building.hpp): a building unlike the office (footprint,
// storeys, heights, walls, circulation along y, room kinds and sizes, columns in large rooms), its
// stairs connecting every storey through their slab openings, and its entrance from outside.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>

#include "host_tools/bim/sample_building.hpp"

namespace bimslam::bim {
namespace {
namespace BIMSLAM_UNITY_ID {

using Eigen::AlignedBox2d;
using Eigen::Vector2d;

// The box spanned by two corners in any order.
AlignedBox2d Box(const Vector2d& a, const Vector2d& b) { return {a.cwiseMin(b), a.cwiseMax(b)}; }

SampleLayout Hall(bool exterior_doors = false, bool furniture = true) {
    SampleBuildingOptions o;
    o.layout = BuildingLayout::kHall;
    o.exterior_doors = exterior_doors;
    o.furniture = furniture;
    return SampleBuildingLayout(o);
}

TEST(HallLayout, IsADifferentBuildingFromTheOffice) {
    const SampleLayout H = Hall(), O = SampleBuildingLayout();
    EXPECT_EQ(H.layout, BuildingLayout::kHall);
    EXPECT_EQ(H.building_name, "Sample hall");
    EXPECT_TRUE(H.footprint_m.isApprox(Vector2d(24, 20)));
    EXPECT_NE(H.footprint_m, O.footprint_m);
    ASSERT_EQ(H.storeys.size(), 3u);
    for (size_t s = 0; s < 3; ++s) {
        EXPECT_NEAR(H.storeys[s].elevation_m, 3.5 * double(s), 1e-12);
        EXPECT_NEAR(H.storeys[s].height_m, 3.5, 1e-12);
    }
    EXPECT_NE(H.exterior_wall_m, O.exterior_wall_m);
    EXPECT_NE(H.interior_wall_m, O.interior_wall_m);
    EXPECT_NE(H.slab_m, O.slab_m);
    const Eigen::AlignedBox3d box = H.Bounds();
    EXPECT_TRUE(box.min().isApprox(Eigen::Vector3d(0, 0, -0.25)));
    EXPECT_TRUE(box.max().isApprox(Eigen::Vector3d(24, 20, 10.5)));

    // The circulation runs along y: a hall on the ground floor, corridors above.
    EXPECT_EQ(H.rooms[H.Corridor(0)].kind, RoomKind::kHall);
    for (int s = 0; s < 3; ++s) {
        const AlignedBox2d c = H.rooms[H.Corridor(s)].Bounds();
        EXPECT_GT(c.sizes().y(), (s == 0 ? 1.5 : 5.0) * c.sizes().x()) << s;
        EXPECT_GT(c.sizes().y(), 12.0) << s;
    }
    EXPECT_GT(H.rooms[H.Corridor(0)].Area(), 80.0);  // the hall: a large room
    // Room kinds the office does not have, and rooms of other shapes: no room of the hall has
    // the sides (to the decimetre) of a room of the office.
    std::set<RoomKind> kinds;
    std::set<std::pair<long, long>> office_sides, hall_sides;
    auto sides = [](const SampleRoom& r) {
        const Vector2d d = r.Bounds().sizes();
        return std::make_pair(std::lround(10 * d.minCoeff()), std::lround(10 * d.maxCoeff()));
    };
    for (const SampleRoom& r : O.rooms) office_sides.insert(sides(r));
    for (const SampleRoom& r : H.rooms) {
        kinds.insert(r.kind);
        if (r.Circulation()) continue;
        hall_sides.insert(sides(r));
        EXPECT_FALSE(office_sides.count(sides(r))) << r.number << " " << r.name;
    }
    for (const RoomKind k : {RoomKind::kHall, RoomKind::kClassroom, RoomKind::kLibrary}) {
        EXPECT_TRUE(kinds.count(k)) << ToString(k);
    }
    EXPECT_GE(hall_sides.size(), 8u) << "rooms of many sizes";
    for (const SampleWall& w : H.walls) EXPECT_FALSE(w.Slanted()) << w.name;
}

TEST(HallLayout, EveryStoreyHasColumnsInALargeRoomAndWindows) {
    const SampleLayout H = Hall();
    for (int s = 0; s < 3; ++s) {
        int columns = 0, windows = 0;
        for (const SampleColumn& c : H.columns) {
            if (c.storey != s) continue;
            ++columns;
            const SampleRoom& room = H.rooms[c.room];
            EXPECT_TRUE(room.Contains(c.centre)) << c.name;
            EXPECT_GT(room.Area(), 60.0) << c.name << " in " << room.name;
            EXPECT_NEAR(c.height_m, 3.25, 1e-12) << c.name;
        }
        for (const SampleWindow& w : H.windows) windows += w.storey == s;
        EXPECT_GE(columns, 2) << s;
        EXPECT_GE(windows, 15) << s;
    }
}

// Every flight climbs one storey, from a stair room to the one above, through an opening in the
// slab above that covers it; its top end is open (the arrival) and its other sides have railings
// or walls; the flights chain the storeys from the ground floor to the top.
TEST(HallLayout, StairsConnectEveryStoreyThroughTheirSlabOpenings) {
    const SampleLayout H = Hall();
    ASSERT_EQ(H.stairs.size(), 2u);
    ASSERT_EQ(H.railings.size(), 2u);
    for (size_t i = 0; i < H.stairs.size(); ++i) {
        const SampleStair& st = H.stairs[i];
        SCOPED_TRACE(st.name);
        EXPECT_EQ(st.storey, int(i));
        EXPECT_NEAR(st.risers * st.riser_m, H.storeys[i].height_m, 1e-9);
        EXPECT_LE(st.riser_m, 0.19);  // a comfortable stair: 2 risers + 1 tread about 0.63 m
        EXPECT_NEAR(2 * st.riser_m + st.tread_m, 0.63, 0.03);
        EXPECT_EQ(H.rooms[st.room_bottom].kind, RoomKind::kStair);
        EXPECT_EQ(H.rooms[st.room_top].kind, RoomKind::kStair);
        EXPECT_EQ(H.rooms[st.room_bottom].storey, int(i));
        EXPECT_EQ(H.rooms[st.room_top].storey, int(i) + 1);
        const AlignedBox2d flight = st.Footprint();
        EXPECT_TRUE(H.rooms[st.room_bottom].Contains(flight.min()));
        EXPECT_TRUE(H.rooms[st.room_bottom].Contains(flight.max()));
        AlignedBox2d opening;
        for (const SampleSlab& s : H.slabs) {
            if (s.storey != int(i) + 1 || s.roof) continue;
            for (const auto& o : s.openings) {
                if (o.contains(flight)) opening = o;
            }
        }
        ASSERT_FALSE(opening.isEmpty()) << "no opening over the flight";
        // The landing beyond the top end: inside the upper stair room, no railing across it.
        const Vector2d top = st.foot + st.RunLength() * st.direction;
        const Vector2d left(-st.direction.y(), st.direction.x());
        const AlignedBox2d arrive = Box(top + 0.05 * st.direction - 0.5 * st.width_m * left,
                                        top + 0.8 * st.direction + 0.5 * st.width_m * left);
        EXPECT_TRUE(H.rooms[st.room_top].Contains(arrive.min()));
        EXPECT_TRUE(H.rooms[st.room_top].Contains(arrive.max()));
        const SampleRailing& rail = H.railings[i];
        EXPECT_EQ(rail.storey, int(i) + 1);
        for (const AlignedBox2d& part : rail.parts) {
            EXPECT_FALSE(part.intersects(arrive)) << rail.name;
            EXPECT_FALSE(part.intersects(flight)) << rail.name;
        }
        // The foot is clear: 0.8 m before it lie in the lower stair room, clear of the railings
        // and flights of that storey.
        const AlignedBox2d before = Box(st.foot - 0.8 * st.direction - 0.5 * st.width_m * left,
                                        st.foot + 0.5 * st.width_m * left);
        EXPECT_TRUE(H.rooms[st.room_bottom].Contains(before.min()));
        EXPECT_TRUE(H.rooms[st.room_bottom].Contains(before.max()));
        for (const SampleRailing& r : H.railings) {
            if (r.storey != st.storey) continue;
            for (const AlignedBox2d& part : r.parts)
                EXPECT_FALSE(part.intersects(before)) << r.name;
        }
        for (const SampleStair& other : H.stairs) {
            if (&other != &st && other.storey == st.storey) {
                EXPECT_FALSE(other.Footprint().intersects(before)) << other.name;
            }
        }
    }
    // The flights stand side by side, not over each other.
    EXPECT_FALSE(H.stairs[0].Footprint().intersects(H.stairs[1].Footprint()));
}

TEST(HallLayout, TheEntranceLeadsFromOutsideIntoTheHall) {
    const SampleLayout closed = Hall(false);
    EXPECT_TRUE(std::none_of(closed.doors.begin(), closed.doors.end(),
                             [](const SampleDoor& d) { return d.rooms[0] < 0; }));
    const SampleLayout H = Hall(true);
    std::vector<SampleDoor> entrances;
    for (const SampleDoor& d : H.doors) {
        if (d.rooms[0] < 0) entrances.push_back(d);
    }
    ASSERT_EQ(entrances.size(), 1u);
    const SampleDoor& e = entrances[0];
    EXPECT_EQ(e.storey, 0);
    EXPECT_EQ(H.rooms[e.rooms[1]].kind, RoomKind::kHall);
    EXPECT_EQ(e.name, "Door 0.00-S");
    EXPECT_NEAR(e.centre.y(), H.exterior_wall_m / 2, 1e-12);  // in the south wall
    EXPECT_GE(e.width_m, 1.6);
    EXPECT_EQ(e.leaves, 2);
    // The door is the only change: the same walls and rooms.
    EXPECT_EQ(closed.walls.size(), H.walls.size());
    EXPECT_EQ(closed.rooms.size(), H.rooms.size());
    EXPECT_EQ(closed.doors.size() + 1, H.doors.size());
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::bim
