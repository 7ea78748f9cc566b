// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Emission of IFC4 STEP text (ISO 10303-21 clear text encoding) without an IFC library: an
// instance counter and a buffer of "#n=IFCNAME(...);" lines, with helpers for the attribute values
// (lengths in the file's unit, reals, strings, references, GlobalIds) and for the few geometric
// entities the sample building uses (placements, extruded boxes and polygons, shapes). Attribute
// orders follow the IFC4 ADD2 TC1 specification (buildingSMART, IFC4 documentation, section
// "Entity definitions"); each helper names the entity it writes.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace bimslam::bim {

class IfcWriter {
public:
    // length_unit_m: the file's length unit in metres (1, 0.01 or 0.001). seed: mixed into every
    // GlobalId.
    IfcWriter(double length_unit_m, uint64_t seed);
    // A writer of entities to append to an existing file (host_tools/changes, the updated IFC):
    // numbering starts at first_id (above the file's largest), any positive length unit is
    // accepted (the file's own, e.g. 0.3048 for feet), and Data() gives the "#n=...;" lines to
    // insert before the DATA section's ENDSEC. Throws common::Error (kInvalidArgument) for a
    // first_id < 1 or a unit that is not positive and finite.
    static IfcWriter Appending(double length_unit_m, uint64_t seed, int first_id);

    // Appends "#n=NAME(args);" (NAME upper-cased as STEP wants) and returns n (1, 2, ...).
    int Add(std::string_view name, std::string_view args);

    // ---- attribute values -------------------------------------------------------------------
    // A length given in metres, written in the file's unit, rounded to the micrometre: the metre
    // and millimetre files then hold exactly the same numbers, 1000 times apart.
    std::string Len(double metres) const;
    // A unitless real (direction ratios, ratios), shortest exact text, always with a '.'.
    static std::string Real(double v);
    static std::string Ref(int id) { return "#" + std::to_string(id); }
    static std::string Refs(const std::vector<int>& ids);  // "(#1,#2)"
    // A STEP string: quoted, ' and \ escaped; empty gives "$" (unset). ASCII only (throws
    // common::Error kInvalidArgument otherwise: every text here is the generator's own).
    static std::string Str(std::string_view s);
    // A fresh IfcGloballyUniqueId (22 characters of the IFC base-64 alphabet 0-9A-Za-z_$, the
    // first one 0-3: 128 bits), quoted, derived from the seed and `key`; the same key and seed
    // always give the same id. Throws common::Error (kInternal) if a key repeats.
    std::string Guid(std::string_view key);
    // The unquoted form of Guid(): 128 bits of a hash of seed and key, IFC base-64 encoded.
    static std::string GlobalId(uint64_t seed, std::string_view key);

    // ---- geometry and representation (ids of the entities written) -------------------------
    int Point(const Eigen::Vector3d& metres);      // IfcCartesianPoint, 3D
    int Point2(const Eigen::Vector2d& metres);     // IfcCartesianPoint, 2D
    int Direction(const Eigen::Vector3d& ratios);  // IfcDirection (need not be normalised)
    // IfcAxis2Placement3D(Location, Axis, RefDirection); the default axes (z, x) are left unset.
    int Placement(const Eigen::Vector3d& origin_m,
                  const Eigen::Vector3d& axis = Eigen::Vector3d::UnitZ(),
                  const Eigen::Vector3d& ref_direction = Eigen::Vector3d::UnitX());
    // IfcLocalPlacement(PlacementRelTo, RelativePlacement); relative_to 0: absolute.
    int LocalPlacement(int relative_to, const Eigen::Vector3d& origin_m,
                       const Eigen::Vector3d& axis = Eigen::Vector3d::UnitZ(),
                       const Eigen::Vector3d& ref_direction = Eigen::Vector3d::UnitX());
    // An axis-aligned box in the object's coordinates: IfcExtrudedAreaSolid of an
    // IfcRectangleProfileDef centred on the box, extruded up along z from min.z.
    int Box(const Eigen::Vector3d& min_m, const Eigen::Vector3d& max_m);
    // IfcExtrudedAreaSolid of an IfcCircleProfileDef, from z0 up by height.
    int Cylinder(const Eigen::Vector2d& centre_m, double radius_m, double z0_m, double height_m);
    // IfcExtrudedAreaSolid of an IfcArbitraryClosedProfileDef (closed IfcPolyline of `polygon`,
    // counter-clockwise, not repeating the first point) placed by `position` (an
    // IfcAxis2Placement3D id; 0 leaves it at the object's origin), extruded along the
    // position's z by depth.
    int Prism(const std::vector<Eigen::Vector2d>& polygon_m, int position, double depth_m);
    // IfcProductDefinitionShape holding one IfcShapeRepresentation(context, 'Body', 'SweptSolid',
    // items).
    int BodyShape(int context, const std::vector<int>& items);

    // ---- the file ---------------------------------------------------------------------------
    // ISO-10303-21 header (FILE_DESCRIPTION, FILE_NAME, FILE_SCHEMA IFC4), the DATA section with
    // everything added, and the trailer. Deterministic: the time stamp is fixed.
    std::string Text(std::string_view file_name, std::string_view description) const;

    double length_unit_m() const { return length_unit_m_; }
    int entities() const { return next_id_ - 1; }
    // The "#n=NAME(...);" lines added so far, one per line.
    const std::string& Data() const { return data_; }

private:
    struct AnyUnit {};
    IfcWriter(AnyUnit, double length_unit_m, uint64_t seed, int first_id);

    double length_unit_m_;
    uint64_t seed_;
    int next_id_ = 1;
    std::string data_;
    std::set<std::string, std::less<>> keys_;
    int z_dir_ = 0;  // shared IfcDirection (0,0,1) for extrusions
};

}  // namespace bimslam::bim
