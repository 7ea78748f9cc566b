// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Moving doors, glass windows and mirrors in the simulated world (world.hpp, moving_doors.hpp).
#include "host_tools/simulate/moving_doors.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "algorithms/common/status.hpp"
#include "algorithms/simulation/lidar_simulator.hpp"
#include "host_tools/bim/occupancy_grid.hpp"
#include "host_tools/simulate/world.hpp"
#include "tests/unit/bim/synthetic_floor.hpp"

namespace bimslam::simulate {
namespace {
namespace BIMSLAM_UNITY_ID {

using bim::ElementRole;

// The synthetic storey with a closed door in the corridor's south wall (x 2..3, y 3.5) and a
// window in the north outer wall (x 4..6, y 8).
bim::BimModel FloorWithDoorAndWindow(uint32_t* door) {
    bim::BimModel m = bim::test_floor::Floor();
    *door = uint32_t(m.elements.size());
    bim::test_floor::AddBox(m, "IfcDoor", ElementRole::kTransient, {2, 3.45, 0}, {3, 3.55, 2.1});
    bim::test_floor::AddBox(m, "IfcWindow", ElementRole::kTransient, {4, 7.97, 0.9},
                            {6, 8.03, 2.1});
    return m;
}

TEST(MovingDoors, TheLeafTurnsAboutItsHingeToItsAngleAtTimeT) {
    uint32_t door_index = 0;
    const bim::BimModel model = FloorWithDoorAndWindow(&door_index);
    MovingDoorsSpec spec;
    spec.global_ids = {model.elements[door_index].global_id};
    spec.period_s = 10;
    spec.max_angle_deg = 90;
    const std::vector<MovingDoor> doors = FindMovingDoors(model, spec, {});
    ASSERT_EQ(doors.size(), 1u);
    const MovingDoor& d = doors[0];
    EXPECT_EQ(d.element, door_index);
    EXPECT_NEAR(d.width_m, 1.0, 1e-6);
    EXPECT_NEAR(d.height_m, 2.05, 1e-6);  // under the 5 cm head
    EXPECT_NEAR(d.hinge.y(), 3.5, 1e-6);  // a jamb, on the wall's centreline
    EXPECT_NEAR(std::min(std::abs(d.hinge.x() - 2), std::abs(d.hinge.x() - 3)), 0.0, 1e-6);
    EXPECT_NEAR(std::abs(d.closed.x()), 1.0, 1e-9);
    EXPECT_NEAR(std::abs(d.swing.y()), 1.0, 1e-9);
    // Closed at t = -phase period, wide open half a period later, at 45 degrees in between.
    const double t_closed = -d.phase * spec.period_s, t_open = t_closed + 5,
                 t_half = t_closed + 2.5;
    EXPECT_NEAR(d.AngleDeg(t_closed), 0.0, 1e-9);
    EXPECT_NEAR(d.AngleDeg(t_open), 90.0, 1e-9);
    EXPECT_NEAR(d.AngleDeg(t_half), 45.0, 1e-9);
    const Eigen::Vector2d far_away(100, 100);  // the walker, nowhere near: the door swings
    for (const double t : {t_closed, t_half, t_open}) {
        common::TriangleMesh mesh;
        std::vector<uint32_t> ids;
        AppendDoorLeaves(doors, t, far_away, &mesh, &ids);
        ASSERT_EQ(ids.size(), mesh.triangles.size());
        EXPECT_EQ(ids.front(), door_index);
        // The leaf's free edge: the vertices farthest from the hinge, at the door's width along
        // the angle's direction (within half the leaf's 4 cm thickness).
        const double a = d.AngleDeg(t) * M_PI / 180;
        const Eigen::Vector2d free_edge =
            d.hinge + d.width_m * (std::cos(a) * d.closed + std::sin(a) * d.swing);
        double nearest = INFINITY;
        for (const auto& v : mesh.vertices) {
            nearest = std::min(nearest, (v.head<2>().cast<double>() - free_edge).norm());
        }
        EXPECT_LT(nearest, 0.021) << t;
    }
    // A walker anywhere near: at every time of the cycle the leaf keeps kWalkerClearanceM from
    // the walker (the walk ignores leaves, so a leaf must not sweep through it), turning only as
    // far as that needs.
    const Eigen::Vector2d opening = d.hinge + 0.5 * d.width_m * d.closed;
    EXPECT_GT(LeafAngleDeg(d, t_closed, opening), 45.0);  // pushed more than half open
    for (const Eigen::Vector2d& walker :
         {opening, Eigen::Vector2d(opening + 0.8 * d.swing),
          Eigen::Vector2d(opening - 0.8 * d.swing),
          Eigen::Vector2d(d.hinge + 0.7 * d.swing + 0.3 * d.closed)}) {
        for (double t = t_closed; t < t_closed + spec.period_s; t += 0.25) {
            const double a = LeafAngleDeg(d, t, walker) * M_PI / 180;
            const Eigen::Vector2d dir = std::cos(a) * d.closed + std::sin(a) * d.swing;
            double distance = INFINITY;
            for (double s = 0; s <= d.width_m; s += 0.01) {
                distance = std::min(distance, (d.hinge + s * dir - walker).norm());
            }
            // (Never farther than the hinge, which does not turn.)
            const double possible = std::min(kWalkerClearanceM, (walker - d.hinge).norm());
            EXPECT_GE(distance, possible - 0.02) << walker.transpose() << " t " << t;
            // With the walker far off, the leaf is where the swing puts it.
            EXPECT_EQ(LeafAngleDeg(d, t, far_away), d.AngleDeg(t));
        }
    }
}

TEST(MovingDoors, AScanAtTwoTimesDiffersWhereTheLeafIs) {
    uint32_t door_index = 0;
    const bim::BimModel model = FloorWithDoorAndWindow(&door_index);
    MovingDoorsSpec spec;
    spec.global_ids = {model.elements[door_index].global_id};
    const std::vector<MovingDoor> doors = FindMovingDoors(model, spec, {});
    ASSERT_EQ(doors.size(), 1u);
    const bim::OccupancyGrid grid = bim::BuildOccupancyGrid(model, 0, {});
    const World world = BuildWorld(model, 0, {}, grid, {}, 1);
    const simulation::Scene scene(world.mesh, world.ids);
    const simulation::LidarModel lidar = simulation::LidarModel::DefaultOs1_32(1024);
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(2.5, 2.0, 1.0);  // in the south room, facing the door
    simulation::ScanImage image[2];
    for (int k = 0; k < 2; ++k) {
        const double t = (-doors[0].phase + 0.5 * k) * spec.period_s;  // closed, then open
        common::TriangleMesh mesh;
        std::vector<uint32_t> ids;
        AppendDoorLeaves(doors, t, {100, 100}, &mesh, &ids);  // the walker far off: it swings
        const simulation::Scene overlay(mesh, ids);
        simulation::SimulatorOptions options;
        options.overlay = &overlay;
        simulation::SimulateScan(scene, lidar, T, simulation::NoiseModel::Noiseless(), 1, &image[k],
                                 options);
    }
    size_t on_closed = 0, differ = 0;
    for (size_t i = 0; i < image[0].range_mm.size(); ++i) {
        on_closed += image[0].element_id[i] == door_index;
        if (image[0].range_mm[i] != image[1].range_mm[i]) {
            ++differ;
            // Where the two scans differ, one of them saw the leaf.
            EXPECT_TRUE(image[0].element_id[i] == door_index ||
                        image[1].element_id[i] == door_index)
                << i;
        }
    }
    EXPECT_GT(on_closed, 100u);
    EXPECT_GT(differ, 100u);
}

TEST(World, GlassWindowsAndMirrorsCarryTheirMaterials) {
    uint32_t door_index = 0;
    const bim::BimModel model = FloorWithDoorAndWindow(&door_index);
    const uint32_t window = door_index + 1;
    const bim::OccupancyGrid grid = bim::BuildOccupancyGrid(model, 0, {});
    EditsSpec e;
    World plain = BuildWorld(model, 0, e, grid, {}, 1);
    EXPECT_TRUE(plain.materials.empty());
    EXPECT_EQ(std::count(plain.ids.begin(), plain.ids.end(), window), 0);  // left out
    e.glass = true;
    e.mirrors = {{"", {11.89, 6, 1.2}, {1.0, 1.5}, 180}};  // on the east wall, facing west
    e.moving_doors.classes = {"IfcDoor"};
    const World w = BuildWorld(model, 0, e, grid, {}, 1);
    ASSERT_EQ(w.materials.size(), w.ids.size());
    size_t glass = 0, mirror = 0;
    for (size_t t = 0; t < w.ids.size(); ++t) {
        if (w.ids[t] == window) {
            EXPECT_EQ(w.materials[t], simulation::Material::kGlass);
            ++glass;
        } else if (w.materials[t] == simulation::Material::kMirror) {
            EXPECT_EQ(w.ids[t], kAddedIdBase);  // the mirror is added object 0
            ++mirror;
        } else {
            EXPECT_EQ(w.materials[t], simulation::Material::kDiffuse);
        }
    }
    EXPECT_EQ(glass, 12u);
    EXPECT_EQ(mirror, 2u);
    ASSERT_EQ(w.added.size(), 1u);
    EXPECT_EQ(w.added[0].kind, "mirror");
    EXPECT_EQ(w.added[0].name, "mirror0");
    // Facing yaw 180: its counter-clockwise normal points to -x.
    const auto& v = w.added[0].mesh.vertices;
    const Eigen::Vector3f n = (v[1] - v[0]).cross(v[2] - v[0]).normalized();
    EXPECT_NEAR(n.x(), -1.0f, 1e-6f);
    // Both doors of the storey swing (the synthetic floor's open leaf and the closed one).
    EXPECT_EQ(w.doors.size(), 2u);
    const nlohmann::json changes = WriteChanges(w, ::testing::TempDir());
    EXPECT_EQ(changes["added"][0]["kind"], "mirror");
    EXPECT_EQ(changes["moving_doors"].size(), 2u);
    // A door class that matches nothing is named.
    e.moving_doors.classes = {"IfcDoorStandardCase"};
    try {
        BuildWorld(model, 0, e, grid, {}, 1);
        FAIL();
    } catch (const common::Error& err) {
        EXPECT_NE(std::string(err.what()).find("edits.moving_doors.classes[0]"), std::string::npos);
    }
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::simulate
