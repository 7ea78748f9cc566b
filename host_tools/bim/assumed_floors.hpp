// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Floors a model leaves out. An architect's model may have no floor slabs at all (Office_A: two
// IfcSlab in the file, both stair landings; its storeys have ceilings and nothing under foot), yet
// every building has floors, and a LiDAR sees them on every scan. Left out, a walk in the real
// building sees the floor as something the model lacks, and a walk simulated in the model sees
// no floor anywhere indoors: its odometry has no height to hold on a flight of stairs (issue 31,
// Office_A's climb).
//
// So the ingest assumes a floor where a storey people stand on has none modelled: a slab
// kAssumedFloorThicknessM thick whose top is the storey's elevation, under every cell the
// building stands on at the storey's slice (IndoorCells: rooms, walls, doors and windows),
// with an opening over each stair and ramp that climbs to the storey from below (the flight's
// and landings' plan, so that the flight keeps its headroom). A storey gets one when it is at least
// kMinWalkStoreyHeight below the next (the last storey counts: Office_A's 'Roof' gets its roof),
// its occupancy grid finds enclosed space, and its floor is not modelled (FloorModelled: floor
// faces under less than half of its free space).
//
// Each is a BimElement of class IfcSlab, role structure, flagged `assumed`, with a GlobalId that
// no IFC file can hold ("assumed-floor-<storey index>": '-' is outside the GlobalId alphabet). It
// is physically there for the simulator's world, the reference session and change detection's
// signed distances; change detection never judges it, and no element list or IFC written back
// names it.
#pragma once

#include <string>

#include "host_tools/bim/bim_model.hpp"

namespace bimslam::bim {

inline constexpr double kAssumedFloorThicknessM = 0.2;

// Appends the assumed floors to `model` (elements and triangles at the end, so that earlier
// element indices stay) and says so in model.assumed_floors; nothing when every storey's floor is
// modelled. The grid's resolution is GridConfig's default (5 cm).
void AddAssumedFloors(BimModel& model);

// "assumed-floor-<storey>".
std::string AssumedFloorId(int storey);

}  // namespace bimslam::bim
