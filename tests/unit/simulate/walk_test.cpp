// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The planned walk: a vehicle's outdoor loop (planned on the outdoor grid, corners rounded to its
// turning radius, a closed loop that starts over), RoundCorners' geometry, and what a Go1's walk
// goes around, through or into.
#include "host_tools/simulate/walk.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "algorithms/common/status.hpp"
#include "tests/unit/bim/synthetic_floor.hpp"

namespace bimslam::simulate {
namespace {
namespace BIMSLAM_UNITY_ID {

double Heading(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return std::atan2(b.y() - a.y(), b.x() - a.x());
}

// The largest heading change between consecutive legs, per metre travelled.
double MaxCurvature(const std::vector<Eigen::Vector2d>& p) {
    double worst = 0;
    for (size_t i = 1; i + 1 < p.size(); ++i) {
        const double turn =
            std::abs(std::remainder(Heading(p[i], p[i + 1]) - Heading(p[i - 1], p[i]), 2 * M_PI));
        const double arc = 0.5 * ((p[i] - p[i - 1]).norm() + (p[i + 1] - p[i]).norm());
        worst = std::max(worst, turn / arc);
    }
    return worst;
}

TEST(RoundCorners, ARightAngleBecomesAnArcTangentToBothLegs) {
    const std::vector<Eigen::Vector2d> square = {{0, 0}, {10, 0}, {10, 10}};
    const auto r = RoundCorners(square, 3.0);
    EXPECT_EQ(r.front(), square.front());
    EXPECT_EQ(r.back(), square.back());
    ASSERT_GT(r.size(), 6u);
    // The arc leaves the first leg 3 m before the corner and joins the second 3 m after it.
    EXPECT_NEAR((r[1] - Eigen::Vector2d(7, 0)).norm(), 0, 1e-9);
    EXPECT_NEAR((r[r.size() - 2] - Eigen::Vector2d(10, 3)).norm(), 0, 1e-9);
    for (size_t i = 1; i + 1 < r.size(); ++i) {
        EXPECT_NEAR((r[i] - Eigen::Vector2d(7, 3)).norm(), 3.0, 1e-9) << i;
    }
    // No corner left: the heading turns at most 1/radius per metre (plus the chords' error).
    EXPECT_LT(MaxCurvature(r), 1.05 / 3.0);
    // A right turn the other way round: the centre is on the right.
    const auto right = RoundCorners({{0, 0}, {10, 0}, {10, -10}}, 3.0);
    for (size_t i = 1; i + 1 < right.size(); ++i) {
        EXPECT_NEAR((right[i] - Eigen::Vector2d(7, -3)).norm(), 3.0, 1e-9) << i;
    }
}

TEST(RoundCorners, ShortLegsShrinkTheRadiusAndStraightLinesStay) {
    // Legs of 2 m: the arc takes at most half of each, so its radius is 1 m.
    const auto r = RoundCorners({{0, 0}, {2, 0}, {2, 2}}, 5.0);
    for (size_t i = 1; i + 1 < r.size(); ++i) {
        EXPECT_NEAR((r[i] - Eigen::Vector2d(1, 1)).norm(), 1.0, 1e-9) << i;
    }
    const std::vector<Eigen::Vector2d> line = {{0, 0}, {1, 0}, {2, 0}};
    EXPECT_EQ(RoundCorners(line, 5.0), line);
}

class VehicleWalk : public ::testing::Test {
protected:
    // A loop 5 m out from the synthetic storey's walls (x 0..12, y 0..8), starting mid-side.
    static Scenario Loop() {
        Scenario s = DefaultScenario(Platform::kVehicle);
        s.path.waypoints = {{6, -5}, {17, -5}, {17, 13}, {-5, 13}, {-5, -5}, {6, -5}};
        return s;
    }
    const bim::BimModel model_ = bim::test_floor::Floor();
};

TEST_F(VehicleWalk, DrivesAroundTheBuildingWithoutSharpTurns) {
    const Scenario s = Loop();
    ASSERT_NO_THROW(s.Validate());
    const Walk w = PlanWalk(model_, 0, s);
    EXPECT_TRUE(w.closed);
    EXPECT_EQ(w.points.front(), Eigen::Vector2d(6, -5));
    EXPECT_EQ(w.points.back(), Eigen::Vector2d(6, -5));
    // Never within its clearance (1.2 m) of the footprint, nor inside it.
    const Eigen::AlignedBox2d footprint(Eigen::Vector2d(-0.1, -0.1), Eigen::Vector2d(12.1, 8.1));
    for (const Eigen::Vector2d& p : w.points) {
        EXPECT_GT(footprint.exteriorDistance(p), 1.2) << p.transpose();
    }
    // Four rounded corners of 5 m: the heading never turns faster than that radius allows.
    EXPECT_LT(MaxCurvature(w.points), 1.05 / 5.0);
    // A longer capture goes round again the same way instead of turning back.
    const std::vector<Eigen::Vector2d> two = RepeatWalk(w, 2);
    EXPECT_EQ(two.size(), 2 * w.points.size() - 1);
    const size_t joint = w.points.size() - 1;
    EXPECT_NEAR(Heading(two[joint], two[joint + 1]), Heading(two[0], two[1]), 1e-9);
}

TEST_F(VehicleWalk, NeedsWaypointsOutsideTheBuilding) {
    Scenario s = DefaultScenario(Platform::kVehicle);
    try {
        s.Validate();
        FAIL() << "a vehicle without waypoints validated";
    } catch (const common::Error& e) {
        EXPECT_NE(std::string(e.what()).find("vehicle_outdoor.yaml"), std::string::npos)
            << e.what();
    }
    // A waypoint inside a room: the outdoor grid does not reach it (the doors are narrower than
    // a car).
    s = Loop();
    s.path.waypoints.insert(s.path.waypoints.begin() + 1, Eigen::Vector2d(3, 2));
    try {
        PlanWalk(model_, 0, s);
        FAIL() << "a waypoint inside the building was driven to";
    } catch (const common::Error& e) {
        EXPECT_NE(std::string(e.what()).find("(3, 2)"), std::string::npos) << e.what();
    }
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace

// The smallest distance(q) over the walk, sampled every 2 cm along it.
double Closest(const std::vector<Eigen::Vector2d>& walk,
               const std::function<double(const Eigen::Vector2d&)>& distance) {
    double best = 1e9;
    for (size_t i = 0; i + 1 < walk.size(); ++i) {
        const double len = (walk[i + 1] - walk[i]).norm();
        const int steps = std::max(1, int(len / 0.02));
        for (int k = 0; k <= steps; ++k) {
            best = std::min(best, distance(walk[i] + (walk[i + 1] - walk[i]) * k / steps));
        }
    }
    return best;
}

// A box the scenario adds where the coverage walk went (the changed building's cabinet stood
// on it, and the simulated Go1 walked through it): the walk now goes around it, its clearance
// kept; so does a cylinder.
TEST(Go1Walk, GoesAroundWhatTheScenarioAddsOnTheFloor) {
    const bim::BimModel model = bim::test_floor::Floor();
    Scenario s = DefaultScenario(Platform::kGo1);
    const Walk plain = PlanWalk(model, 0, s);
    // The walk's point with the most room around it (a room's middle), for the box to stand on.
    size_t at = 0;
    float room = 0;
    for (size_t i = 0; i < plain.points.size(); ++i) {
        int x, y;
        ASSERT_TRUE(plain.grid.ToCell(plain.points[i], &x, &y));
        const float c = plain.grid.clearance[size_t(y) * plain.grid.width + x];
        if (c > room) room = c, at = i;
    }
    ASSERT_GT(room, 1.0f) << "the synthetic floor has a room with space for a box";
    const Eigen::Vector2d p = plain.points[at];
    const Eigen::Vector3d size(0.6, 0.4, 0.8);
    const Eigen::AlignedBox2d box(p - size.head<2>() / 2, p + size.head<2>() / 2);
    const auto to_box = [&](const Eigen::Vector2d& q) { return box.exteriorDistance(q); };
    ASSERT_EQ(Closest(plain.points, to_box), 0.0) << "the plain walk passes through the box";

    s.edits.boxes.push_back({"box on the walk", Eigen::Vector3d(p.x(), p.y(), 0.4), size, 0.0});
    const Walk around = PlanWalk(model, 0, s);
    // 0.3 m is the Go1's clearance; one grid cell (5 cm) of rasterisation.
    EXPECT_GT(Closest(around.points, to_box), 0.3 - 0.05);

    Scenario c = DefaultScenario(Platform::kGo1);
    c.edits.cylinders.push_back({"bin on the walk", Eigen::Vector3d(p.x(), p.y(), 0.0), 0.3, 1.0});
    const Walk round_bin = PlanWalk(model, 0, c);
    const auto to_bin = [&](const Eigen::Vector2d& q) { return (q - p).norm() - 0.3; };
    EXPECT_GT(Closest(round_bin.points, to_bin), 0.3 - 0.05);
}

// A box in the south-west room's doorway (x 2..3 in the corridor's south wall) cuts the room off:
// the walk says so, naming the edit, says that the room's viewpoint is left out, and does not go
// in. The box and cylinder on the walk above
// cut nothing off and say nothing.
TEST(Go1Walk, SaysWhichObjectCutsFloorOffTheWalk) {
    const bim::BimModel model = bim::test_floor::Floor();
    Scenario s = DefaultScenario(Platform::kGo1);
    EXPECT_TRUE(PlanWalk(model, 0, s).notes.empty());
    s.edits.boxes.push_back(
        {"crate in the door", Eigen::Vector3d(2.5, 3.5, 0.4), Eigen::Vector3d(1.2, 0.5, 0.8), 0.0});
    const Walk w = PlanWalk(model, 0, s);
    ASSERT_EQ(w.notes.size(), 2u);
    // The room's viewpoint is left out of the coverage walk, and that is said too.
    EXPECT_NE(w.notes[1].find("1 viewpoint(s) of the coverage walk cannot be reached"),
              std::string::npos)
        << w.notes[1];
    EXPECT_NE(w.notes[0].find("edits.boxes[0] (crate in the door) cuts"), std::string::npos)
        << w.notes[0];
    EXPECT_NE(w.notes[0].find("m2 of free floor"), std::string::npos) << w.notes[0];
    // The room is x 0..6, y 0..3.5 less its walls: about 17 m2 of free floor.
    const double m2 = std::stod(w.notes[0].substr(w.notes[0].find(" cuts ") + 6));
    EXPECT_GT(m2, 12.0);
    EXPECT_LT(m2, 21.0);
    for (const Eigen::Vector2d& p : w.points) {
        EXPECT_FALSE(p.x() < 5.9 && p.y() < 3.3)
            << "the walk went into the cut-off room at " << p.transpose();
    }
}

double Length(const std::vector<Eigen::Vector2d>& p) {
    double len = 0;
    for (size_t i = 1; i < p.size(); ++i) len += (p[i] - p[i - 1]).norm();
    return len;
}

// Issue 33, item 7: a wall demolished between visits opens the way. The synthetic floor's box7
// parts its two south rooms (x = 6, y 0..3.5); from one room's middle to the other's the walk
// goes round by the corridor while the wall stands in the walk's grid, and straight through where
// it stood with edits.removed.walk_through. Without it the removed wall stays in the grid (as
// before visits, so earlier captures stay the same).
TEST(Go1Walk, GoesThroughARemovedWallOnlyWithWalkThrough) {
    const bim::BimModel model = bim::test_floor::Floor();
    Scenario s = DefaultScenario(Platform::kGo1);
    s.path.mode = PathMode::kWaypoints;
    s.path.waypoints = {{3.0, 1.5}, {9.0, 1.5}};
    s.edits.removed.global_ids = {"box7"};
    const Walk around = PlanWalk(model, 0, s);
    EXPECT_GT(Length(around.points), 9.0);  // up through one door, along the corridor, down
    s.edits.removed.walk_through = true;
    const Walk through = PlanWalk(model, 0, s);
    EXPECT_LT(Length(through.points), 6.5);
    bool crossed = false;
    for (size_t i = 1; i < through.points.size(); ++i) {
        const Eigen::Vector2d a = through.points[i - 1], b = through.points[i];
        crossed = crossed || ((a.x() - 6.0) * (b.x() - 6.0) <= 0 && a.y() < 3.3 && b.y() < 3.3);
    }
    EXPECT_TRUE(crossed) << "the walk did not cross x = 6 in the south rooms";
}

// The synthetic floor with a door to the outside in its east wall (x = 12, y 5.5 .. 6.5, into the
// north room) and an annex of added walls outside it (x 12 .. 15, y 4.5 .. 7.5): a room outside
// the model. With walk_through (a visit's default) the added walls are on the walk's grid before
// its free space is found, so the annex is enclosed floor the walk enters through the door;
// without, the annex is outdoors and a waypoint in it is refused.
TEST(Go1Walk, EntersAnAnnexBuiltOutsideThroughADoorOnlyWithWalkThrough) {
    bim::BimModel model = bim::SelectElements(
        bim::test_floor::Floor(), [](const bim::BimElement& e) { return e.global_id != "box3"; });
    using bim::test_floor::AddBox;
    AddBox(model, "IfcWall", bim::ElementRole::kStructure, {11.9, -0.1, 0}, {12.1, 5.5, 3});
    AddBox(model, "IfcWall", bim::ElementRole::kStructure, {11.9, 6.5, 0}, {12.1, 8.1, 3});
    AddBox(model, "IfcDoor", bim::ElementRole::kTransient, {11.95, 5.5, 0}, {12.05, 6.5, 2.1});
    Scenario s = DefaultScenario(Platform::kGo1);
    s.path.mode = PathMode::kWaypoints;
    s.path.waypoints = {{7.0, 6.0}, {13.5, 6.0}};
    s.edits.boxes = {{"annex south", {13.55, 4.5, 1.25}, {3.1, 0.15, 2.5}, 0},
                     {"annex north", {13.55, 7.5, 1.25}, {3.1, 0.15, 2.5}, 0},
                     {"annex east", {15.0, 6.0, 1.25}, {0.15, 3.15, 2.5}, 0}};
    EXPECT_THROW(PlanWalk(model, 0, s), common::Error);
    s.edits.removed.walk_through = true;
    const Walk w = PlanWalk(model, 0, s);
    EXPECT_NEAR((w.points.back() - Eigen::Vector2d(13.5, 6.0)).norm(), 0, 1e-9);
    for (const Eigen::Vector2d& p : w.points) {
        // Inside, or in the annex: never round the outside of the building.
        EXPECT_TRUE((p.x() < 12 && p.y() > 0 && p.y() < 8) ||
                    (p.x() > 11.9 && p.x() < 15 && p.y() > 4.5 && p.y() < 7.5))
            << p.transpose();
    }
    // A coverage walk covers the annex as a room of the storey.
    s.path = PathSpec{};
    bool in_annex = false;
    for (const Eigen::Vector2d& p : PlanWalk(model, 0, s).points) in_annex |= p.x() > 12.3;
    EXPECT_TRUE(in_annex);
}

TEST(Go1Walk, ACoverageWalkCoversTheEnclosedRegionItStartsIn) {
    // The synthetic storey with the south-east room's door walled up: the room (x 6..12, y
    // 0..3.5, about 19 m2) is an enclosed region joined to the rest by nothing, as Duplex_A's
    // second dwelling is.
    bim::BimModel model = bim::test_floor::Floor();
    bim::test_floor::Wall(model, 8, 3.5, 9, 3.5);
    const Eigen::AlignedBox2d room(Eigen::Vector2d(6.1, 0.1), Eigen::Vector2d(11.9, 3.4));
    Scenario s = DefaultScenario(Platform::kGo1);
    const Walk largest = PlanWalk(model, 0, s);
    ASSERT_EQ(largest.grid.region_areas_m2.size(), 2u);
    EXPECT_GT(largest.grid.region_areas_m2[1], 10.0);
    for (const Eigen::Vector2d& p : largest.points) ASSERT_FALSE(room.contains(p)) << p.transpose();
    s.path.start = Pose2d{{9.0, 1.75}, 0.0};
    const Walk in_room = PlanWalk(model, 0, s);
    EXPECT_FALSE(in_room.starts_outside);
    for (const Eigen::Vector2d& p : in_room.points) ASSERT_TRUE(room.contains(p)) << p.transpose();
    EXPECT_GE(in_room.points.size(), 2u);  // from the start to the room's one viewpoint
}

// A roof that comes down over the north room (z 3 m at y 5 to 1 m at y 8): a person's walk keeps
// the top of the rig (HeadroomFor: the 1.2 m base, the hand-held mount's 0.1 m, its bob, 0.15 m)
// under it, where the roof is 1.47 m high at y 7.3, the cells beyond are not free and the walk
// stays south of that line by its clearance; under a Go1's top (0.76 m) all of it is free. Before
// the headroom, FZK-Haus' attic walk carried the sensor 8 s inside its roof, every scan empty.
TEST(HandheldWalk, KeepsTheRigUnderALowRoof) {
    bim::BimModel model = bim::test_floor::Floor();
    bim::test_floor::AddRoofFace(model);
    const auto free_at = [](const Walk& w, double x, double y) {
        int cx, cy;
        EXPECT_TRUE(w.grid.ToCell({x, y}, &cx, &cy));
        return w.grid.At(cx, cy) == bim::Cell::kFree;
    };
    const Scenario person = DefaultScenario(Platform::kHandheld);
    EXPECT_NEAR(HeadroomFor(person), 1.47, 1e-9);
    const Walk walk = PlanWalk(model, 0, person);
    EXPECT_FALSE(free_at(walk, 3, 7.5));
    EXPECT_TRUE(free_at(walk, 3, 6.5));
    for (const Eigen::Vector2d& p : walk.points) EXPECT_LT(p.y(), 7.3 - 0.35 + 0.05) << p.x();
    EXPECT_TRUE(free_at(PlanWalk(model, 0, DefaultScenario(Platform::kGo1)), 3, 7.5));
    EXPECT_EQ(HeadroomFor(DefaultScenario(Platform::kVehicle)), 0.0);
}

}  // namespace bimslam::simulate
