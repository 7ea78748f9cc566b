// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// A small building for the change-detection tests, simulated with the project's own LiDAR
// simulator (algorithms/simulation, the OS1-32 beam pattern, 1 cm range noise): two rooms side by
// side with no door between them, and keyframes walked around room A only.
//
//   model (the BIM)                          world (as built)
//   floor, ceiling, six walls                the same, except:
//   column A in room A at (5.0, 3.5)         column A removed
//   column C in room A at (2.0, 4.5)         the north wall of room A built 3 cm further north
//   column B in room B at (10.0, 3.0)        column B removed (out of view: not judged)
//                                            a box 0.8 x 0.5 x 0.6 m on the floor at (3.0, 1.5)
//                                            a person crossing in two keyframes only
#pragma once

#include <Eigen/Geometry>
#include <vector>

#include "algorithms/changes/aligned_map.hpp"
#include "algorithms/changes/change_model.hpp"
#include "algorithms/common/point_cloud.hpp"
#include "algorithms/common/triangle_mesh.hpp"

namespace bimslam::simulation {
struct ScanImage;
struct LidarModel;
}  // namespace bimslam::simulation

namespace bimslam::changes::test {

// Element indices of the model.
enum Element : uint32_t {
    kFloor,
    kCeiling,
    kWallSouth,
    kWallNorthA,
    kWallNorthB,
    kWallWest,
    kWallEast,
    kWallDivider,
    kColumnA,
    kColumnC,
    kColumnB,
    kElementCount
};

struct ChangeScene {
    ChangeModel model;
    common::TriangleMesh world;              // as built, people excluded
    std::vector<common::PointCloud> clouds;  // per keyframe, lidar frame
    std::vector<Eigen::Isometry3d> poses;    // T_world_lidar per keyframe
    std::vector<MapKeyframe> keyframes;      // views of the two above
    Eigen::AlignedBox3d added_box;           // truth of the added box
    std::vector<Eigen::Vector2d> person_at;  // where the person stood, per keyframe it is in
    double wall_offset_m = 0.03;             // north wall of room A, +y
};

// An axis-aligned solid box, faces counter-clockwise seen from outside.
common::TriangleMesh SolidBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi);
void Append(common::TriangleMesh* to, const common::TriangleMesh& m);
// The decoded points of a simulated scan, in the sensor's (lidar) frame, as the driver gives them.
common::PointCloud ToCloud(const simulation::ScanImage& image, const simulation::LidarModel& lidar);

// The scene above, simulated (deterministic). Built once and shared: the tests only read it.
const ChangeScene& SharedChangeScene();

// The changed-building scenario's corridor in small (host_tools/simulate/scenarios/
// changed_building.yaml): a corridor 16 x 2 x 3 m, built as modelled, walked along and back by a
// Go1 (the sensor 0.6 m above the floor, 0.5 m/s, a keyframe a second) while a person walks to and
// fro along it, 0.9 m beside the walk, at 1.2 m/s: the person passes the same places again and
// again, and is seen there from many keyframes at the same heights (the sensor's rings).
struct CorridorScene {
    ChangeModel model;  // floor, ceiling, four walls
    std::vector<common::PointCloud> clouds;
    std::vector<Eigen::Isometry3d> poses;
    std::vector<MapKeyframe> keyframes;
    Eigen::Vector2d person_from, person_to;  // the person's line
    double person_radius_m = 0.25, person_height_m = 1.75;
};
const CorridorScene& SharedCorridorScene();

}  // namespace bimslam::changes::test
