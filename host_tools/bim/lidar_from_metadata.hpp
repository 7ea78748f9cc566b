// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The Ouster driver's sensor description (drivers/ouster SensorInfo, parsed from the metadata
// JSON) as the simulator's neutral LidarModel. algorithms/simulation may not use drivers/, so the
// conversion lives here, in the host tools that may use both.
//
// Field by field (specs/ouster-lidar.md, "Metadata JSON" and "Range -> XYZ"):
//   beam_altitude_deg, beam_azimuth_deg  <- beam_altitude_angles, beam_azimuth_angles (H each)
//   columns                              <- data_format.columns_per_frame (W of lidar_mode)
//   frame_rate_hz                        <- the rate of lidar_mode ("1024x10": 10 Hz)
//   beam_origin_mm, beam_z_mm            <- beam_to_lidar_transform [0][3] and [2][3] (the
//                                           driver fills it from lidar_origin_to_beam_origin_mm
//                                           and the product-line default before FW 2.5)
//   lidar_to_sensor_transform            <- lidar_to_sensor_transform (translation in mm)
// so that a simulated range image decodes with the driver's XyzLut of the same SensorInfo to the
// ray-cast points. The simulator casts every column: a column_window is not applied.
#pragma once

#include <filesystem>

#include "algorithms/simulation/lidar_model.hpp"
#include "drivers/ouster/sensor_info.hpp"

namespace bimslam::bim {

// Throws common::Error (kInvalidArgument) when the model is not usable (LidarModel::Validate),
// the message starting with info.source when it names one.
simulation::LidarModel LidarModelFromSensorInfo(const ouster::SensorInfo& info);

// Reads the metadata JSON with the driver's parser (either layout). Throws common::FileError
// naming the file: the parser's errors as they are, a model the simulator cannot use with
// kInvalidArgument.
simulation::LidarModel LidarModelFromMetadataFile(const std::filesystem::path& path);

}  // namespace bimslam::bim
