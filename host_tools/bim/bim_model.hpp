// A building model as the host tools use it: its storeys, its elements (with IFC class, GlobalId
// and storey), and one triangle mesh of their geometry in metres, each triangle tagged with its
// element. ifc_model.hpp fills it from an IFC file (the only code that includes IFC++); the
// occupancy grid, the coverage path, the LiDAR simulation and the change detection read it.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "algorithms/common/triangle_mesh.hpp"

namespace bimslam::bim {

struct BimStorey {
    std::string name;
    std::string global_id;
    double elevation_m = 0.0;  // IfcBuildingStorey.Elevation, in metres
};

// What the LiDAR sees of an element: permanent structure (walls, slabs, columns, beams, stairs,
// roofs, coverings; railings configurable) or the rest (doors, windows, curtain walls, spaces,
// furniture, proxies: things a LiDAR sees through, or that move). The paper's semantic filter.
enum class ElementRole : uint8_t { kStructure, kTransient };

struct BimElement {
    std::string global_id;
    std::string ifc_class;  // e.g. "IfcWallStandardCase"
    std::string name;
    int storey = -1;  // index into BimModel::storeys, -1 when not contained in one
    ElementRole role = ElementRole::kTransient;
    uint32_t first_triangle = 0;  // its triangles are [first_triangle, first_triangle + count)
    uint32_t triangle_count = 0;
};

// An element whose geometry could not be built: reported, skipped, never fatal.
struct FailedElement {
    std::string global_id;
    std::string ifc_class;
    std::string reason;
};

struct BimModel {
    std::string file;             // where it came from
    std::string schema;           // "IFC2X3", "IFC4", ...
    double length_unit_m = 1.0;   // the file's length unit in metres (0.001 for millimetres)
    std::vector<BimStorey> storeys;  // by elevation, lowest first
    std::vector<BimElement> elements;  // elements with geometry, triangles contiguous per element
    // Every IfcProduct subtype in the file (spaces included, with or without geometry) -> count.
    std::map<std::string, size_t> class_counts;
    std::vector<FailedElement> failed;

    common::TriangleMesh mesh;              // metres, the model's coordinate system ("bim" frame)
    std::vector<uint32_t> triangle_element;  // per triangle: index into elements

    Eigen::AlignedBox3d Bounds() const;  // of the mesh; empty box when there is no geometry
};

}  // namespace bimslam::bim
