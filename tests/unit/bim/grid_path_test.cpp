// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include <gtest/gtest.h>

#include <cmath>

#include "algorithms/common/se3.hpp"
#include "algorithms/io/file_util.hpp"
#include "host_tools/bim/coverage_path.hpp"
#include "host_tools/bim/occupancy_grid.hpp"
#include "tests/support/test_support.hpp"
#include "tests/unit/bim/synthetic_floor.hpp"

namespace bimslam::bim {
namespace {
namespace BIMSLAM_UNITY_ID {
using test_floor::AddRoofFace;
using test_floor::Floor;

TEST(OccupancyGrid, SliceFootprintsAndReachableFreeSpace) {
    const BimModel m = Floor();
    GridConfig config;
    const OccupancyGrid g = BuildOccupancyGrid(m, 0, config);
    auto cell = [&g](double x, double y) {
        int cx, cy;
        EXPECT_TRUE(g.ToCell({x, y}, &cx, &cy));
        return g.At(cx, cy);
    };
    EXPECT_EQ(cell(3, 1.5), Cell::kFree);         // south-west room
    EXPECT_EQ(cell(10, 2), Cell::kFree);          // south-east room
    EXPECT_EQ(cell(3, 7), Cell::kFree);           // north room
    EXPECT_EQ(cell(2.5, 3.5), Cell::kFree);       // a doorway
    EXPECT_EQ(cell(6.0, 1.0), Cell::kOccupied);   // a wall
    EXPECT_EQ(cell(9.7, 6.9), Cell::kOccupied);   // the desk's footprint
    EXPECT_EQ(cell(-0.5, -0.5), Cell::kUnknown);  // outdoors
    EXPECT_EQ(cell(2.02, 4.0), Cell::kFree);      // a door leaf does not block
    // Free area: the inside minus walls and desk, about 12 x 8 - walls.
    const double area = double(g.FreeCells()) * g.resolution * g.resolution;
    EXPECT_GT(area, 80.0);
    EXPECT_LT(area, 92.0);
    // Clearance in the middle of the 6 x 3.5 south-west room: 3.5 / 2 - 0.1 to the walls.
    int cx, cy;
    ASSERT_TRUE(g.ToCell({3.0, 1.75}, &cx, &cy));
    EXPECT_NEAR(g.clearance[size_t(cy) * g.width + cx], 1.65, 0.06);

    config.object_footprints = false;
    const OccupancyGrid no_objects = BuildOccupancyGrid(m, 0, config);
    ASSERT_TRUE(no_objects.ToCell({9.7, 6.9}, &cx, &cy));
    EXPECT_EQ(no_objects.At(cx, cy), Cell::kFree);

    config.seed = Eigen::Vector2d(6.0, 1.0);  // inside a wall
    EXPECT_THROW(BuildOccupancyGrid(m, 0, config), common::Error);
    EXPECT_THROW(BuildOccupancyGrid(m, 1, GridConfig{}), common::Error);
    config = {};
    config.resolution_m = 0;
    EXPECT_THROW(BuildOccupancyGrid(m, 0, config), common::Error);
}

// The floor slab (the IfcSlab at and below z 0) cut back to end at x = x_end.
void EndFloorSlabAt(BimModel& m, float x_end) {
    for (const BimElement& e : m.elements) {
        if (e.ifc_class != "IfcSlab") continue;
        for (uint32_t t = e.first_triangle; t < e.first_triangle + e.triangle_count; ++t) {
            for (const uint32_t k : m.mesh.triangles[t]) {
                Eigen::Vector3f& v = m.mesh.vertices[k];
                if (v.z() <= 0 && v.x() > x_end) v.x() = x_end;
            }
        }
    }
}

TEST(OccupancyGrid, StandableCellsHaveAFloorUnderThemAndHeadroomAboveThem) {
    BimModel m = Floor();
    const OccupancyGrid g = BuildOccupancyGrid(m, 0, {});
    const auto at = [&g](const std::vector<uint8_t>& s, double x, double y) {
        int cx, cy;
        EXPECT_TRUE(g.ToCell({x, y}, &cx, &cy));
        return s[size_t(cy) * g.width + cx] != 0;
    };
    const std::vector<uint8_t> person = StandableCells(m, g, 1.9);
    EXPECT_TRUE(at(person, 3, 1.5));
    EXPECT_TRUE(at(person, 10, 2));
    EXPECT_TRUE(at(person, 3, 7));
    EXPECT_FALSE(at(person, 6.0, 1.0));    // a wall
    EXPECT_FALSE(at(person, 9.7, 6.9));    // the desk
    EXPECT_FALSE(at(person, -0.5, -0.5));  // outdoors

    // The roof comes down to 1.9 m at y = 5 + 1.1 / (2 / 3) = 6.65: a person stands before it, not
    // past it; the Go1 (0.8 m) under all of it (the grid's one slice at 0.6 m sees none of it).
    AddRoofFace(m);
    const std::vector<uint8_t> roofed = StandableCells(m, g, 1.9);
    EXPECT_TRUE(at(roofed, 3, 6.4));
    EXPECT_FALSE(at(roofed, 3, 6.9));
    EXPECT_FALSE(at(roofed, 3, 7.5));
    EXPECT_TRUE(at(roofed, 3, 1.5));
    const std::vector<uint8_t> go1 = StandableCells(m, g, 0.8);
    EXPECT_TRUE(at(go1, 3, 7.5));

    // The floor slab only under x < 6: the east half is a void (as FZK-Haus' attic floor stops
    // short of its eaves), free at the slice's height and no place to stand.
    BimModel half = Floor();
    EndFloorSlabAt(half, 6);
    const std::vector<uint8_t> voided = StandableCells(half, g, 1.9);
    EXPECT_TRUE(at(voided, 3, 1.5));
    EXPECT_FALSE(at(voided, 10, 2));
    EXPECT_FALSE(at(voided, 9, 7));

    // Under less than half of the free space (x < 2): the model has no floor slabs to speak of,
    // as Office_A has none, and the floor is not asked for.
    EndFloorSlabAt(half, 2);
    const std::vector<uint8_t> unmodelled = StandableCells(half, g, 1.9);
    EXPECT_TRUE(at(unmodelled, 10, 2));
    EXPECT_TRUE(at(unmodelled, 3, 1.5));
}

// The same overhead rule on the grid itself (GridConfig::headroom_m): the cells under the roof
// lower than the platform's top are not free, so no walk is planned through them.
TEST(OccupancyGrid, AHeadroomKeepsTheWalkOutFromUnderALowRoof) {
    BimModel m = Floor();
    AddRoofFace(m);
    const auto free_at = [](const OccupancyGrid& g, double x, double y) {
        int cx, cy;
        EXPECT_TRUE(g.ToCell({x, y}, &cx, &cy));
        return g.At(cx, cy) == Cell::kFree;
    };
    const OccupancyGrid slice_only = BuildOccupancyGrid(m, 0, {});
    EXPECT_TRUE(free_at(slice_only, 3, 7.5));  // the slice at 0.6 m passes under the roof
    GridConfig person;
    person.headroom_m = 1.9;
    const OccupancyGrid g = BuildOccupancyGrid(m, 0, person);
    EXPECT_TRUE(free_at(g, 3, 6.4));
    EXPECT_FALSE(free_at(g, 3, 6.9));
    EXPECT_FALSE(free_at(g, 3, 7.5));
    EXPECT_TRUE(free_at(g, 3, 1.5));
    EXPECT_TRUE(free_at(g, 10, 2));
    GridConfig go1;
    go1.headroom_m = 0.8;
    EXPECT_TRUE(free_at(BuildOccupancyGrid(m, 0, go1), 3, 7.5));
    GridConfig bad;
    bad.headroom_m = 0.2;  // below what counts as the floor's own
    EXPECT_THROW(BuildOccupancyGrid(m, 0, bad), common::Error);
}

TEST(OccupancyGrid, WritesMapServerFiles) {
    test::TempDir tmp;
    const OccupancyGrid g = BuildOccupancyGrid(Floor(), 0, {});
    WriteGrid(g, tmp / "ground");
    const std::string yaml = io::ReadFileToString(tmp / "ground.yaml");
    EXPECT_NE(yaml.find("image: ground.pgm"), std::string::npos) << yaml;
    EXPECT_NE(yaml.find("resolution: 0.05"), std::string::npos) << yaml;
    EXPECT_TRUE(std::filesystem::exists(tmp / "ground.png"));
    const std::string pgm = io::ReadFileToString(tmp / "ground.pgm");
    EXPECT_EQ(pgm.rfind("P5\n" + std::to_string(g.width) + " " + std::to_string(g.height), 0), 0u);
}

TEST(CoveragePath, EntersEveryRoomKeepsClearAndIsSmooth) {
    const OccupancyGrid g = BuildOccupancyGrid(Floor(), 0, {});
    PathConfig config;
    const CoveragePath p = PlanCoveragePath(g, config);
    EXPECT_EQ(p.rooms, 4);  // three rooms and the corridor
    EXPECT_EQ(p.unreachable_viewpoints, 0);
    // Every room is entered: some pose at least 0.8 m inside its walls.
    const Eigen::AlignedBox2d rooms[] = {{Eigen::Vector2d(0, 0), Eigen::Vector2d(6, 3.5)},
                                         {Eigen::Vector2d(6, 0), Eigen::Vector2d(12, 3.5)},
                                         {Eigen::Vector2d(0, 5), Eigen::Vector2d(12, 8)},
                                         {Eigen::Vector2d(0, 3.5), Eigen::Vector2d(12, 5)}};
    for (const auto& room : rooms) {
        const Eigen::AlignedBox2d inner(room.min() + Eigen::Vector2d::Constant(0.6),
                                        room.max() - Eigen::Vector2d::Constant(0.6));
        bool entered = false;
        for (const auto& q : p.points) entered = entered || inner.contains(q);
        EXPECT_TRUE(entered) << room.min().transpose() << " .. " << room.max().transpose();
    }
    EXPECT_GE(p.min_clearance_m, config.clearance_m - g.resolution);
    ASSERT_GT(p.points.size(), 100u);
    EXPECT_LT((p.points.back() - p.points.front()).norm(), 2 * config.spacing_m);  // closed
    // At walking speed, slower in turns.
    EXPECT_GE(p.duration_s, p.length_m / config.speed_mps - 1e-6);
    EXPECT_LT(p.duration_s, 2 * p.length_m / config.speed_mps);
    // Smooth enough to walk: spacing holds, the heading turns no faster than the limit.
    double max_rate = 0;
    for (size_t i = 1; i < p.poses.size(); ++i) {
        const double dt = 1e-9 * double(p.poses[i].stamp_ns - p.poses[i - 1].stamp_ns);
        ASSERT_GT(dt, 0);
        EXPECT_LT((p.points[i] - p.points[i - 1]).norm(), 1.5 * config.spacing_m);
        const double dyaw =
            common::RotationAngle(common::Between(p.poses[i - 1].Pose(), p.poses[i].Pose()));
        max_rate = std::max(max_rate, dyaw / dt);
    }
    EXPECT_LT(max_rate, config.max_yaw_rate_radps + 1e-6);
    EXPECT_NEAR(p.poses[0].translation.z(), 0.6, 1e-12);
    const io::Image img = PathImage(g, p);
    EXPECT_EQ(img.width, g.width);
    EXPECT_EQ(img.channels, 3);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::bim
