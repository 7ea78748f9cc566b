// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// IMU samples as a CSV file beside a folder of per-scan clouds (cloud_folder.hpp), so that such a
// folder replays with its IMU as the recording did:
//   t_s,gyro_x,gyro_y,gyro_z,accel_x,accel_y,accel_z
//   1234.567890123,0.001,-0.002,0.0005,0.12,-0.03,9.81
// one sample a line after the header; t_s in seconds of the scans' clock (times.txt's), angular
// rate in rad/s and specific force in m/s^2, both in the lidar's sensor frame.
#pragma once

#include <filesystem>
#include <vector>

#include "algorithms/odometry/lidar_odometry.hpp"

namespace bimslam::replay {

void WriteImuCsv(const std::filesystem::path& path,
                 const std::vector<odometry::ImuMeasurement>& samples);

// Throws common::FileError naming the file and the line: a wrong header, a line without seven
// finite numbers, times that go back.
std::vector<odometry::ImuMeasurement> ReadImuCsv(const std::filesystem::path& path);

}  // namespace bimslam::replay
