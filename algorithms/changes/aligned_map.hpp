// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The session's map in the model's frame (Step 3 of the paper, first half): every keyframe cloud
// placed at its (anchored) pose and merged, then voxel-filtered. A voxel keeps the centroid of
// the points that fell in it, how many points that was, and how many distinct keyframes saw it
// (the points of one keyframe are added together, so "distinct" is a comparison with the last
// keyframe that touched the voxel). The voxels come out in Morton (z-order) of their indices:
// neighbours in the map are neighbours in memory, which makes the nearest-element queries that
// follow coherent.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <span>
#include <vector>

#include "algorithms/common/point_cloud.hpp"

namespace bimslam::changes {

// A keyframe cloud (in its own lidar frame) and its pose in the model's frame. Not owned.
struct MapKeyframe {
    const common::PointCloud* cloud = nullptr;
    Eigen::Isometry3d T_world_lidar = Eigen::Isometry3d::Identity();
};

struct AlignedMapConfig {
    double voxel_m = 0.05;  // voxel filter; also the voxel of the new objects' meshes
    // Points of a keyframe farther than this from its sensor are left out: a 0.1 deg anchoring
    // error moves them by more than 4 cm, and the beams are 0.4 m apart there.
    double max_range_m = 25.0;
    double min_range_m = 0.5;  // the rig itself (the odometry crops at 0.5 m already)
    void Validate() const;
};

struct AlignedMap {
    std::vector<Eigen::Vector3f> xyz;      // voxel centroids, model frame
    std::vector<uint32_t> points;          // raw points merged into each voxel
    std::vector<uint16_t> keyframes;       // distinct keyframes that saw each voxel
    std::vector<uint32_t> first_keyframe;  // index of the first keyframe that saw it
    size_t input_points = 0;               // points of all keyframes
    size_t cropped_points = 0;             // of them, outside [min_range_m, max_range_m]
    size_t size() const { return xyz.size(); }
};

// The order of `points` along the Morton (z-order) curve of their voxels of `voxel_m`: spatial
// neighbours close in the order, for queries whose answer for one point is a good start for the
// next (model_distance.hpp).
std::vector<uint32_t> MortonOrder(std::span<const Eigen::Vector3f> points, float voxel_m);

// Throws common::Error (kInvalidArgument) for a null cloud, a non-finite pose or an invalid
// config. Non-finite points are skipped (counted as cropped).
AlignedMap BuildAlignedMap(std::span<const MapKeyframe> keyframes, const AlignedMapConfig& config);

}  // namespace bimslam::changes
