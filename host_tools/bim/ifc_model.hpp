// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// IFC ingest: an IFC file (STEP, IFC2X3 or IFC4, any length unit) to a BimModel (bim_model.hpp):
// storeys, elements with GlobalId, IFC class, storey and role, and one triangle mesh in metres in
// the model's world coordinates, openings subtracted. The only code in the project that includes
// IFC++ (ifc_model.cpp); see README.md in this folder for what is counted, what fails and why.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <string_view>

#include "host_tools/bim/bim_model.hpp"

namespace bimslam::bim {

struct IfcLoadOptions {
    // Railings (IfcRailing) are permanent, and a robot must not walk through them: structure by
    // default. false makes them transient (a LiDAR sees little of thin balusters or glass).
    bool railings_are_structure = true;
    // IfcSpace volumes get geometry (role transient). Off by default: a LiDAR does not see spaces,
    // and their volumes would fill every room of a "--all" mesh. Spaces are counted either way.
    bool space_geometry = false;
    // Opening elements (IfcOpeningElement, IfcVoidingFeature) get geometry of their own (role
    // transient). Off by default; the openings are subtracted from their walls either way.
    bool opening_geometry = false;
    // A floor assumed under each storey people stand on whose floor the file does not model
    // (assumed_floors.hpp: Office_A has no floor slabs). false reads the file as it is.
    bool assume_floors = true;
    // Segments of a full circle when IFC++ tessellates arcs, circles and round profiles (IFC++'s
    // default is 14). More costs triangles and CSG time; fewer makes round columns polygonal.
    int vertices_per_circle = 16;
    // Optional progress report, fraction in [0, 1] over parsing and geometry (called often).
    std::function<void(double)> progress;

    // Throws common::Error (kInvalidArgument) naming the field and value.
    void Validate() const;
};

// Reads and converts an IFC file. Throws common::FileError naming the file: kNotFound / kIoError
// when it cannot be read; kParseError when it is not an ISO-10303-21 file, its schema is not IFC2X3
// or IFC4, it holds no entities or no IfcProject, or its length unit is unusable; kDataLoss when it
// is cut off (no END-ISO-10303-21). Elements whose geometry fails are reported in
// BimModel::failed and skipped, never fatal.
// Openings are cut 1 mm wider, higher and deeper than modelled: carve's CSG fails where an
// opening's faces lie in its wall's, as exporters make them. carve orders by pointer, so the
// triangles of a file vary slightly from run to run (not the elements, storeys or counts).
// IFC++ and carve keep process-wide state: concurrent calls are serialized.
BimModel LoadIfc(const std::filesystem::path& path, const IfcLoadOptions& options = {});

// The same for STEP text already in memory; `name` names it in errors and in BimModel::file.
BimModel ParseIfc(const std::string& name, const std::string& step_text,
                  const IfcLoadOptions& options = {});

// The semantic filter by IFC class name alone (e.g. "IfcWallStandardCase" -> kStructure): walls,
// slabs, columns, beams, stairs, stair flights, ramps, ramp flights, roofs, coverings, members and
// plates (and their *StandardCase / *ElementedCase subtypes), railings when configured. Everything
// else is transient. LoadIfc refines it: members and plates of a curtain wall and building element
// parts take the role of the element they are part of.
ElementRole RoleOfClass(std::string_view ifc_class, const IfcLoadOptions& options = {});

}  // namespace bimslam::bim
