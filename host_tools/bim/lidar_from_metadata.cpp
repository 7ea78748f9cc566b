// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/bim/lidar_from_metadata.hpp"

#include <string>

#include "algorithms/common/status.hpp"
#include "drivers/ouster/metadata.hpp"

namespace bimslam::bim {

simulation::LidarModel LidarModelFromSensorInfo(const ouster::SensorInfo& info) {
    simulation::LidarModel m;
    m.beam_altitude_deg = info.beam_altitude_angles_deg;
    m.beam_azimuth_deg = info.beam_azimuth_angles_deg;
    m.columns = info.format.columns_per_frame;
    m.frame_rate_hz = info.frame_rate_hz;
    // The spec's n and z0 come from beam_to_lidar_transform, as the driver's XyzLut takes them.
    m.beam_origin_mm = info.beam_to_lidar_transform(0, 3);
    m.beam_z_mm = info.beam_to_lidar_transform(2, 3);
    m.lidar_to_sensor_transform = info.lidar_to_sensor_transform;
    try {
        m.Validate();
    } catch (const common::Error& e) {
        if (info.source.empty()) throw;
        throw common::Error(e.code(), info.source + ": " + e.what());
    }
    return m;
}

simulation::LidarModel LidarModelFromMetadataFile(const std::filesystem::path& path) {
    ouster::SensorInfo info = ouster::LoadMetadata(path);  // its FileErrors name the file
    info.source.clear();                                   // the FileError below names it instead
    try {
        return LidarModelFromSensorInfo(info);
    } catch (const common::Error& e) {
        throw common::FileError(e.code(), path.string(), 0, e.what());
    }
}

}  // namespace bimslam::bim
