// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// A synthetic storey for the tests of the grid, the walk and the reference session: 12 x 8 m,
// two south rooms and a north room off a corridor (y 3.5 .. 5), 1 m doors, a desk, an open door
// leaf. Walls are 0.2 m thick boxes, 3 m high, between a floor and a ceiling slab.
#pragma once

#include <algorithm>
#include <string>

#include "host_tools/bim/bim_model.hpp"

namespace bimslam::bim::test_floor {

// Appends an axis-aligned box as an element.
inline void AddBox(BimModel& m, const std::string& cls, ElementRole role, Eigen::Vector3d lo,
                   Eigen::Vector3d hi) {
    BimElement e;
    e.global_id = "box" + std::to_string(m.elements.size());
    e.ifc_class = cls;
    e.role = role;
    e.storey = 0;
    e.first_triangle = uint32_t(m.mesh.triangles.size());
    const uint32_t base = uint32_t(m.mesh.vertices.size());
    for (int i = 0; i < 8; ++i) {
        m.mesh.vertices.emplace_back(float(i & 1 ? hi.x() : lo.x()), float(i & 2 ? hi.y() : lo.y()),
                                     float(i & 4 ? hi.z() : lo.z()));
    }
    const uint32_t faces[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6},
                                   {0, 1, 4}, {1, 5, 4}, {2, 6, 3}, {3, 6, 7},
                                   {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
    for (const auto& f : faces) {
        m.mesh.triangles.push_back({base + f[0], base + f[1], base + f[2]});
        m.triangle_element.push_back(uint32_t(m.elements.size()));
    }
    e.triangle_count = 12;
    m.elements.push_back(e);
}

inline void Wall(BimModel& m, double x0, double y0, double x1, double y1) {
    const double t = 0.1;  // half thickness
    AddBox(m, "IfcWall", ElementRole::kStructure, {std::min(x0, x1) - t, std::min(y0, y1) - t, 0},
           {std::max(x0, x1) + t, std::max(y0, y1) + t, 3});
}

// 12 x 8 m: two south rooms and a north room off a corridor (y 3.5..5), 1 m doors, a desk.
inline BimModel Floor() {
    BimModel m;
    m.file = "synthetic";
    m.storeys.push_back({"Ground", "g", 0.0});
    Wall(m, 0, 0, 12, 0);
    Wall(m, 0, 8, 12, 8);
    Wall(m, 0, 0, 0, 8);
    Wall(m, 12, 0, 12, 8);
    Wall(m, 0, 3.5, 2, 3.5);  // south side of the corridor, doors at x 2..3 and 8..9
    Wall(m, 3, 3.5, 8, 3.5);
    Wall(m, 9, 3.5, 12, 3.5);
    Wall(m, 6, 0, 6, 3.5);
    Wall(m, 0, 5, 5, 5);  // north side, door at x 5..6
    Wall(m, 6, 5, 12, 5);
    AddBox(m, "IfcSlab", ElementRole::kStructure, {-0.1, -0.1, -0.2}, {12.1, 8.1, 0});
    AddBox(m, "IfcSlab", ElementRole::kStructure, {-0.1, -0.1, 3.0}, {12.1, 8.1, 3.2});
    AddBox(m, "IfcFurniture", ElementRole::kTransient, {9, 6.5, 0}, {10.5, 7.3, 0.75});
    AddBox(m, "IfcDoor", ElementRole::kTransient, {2, 3.45, 0}, {2.05, 4.4, 2.0});  // open leaf
    return m;
}

// A slab of structure, the quadrilateral a b c d (two triangles), as element `id`.
inline void AddSlabFace(BimModel& m, const std::string& id, const Eigen::Vector3f& a,
                        const Eigen::Vector3f& b, const Eigen::Vector3f& c,
                        const Eigen::Vector3f& d) {
    BimElement e;
    e.global_id = id;
    e.ifc_class = "IfcSlab";
    e.role = ElementRole::kStructure;
    e.first_triangle = uint32_t(m.mesh.triangles.size());
    e.triangle_count = 2;
    const uint32_t base = uint32_t(m.mesh.vertices.size());
    for (const Eigen::Vector3f& v : {a, b, c, d}) m.mesh.vertices.push_back(v);
    m.mesh.triangles.push_back({base, base + 1, base + 2});
    m.mesh.triangles.push_back({base, base + 2, base + 3});
    m.triangle_element.insert(m.triangle_element.end(), 2, uint32_t(m.elements.size()));
    m.elements.push_back(e);
}

// A sloped roof face over the north room: z 3 at y 5 down to 1 at y 8 (two triangles).
inline void AddRoofFace(BimModel& m) {
    AddSlabFace(m, "roof", {0, 5, 3}, {12, 5, 3}, {12, 8, 1}, {0, 8, 1});
}

}  // namespace bimslam::bim::test_floor
