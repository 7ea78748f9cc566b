// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Stairs read from the model's geometry and the walkable 3D graph (host_tools/bim/stairs.hpp), on
// the project's sample buildings: the office's one flight (16 risers of 0.2 m, treads 0.28 m,
// 1.2 m wide) and the hall's two; a stair without geometry and one too steep for the platform
// leave the upper storeys unreached, with a message that names them and the reason.
#include <gtest/gtest.h>

#include <regex>
#include <string>
#include <utility>

#include "algorithms/common/status.hpp"
#include "host_tools/bim/building_graph.hpp"
#include "host_tools/bim/ifc_model.hpp"
#include "host_tools/bim/sample_building.hpp"

namespace bimslam::bim {
namespace {
namespace BIMSLAM_UNITY_ID {

BimModel Office() { return ParseIfc("office.ifc", SampleBuildingIfc()); }

BuildingGraph Graph(const BimModel& model, const StairLimits& limits = {}) {
    return BuildBuildingGraph(model, GridConfig{}, limits, 0.35, DefaultWalkStorey(model));
}

TEST(Stairs, TheOfficeFlightHasTheLayoutsRiseRunAndWidth) {
    const SampleLayout layout = SampleBuildingLayout();
    ASSERT_EQ(layout.stairs.size(), 1u);
    const SampleStair& st = layout.stairs[0];
    const BimModel model = Office();
    const std::vector<StairFlight> flights = FindStairFlights(model);
    ASSERT_EQ(flights.size(), 1u);
    const StairFlight& f = flights[0];
    EXPECT_TRUE(f.Walkable()) << f.problem;
    EXPECT_EQ(f.lower, 0);
    EXPECT_EQ(f.upper, 1);
    EXPECT_EQ(f.risers, st.risers);
    EXPECT_EQ(int(f.levels.size()), st.risers - 1);
    EXPECT_NEAR(f.rise_m, st.riser_m, 1e-4);
    EXPECT_NEAR(f.run_m, st.tread_m, 0.01);
    EXPECT_NEAR(f.width_m, st.width_m, 0.06);
    // Each tread at its height, on the flight's axis.
    for (size_t k = 0; k < f.levels.size(); ++k) {
        EXPECT_NEAR(f.levels[k].centre.z(), st.riser_m * double(k + 1), 1e-4) << "tread " << k;
        const Eigen::Vector2d along = st.foot + st.direction * st.tread_m * (double(k) + 0.5);
        EXPECT_LT((f.levels[k].centre.head<2>() - along).norm(), 0.03) << "tread " << k;
    }
}

TEST(Stairs, TheLineStepsUpOneRiserAtEachTreadsEdge) {
    const SampleStair st = SampleBuildingLayout().stairs[0];
    const BimModel model = Office();
    const BuildingGraph g = Graph(model);
    ASSERT_EQ(g.flights.size(), 1u);
    const std::vector<Eigen::Vector3d> line = g.flights[0].Line();
    ASSERT_GE(line.size(), 3u * size_t(st.risers));
    EXPECT_NEAR(line.front().z(), 0.0, 1e-9);
    EXPECT_NEAR(line.back().z(), 3.2, 1e-9);
    // The riser k lies k treads up the flight from its foot (the layout's first riser).
    int risers = 0;
    for (size_t i = 1; i < line.size(); ++i) {
        if (line[i].z() - line[i - 1].z() < 1e-6) continue;
        const double along = (line[i].head<2>() - st.foot).dot(st.direction);
        EXPECT_NEAR(along, risers * st.tread_m, 0.03) << "riser " << risers;
        EXPECT_NEAR(line[i].z() - line[i - 1].z(), st.riser_m, 1e-4);
        ++risers;
    }
    EXPECT_EQ(risers, st.risers);
}

TEST(Stairs, TheOfficeGraphReachesEveryStorey) {
    const BimModel model = Office();
    const BuildingGraph g = Graph(model);
    EXPECT_EQ(g.floors, (std::vector<int>{0, 1}));
    EXPECT_EQ(g.reached, (std::vector<int>{0, 1}));
    EXPECT_TRUE(g.problems.empty()) << g.problems.front();
    const StairFlight& f = g.flights[0];
    // Entry and exit stand on free floor of their storeys, with the clearance.
    for (const auto& [storey, cell] : {std::pair{f.lower, f.entry_cell}, {f.upper, f.exit_cell}}) {
        const OccupancyGrid& grid = g.grids[size_t(storey)];
        ASSERT_TRUE(grid.Inside(cell.x(), cell.y()));
        EXPECT_EQ(grid.At(cell.x(), cell.y()), Cell::kFree);
        EXPECT_GE(grid.clearance[size_t(cell.y()) * grid.width + cell.x()], 0.35);
    }
    // The stairwell is closed on the upper storey: no free cell over a tread below its floor.
    const OccupancyGrid& upper = g.grids[1];
    for (const StairLevel& l : f.levels) {
        int x, y;
        ASSERT_TRUE(upper.ToCell(l.centre.head<2>(), &x, &y));
        EXPECT_NE(upper.At(x, y), Cell::kFree) << "tread at " << l.centre.transpose();
    }
}

TEST(Stairs, TheHallsTwoFlightsReachItsThreeStoreys) {
    SampleBuildingOptions options;
    options.layout = BuildingLayout::kHall;
    const BimModel model = ParseIfc("hall.ifc", SampleBuildingIfc(options));
    const BuildingGraph g = Graph(model, StairLimits::Go1());
    EXPECT_EQ(g.reached, (std::vector<int>{0, 1, 2}));
    ASSERT_EQ(g.flights.size(), 2u);
    for (const StairFlight& f : g.flights) {
        EXPECT_TRUE(f.Walkable()) << f.problem;
        EXPECT_NEAR(f.rise_m, 0.175, 1e-4);
        EXPECT_EQ(f.upper, f.lower + 1);
    }
}

// `bim sample --layout hall --storeys N`: the upper plans and the flights take turns, and every
// storey is reached from the ground floor through the file's stairs and slab openings.
TEST(Stairs, ATallerHallIsReachedStoreyByStorey) {
    SampleBuildingOptions options;
    options.layout = BuildingLayout::kHall;
    options.storeys = 5;
    const SampleLayout L = SampleBuildingLayout(options);
    ASSERT_EQ(L.storeys.size(), 5u);
    EXPECT_EQ(L.storeys[4].name, "Fourth Floor");
    EXPECT_NEAR(L.storeys[4].elevation_m, 14.0, 1e-12);
    EXPECT_EQ(L.stairs.size(), 4u);
    const BimModel model = ParseIfc("hall5.ifc", SampleBuildingIfc(options));
    const BuildingGraph g = Graph(model, StairLimits::Go1());
    EXPECT_EQ(g.reached, (std::vector<int>{0, 1, 2, 3, 4}));
    ASSERT_EQ(g.flights.size(), 4u);
    for (const StairFlight& f : g.flights) {
        EXPECT_TRUE(f.Walkable()) << f.problem;
        EXPECT_EQ(f.upper, f.lower + 1);
    }
    // The three-storey hall is the default's, and only the hall takes a count, 2 to 8.
    options.storeys = 3;
    SampleBuildingOptions plain;
    plain.layout = BuildingLayout::kHall;
    EXPECT_EQ(SampleBuildingIfc(options), SampleBuildingIfc(plain));
    for (const auto& [layout, storeys] :
         {std::pair{BuildingLayout::kHall, 1}, std::pair{BuildingLayout::kHall, 9},
          std::pair{BuildingLayout::kOffice, 3}}) {
        options.layout = layout;
        options.storeys = storeys;
        EXPECT_THROW(options.Validate(), common::Error) << storeys;
    }
}

TEST(Stairs, AFlightTooSteepForTheGo1LeavesTheUpperStoreyUnreached) {
    const BimModel model = Office();
    StairLimits limits = StairLimits::Go1();
    limits.max_riser_m = 0.18;  // the office's risers are 0.2 m
    const BuildingGraph g = Graph(model, limits);
    EXPECT_EQ(g.reached, (std::vector<int>{0}));
    EXPECT_FALSE(g.AllReached());
    ASSERT_FALSE(g.flights[0].Walkable());
    EXPECT_NE(g.flights[0].problem.find("too steep"), std::string::npos) << g.flights[0].problem;
    // One message per unwalkable flight, one per storey not reached: names and reason.
    const std::string all = [&] {
        std::string s;
        for (const std::string& p : g.problems) s += p + "\n";
        return s;
    }();
    EXPECT_NE(all.find("from 'Ground Floor' to 'First Floor' cannot be walked: too steep"),
              std::string::npos)
        << all;
    EXPECT_NE(all.find("storey 'First Floor' is not reached from 'Ground Floor'"),
              std::string::npos)
        << all;
}

TEST(Stairs, AStairWithoutGeometryIsSaid) {
    // The flight's representation removed from the file: IfcStair and IfcStairFlight stay, with
    // nothing to walk on.
    std::string text = SampleBuildingIfc();
    const std::regex flight(R"((IFCSTAIRFLIGHT\('[^']*',#\d+,'[^']*',\$,\$,#\d+,)#\d+)");
    ASSERT_TRUE(std::regex_search(text, flight));
    text = std::regex_replace(text, flight, "$1$$");
    const BimModel model = ParseIfc("office.ifc", text);
    const BuildingGraph g = Graph(model);
    EXPECT_TRUE(g.flights.empty());
    EXPECT_EQ(g.reached, (std::vector<int>{0}));
    std::string all;
    for (const std::string& p : g.problems) all += p + "\n";
    EXPECT_NE(all.find("have no geometry: no flight to walk"), std::string::npos) << all;
    EXPECT_NE(all.find("storey 'First Floor' is not reached from 'Ground Floor': the model has no "
                       "stair or ramp with geometry"),
              std::string::npos)
        << all;
}

// What the file declares of its flight (IfcStairFlight's attributes, read by IFC++) against what
// the geometry gives: the sample writes Revit's counts (16 risers climbed, 15 treads) and agrees.
TEST(Stairs, TheOfficeFlightAgreesWithWhatItsFileDeclares) {
    const SampleStair st = SampleBuildingLayout().stairs[0];
    const std::vector<StairFlight> flights = FindStairFlights(Office());
    ASSERT_EQ(flights.size(), 1u);
    const DeclaredFlight& d = flights[0].declared;
    EXPECT_EQ(d.risers, st.risers);
    EXPECT_EQ(d.treads, st.risers - 1);
    EXPECT_NEAR(d.riser_height_m, st.riser_m, 1e-9);
    EXPECT_NEAR(d.tread_length_m, st.tread_m, 1e-9);
    const DeclaredCheck check = CheckDeclared(flights[0]);
    EXPECT_TRUE(check.declared);
    EXPECT_FALSE(check.in_feet);
    EXPECT_EQ(check.differs, "");
}

// A file whose declarations contradict its geometry is said, each figure that differs.
TEST(Stairs, AFlightWhoseFileDeclaresOtherwiseIsSaid) {
    std::string text = SampleBuildingIfc();
    // NumberOfRisers 16 -> 18, RiserHeight 0.2 -> 0.18 (the sample is in metres).
    const std::regex attributes(R"((IFCSTAIRFLIGHT\([^;]*),16,15,0\.2,)");
    ASSERT_TRUE(std::regex_search(text, attributes));
    text = std::regex_replace(text, attributes, "$1,18,15,0.18,");
    const std::vector<StairFlight> flights = FindStairFlights(ParseIfc("office.ifc", text));
    ASSERT_EQ(flights.size(), 1u);
    EXPECT_TRUE(flights[0].Walkable()) << flights[0].problem;  // the geometry is what is walked
    EXPECT_EQ(CheckDeclared(flights[0]).differs,
              "16 risers in its geometry, 18 declared; risers of 0.200 m, 0.180 m declared");
    // Lengths written in feet into a file in metres (Revit's exporters: Autodesk/revit-ifc#552)
    // agree read in feet, and that is said.
    text = std::regex_replace(text, std::regex(R"((IFCSTAIRFLIGHT\([^;]*),18,15,0\.18,0\.28,)"),
                              "$1,16,15,0.656168,0.918635,");
    const DeclaredCheck feet = CheckDeclared(FindStairFlights(ParseIfc("office.ifc", text))[0]);
    EXPECT_TRUE(feet.in_feet);
    EXPECT_EQ(feet.differs, "");
}

TEST(Stairs, LimitsAreValidated) {
    StairLimits l;
    l.max_riser_m = 0;
    EXPECT_THROW(l.Validate(), common::Error);
    l = StairLimits{};
    l.max_pitch_deg = 95;
    EXPECT_THROW(l.Validate(), common::Error);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::bim
