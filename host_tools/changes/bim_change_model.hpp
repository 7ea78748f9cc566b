// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The BIM model as change detection sees it (algorithms/changes/change_model.hpp), and where a new
// object is in the building: its storey and the IfcSpace it stands in.
#pragma once

#include <vector>

#include "algorithms/changes/change_detector.hpp"
#include "host_tools/bim/bim_model.hpp"

namespace bimslam::change_detection {

// Physical elements: all but spaces, openings, virtual elements and annotations (not built).
bool Physical(const bim::BimElement& element);
// The elements change detection judges and lists (changes.json, elements.csv): physical ones from
// the file, not the floors its reader assumed (bim/assumed_floors.hpp).
bool Listed(const bim::BimElement& element);

// Elements keep their BimModel index. The mesh holds the physical elements' triangles; an element
// is opaque unless beams pass it (bim::PassThrough: doors taken as open, windows, curtain walls),
// and judged when it is Listed.
// Throws common::Error (kInvalidArgument) naming the model when it has no physical element with
// geometry: there is nothing to compare with.
changes::ChangeModel ToChangeModel(const bim::BimModel& model);

struct ObjectPlace {
    int storey = -1;  // index into BimModel::storeys, -1 without storeys
    int space = -1;   // element index of the IfcSpace it stands in, -1 for none
};

// The storey of an object whose bottom is at bottom_z (model frame): the highest storey whose
// elevation is at most bottom_z + 0.3 m (a floor's finish lies above the storey's elevation),
// else the lowest. Its space: the IfcSpace whose volume holds the point 0.1 m above the centre of
// its base (ray parity against the space's closed mesh; spaces need
// IfcLoadOptions::space_geometry).
std::vector<ObjectPlace> PlaceObjects(const bim::BimModel& model,
                                      const std::vector<changes::NewObject>& objects);

// The IfcSpace whose closed mesh holds each point (the mesh's frame: origin_m subtracted): its
// element index, -1 for none (ray parity, as PlaceObjects).
std::vector<int> SpacesAt(const bim::BimModel& model, const std::vector<Eigen::Vector3f>& points);

// The storey under something whose bottom is at bottom_z (model frame), PlaceObjects' rule; -1
// without storeys.
int StoreyUnder(const bim::BimModel& model, double bottom_z);

// An element's storey: its IfcBuildingStorey (by IfcRelContainedInSpatialStructure), else, for
// an element contained in the building or in nothing, the storey under its lowest point
// (StoreyUnder); -1 without storeys. `from_height` says which.
int ElementStorey(const bim::BimModel& model, size_t element, bool* from_height = nullptr);

}  // namespace bimslam::change_detection
