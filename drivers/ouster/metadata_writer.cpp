// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include <nlohmann/json.hpp>

#include "drivers/ouster/metadata.hpp"

namespace bimslam::ouster {
namespace {
nlohmann::json Matrix(const Eigen::Matrix4d& m) {
    nlohmann::json out = nlohmann::json::array();
    for (int r = 0; r < 4; ++r) {
        for (int c = 0; c < 4; ++c) out.push_back(m(r, c));  // row-major, as the metadata
    }
    return out;
}
}  // namespace

std::string SerializeMetadata(const SensorInfo& info) {
    const DataFormat& f = info.format;
    nlohmann::json j;
    j["sensor_info"] = {{"prod_line", info.prod_line},
                        {"prod_sn", std::to_string(info.prod_sn)},
                        {"build_rev", info.build_rev},
                        {"initialization_id", info.init_id},
                        {"status", "RUNNING"}};
    j["beam_intrinsics"] = {{"beam_altitude_angles", info.beam_altitude_angles_deg},
                            {"beam_azimuth_angles", info.beam_azimuth_angles_deg},
                            {"lidar_origin_to_beam_origin_mm", info.lidar_origin_to_beam_origin_mm},
                            {"beam_to_lidar_transform", Matrix(info.beam_to_lidar_transform)}};
    j["lidar_intrinsics"] = {{"lidar_to_sensor_transform", Matrix(info.lidar_to_sensor_transform)}};
    j["imu_intrinsics"] = {{"imu_to_sensor_transform", Matrix(info.imu_to_sensor_transform)}};
    j["lidar_data_format"] = {{"pixels_per_column", f.pixels_per_column},
                              {"columns_per_packet", f.columns_per_packet},
                              {"columns_per_frame", f.columns_per_frame},
                              {"pixel_shift_by_row", f.pixel_shift_by_row},
                              {"column_window", {f.column_window_first, f.column_window_last}},
                              {"udp_profile_lidar", std::string(ToString(f.lidar_profile))},
                              {"udp_profile_imu", std::string(ToString(f.imu_profile))}};
    if (f.header_type != HeaderType::kStandard) {
        j["lidar_data_format"]["header_type"] = std::string(ToString(f.header_type));
    }
    if (f.imu_profile == ImuProfile::kAccel32Gyro32Nmea) {
        j["imu_data_format"] = {{"imu_measurements_per_packet", f.imu_measurements_per_packet}};
    }
    j["config_params"] = {{"lidar_mode", info.lidar_mode},
                          {"udp_profile_lidar", std::string(ToString(f.lidar_profile))},
                          {"udp_profile_imu", std::string(ToString(f.imu_profile))}};
    if (info.udp_port_lidar) j["config_params"]["udp_port_lidar"] = *info.udp_port_lidar;
    if (info.udp_port_imu) j["config_params"]["udp_port_imu"] = *info.udp_port_imu;
    j["calibration_status"] = {{"reflectivity", {{"valid", false}}}};
    return j.dump(4) + "\n";
}

}  // namespace bimslam::ouster
