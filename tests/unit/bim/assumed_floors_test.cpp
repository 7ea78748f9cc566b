// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Floors assumed where a model has none (host_tools/bim/assumed_floors.hpp), on the sample office
// with its floor slabs taken out: a closed slab under each storey, open over the stair from below,
// and a building that is walked as before. The real model without slabs (Office_A) is
// tests/data/ifc_data_test.cpp's.
#include "host_tools/bim/assumed_floors.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <regex>
#include <string>

#include "host_tools/bim/building_graph.hpp"
#include "host_tools/bim/ifc_model.hpp"
#include "host_tools/bim/occupancy_grid.hpp"
#include "host_tools/bim/sample_building.hpp"
#include "host_tools/changes/bim_change_model.hpp"

namespace bimslam::bim {
namespace {
namespace BIMSLAM_UNITY_ID {

BimModel Office() { return ParseIfc("office.ifc", SampleBuildingIfc()); }

BimModel WithoutSlabs(const BimModel& model) {
    return SelectElements(model, [](const BimElement& e) { return e.ifc_class != "IfcSlab"; });
}

// The assumed floor's element of a storey, or nullptr.
const BimElement* FloorOf(const BimModel& m, int storey) {
    for (const BimElement& e : m.elements) {
        if (e.assumed && e.storey == storey) return &e;
    }
    return nullptr;
}

// Whether an up-facing triangle of `e` at height z covers plan point p.
bool Covers(const BimModel& m, const BimElement& e, const Eigen::Vector2d& p, double z) {
    for (uint32_t t = e.first_triangle; t < e.first_triangle + e.triangle_count; ++t) {
        const auto& tri = m.mesh.triangles[t];
        const Eigen::Vector3d a = m.mesh.vertices[tri[0]].cast<double>();
        const Eigen::Vector3d b = m.mesh.vertices[tri[1]].cast<double>();
        const Eigen::Vector3d c = m.mesh.vertices[tri[2]].cast<double>();
        if ((b - a).cross(c - a).z() <= 0 || std::abs(a.z() - z) > 1e-4) continue;
        const auto side = [&p](const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
            return (v.x() - u.x()) * (p.y() - u.y()) - (v.y() - u.y()) * (p.x() - u.x());
        };
        if (side(a, b) >= 0 && side(b, c) >= 0 && side(c, a) >= 0) return true;
    }
    return false;
}

// The volume its triangles enclose (divergence theorem): the slab's when it is closed and every
// face points out of it.
double EnclosedVolume(const BimModel& m, const BimElement& e) {
    double six_v = 0;
    for (uint32_t t = e.first_triangle; t < e.first_triangle + e.triangle_count; ++t) {
        const auto& tri = m.mesh.triangles[t];
        const Eigen::Vector3d a = m.mesh.vertices[tri[0]].cast<double>();
        const Eigen::Vector3d b = m.mesh.vertices[tri[1]].cast<double>();
        const Eigen::Vector3d c = m.mesh.vertices[tri[2]].cast<double>();
        six_v += a.dot(b.cross(c));
    }
    return six_v / 6;
}

TEST(AssumedFloors, AModelWithItsFloorsHasNoneAssumed) {
    const BimModel office = Office();
    EXPECT_TRUE(office.assumed_floors.empty());
    for (const BimElement& e : office.elements) EXPECT_FALSE(e.assumed) << e.global_id;
}

TEST(AssumedFloors, EveryStoreyWithoutItsSlabGetsAClosedFloorOpenOverTheStair) {
    const BimModel office = Office();
    BimModel m = WithoutSlabs(office);
    const size_t elements = m.elements.size();
    AddAssumedFloors(m);
    ASSERT_EQ(m.assumed_floors.size(), 2u);
    ASSERT_EQ(m.elements.size(), elements + 2);  // appended: earlier indices stay
    EXPECT_EQ(m.triangle_element.size(), m.mesh.triangles.size());

    const SampleLayout layout = SampleBuildingLayout();
    const SampleStair& stair = layout.stairs.at(0);
    const Eigen::Vector2d on_flight = stair.Footprint().center();
    const Eigen::Vector2d in_a_room = stair.Footprint().center() + Eigen::Vector2d(0, 4.0);
    for (int s = 0; s < 2; ++s) {
        SCOPED_TRACE("storey " + std::to_string(s));
        const BimElement* floor = FloorOf(m, s);
        ASSERT_NE(floor, nullptr);
        EXPECT_EQ(floor->global_id, AssumedFloorId(s));
        EXPECT_EQ(floor->ifc_class, "IfcSlab");
        EXPECT_EQ(floor->role, ElementRole::kStructure);
        const AssumedFloor& said = m.assumed_floors[size_t(s)];
        EXPECT_EQ(said.storey, s);
        // The office is 30 x 15 m: its floor is the footprint less the stairwell.
        EXPECT_GT(said.area_m2, 0.95 * 30 * 15 - 10);
        EXPECT_LT(said.area_m2, 1.01 * 30.3 * 15.3);
        // Closed and facing out: it encloses its area times its thickness.
        EXPECT_NEAR(EnclosedVolume(m, *floor), said.area_m2 * kAssumedFloorThicknessM,
                    1e-3 * said.area_m2);
        const double z = m.storeys[size_t(s)].elevation_m;
        EXPECT_TRUE(Covers(m, *floor, in_a_room, z));
        // The ground floor runs under the flight's foot; the first floor is open over it.
        EXPECT_EQ(Covers(m, *floor, on_flight, z), s == 0);
    }
    // The opening is the flight's plan (1.2 m x 15 treads of 0.28 m), not the storey.
    EXPECT_EQ(m.assumed_floors[0].opening_m2, 0.0);
    EXPECT_GT(m.assumed_floors[1].opening_m2, 0.9 * stair.width_m * stair.RunLength());
    EXPECT_LT(m.assumed_floors[1].opening_m2, 1.5 * stair.width_m * stair.RunLength() + 1.0);

    // Read back without its slabs and with assumed floors, the office is walked as before: the
    // flight joins both storeys, and nobody stands over the stairwell.
    const BuildingGraph graph =
        BuildBuildingGraph(m, GridConfig{}, StairLimits{}, 0.35, DefaultWalkStorey(m));
    EXPECT_EQ(graph.reached, (std::vector<int>{0, 1}));
    EXPECT_TRUE(graph.problems.empty()) << graph.problems.front();
    const OccupancyGrid upper = BuildOccupancyGrid(m, 1, GridConfig{});
    const std::vector<uint8_t> standable = StandableCells(m, upper, 1.9);
    int x, y;
    ASSERT_TRUE(upper.ToCell(on_flight, &x, &y));
    EXPECT_FALSE(standable[size_t(y) * upper.width + x]);
    ASSERT_TRUE(upper.ToCell(in_a_room, &x, &y));
    EXPECT_TRUE(standable[size_t(y) * upper.width + x]);
}

// Change detection casts its beams against an assumed floor (the floor is where the model says it
// is) but never judges it: no verdict, no line in changes.json or elements.csv.
TEST(AssumedFloors, ChangeDetectionCastsAgainstThemAndNeverJudgesThem) {
    BimModel m = WithoutSlabs(Office());
    AddAssumedFloors(m);
    const changes::ChangeModel cm = change_detection::ToChangeModel(m);
    size_t assumed = 0, judged = 0;
    for (size_t e = 0; e < m.elements.size(); ++e) {
        const bool listed = change_detection::Listed(m.elements[e]);
        EXPECT_EQ(cm.Judged(e), listed && cm.element_opaque[e]) << m.elements[e].global_id;
        judged += cm.Judged(e);
        if (!m.elements[e].assumed) continue;
        ++assumed;
        EXPECT_TRUE(cm.element_opaque[e]);
        EXPECT_FALSE(listed);
        EXPECT_FALSE(cm.Judged(e));
    }
    EXPECT_EQ(assumed, 2u);
    EXPECT_GT(judged, 20u);  // the walls and the rest still are
    size_t floor_triangles = 0;
    for (const uint32_t e : cm.triangle_element) floor_triangles += m.elements[e].assumed;
    EXPECT_GT(floor_triangles, 0u);
}

// The sample's IFC text with its floor slabs written as proxies (what a model whose author did not
// model floors as slabs reads as: no floor faces in the structure).
std::string FloorsAsProxies() {
    std::string text = SampleBuildingIfc();
    const std::regex floor_slab(R"(=IFCSLAB\(([^\n]*),\.FLOOR\.\);)");
    text = std::regex_replace(text, floor_slab, "=IFCBUILDINGELEMENTPROXY($1,.NOTDEFINED.);");
    return text;
}

TEST(AssumedFloors, TheReaderAssumesThemUnlessToldNot) {
    const std::string text = FloorsAsProxies();
    const BimModel assumed = ParseIfc("office.ifc", text);
    ASSERT_EQ(assumed.assumed_floors.size(), 2u);
    EXPECT_NE(FloorOf(assumed, 0), nullptr);
    EXPECT_NE(FloorOf(assumed, 1), nullptr);
    IfcLoadOptions as_written;
    as_written.assume_floors = false;
    const BimModel plain = ParseIfc("office.ifc", text, as_written);
    EXPECT_TRUE(plain.assumed_floors.empty());
    EXPECT_EQ(plain.elements.size() + 2, assumed.elements.size());
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::bim
