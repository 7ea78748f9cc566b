// The demo's stand-in world until the IFC sample building and the LiDAR simulator exist: a
// storey of rooms made of vertical wall segments between a floor and a ceiling, scanned along a
// loop by the project's built-in OS1-32 with exact ray casting (demo_capture.hpp). Deterministic;
// no third-party data.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

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
    // Distance along the unit direction `dir` from `origin` to the first wall, floor or ceiling,
    // and the cosine of the incidence angle there; +inf when the ray leaves the storey.
    double Cast(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
                double* cos_incidence = nullptr) const;
};

}  // namespace bimslam::cli
