// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// A building model as the host tools use it: its storeys, its elements (with IFC class, GlobalId
// and storey), and one triangle mesh of their geometry in metres, each triangle tagged with its
// element. ifc_model.hpp fills it from an IFC file (the only code that includes IFC++); the
// occupancy grid, the coverage path, the LiDAR simulation and the change detection read it.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <string_view>
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
// "structure" / "transient".
std::string_view ToString(ElementRole role);

// Elements a walking robot passes and a LiDAR sees through: doors (taken as open), windows and
// curtain walls (glass), spaces, openings, virtual elements and annotations (not physical).
bool PassThrough(std::string_view ifc_class);

// What the model's author wrote of a stair flight (IfcStairFlight's NumberOfRisers,
// NumberOfTreads, RiserHeight and TreadLength, attributes in IFC2X3 and IFC4 alike), kept to check
// the flights found from the geometry against (stairs.hpp). 0 where the file leaves one unset.
struct DeclaredFlight {
    int risers = 0;
    int treads = 0;
    double riser_height_m = 0;  // in metres as the file's length unit reads them
    double tread_length_m = 0;
    double length_unit_m = 1.0;  // the file's length unit (what the lengths were multiplied by)
    bool Any() const {
        return risers > 0 || treads > 0 || riser_height_m > 0 || tread_length_m > 0;
    }
};

struct BimElement {
    std::string global_id;
    std::string ifc_class;  // e.g. "IfcWallStandardCase"
    std::string name;
    int storey = -1;  // index into BimModel::storeys, -1 when not contained in one
    ElementRole role = ElementRole::kTransient;
    uint32_t first_triangle = 0;  // its triangles are [first_triangle, first_triangle + count)
    uint32_t triangle_count = 0;
    // A spatial element's IfcSpatialElement.LongName: a space's "Open office", whose Name is often
    // its number ("0.00"); "" for other elements and when the file has none.
    std::string long_name{};
    DeclaredFlight declared_flight{};  // an IfcStairFlight's attributes; all 0 for other elements
    // Not in the file: a floor the ingest assumed where the file models none (assumed_floors.hpp).
    bool assumed = false;
};

// An element whose geometry could not be built (reported, skipped, never fatal), or was built
// without some of its faces (BimModel::incomplete).
struct FailedElement {
    std::string global_id;
    std::string ifc_class;
    std::string reason;
};

// A floor the ingest assumed where the file models none (assumed_floors.hpp).
struct AssumedFloor {
    int storey = -1;
    double area_m2 = 0;     // of its top
    double opening_m2 = 0;  // left open over stairs and ramps that climb to it
};

struct BimModel {
    std::string file;                  // where it came from
    std::string schema;                // "IFC2X3", "IFC4", ...
    double length_unit_m = 1.0;        // the file's length unit in metres (0.001 for millimetres)
    std::vector<BimStorey> storeys;    // by elevation, lowest first
    std::vector<BimElement> elements;  // elements with geometry, triangles contiguous per element
    // Every IfcProduct subtype in the file (spaces included, with or without geometry) -> count.
    std::map<std::string, size_t> class_counts;
    std::vector<FailedElement> failed;
    // Faces (IfcFace) of breps and surface models listed with a hole before their outer boundary,
    // or with no boundary marked outer: IFC++ takes the first as the outer one and would drop the
    // face, so the ingest puts the outer one (else the largest loop) first. Counted once a face.
    size_t faces_reordered = 0;
    // Faces IFC++ still could not triangulate, each counted once; the elements that lack them are
    // in `incomplete` (they have geometry, so they are in `elements` too), the reason names them.
    size_t faces_lost = 0;
    std::vector<FailedElement> incomplete;
    // What the reader reported while loading (IFC++'s messages, deduplicated, "<class> <GlobalId>:
    // <message>" when about one element), at most a few hundred; warning_count counts them all.
    std::vector<std::string> warnings;
    size_t warning_count = 0;
    // Floors not in the file, assumed under storeys whose floor it does not model; their elements
    // are flagged BimElement::assumed.
    std::vector<AssumedFloor> assumed_floors;

    // Metres, the model's coordinate system ("bim" frame) minus origin_m. Vertices are never shared
    // between elements: each element's triangles index only its own vertices.
    common::TriangleMesh mesh;
    std::vector<uint32_t> triangle_element;  // per triangle: index into elements
    // Zero unless the geometry lies far (> 10 km) from the model's origin: then the mesh is stored
    // relative to this point (whole metres) so that float vertices keep millimetres.
    Eigen::Vector3d origin_m = Eigen::Vector3d::Zero();

    // Of the mesh, in the model's coordinates (origin_m added); an empty box without geometry.
    Eigen::AlignedBox3d Bounds() const;
};

// The index of the storey called `name`; throws common::Error (kInvalidArgument) naming the
// storeys the model has when there is none.
int FindStorey(const BimModel& model, const std::string& name);
// The storey a walk takes when none is named: the lowest with at least kMinWalkStoreyHeight to
// the next one (the last one counts as high enough), so that a foundation's or crawl space's level
// is passed over. Duplex_A's lowest, 'T/FDN', lies 1.25 m under 'Level 1': a hand-held sensor
// walked there sat in Level 1's slab and 25 scans held under 50 points. 0 when none qualifies.
inline constexpr double kMinWalkStoreyHeight = 2.0;  // m: a room a person stands in
int DefaultWalkStorey(const BimModel& model);
// The indices of the storeys named, in that order; every storey when `names` is empty.
std::vector<int> StoreyIndices(const BimModel& model, const std::vector<std::string>& names);

// The elements `keep` accepts, with their triangles and only the vertices those use (indices
// renumbered, order kept); storeys, class counts, failures, face counts, warnings and the assumed
// floors' list are copied as they are.
BimModel SelectElements(const BimModel& model, const std::function<bool(const BimElement&)>& keep);

}  // namespace bimslam::bim
