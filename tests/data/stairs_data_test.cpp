// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The walkable 3D graph (host_tools/bim/stairs.hpp) of the real models in ../shared/data/ifc: the
// stairs their exporters wrote (Revit's IfcStair with IfcStairFlight parts, ArchiCAD's spiral
// IfcStair with its own geometry) join their floors, and each flight found from the geometry has
// the risers, treads, riser height and tread length its exporter declared; a floor the file leaves
// out is assumed, open over the stairs. Each skips, saying so, when the file is absent.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "algorithms/simulation/scene.hpp"
#include "host_tools/bim/building_graph.hpp"
#include "host_tools/bim/ifc_model.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::bim {
namespace {
namespace BIMSLAM_UNITY_ID {

struct Case {
    std::string file;
    std::vector<std::string> floors;  // the storeys one stands in, lowest first
    // Why the Go1 does not reach the upper floors (a message part), or empty when it does.
    std::string go1_stopped_by;
    // Whether its exporter wrote IfcStairFlight's NumberOfRisers, NumberOfTreads, RiserHeight
    // and TreadLength (Revit does; ArchiCAD's FZK-Haus has no IfcStairFlight).
    bool declares = false;
    // The storeys whose floor the file does not model, assumed at ingest (assumed_floors.hpp).
    std::vector<std::string> assumed_floors{};
};

class StairsData : public ::testing::TestWithParam<Case> {};

std::string Problems(const BuildingGraph& g) {
    std::string s;
    for (const std::string& p : g.problems) s += "\n  " + p;
    return s;
}

TEST_P(StairsData, EveryFloorIsReachedByTheStairs) {
    const Case& c = GetParam();
    BIMSLAM_REQUIRE_SHARED_DATA(path, "ifc/" + c.file);
    const BimModel model = LoadIfc(path);
    for (const bool go1 : {false, true}) {
        SCOPED_TRACE(go1 ? "Go1" : "handheld");
        const BuildingGraph g =
            BuildBuildingGraph(model, GridConfig{}, go1 ? StairLimits::Go1() : StairLimits{},
                               go1 ? 0.3 : 0.35, DefaultWalkStorey(model));
        std::vector<std::string> floors, reached;
        for (const int s : g.floors) floors.push_back(model.storeys[size_t(s)].name);
        for (const int s : g.reached) reached.push_back(model.storeys[size_t(s)].name);
        EXPECT_EQ(floors, c.floors);
        if (go1 && !c.go1_stopped_by.empty()) {
            // The message names the storey left out and the reason.
            EXPECT_EQ(reached, std::vector<std::string>{c.floors.front()});
            EXPECT_NE(Problems(g).find("storey '" + c.floors.back() + "' is not reached from '" +
                                       c.floors.front() + "'"),
                      std::string::npos)
                << Problems(g);
            EXPECT_NE(Problems(g).find(c.go1_stopped_by), std::string::npos) << Problems(g);
            continue;
        }
        EXPECT_EQ(reached, c.floors) << Problems(g);
        for (const StairFlight& f : g.flights) {
            // The outside yardstick: what the authoring tool declared of each flight.
            const DeclaredCheck check = CheckDeclared(f);
            EXPECT_EQ(check.declared, c.declares) << f.name;
            EXPECT_EQ(check.differs, "") << f.name;
            // Both Revit files write RiserHeight and TreadLength in feet though their unit is the
            // metre (Autodesk/revit-ifc#552 reports the same of other lengths).
            EXPECT_EQ(check.in_feet, c.declares) << f.name;
            if (!f.Walkable()) continue;
            // Risers of 0.14-0.22 m, 25-50 degrees (a spiral stair's walking line is steep),
            // 0.6 m or wider.
            EXPECT_GT(f.rise_m, 0.14) << f.name;
            EXPECT_LT(f.rise_m, 0.22) << f.name;
            EXPECT_GT(f.pitch_deg, 25) << f.name;
            EXPECT_LT(f.pitch_deg, 50) << f.name;
            EXPECT_GT(f.width_m, 0.6) << f.name;
        }
    }
}

// A floor is assumed only where the file models none (Office_A has no floor slabs: its two
// IfcSlab are stair landings), and it is open over the stairs: a beam straight down over each tread
// of a flight that climbs to it meets the flight, and one over where the walk steps off the flight
// meets the assumed floor at the storey's elevation.
TEST_P(StairsData, FloorsAreAssumedWhereTheFileHasNoneOpenOverTheStairs) {
    const Case& c = GetParam();
    BIMSLAM_REQUIRE_SHARED_DATA(path, "ifc/" + c.file);
    const BimModel model = LoadIfc(path);
    std::vector<std::string> assumed;
    for (const AssumedFloor& f : model.assumed_floors)
        assumed.push_back(model.storeys[size_t(f.storey)].name);
    EXPECT_EQ(assumed, c.assumed_floors);
    if (assumed.empty()) return;

    const simulation::Scene scene(model.mesh, model.triangle_element);
    const auto down = [&](const Eigen::Vector2d& p, double z) {
        const Eigen::Vector3f from(float(p.x()), float(p.y()), float(z + 1.5 - model.origin_m.z()));
        return scene.Intersect(from, -Eigen::Vector3f::UnitZ());
    };
    size_t treads = 0;
    for (const StairFlight& f : FindStairFlights(model)) {
        const BimElement* floor = nullptr;
        for (const BimElement& e : model.elements) {
            if (e.assumed && e.storey == f.upper) floor = &e;
        }
        if (!floor || !f.Walkable()) continue;
        for (const StairLevel& l : f.levels) {
            const auto hit = down(l.centre.head<2>(), f.upper_z);
            ASSERT_TRUE(hit) << f.name;
            EXPECT_FALSE(model.elements[hit->id].assumed)
                << f.name << ": the floor covers the tread at " << l.centre.transpose();
            ++treads;
        }
        const auto off = down(f.exit, f.upper_z);
        ASSERT_TRUE(off) << f.name;
        EXPECT_EQ(model.elements[off->id].global_id, floor->global_id)
            << f.name << ": steps off onto " << model.elements[off->id].name;
        EXPECT_NEAR(1.5 - off->t, 0.0, 1e-3) << f.name;
    }
    EXPECT_GT(treads, 0u) << "no flight climbs to a storey with an assumed floor";
}

INSTANTIATE_TEST_SUITE_P(
    Models, StairsData,
    ::testing::Values(Case{"AC20-FZK-Haus.ifc",
                           {"Erdgeschoss", "Dachgeschoss"},
                           "too steep: it climbs at 47.7 degrees",
                           false},
                      Case{"Duplex_A_20110907.ifc", {"Level 1", "Level 2"}, "", true},
                      Case{"Office_A_20110811.ifc",
                           {"Level 1", "Level 2"},
                           "",
                           true,
                           {"Level 1", "Level 2", "Roof"}}),
    [](const auto& param_info) {
        return ::bimslam::test::Identifier(param_info.param.file.substr(0, 6));
    });

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::bim
