// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// A small IFC4 file the tests write: one IfcFurniture whose body is an IfcFacetedBrep, a square
// frame whose top face lists its bounds in a chosen order (issue 38: IFC++ takes a face's first
// bound as its outer one). Used by tests/unit/bim/ifc_face_bounds_test.cpp and the `bim info`
// tests of tests/integration/cli_test.cpp.
#pragma once

#include <map>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace bimslam::test {

// How the top face lists its bounds.
enum class FrameTop {
    kOuterFirst,          // IfcFaceOuterBound, then the hole (IfcFaceBound): as IFC++ expects
    kHoleFirst,           // the hole, then the IfcFaceOuterBound (Revit 2015 via xBIM does this)
    kUnmarkedHoleFirst,   // two IfcFaceBound, the hole first: the larger loop is the outer one
    kHoleOutsideOfOuter,  // the outer bound first, but the "hole" lies beside it: no valid face
};

// A square frame lying on the floor: 1 x 1 m outside, 0.1 m thick (z 0 .. 0.1), with a
// 0.4 x 0.4 m square hole through it (x and y 0.3 .. 0.7). Ten faces: top and bottom (each an
// outer square and a hole), four outer sides, four sides of the hole; a closed shell, every loop
// wound counter-clockwise seen from outside the solid (holes clockwise in their face). One
// IfcFurniture, lengths in metres times `units_per_metre`.
inline std::string FrameIfc(FrameTop top, double units_per_metre = 1.0) {
    constexpr double kHeight = 0.1;
    using Ring = std::vector<std::pair<double, double>>;
    const Ring outer = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};  // counter-clockwise from above
    const Ring hole = {{0.3, 0.3}, {0.3, 0.7}, {0.7, 0.7}, {0.7, 0.3}};  // clockwise from above
    std::string data;
    int next = 100;
    auto add = [&](const std::string& entity) {
        data += "#" + std::to_string(++next) + "=" + entity + ";\n";
        return "#" + std::to_string(next);
    };
    std::map<std::tuple<double, double, double>, std::string> points;
    auto point = [&](double x, double y, double z) {
        auto [it, fresh] = points.try_emplace({x, y, z});
        if (fresh) {
            auto L = [&](double v) { return std::to_string(v * units_per_metre); };
            it->second = add("IFCCARTESIANPOINT((" + L(x) + "," + L(y) + "," + L(z) + "))");
        }
        return it->second;
    };
    auto loop = [&](const Ring& ring, double z, bool reversed) {
        std::string list;
        for (size_t i = 0; i < ring.size(); ++i) {
            const auto& [x, y] = ring[reversed ? ring.size() - 1 - i : i];
            list += (i == 0 ? "" : ",") + point(x, y, z);
        }
        return add("IFCPOLYLOOP((" + list + "))");
    };
    auto bound = [&](const std::string& type, const std::string& loop_ref) {
        return add(type + "(" + loop_ref + ",.T.)");
    };
    std::vector<std::string> faces;
    auto face = [&](const std::vector<std::string>& bounds) {
        std::string list;
        for (const auto& b : bounds) list += (list.empty() ? "" : ",") + b;
        faces.push_back(add("IFCFACE((" + list + "))"));
    };
    // Top (normal +z): the outer square counter-clockwise from above, the hole clockwise.
    // The broken variant's top hole lies 2 m to the east of the frame: the face has no valid shape.
    Ring top_ring = hole;
    if (top == FrameTop::kHoleOutsideOfOuter) {
        for (auto& corner : top_ring) corner.first += 2.0;
    }
    const std::string top_outer = loop(outer, kHeight, false);
    const std::string top_hole = loop(top_ring, kHeight, false);
    switch (top) {
        case FrameTop::kOuterFirst:
        case FrameTop::kHoleOutsideOfOuter:
            face({bound("IFCFACEOUTERBOUND", top_outer), bound("IFCFACEBOUND", top_hole)});
            break;
        case FrameTop::kHoleFirst:
            face({bound("IFCFACEBOUND", top_hole), bound("IFCFACEOUTERBOUND", top_outer)});
            break;
        case FrameTop::kUnmarkedHoleFirst:
            face({bound("IFCFACEBOUND", top_hole), bound("IFCFACEBOUND", top_outer)});
            break;
    }
    // Bottom (normal -z): both loops reversed, in the order IFC++ expects.
    face({bound("IFCFACEOUTERBOUND", loop(outer, 0, true)),
          bound("IFCFACEBOUND", loop(hole, 0, true))});
    // Sides: along each ring's edge a -> b, the quad a0 b0 b1 a1 faces (b - a) x z: outwards for
    // the counter-clockwise outer square, into the hole for the clockwise hole.
    for (const Ring* ring : {&outer, &hole}) {
        for (size_t i = 0; i < ring->size(); ++i) {
            const auto& [ax, ay] = (*ring)[i];
            const auto& [bx, by] = (*ring)[(i + 1) % ring->size()];
            face({bound("IFCFACEOUTERBOUND",
                        add("IFCPOLYLOOP((" + point(ax, ay, 0) + "," + point(bx, by, 0) + "," +
                            point(bx, by, kHeight) + "," + point(ax, ay, kHeight) + "))"))});
        }
    }
    std::string shell;
    for (const auto& f : faces) shell += (shell.empty() ? "" : ",") + f;
    const std::string brep = add("IFCFACETEDBREP(" + add("IFCCLOSEDSHELL((" + shell + "))") + ")");
    const std::string prefix = units_per_metre == 1000 ? ".MILLI." : "$";
    return "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION(('ViewDefinition [none]'),'2;1');\n"
           "FILE_NAME('frame.ifc','2024-01-01T00:00:00',(''),(''),'bimslam','test','');\n"
           "FILE_SCHEMA(('IFC4'));\nENDSEC;\nDATA;\n"
           "#1=IFCPROJECT('0YvctVUKr0kugbFTf53O9L',$,'Test',$,$,$,$,(#10),#2);\n"
           "#2=IFCUNITASSIGNMENT((#3));\n#3=IFCSIUNIT(*,.LENGTHUNIT.," +
           prefix +
           ",.METRE.);\n"
           "#10=IFCGEOMETRICREPRESENTATIONCONTEXT($,'Model',3,1.0E-5,#11,$);\n"
           "#11=IFCAXIS2PLACEMENT3D(#12,$,$);\n#12=IFCCARTESIANPOINT((0.,0.,0.));\n"
           "#20=IFCBUILDING('2FCZDorxHDT8NI01kdXi8P',$,'Building',$,$,#21,$,$,.ELEMENT.,$,$,$);\n"
           "#21=IFCLOCALPLACEMENT($,#11);\n"
           "#22=IFCRELAGGREGATES('3qzoyCPy1CtfV237Rle9$t',$,$,$,#1,(#20));\n"
           "#30=IFCBUILDINGSTOREY('0w984V0GL6yR4z75YWgVfX',$,'Ground',$,$,#31,$,$,.ELEMENT.,0.);\n"
           "#31=IFCLOCALPLACEMENT(#21,#11);\n"
           "#32=IFCRELAGGREGATES('2KCuWpxWz0dOIBT1KsPqR1',$,$,$,#20,(#30));\n"
           "#40=IFCFURNITURE('3vB2YO$MX4xv5uCqZZG05x',$,'Frame',$,$,#31,#41,$,$);\n"
           "#41=IFCPRODUCTDEFINITIONSHAPE($,$,(#42));\n"
           "#42=IFCSHAPEREPRESENTATION(#10,'Body','Brep',(" +
           brep +
           "));\n"
           "#43=IFCRELCONTAINEDINSPATIALSTRUCTURE('3Sa3dTJGn0H8TQIGiuGQd5',$,$,$,(#40),#30);\n" +
           data + "ENDSEC;\nEND-ISO-10303-21;\n";
}

}  // namespace bimslam::test
