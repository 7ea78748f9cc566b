// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// IFC ingest on hand-written IFC4 files: geometry in metres whatever the unit, openings
// subtracted, storeys, roles, class counts, failures, and errors that name the file.
#include "host_tools/bim/ifc_model.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>

#include "algorithms/common/status.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::bim {
namespace {
namespace BIMSLAM_UNITY_ID {
using common::StatusCode;

struct Spec {
    double units_per_metre = 1.0;  // 1000: a millimetre file
    std::string schema = "IFC4";
    bool first_floor_elevation = true;  // false: the storey's Elevation is $ (placement z counts)
    double site_x_m = 0.0, site_y_m = 0.0;  // where the building's placement puts it
    bool broken_wall = false;               // a second wall whose extrusion has no profile

    Spec& Units(double per_metre) {
        units_per_metre = per_metre;
        return *this;
    }
    Spec& Schema(std::string name) {
        schema = std::move(name);
        return *this;
    }
    Spec& NoFirstFloorElevation() {
        first_floor_elevation = false;
        return *this;
    }
    Spec& Site(double x_m, double y_m) {
        site_x_m = x_m;
        site_y_m = y_m;
        return *this;
    }
    Spec& BrokenWall() {
        broken_wall = true;
        return *this;
    }
};

// A two-storey building: on the ground floor (elevation 0) a 4 x 0.2 x 2.5 m wall from (1, 2) to
// (5, 2.2) with a 1 x 1.2 m window opening at x 2.5 .. 3.5, z 0.8 .. 2.0 and a window in it, a
// room (IfcSpace, no geometry), a curtain wall whose only geometry is a panel (IfcPlate, 1 x 0.05
// x 2 at x 7 .. 8) and a free-standing post (IfcMember, 0.1 x 0.1 x 2.5 at x 7.5, y 1); on the
// first floor (elevation 3) a 6 x 5 x 0.2 m slab.
std::string MinimalIfc(const Spec& s = {}) {
    auto L = [&](double metres) { return std::to_string(metres * s.units_per_metre); };
    const std::string prefix = s.units_per_metre == 1000 ? ".MILLI." : "$";
    std::string t =
        "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION(('ViewDefinition [none]'),'2;1');\n"
        "FILE_NAME('test.ifc','2024-01-01T00:00:00',(''),(''),'bimslam','test','');\n"
        "FILE_SCHEMA(('" +
        s.schema + "'));\nENDSEC;\nDATA;\n";
    t += "#1=IFCPROJECT('0YvctVUKr0kugbFTf53O9L',$,'Test',$,$,$,$,(#10),#2);\n"
         "#2=IFCUNITASSIGNMENT((#3,#4));\n"
         "#3=IFCSIUNIT(*,.LENGTHUNIT.," +
         prefix +
         ",.METRE.);\n"
         "#4=IFCSIUNIT(*,.PLANEANGLEUNIT.,$,.RADIAN.);\n"
         "#10=IFCGEOMETRICREPRESENTATIONCONTEXT($,'Model',3,1.0E-5,#11,$);\n"
         "#11=IFCAXIS2PLACEMENT3D(#12,$,$);\n#12=IFCCARTESIANPOINT((0.,0.,0.));\n"
         "#13=IFCDIRECTION((0.,0.,1.));\n#14=IFCDIRECTION((1.,0.,0.));\n"
         "#20=IFCBUILDING('2FCZDorxHDT8NI01kdXi8P',$,'Building',$,$,#21,$,$,.ELEMENT.,$,$,$);\n"
         "#21=IFCLOCALPLACEMENT($,#24);\n#24=IFCAXIS2PLACEMENT3D(#25,$,$);\n"
         "#25=IFCCARTESIANPOINT((" +
         L(s.site_x_m) + "," + L(s.site_y_m) +
         ",0.));\n"
         "#22=IFCRELAGGREGATES('3qzoyCPy1CtfV237Rle9$t',$,$,$,#1,(#20));\n"
         "#30=IFCBUILDINGSTOREY('0w984V0GL6yR4z75YWgVfX',$,'Ground "
         "floor',$,$,#31,$,$,.ELEMENT.,0.);\n"
         "#31=IFCLOCALPLACEMENT(#21,#11);\n"
         "#32=IFCBUILDINGSTOREY('1kTvXnbbzCWw8lcMd1dR4o',$,'First floor',$,$,#33,$,$,.ELEMENT.," +
         (s.first_floor_elevation ? L(3.0) : "$") +
         ");\n"
         "#33=IFCLOCALPLACEMENT(#21,#34);\n#34=IFCAXIS2PLACEMENT3D(#35,$,$);\n"
         "#35=IFCCARTESIANPOINT((0.,0.," +
         L(3.0) +
         "));\n"
         "#36=IFCRELAGGREGATES('2KCuWpxWz0dOIBT1KsPqR1',$,$,$,#20,(#32,#30));\n";
    // A box-shaped body: an extruded rectangle with its corner at the placement's origin.
    auto box = [&](int id, double dx, double dy, double dz) {
        const std::string i = std::to_string(id);
        auto n = [&](int k) { return "#" + std::to_string(id + k); };
        return "#" + i + "=IFCPRODUCTDEFINITIONSHAPE($,$,(" + n(1) + "));\n" + n(1) +
               "=IFCSHAPEREPRESENTATION(#10,'Body','SweptSolid',(" + n(2) + "));\n" + n(2) +
               "=IFCEXTRUDEDAREASOLID(" + n(3) + ",#11,#13," + L(dz) + ");\n" + n(3) +
               "=IFCRECTANGLEPROFILEDEF(.AREA.,$," + n(4) + "," + L(dx) + "," + L(dy) + ");\n" +
               n(4) + "=IFCAXIS2PLACEMENT2D(" + n(5) + ",$);\n" + n(5) + "=IFCCARTESIANPOINT((" +
               L(dx / 2) + "," + L(dy / 2) + "));\n";
    };
    auto place = [&](int id, const std::string& rel_to, double x, double y, double z) {
        const std::string i = std::to_string(id);
        return "#" + i + "=IFCLOCALPLACEMENT(" + rel_to + ",#" + std::to_string(id + 1) + ");\n#" +
               std::to_string(id + 1) + "=IFCAXIS2PLACEMENT3D(#" + std::to_string(id + 2) +
               ",#13,#14);\n#" + std::to_string(id + 2) + "=IFCCARTESIANPOINT((" + L(x) + "," +
               L(y) + "," + L(z) + "));\n";
    };
    t += "#40=IFCWALL('3vB2YO$MX4xv5uCqZZG05x',$,'Wall 1',$,$,#41,#45,$,.STANDARD.);\n" +
         place(41, "#31", 1, 2, 0) + box(45, 4.0, 0.2, 2.5);
    // The opening reaches 0.1 m beyond both faces of the wall, as exporters make them.
    t += "#60=IFCOPENINGELEMENT('1Ugw1Yvqf8pf4iVDbYPnRy',$,'Opening',$,$,#61,#65,$,.OPENING.);\n" +
         place(61, "#41", 1.5, -0.1, 0.8) + box(65, 1.0, 0.4, 1.2) +
         "#71=IFCRELVOIDSELEMENT('0gqEDCKR53ZOP4OFwXV2a2',$,$,$,#40,#60);\n";
    t += "#80=IFCWINDOW('2Vo8NEJIz6hgbV0aHAHFZb',$,'Window 1',$,$,#81,#85,$," + L(1.2) + "," +
         L(1.0) + ",.WINDOW.,.SINGLE_PANEL.,$);\n" + place(81, "#61", 0, 0.175, 0) +
         box(85, 1.0, 0.05, 1.2) +
         "#91=IFCRELFILLSELEMENT('1c8cMsAGD5nBjBmwjQ5Ux$',$,$,$,#60,#80);\n";
    t += "#100=IFCSPACE('0BTBFw6f90Nfh9rP1dlXrb',$,'Room 1',$,$,#31,$,$,.ELEMENT.,.INTERNAL.,$);\n"
         "#101=IFCRELAGGREGATES('1mAHpTZfTAJxZPr8V2YCjp',$,$,$,#30,(#100));\n";
    t += "#110=IFCSLAB('2cCrhzNuj4dPY$sBCAKY4m',$,'Slab 1',$,$,#111,#115,$,.FLOOR.);\n" +
         place(111, "#33", 0, 0, 0) + box(115, 6.0, 5.0, 0.2);
    t += "#140=IFCCURTAINWALL('0pCGvT2vn1bB0rdfm3V3Qx',$,'Curtain "
         "wall',$,$,#141,$,$,.NOTDEFINED.);\n" +
         place(141, "#31", 7, 0, 0) +
         "#145=IFCPLATE('3b3UVOHiH2xQ0wdMrmZ2Ng',$,'Panel',$,$,#146,#150,$,.CURTAIN_PANEL.);\n" +
         place(146, "#141", 0, 0, 0) + box(150, 1.0, 0.05, 2.0) +
         "#157=IFCRELAGGREGATES('1GVwuIWm1EOAhBKEZ2n4Lb',$,$,$,#140,(#145));\n" +
         "#160=IFCMEMBER('2x6sKxy0bBcfDa2Kp_pq1y',$,'Post',$,$,#161,#165,$,.POST.);\n" +
         place(161, "#31", 7.5, 1, 0) + box(165, 0.1, 0.1, 2.5);
    std::string ground = "#40,#80,#140,#160";
    if (s.broken_wall) {
        t +=
            "#180=IFCWALL('1OLhAj5C1F5ePgxTqBpBVR',$,'Broken wall',$,$,#181,#185,$,.STANDARD.);\n" +
            place(181, "#31", 0, 4, 0) +
            "#185=IFCPRODUCTDEFINITIONSHAPE($,$,(#186));\n"
            "#186=IFCSHAPEREPRESENTATION(#10,'Body','SweptSolid',(#187));\n"
            "#187=IFCEXTRUDEDAREASOLID($,#11,#13," +
            L(2.5) + ");\n";
        ground += ",#180";
    }
    t += "#130=IFCRELCONTAINEDINSPATIALSTRUCTURE('3Sa3dTJGn0H8TQIGiuGQd5',$,$,$,(" + ground +
         "),#30);\n"
         "#131=IFCRELCONTAINEDINSPATIALSTRUCTURE('0Kt0VKkBj7WRVpSv8YdHQ9',$,$,$,(#110),#32);\n"
         "ENDSEC;\nEND-ISO-10303-21;\n";
    return t;
}

const BimElement* Find(const BimModel& m, const std::string& ifc_class) {
    for (const auto& e : m.elements) {
        if (e.ifc_class == ifc_class) return &e;
    }
    return nullptr;
}

Eigen::Vector3d Corner(const BimModel& m, uint32_t t, int k) {
    return m.mesh.vertices[m.mesh.triangles[t][k]].cast<double>() + m.origin_m;
}

// Volume enclosed by an element's triangles (divergence theorem): positive for closed meshes
// wound counter-clockwise seen from outside.
double Volume(const BimModel& m, const BimElement& e) {
    double v = 0;
    for (uint32_t t = e.first_triangle; t < e.first_triangle + e.triangle_count; ++t) {
        v += Corner(m, t, 0).dot(Corner(m, t, 1).cross(Corner(m, t, 2))) / 6.0;
    }
    return v;
}

// How many of an element's triangles the line p + s * dir (any s) crosses (Moeller-Trumbore).
int Crossings(const BimModel& m, const BimElement& e, const Eigen::Vector3d& p,
              const Eigen::Vector3d& dir) {
    int n = 0;
    for (uint32_t t = e.first_triangle; t < e.first_triangle + e.triangle_count; ++t) {
        const Eigen::Vector3d a = Corner(m, t, 0), e1 = Corner(m, t, 1) - a,
                              e2 = Corner(m, t, 2) - a;
        const Eigen::Vector3d h = dir.cross(e2);
        const double det = e1.dot(h);
        if (std::abs(det) < 1e-12) continue;
        const Eigen::Vector3d s = p - a;
        const double u = s.dot(h) / det;
        const Eigen::Vector3d q = s.cross(e1);
        const double v = dir.dot(q) / det;
        if (u >= 0 && v >= 0 && u + v <= 1) ++n;
    }
    return n;
}

TEST(IfcModel, WallWithAWindowOpeningHasAHole) {
    const BimModel m = ParseIfc("minimal.ifc", MinimalIfc());
    EXPECT_EQ(m.file, "minimal.ifc");
    EXPECT_EQ(m.schema, "IFC4");
    EXPECT_DOUBLE_EQ(m.length_unit_m, 1.0);
    EXPECT_TRUE(m.failed.empty()) << m.failed.front().reason;
    const BimElement* wall = Find(m, "IfcWall");
    ASSERT_NE(wall, nullptr);
    EXPECT_EQ(wall->global_id, "3vB2YO$MX4xv5uCqZZG05x");
    EXPECT_EQ(wall->name, "Wall 1");
    EXPECT_EQ(wall->role, ElementRole::kStructure);
    EXPECT_EQ(wall->storey, 0);
    // 4 x 0.2 x 2.5 minus the 1 x 0.2 x 1.2 opening, cut 1 mm wider and higher (ifc_geometry.cpp).
    EXPECT_NEAR(Volume(m, *wall), 2.0 - 0.2 * 1.001 * 1.201, 1e-6);
    const Eigen::Vector3d across(0, 1, 0);
    EXPECT_EQ(Crossings(m, *wall, {3.0, 0, 1.4}, across), 0);  // through the opening
    EXPECT_EQ(Crossings(m, *wall, {2.0, 0, 1.4}, across), 2);  // beside it
    EXPECT_EQ(Crossings(m, *wall, {3.0, 0, 0.4}, across), 2);  // below it
    const BimElement* window = Find(m, "IfcWindow");
    ASSERT_NE(window, nullptr);
    EXPECT_EQ(window->role, ElementRole::kTransient);
    EXPECT_EQ(window->storey, 0);
    EXPECT_NEAR(Volume(m, *window), 1.0 * 0.05 * 1.2, 1e-6);
    const Eigen::AlignedBox3d box = m.Bounds();
    EXPECT_NEAR(box.min().x(), 0.0, 1e-6);
    EXPECT_NEAR(box.max().x(), 8.0, 1e-6);
    EXPECT_NEAR(box.max().y(), 5.0, 1e-6);
    EXPECT_NEAR(box.max().z(), 3.2, 1e-6);
    EXPECT_TRUE(m.origin_m.isZero());
}

TEST(IfcModel, TrianglesAreContiguousPerElementAndShareNoVertices) {
    const BimModel m = ParseIfc("minimal.ifc", MinimalIfc());
    ASSERT_TRUE(m.mesh.IndicesValid());
    ASSERT_EQ(m.triangle_element.size(), m.mesh.triangles.size());
    // wall, window, slab, panel, post (no geometry: the space, the opening, the curtain wall)
    ASSERT_EQ(m.elements.size(), 5u);
    std::vector<int> owner(m.mesh.vertices.size(), -1);
    uint32_t next = 0;
    for (size_t i = 0; i < m.elements.size(); ++i) {
        const BimElement& e = m.elements[i];
        EXPECT_EQ(e.first_triangle, next);
        EXPECT_GT(e.triangle_count, 0u);
        next += e.triangle_count;
        for (uint32_t t = e.first_triangle; t < e.first_triangle + e.triangle_count; ++t) {
            EXPECT_EQ(m.triangle_element[t], i);
            for (const uint32_t v : m.mesh.triangles[t]) {
                EXPECT_TRUE(owner[v] == -1 || owner[v] == int(i)) << "vertex " << v << " shared";
                owner[v] = int(i);
            }
            const Eigen::Vector3d n =
                (Corner(m, t, 1) - Corner(m, t, 0)).cross(Corner(m, t, 2) - Corner(m, t, 0));
            EXPECT_GT(n.norm(), 0.0);
        }
        EXPECT_GT(Volume(m, e), 0.0) << e.ifc_class << ": closed, wound outwards";
    }
    EXPECT_EQ(next, m.mesh.triangles.size());
    for (const auto& v : m.mesh.vertices) EXPECT_TRUE(v.allFinite());
}

TEST(IfcModel, MillimetresGiveTheSameMetresAsMetres) {
    const BimModel m = ParseIfc("m.ifc", MinimalIfc());
    const BimModel mm = ParseIfc("mm.ifc", MinimalIfc(Spec().Units(1000)));
    EXPECT_DOUBLE_EQ(m.length_unit_m, 1.0);
    EXPECT_DOUBLE_EQ(mm.length_unit_m, 0.001);
    ASSERT_EQ(mm.elements.size(), m.elements.size());
    ASSERT_EQ(mm.storeys.size(), 2u);
    EXPECT_NEAR(mm.storeys[1].elevation_m, 3.0, 1e-9);
    for (size_t i = 0; i < m.elements.size(); ++i) {
        const BimElement &a = m.elements[i], &b = mm.elements[i];
        ASSERT_EQ(a.global_id, b.global_id);
        EXPECT_NEAR(Volume(mm, b), Volume(m, a), 1e-6) << a.ifc_class;
        // The same surface: every corner of one is a corner of the other.
        auto corners = [](const BimModel& x, const BimElement& e) {
            std::vector<Eigen::Vector3d> c;
            for (uint32_t t = e.first_triangle; t < e.first_triangle + e.triangle_count; ++t) {
                for (int k = 0; k < 3; ++k) c.push_back(Corner(x, t, k));
            }
            return c;
        };
        const auto ca = corners(m, a), cb = corners(mm, b);
        for (const auto& p : cb) {
            double best = 1e9;
            for (const auto& q : ca) best = std::min(best, (p - q).norm());
            ASSERT_LT(best, 1e-5) << a.ifc_class << " corner " << p.transpose();
        }
    }
    const Eigen::AlignedBox3d ba = m.Bounds(), bb = mm.Bounds();
    EXPECT_LT((ba.min() - bb.min()).norm(), 1e-5);
    EXPECT_LT((ba.max() - bb.max()).norm(), 1e-5);
}

TEST(IfcModel, StoreysSortedWithElevationsInMetres) {
    for (const double units : {1.0, 1000.0}) {
        const BimModel m = ParseIfc("m.ifc", MinimalIfc(Spec().Units(units)));
        ASSERT_EQ(m.storeys.size(), 2u);
        EXPECT_EQ(m.storeys[0].name, "Ground floor");  // listed second in the file
        EXPECT_EQ(m.storeys[0].global_id, "0w984V0GL6yR4z75YWgVfX");
        EXPECT_DOUBLE_EQ(m.storeys[0].elevation_m, 0.0);
        EXPECT_EQ(m.storeys[1].name, "First floor");
        EXPECT_NEAR(m.storeys[1].elevation_m, 3.0, 1e-9);
        const BimElement* slab = Find(m, "IfcSlab");
        ASSERT_NE(slab, nullptr);
        EXPECT_EQ(slab->storey, 1);
    }
    // Without an Elevation, the storey's placement says where it is.
    const BimModel m = ParseIfc("m.ifc", MinimalIfc(Spec().Units(1000).NoFirstFloorElevation()));
    ASSERT_EQ(m.storeys.size(), 2u);
    EXPECT_NEAR(m.storeys[1].elevation_m, 3.0, 1e-9);
}

// A walk with no storey named takes the lowest a person stands in: Duplex_A's storeys (its
// foundation level 1.25 m under Level 1) give Level 1; storeys all 2 m apart, the lowest.
TEST(IfcModel, AWalksDefaultStoreyPassesOverAFoundationLevel) {
    BimModel m;
    EXPECT_EQ(DefaultWalkStorey(m), 0) << "no storeys";
    m.storeys = {
        {"T/FDN", "a", -1.25}, {"Level 1", "b", 0.0}, {"Level 2", "c", 3.1}, {"Roof", "d", 6.0}};
    EXPECT_EQ(DefaultWalkStorey(m), 1);
    m.storeys = {{"Ground", "a", 0.0}, {"First", "b", 2.0}};
    EXPECT_EQ(DefaultWalkStorey(m), 0);
    m.storeys = {{"Crawl space", "a", -1.0}, {"Loft", "b", 0.0}};
    EXPECT_EQ(DefaultWalkStorey(m), 1) << "the last one counts as high enough";
}

TEST(IfcModel, ClassCountsIncludeProductsWithoutGeometry) {
    const BimModel m = ParseIfc("m.ifc", MinimalIfc());
    const std::map<std::string, size_t> expected = {
        {"IfcBuilding", 1},       {"IfcBuildingStorey", 2}, {"IfcCurtainWall", 1}, {"IfcMember", 1},
        {"IfcOpeningElement", 1}, {"IfcPlate", 1},          {"IfcSlab", 1},        {"IfcSpace", 1},
        {"IfcWall", 1},           {"IfcWindow", 1}};
    EXPECT_EQ(m.class_counts, expected);
    EXPECT_EQ(Find(m, "IfcSpace"), nullptr);
    EXPECT_EQ(Find(m, "IfcOpeningElement"), nullptr);
}

TEST(IfcModel, OptionsAddOpeningsAndMakeRailingsTransient) {
    IfcLoadOptions options;
    options.opening_geometry = true;
    const BimModel m = ParseIfc("m.ifc", MinimalIfc(), options);
    const BimElement* opening = Find(m, "IfcOpeningElement");
    ASSERT_NE(opening, nullptr);
    EXPECT_EQ(opening->role, ElementRole::kTransient);
    EXPECT_EQ(opening->storey, 0);  // through the wall it voids
    EXPECT_NEAR(Volume(m, *opening), 1.0 * 0.4 * 1.2, 1e-6);

    options = {};
    options.vertices_per_circle = 2;
    EXPECT_THROW(options.Validate(), common::Error);
    EXPECT_THROW(ParseIfc("m.ifc", MinimalIfc(), options), common::Error);
}

TEST(IfcModel, CurtainWallPartsAreTransientFreeMembersStructure) {
    const BimModel m = ParseIfc("m.ifc", MinimalIfc());
    const BimElement* panel = Find(m, "IfcPlate");
    ASSERT_NE(panel, nullptr);
    EXPECT_EQ(panel->role, ElementRole::kTransient);
    EXPECT_EQ(panel->storey, 0);  // through its curtain wall
    const BimElement* post = Find(m, "IfcMember");
    ASSERT_NE(post, nullptr);
    EXPECT_EQ(post->role, ElementRole::kStructure);
}

TEST(IfcModel, RoleOfClass) {
    for (const char* structure : {"IfcWall",
                                  "IfcWallStandardCase",
                                  "IfcWallElementedCase",
                                  "IfcSlab",
                                  "IfcSlabStandardCase",
                                  "IfcColumn",
                                  "IfcColumnStandardCase",
                                  "IfcBeam",
                                  "IfcBeamStandardCase",
                                  "IfcStair",
                                  "IfcStairFlight",
                                  "IfcRamp",
                                  "IfcRampFlight",
                                  "IfcRoof",
                                  "IfcCovering",
                                  "IfcMember",
                                  "IfcMemberStandardCase",
                                  "IfcPlate",
                                  "IfcPlateStandardCase",
                                  "IfcRailing",
                                  "IFCWALLSTANDARDCASE"}) {
        EXPECT_EQ(RoleOfClass(structure), ElementRole::kStructure) << structure;
    }
    for (const char* transient :
         {"IfcDoor", "IfcDoorStandardCase", "IfcWindow", "IfcCurtainWall", "IfcSpace",
          "IfcFurnishingElement", "IfcFurniture", "IfcBuildingElementProxy", "IfcFlowTerminal",
          "IfcOpeningElement", "IfcSite", "IfcAnnotation", "IfcWallType", "IfcStandardCase", ""}) {
        EXPECT_EQ(RoleOfClass(transient), ElementRole::kTransient) << transient;
    }
    IfcLoadOptions no_railings;
    no_railings.railings_are_structure = false;
    EXPECT_EQ(RoleOfClass("IfcRailing", no_railings), ElementRole::kTransient);
}

TEST(IfcModel, FarFromTheOriginStoresRelativeToWholeMetres) {
    const BimModel m = ParseIfc("far.ifc", MinimalIfc(Spec().Site(691234.567, 5334567.891)));
    EXPECT_FALSE(m.origin_m.isZero());
    EXPECT_EQ(m.origin_m, m.origin_m.array().round().matrix());
    const Eigen::AlignedBox3d box = m.Bounds();
    EXPECT_NEAR(box.min().x(), 691234.567, 1e-3);
    EXPECT_NEAR(box.max().y(), 5334567.891 + 5.0, 1e-3);
    for (const auto& v : m.mesh.vertices) EXPECT_LT(v.norm(), 100.0f);
    const BimElement* wall = Find(m, "IfcWall");
    ASSERT_NE(wall, nullptr);
    EXPECT_NEAR(Volume(m, *wall), 2.0 - 0.2 * 1.001 * 1.201, 1e-3);  // floats keep millimetres
}

TEST(IfcModel, ElementWithBrokenGeometryIsReportedNotFatal) {
    const BimModel m = ParseIfc("broken.ifc", MinimalIfc(Spec().BrokenWall()));
    ASSERT_EQ(m.failed.size(), 1u);
    EXPECT_EQ(m.failed[0].global_id, "1OLhAj5C1F5ePgxTqBpBVR");
    EXPECT_EQ(m.failed[0].ifc_class, "IfcWall");
    EXPECT_FALSE(m.failed[0].reason.empty());
    EXPECT_EQ(m.elements.size(), 5u);
    EXPECT_EQ(m.class_counts.at("IfcWall"), 2u);
}

TEST(IfcModel, MessagesAreCollectedNotPrinted) {
    std::string text = MinimalIfc();
    text.insert(text.find("#1="), "#999=IFCFROBNICATOR('x',$);\n");
    testing::internal::CaptureStdout();
    testing::internal::CaptureStderr();
    const BimModel m = ParseIfc("m.ifc", text);
    EXPECT_EQ(testing::internal::GetCapturedStdout(), "");
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
    EXPECT_EQ(m.elements.size(), 5u);
    ASSERT_FALSE(m.warnings.empty());
    EXPECT_GE(m.warning_count, m.warnings.size());
    bool named = false;
    for (const auto& w : m.warnings) named |= w.find("IFCFROBNICATOR") != std::string::npos;
    EXPECT_TRUE(named) << m.warnings.front();
}

TEST(IfcModel, ReportsProgressUpToOne) {
    std::vector<double> seen;
    IfcLoadOptions options;
    options.progress = [&](double f) { seen.push_back(f); };
    ParseIfc("m.ifc", MinimalIfc(), options);
    ASSERT_GE(seen.size(), 3u);
    EXPECT_EQ(seen.front(), 0.0);
    EXPECT_EQ(seen.back(), 1.0);
    for (const double f : seen) {
        EXPECT_GE(f, 0.0);
        EXPECT_LE(f, 1.0);
    }
}

TEST(IfcModel, IfcAddendaAreReadAsIfc4) {
    const BimModel m = ParseIfc("add2.ifc", MinimalIfc(Spec().Schema("IFC4_ADD2_TC1")));
    EXPECT_EQ(m.schema, "IFC4");
    EXPECT_EQ(m.elements.size(), 5u);
}

// Expects ParseIfc to throw a FileError with `code` naming the file.
void ExpectError(const std::string& text, StatusCode code, const std::string& says) {
    try {
        ParseIfc("bad.ifc", text);
        ADD_FAILURE() << "no error; expected " << ToString(code) << " (" << says << ")";
    } catch (const common::FileError& e) {
        EXPECT_EQ(e.code(), code) << e.what();
        EXPECT_EQ(e.path(), "bad.ifc");
        EXPECT_NE(std::string(e.what()).find("bad.ifc"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
}

TEST(IfcModel, BadInputIsAnErrorNamingTheFile) {
    const std::string good = MinimalIfc();
    ExpectError("", StatusCode::kParseError, "not an ISO-10303-21 (STEP) file");
    ExpectError("hello world\n", StatusCode::kParseError, "not an ISO-10303-21 (STEP) file");
    ExpectError("\x89PNG\r\n\x1a\n" + std::string(100, '\x01'), StatusCode::kParseError,
                "not an ISO-10303-21");
    ExpectError(good.substr(0, good.size() / 2), StatusCode::kDataLoss,
                "cut off: no END-ISO-10303-21");
    ExpectError(good.substr(0, good.find("ENDSEC;\nEND-ISO")), StatusCode::kDataLoss,
                "cut off: no END-ISO-10303-21");
    // cut inside a string and inside a comment
    ExpectError(good.substr(0, good.find("Wall 1") + 2), StatusCode::kDataLoss, "never closes");
    std::string comment = good;
    comment.insert(comment.find("#40="), "/* a comment that is cut off ");
    ExpectError(comment.substr(0, comment.find("cut off") + 7), StatusCode::kDataLoss,
                "never closes");
    ExpectError(MinimalIfc(Spec().Schema("IFC4X3")), StatusCode::kParseError, "IFC4X3");
    ExpectError(MinimalIfc(Spec().Schema("CONFIG_CONTROL_DESIGN")), StatusCode::kParseError,
                "CONFIG_CONTROL_DESIGN");
    std::string no_schema = good;
    no_schema.erase(no_schema.find("FILE_SCHEMA"),
                    no_schema.find("ENDSEC;") - no_schema.find("FILE_SCHEMA"));
    ExpectError(no_schema, StatusCode::kParseError, "FILE_SCHEMA");
    const std::string head = good.substr(0, good.find("DATA;\n") + 6);
    ExpectError(head + "ENDSEC;\nEND-ISO-10303-21;\n", StatusCode::kParseError, "no entities");
    ExpectError(head + "#1=IFCCARTESIANPOINT((0.,0.,0.));\nENDSEC;\nEND-ISO-10303-21;\n",
                StatusCode::kParseError, "no IfcProject");
    ExpectError(head + "garbage;\n#1=;\n#2=IFCFOO(;\nENDSEC;\nEND-ISO-10303-21;\n",
                StatusCode::kParseError, "");
    std::string nul = good;
    nul[nul.find("Wall 1")] = '\0';
    ExpectError(nul, StatusCode::kParseError, "NUL");
    std::string escape = good;
    escape.replace(escape.find("Wall 1"), 6, "W\\X2\\00");
    ExpectError(escape, StatusCode::kParseError, "escape");
}

TEST(IfcModel, StringsThatConfuseIfcppAreKept) {
    std::string text = MinimalIfc();
    text.replace(text.find("'Wall 1'"), 8, "'Wall /* not a comment */ 1'");
    text.replace(text.find("'Slab 1'"), 8, "'C:\\'");  // a lone backslash before the quote
    text.replace(text.find("'Window 1'"), 10, "'Fen\\X2\\00EA\\X0\\tre'");
    text.replace(text.find("'Post'"), 6, "'Post\\\\'");  // an escaped backslash before the quote
    const BimModel m = ParseIfc("m.ifc", text);
    EXPECT_EQ(m.elements.size(), 5u);
    ASSERT_NE(Find(m, "IfcWall"), nullptr);
    EXPECT_EQ(Find(m, "IfcWall")->name, "Wall /* not a comment */ 1");
    ASSERT_NE(Find(m, "IfcWindow"), nullptr);
    EXPECT_EQ(Find(m, "IfcWindow")->name, "Fen\xC3\xAAtre");
    ASSERT_NE(Find(m, "IfcSlab"), nullptr);
    ASSERT_NE(Find(m, "IfcMember"), nullptr);
    EXPECT_EQ(Find(m, "IfcMember")->name.rfind("Post\\", 0), 0u) << Find(m, "IfcMember")->name;
    EXPECT_EQ(m.storeys.size(), 2u);
}

TEST(IfcModel, MissingFileIsNotFound) {
    test::TempDir tmp;
    const auto path = tmp / "absent.ifc";
    try {
        LoadIfc(path);
        ADD_FAILURE() << "no error";
    } catch (const common::FileError& e) {
        EXPECT_EQ(e.code(), StatusCode::kNotFound) << e.what();
        EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
    }
    test::WriteBytes(tmp / "half.ifc", MinimalIfc().substr(0, 900));
    try {
        LoadIfc(tmp / "half.ifc");
        ADD_FAILURE() << "no error";
    } catch (const common::FileError& e) {
        EXPECT_EQ(e.code(), StatusCode::kDataLoss) << e.what();
        EXPECT_EQ(e.path(), (tmp / "half.ifc").string());
    }
    test::WriteBytes(tmp / "ok.ifc", MinimalIfc());
    EXPECT_EQ(LoadIfc(tmp / "ok.ifc").elements.size(), 5u);
}

// Mutations of a valid file: an error naming the file or a model, never a crash or a hang.
TEST(IfcModel, MutatedFilesNeverCrash) {
    const std::string good = MinimalIfc();
    // Edits land anywhere: the entities IFC++ parses are past the header.
    const auto counts =
        test::FuzzReader("mutant.ifc", {{good, good.size()}}, 300, 7, "0123456789'()#,$.;*/\\XE-\n",
                         [](const std::string& bytes) { ParseIfc("mutant.ifc", bytes); });
    EXPECT_GT(counts.rejected, 0u);
    EXPECT_GT(counts.accepted, 0u);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::bim
