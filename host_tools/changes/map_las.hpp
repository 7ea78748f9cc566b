// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// map_bim.las (issue 34 item 2): the map of `bimslam changes` as an ASPRS LAS 1.4 point cloud
// (algorithms/io/las.hpp), for the tools surveyors and BIM users load clouds in. The same points,
// in the same order, as map_bim.ply; README.md of this folder has the table of fields.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>

#include "algorithms/changes/change_detector.hpp"
#include "algorithms/io/las.hpp"
#include "algorithms/io/session.hpp"

namespace bimslam::change_detection {

// The ASPRS class of a map point (LAS 1.4 R15 Table 17): a point on the model is 6 Building (it
// lies on a built element: wall, slab, column, door, furniture of the model), a point bimslam
// could not explain (off the model, in no object) or outside the compared region is
// 1 Unclassified (processed, in no class); the classes ASPRS has no code for are user codes:
// 64 new object, 65 transient, 66 moved element. The point's own class (map_bim.ply's
// scalar_class) is in its user data byte, so nothing is lost.
uint8_t LasClass(changes::PointClass c);
inline constexpr uint8_t kLasClassNewObject = io::kLasClassFirstUser;
inline constexpr uint8_t kLasClassTransient = io::kLasClassFirstUser + 1;
inline constexpr uint8_t kLasClassMoved = io::kLasClassFirstUser + 2;

// GPS time of a point seen first by a keyframe stamped `stamp_ns` (sensor clock): adjusted
// standard GPS time when the session knows its clock offset (SessionManifest::
// host_minus_sensor_ns), else the sensor clock's seconds as they are.
double MapGpsTime(int64_t stamp_ns, const io::SessionManifest& manifest);

// The map as LAS: every map point at its model-file coordinates (`origin_m` added back), class,
// user data, `visit` as point source id (and file source id), the first keyframe's time, and the
// extra bytes distance (float, m; no_data 1e9 as the PLY), element and object (int32, no_data
// -1) and keyframes (uint16). `session` is the one the map was made of.
io::LasData MapLas(const changes::ChangeResult& r, const Eigen::Vector3d& origin_m,
                   const io::Session& session, uint16_t visit);

}  // namespace bimslam::change_detection
