// The demo's stand-in world until the IFC sample building and the LiDAR simulator exist: a
// storey of rooms made of vertical wall segments between a floor and a ceiling, scanned along a
// loop by an OS1-32-like beam pattern with exact ray casting. Deterministic; no third-party data.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "algorithms/common/point_cloud.hpp"

namespace bimslam::cli {

struct DemoScene {
    struct Wall {
        Eigen::Vector2d a, b;
    };
    std::vector<Wall> walls;
    double floor_z = 0.0;
    double ceiling_z = 3.0;
    // A closed walk through every room, through the doors (a polyline, metres).
    std::vector<Eigen::Vector2d> loop;

    // An office floor: a corridor with rooms on both sides, doors, a slanted wall and pillars.
    static DemoScene Office();
    // Length of the loop in metres.
    double LoopLength() const;
    // Pose on the loop at arc length s (wraps), sensor at height z, x axis along the walk.
    Eigen::Isometry3d PoseAt(double s, double lateral_offset, double z) const;
};

// One rotation of a 32-beam, `columns`-column sensor at T_world_lidar: points in the lidar frame,
// with intensity (incidence-dependent), ring and per-column time offsets of a 10 Hz spin;
// ranges beyond 50 m or below 0.3 m give no point. Gaussian range noise of sigma_m.
common::PointCloud ScanScene(const DemoScene& scene, const Eigen::Isometry3d& T_world_lidar,
                             int columns, double sigma_m, uint32_t seed);

}  // namespace bimslam::cli
