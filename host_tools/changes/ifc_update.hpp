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
#pragma once

#include <string>

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

// `text` is the original file (`name` in errors), `model` what bim::LoadIfc made of it, `seed` the
// seed of the new GlobalIds (the object proxies take SessionChanges::object_global_ids). Throws
// common::FileError naming the file when it has no DATA section or no 3D representation context,
// and common::Error (kInvalidArgument) for a schema other than IFC2X3 and IFC4.
IfcUpdate UpdateIfc(const std::string& name, const std::string& text, const bim::BimModel& model,
                    const SessionChanges& found, uint64_t seed);

}  // namespace bimslam::change_detection
