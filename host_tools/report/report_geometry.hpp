// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The model's geometry as the report draws it: floor-plan sections per storey (the mesh cut by a
// horizontal plane, as an architect's plan is) and the model's triangles per IFC class for the 3D
// view, with the element of each triangle for click-to-inspect. Coordinates are the mesh's
// (bim::BimModel: the model's frame minus origin_m); the page adds origin_m back where it prints
// coordinates.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "host_tools/bim/bim_model.hpp"

namespace bimslam::report {

// Base64 (RFC 4648) of raw bytes: typed arrays in the page's JSON.
std::string Base64(const void* data, size_t bytes);
template <class T>
std::string Base64(const std::vector<T>& v) {
    return Base64(v.data(), v.size() * sizeof(T));
}

// What a floor plan shows of an element class: "wall", "door", "window", "column" or "other".
std::string PlanClass(const std::string& ifc_class);

// Per storey: {name, elevation, cut_z, segments: {wall: [x0,y0,x1,y1,...], door, ...},
// segment_elements: {wall: [element, segments, element, segments, ...], ...}}: the triangles of
// the storey's elements cut at elevation + cut_height_m, each element's segments in one run (the
// plans colour an element by its deviation). Elements of no storey go to
// the storey whose elevation range holds the cut.
nlohmann::json PlanSections(const bim::BimModel& model, double cut_height_m);

// {classes: [{name, triangles, storeys: [[first index, index count] per storey], positions (b64
// float32 xyz), indices (b64 uint32), element (b64 uint32 per triangle)}], elements: [{g, c, n,
// s}]} for the 3D view, spaces and openings left out. Each class's triangles are ordered by their
// element's storey (ElementStoreys), so that one storey's are one range of the index buffer.
nlohmann::json ModelBuffers(const bim::BimModel& model);

// Non-indexed triangles of the given elements, storey by storey (ElementStoreys): {positions (b64
// float32 xyz), storeys: [[first vertex, vertices] per storey]}: missing elements in red.
nlohmann::json ElementTriangles(const bim::BimModel& model, const std::vector<size_t>& elements);

// The storey (index) a point at height z stands on: the highest whose elevation is at most
// z - 0.1 m (a sensor is above its floor), else the lowest; -1 without storeys.
int StoreyAt(const bim::BimModel& model, double z);

// The storey a map point at height z (mesh frame) belongs to: the highest whose elevation is at
// most z + 5 cm (a floor's surface is its storey's, a ceiling the storey's below).
int StoreyOfPoint(const bim::BimModel& model, double z);

// Per element: its IfcBuildingStorey, else the storey of its lowest point (StoreyOfPoint); -1
// without storeys.
std::vector<int> ElementStoreys(const bim::BimModel& model);

// An element's bounding box in the model's frame (the mesh's plus origin_m).
Eigen::AlignedBox3d ElementBox(const bim::BimModel& model, size_t index);

// Positions minus `origin` (the mesh's frame), every k-th so that at most `max` remain (the last
// always), rounded to the millimetre: [x, y, z, ...].
std::vector<float> ThinPoints(const std::vector<Eigen::Vector3d>& p, const Eigen::Vector3d& origin,
                              size_t max);

// A walk (model frame) split by storey (storey_split.hpp), thinned to at most max_points, in the
// mesh frame: [{lower, upper, xyz}] (lower == upper on a floor; on a flight the storeys below and
// above).
nlohmann::json StoreyRuns(const std::vector<Eigen::Vector3d>& positions, const bim::BimModel& model,
                          size_t max_points);

// The model's stairs and ramps (bim::FindStairFlights) as the plans draw them: [{name, lower,
// upper, rise_m, risers, treads: [x y of 4 corners per level, flat], line: [x y, flat]}] (mesh
// frame), each drawn on the plans of the storeys it joins.
nlohmann::json FlightOutlines(const bim::BimModel& model);

}  // namespace bimslam::report
