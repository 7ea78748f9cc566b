// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// A keyframe cloud prepared for registration: points thinned to a voxel grid, each with the
// normal of the surface it lies on, oriented towards the sensor that saw it.
//
// Why oriented normals. The reference session of a building sees both faces of every interior
// wall (a 0.15 m wall has rooms on both sides) and both walls of every corner. A voxel of a
// plane map that holds either pair fits no plane, and a map of 0.25-0.5 m voxels loses most of
// its wall voxels that way. Points whose normals point to opposite sides (the two faces of a
// wall) or to different axes (the two walls of a corner) go into different bins of the
// SurfelMap, and each bin fits its own plane. A normal can be oriented because each cloud is in
// its sensor's frame: the sensor is at the origin and sees the face whose normal points at it.
//
// Normals come from the planes of a voxel grid over the cloud itself (the eigenvector of the
// smallest eigenvalue of the voxel's covariance, Pauly et al. 2002), first at normal_voxel_size,
// then, for points whose small voxel holds no plane (a floor far from the sensor, where each
// voxel holds a single ring: a line, not a plane), at coarse_normal_voxel_size. Points on no
// plane at either scale (corners, edges, clutter) are left out: they give no point-to-plane
// residual.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <vector>

#include "algorithms/common/point_cloud.hpp"

namespace bimslam::registration {

struct OrientedCloudConfig {
    double min_range = 0.5;                 // m: closer points (the rig, the operator) are dropped
    double max_range = 60.0;                // m
    double normal_voxel_size = 0.4;         // m
    double coarse_normal_voxel_size = 1.0;  // m
    int min_plane_points = 6;
    // A voxel holds a plane when the spread across it (the smallest eigenvalue's standard
    // deviation) is at most max_thickness, the second spread is at least three times it and a
    // tenth of the voxel (points on a line, such as one ring crossing the voxel, define no plane:
    // their range noise would tilt it towards the rays), and no point lies farther than three
    // thicknesses from it. 3 cm: an OS1's range noise is 1-3 cm; a voxel over an edge is thicker.
    double max_thickness = 0.03;      // m
    double thin_voxel_size = 0.05;    // m: the input thinned first (one point per voxel)
    double sample_voxel_size = 0.15;  // m: one point (the first) per voxel of this size
    size_t max_points = 0;            // 0: no cap; else evenly thinned to at most this many

    void Validate() const;  // throws common::Error naming the field
};

struct OrientedCloud {
    std::vector<Eigen::Vector3f> points;   // the cloud's frame
    std::vector<Eigen::Vector3f> normals;  // unit, pointing to the sensor's side of the surface
    size_t input_points = 0;               // before thinning
    size_t size() const { return points.size(); }
    bool empty() const { return points.empty(); }
};

// The oriented, thinned cloud of `cloud`, whose sensor is at the origin of its frame.
OrientedCloud MakeOrientedCloud(const common::PointCloud& cloud, const OrientedCloudConfig& config);
OrientedCloud MakeOrientedCloud(const std::vector<Eigen::Vector3f>& points,
                                const OrientedCloudConfig& config);

// Several clouds joined in the frame of the first: clouds[k] mapped by T_first_k (a query
// keyframe with its neighbours, placed by odometry).
OrientedCloud MergeOriented(const std::vector<const OrientedCloud*>& clouds,
                            const std::vector<Eigen::Isometry3d>& T_first_k);

}  // namespace bimslam::registration
