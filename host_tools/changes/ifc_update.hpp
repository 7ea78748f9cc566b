// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The updated IFC of `bimslam changes`: the original STEP text, untouched, with entities appended
// before the DATA section's ENDSEC (ids above the file's largest):
//   - each new object as an IfcBuildingElementProxy whose Body is its voxel mesh (IFC4:
//     IfcTriangulatedFaceSet, 'Tessellation'; IFC2X3: IfcFacetedBrep of triangular faces,
//     'Brep'), placed absolutely (its vertices in the model's coordinates, in the file's length
//     unit), contained in its storey (IfcRelContainedInSpatialStructure), with a property set
//     bimslam_NewObject (volume, points, session, space);
//   - on each missing or deviating element a property set bimslam_ChangeDetection stating the
//     verdict and its numbers (IfcRelDefinesByProperties). Nothing is deleted.
// The entities reuse the file's first IfcOwnerHistory (IFC2X3 requires one) and its 'Body'
// representation subcontext (else its 3D 'Model' context).
// IfcAppender writes those entities; the as-is model of a project's visits (host_tools/mapping,
// model_asis.ifc) appends its own with it.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "host_tools/bim/bim_model.hpp"
#include "host_tools/changes/change_report.hpp"

namespace bimslam::change_detection {

struct IfcUpdate {
    std::string text;  // the updated file
    size_t proxies = 0;
    size_t element_property_sets = 0;
    size_t entities = 0;             // appended
    std::vector<std::string> notes;  // what could not be done (an element not found by GlobalId)
};

// Entities appended to an IFC file's text (see above). `text` is the original file (`name` in
// errors), `model` what bim::LoadIfc made of it, `seed` the seed of the new GlobalIds. Throws as
// UpdateIfc does. The file and the model must outlive the appender.
class IfcAppender {
public:
    using Values = std::vector<std::pair<std::string, std::string>>;  // (name, IFC value)
    IfcAppender(const std::string& name, const std::string& text, const bim::BimModel& model,
                uint64_t seed);
    ~IfcAppender();

    // A proxy whose Body is the mesh (vertices in the model file's coordinates, metres), with
    // its GlobalId, Name, Description and ObjectType, contained in `storey` (an index into
    // model.storeys; -1: the building). Returns its entity id.
    int Proxy(const std::vector<Eigen::Vector3d>& vertices,
              const std::vector<std::array<uint32_t, 3>>& triangles, const std::string& global_id,
              const std::string& name, const std::string& description,
              const std::string& object_type, int storey);
    // A property set on entities (`key`: unique, seeds its GlobalIds).
    void PropertySet(const std::string& key, const std::string& set_name, const Values& values,
                     const std::vector<int>& entities);
    // A property set on the element of this GlobalId; false (and a note) when the file has none.
    bool ElementPropertySet(const std::string& global_id, const std::string& ifc_class,
                            const std::string& key, const std::string& set_name,
                            const Values& values);
    // An IfcGroup (Name, Description) of the elements of these GlobalIds, by an
    // IfcRelAssignsToGroup; returns how many the file has (those it has not are noted).
    size_t Group(const std::string& key, const std::string& name, const std::string& description,
                 const std::vector<std::string>& global_ids);
    // The proxies made so far contained in their storeys (`group`: seeds the relations'
    // GlobalIds, unique per call).
    void Contain(const std::string& group);
    // The file with the entities (the proxies not contained yet are, as by Contain).
    IfcUpdate Finish(const std::string& group);

    // IFC values: IfcLabel, IfcText, IfcInteger, IfcReal, IfcLengthMeasure (the file's unit).
    static std::string Label(const std::string& s);
    static std::string Text(const std::string& s);
    static std::string Int(size_t v);
    static std::string Real(double v);
    std::string Length(double metres) const;

private:
    struct State;
    std::unique_ptr<State> s_;
};

// `text` is the original file (`name` in errors), `model` what bim::LoadIfc made of it, `seed` the
// seed of the new GlobalIds (the object proxies take SessionChanges::object_global_ids). Throws
// common::FileError naming the file when it has no DATA section or no 3D representation context,
// and common::Error (kInvalidArgument) for a schema other than IFC2X3 and IFC4.
IfcUpdate UpdateIfc(const std::string& name, const std::string& text, const bim::BimModel& model,
                    const SessionChanges& found, uint64_t seed);

}  // namespace bimslam::change_detection
