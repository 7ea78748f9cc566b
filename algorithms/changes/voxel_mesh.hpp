// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// New objects as voxel solids and their surface meshes. A solid is a set of cubic voxels (indices
// on a lattice of voxel_m); its mesh has the faces between an occupied and an empty voxel only,
// two triangles each, counter-clockwise seen from outside, with the lattice corners as shared
// vertices: every edge of the mesh is used once in each direction, so the surface is closed
// (watertight) and consistently oriented, and its volume is the voxel count times voxel_m^3.
#pragma once

#include <Eigen/Core>
#include <span>
#include <vector>

#include "algorithms/common/triangle_mesh.hpp"

namespace bimslam::changes {

struct VoxelSolid {
    float voxel_m = 0.05f;
    std::vector<Eigen::Vector3i> voxels;  // sorted by (x, y, z), unique

    double volume_m3() const;
    // Of the voxels' cubes, in metres.
    Eigen::Vector3d box_min() const;
    Eigen::Vector3d box_max() const;
    Eigen::Vector3d centroid() const;  // of the solid (voxel centres, equally weighted)
};

// The solid of an object seen from its top and sides: the (x, y) columns of the voxels the points
// fall in, holes of one column closed (a morphological closing of the footprint, 8-neighbours),
// each column filled from base_z (the floor the object stands on, or its lowest point) up to its
// highest voxel. A LiDAR never sees an object's inside or underside, and the objects of a building
// stand on something: 2.5D (a table becomes a block down to the floor; README.md, "Limits").
VoxelSolid MakeVoxelSolid(std::span<const Eigen::Vector3f> points, float voxel_m, float base_z);

// An object's rectangle in plan of the smallest perimeter, whatever its turn about z: its sides
// (long_m >= short_m) and the long side's direction (yaw_deg in [0, 180)). An axis-aligned box
// measures a turned object larger (a 0.6 m crate turned 15 deg: 0.74 m), so visits that saw one
// object at two turns compare these instead (the history's moved objects). The perimeter, not the
// area: of a crate seen from one corner (two faces, an L in plan) the smallest area is the
// diagonal's (0.85 x 0.46 m for 0.6 x 0.6, the sample hall's Go1 visit), the smallest perimeter
// the crate's own. Tried every 0.5 deg over a quarter turn: the sides within side * (1 - cos
// 0.25 deg) + other * sin 0.25 deg of the exact rectangle's (under 4 mm for 0.8 m).
// Its centre is where a turned object stands better than its axis-aligned box's: a bed turned 5
// deg and seen without one corner had its box's centre 7 cm off along x, its rectangle's within
// 1 cm (the history's moved offsets).
struct PlanRectangle {
    double long_m = 0, short_m = 0, yaw_deg = 0;
    Eigen::Vector2d center = Eigen::Vector2d::Zero();
};
PlanRectangle SmallestPlanRectangle(std::span<const Eigen::Vector3f> points);

// The exposed faces of the solid.
common::TriangleMesh VoxelSurface(const VoxelSolid& solid);

}  // namespace bimslam::changes
