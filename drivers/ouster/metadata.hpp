// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Ouster metadata JSON, both layouts (specs/ouster-lidar.md, "Metadata JSON: two layouts"):
// flat (FW 1.12-2.x tools) and nested (FW 2.2+), with the spec's defaults for missing fields.
#pragma once

#include <filesystem>
#include <string>

#include "drivers/ouster/sensor_info.hpp"

namespace bimslam::ouster {

// Parses and validates; throws common::FileError (kParseError) whose message names the file and
// the field ("beam_altitude_angles: 30 entries, pixels_per_column is 32").
SensorInfo ParseMetadata(const std::string& name, const std::string& json_text);
SensorInfo LoadMetadata(const std::filesystem::path& path);

// The nested layout of FW 2.2+ (all seven sections), as the Ouster tools save it next to a
// capture; ParseMetadata reads it back to the same SensorInfo (but `source`). For the capture
// simulator and for tests.
std::string SerializeMetadata(const SensorInfo& info);

}  // namespace bimslam::ouster
