// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// A spinning multi-beam LiDAR's geometry (an Ouster OS sensor's intrinsics), as a neutral struct:
// algorithms/ may not use drivers/, so host tools convert drivers/ouster's SensorInfo into this
// (host_tools/bim/lidar_from_metadata.hpp).
//
// Rays follow specs/ouster-lidar.md "Range -> XYZ" (the Ouster SDK's XYZ table) exactly: for
// pixel (u, v) of the STAGGERED H x W image (u = beam, v = measurement id)
//     theta_e = 2 pi - v 2 pi / W,  theta_a = -azimuth[u],  phi = altitude[u]
//     dir     = (cos(theta_e + theta_a) cos phi, sin(theta_e + theta_a) cos phi, sin phi)
//     d       = z0 != 0 ? sqrt(n^2 + z0^2) : n
//     off     = (n cos theta_e - d dir.x, n sin theta_e - d dir.y, -d dir.z + z0)      [mm]
//     dir'    = R dir,  off' = R off + t        (R, t of lidar_to_sensor_transform, t in mm)
// so that the driver's point for a range r (metres) is r * Direction(u, v) + Origin(u, v): the
// simulator casts each ray from Origin along Direction and reports the hit distance as the range.
// The beam itself leaves from Origin + BeamOriginDistance() * Direction (the point on the circle
// of radius n where the beam is emitted), so hits closer than that are not ranges.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace bimslam::simulation {

struct LidarModel {
    std::vector<double> beam_altitude_deg;  // H entries, elevation above the XY plane
    std::vector<double> beam_azimuth_deg;   // H entries, per-beam azimuth offset
    int columns = 1024;                     // W: measurement ids per rotation
    double frame_rate_hz = 10.0;            // rotations per second
    // beam_to_lidar_transform: n = [0][3] (lidar_origin_to_beam_origin_mm), z0 = [2][3].
    double beam_origin_mm = 15.806;  // n
    double beam_z_mm = 0.0;          // z0
    // Lidar frame to sensor frame, translation in millimetres.
    Eigen::Matrix4d lidar_to_sensor_transform = Eigen::Matrix4d::Identity();

    int beams() const { return static_cast<int>(beam_altitude_deg.size()); }  // H
    size_t pixels() const { return static_cast<size_t>(beams()) * columns; }

    // Throws common::Error (kInvalidArgument) naming the field and value when the model is not
    // usable: no beams, mismatched angle arrays, non-finite values, columns < 1, rate <= 0, a
    // lidar_to_sensor_transform that is not rigid.
    void Validate() const;

    // Unit ray direction of pixel (u, v) in the sensor frame (the driver's table direction).
    Eigen::Vector3d Direction(int u, int v) const;
    // Ray origin of pixel (u, v) in the sensor frame, metres (the driver's table offset).
    Eigen::Vector3d Origin(int u, int v) const;
    // d in metres: distance along the ray from Origin to the beam's emission point.
    double BeamOriginDistance() const;
    // Time of column v after the start of the rotation: v / (W * frame_rate), in nanoseconds.
    int64_t ColumnTimeOffsetNs(int v) const;

    // The project's own OS1-32 (the same table as drivers/ouster BuiltinOs1_32): 32 beams
    // uniform over +22.5 ... -22.5 deg, the four detector columns' azimuth offsets +4.23, +1.41,
    // -1.41, -4.23 deg (beam u has column u % 4), n = 15.806 mm, and the spec's default
    // lidar_to_sensor_transform (180 deg about Z, z = 36.18 mm). Throws for columns < 1 or a
    // rate <= 0.
    static LidarModel DefaultOs1_32(int columns = 1024, double rate_hz = 10.0);
};

}  // namespace bimslam::simulation
