// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Internal to the IFC ingest (the only code that includes IFC++): puts every face's outer
// boundary first in the loaded model, before IFC++ converts it. IFC++ (FaceConverter's
// convertIfcFaceList, Sweeper::createTriangulated3DFace) takes a face's first bound as its outer
// one; when that is a hole, carve cannot merge the loops and the face is dropped. ISO 16739
// (IfcFace) lets the bounds come in any order and marks the outer one as IfcFaceOuterBound, which
// may also be absent. IFC++'s classes are only forward-declared here.
#pragma once

#include <cstddef>

class BuildingModel;  // IFC++ (global namespace)

namespace bimslam::bim::ifc {

// For every IfcFace (and subtype) of the model with two or more bounds: its IfcFaceOuterBound
// goes first; where none, or more than one, is marked outer, the polygon loop of largest area goes
// first (the outer loop of a face with holes encloses them all). The other bounds keep their
// order. Returns how many faces changed order.
size_t PutOuterBoundsFirst(BuildingModel& model);

}  // namespace bimslam::bim::ifc
