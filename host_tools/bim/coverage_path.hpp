// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// A walk through every room of a storey (paper, Step 1): the occupancy grid's free space is split
// into rooms where it narrows to doors; each room gets viewpoints; a tour visits them all along
// the cheapest paths, which keep away from walls; the tour is then straightened and rounded so a
// legged robot can follow it, and timed at a walking speed.
//
// Rooms: cells with more clearance than `room_split_m` fall apart at doorways narrower than twice
// that (the idea behind morphological room segmentation, cf. Bormann et al., "Room Segmentation:
// Survey, Implementation, and Analysis", ICRA 2016). Viewpoints: the cell of most clearance of
// each room, then farthest-point sampling until every cell of the room's interior (a metre from
// its walls) is within `view_spacing_m` of one. Tour: geodesic distances on the grid, nearest
// neighbour then 2-opt. The walk passes through every viewpoint (they are kept as corners).
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <vector>

#include "algorithms/io/image.hpp"
#include "algorithms/io/trajectory.hpp"
#include "host_tools/bim/occupancy_grid.hpp"

namespace bimslam::bim {

struct PathConfig {
    double clearance_m = 0.3;       // from any wall or object: half a Go1 (0.3 m wide) plus 0.15 m
    double room_split_m = 0.55;     // rooms part where the free space is narrower than twice this
    double min_room_area_m2 = 1.0;  // smaller pockets get no viewpoint of their own
    double view_spacing_m = 4.0;    // viewpoints in a large room are at most this far apart
    double speed_mps = 0.5;         // walking speed of the timing
    // The walk slows where the heading turns faster than this (a Go1 turns comfortably at about
    // 1 rad/s while trotting; a dead end is a turn on the spot).
    double max_yaw_rate_radps = 1.0;
    double sensor_height_m = 0.6;  // sensor above the floor
    double spacing_m = 0.1;        // distance between the poses of the result
    int smoothing_passes = 3;      // corner cutting (Chaikin) passes that keep the clearance

    void Validate() const;  // throws common::Error naming the field and value
};

struct CoveragePath {
    std::vector<Eigen::Vector2d> viewpoints;  // in tour order
    std::vector<int> viewpoint_room;          // room index of each viewpoint
    int rooms = 0;                            // rooms found
    int unreachable_viewpoints = 0;           // dropped: no path with the clearance reaches them
    std::vector<Eigen::Vector2d> points;      // the smoothed closed walk, spacing_m apart
    std::vector<io::StampedPose> poses;       // T_bim_sensor along it: yaw along the walk
    double length_m = 0;
    double duration_s = 0;       // at speed_mps, slower in turns (max_yaw_rate_radps)
    double min_clearance_m = 0;  // the least clearance along the walk
};

// Throws common::Error when the grid holds no cell with the clearance.
CoveragePath PlanCoveragePath(const OccupancyGrid& grid, const PathConfig& config);

// The way from `from` to `to` (model x y) through the grid's free space, keeping the clearance:
// A* on the grid, straightened (corners only; the walk's motion model rounds them). Throws
// common::Error naming the point when an end is not free with the clearance, or when no way joins
// them.
std::vector<Eigen::Vector2d> PlanRoute(const OccupancyGrid& grid, const PathConfig& config,
                                       const Eigen::Vector2d& from, const Eigen::Vector2d& to);

// Poses every 1 / rate_hz seconds from the walk's first stamp to its last, interpolated between its
// poses (se3.hpp Interpolate): what a sensor at that frame rate sees along it.
std::vector<io::StampedPose> SampleWalk(const std::vector<io::StampedPose>& walk, double rate_hz);

// The grid with the walk drawn over it (red) and the viewpoints (blue).
io::Image PathImage(const OccupancyGrid& grid, const CoveragePath& path);

}  // namespace bimslam::bim
