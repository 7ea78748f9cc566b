// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// What the Ouster metadata JSON says about a sensor (specs/ouster-lidar.md, "Metadata JSON"), in
// one layout-independent struct. metadata.hpp parses both JSON layouts into it.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace bimslam::ouster {

// udp_profile_lidar values.
enum class LidarProfile : uint8_t {
    kLegacy,
    kRng19Rfl8Sig16Nir16,
    kRng15Rfl8Nir8,
    kRng19Rfl8Sig16Nir16Dual,
    kRng15Rfl8Nir8Dual,
    kFusaRng15Rfl8Nir8Dual,
};
// udp_profile_imu values.
enum class ImuProfile : uint8_t { kLegacy, kAccel32Gyro32Nmea };
// lidar_data_format.header_type (FW 3.2+); STANDARD when absent.
enum class HeaderType : uint8_t { kStandard, kFusa };

// The metadata strings ("LEGACY", "RNG19_RFL8_SIG16_NIR16", ...) and back.
std::string_view ToString(LidarProfile p);
std::string_view ToString(ImuProfile p);
std::string_view ToString(HeaderType h);
std::optional<LidarProfile> ParseLidarProfile(std::string_view s);
std::optional<ImuProfile> ParseImuProfile(std::string_view s);
std::optional<HeaderType> ParseHeaderType(std::string_view s);

struct DataFormat {
    int pixels_per_column = 0;  // H: 16, 32, 64 or 128 (64 for FW < 2.0, any beams)
    int columns_per_packet = 16;
    int columns_per_frame = 0;            // W: 512, 1024, 2048 (4096 for 4096x5)
    std::vector<int> pixel_shift_by_row;  // H entries, for destaggering
    // Columns the sensor sends, inclusive; last < first when the window wraps past W - 1.
    int column_window_first = 0;
    int column_window_last = 0;
    LidarProfile lidar_profile = LidarProfile::kLegacy;
    ImuProfile imu_profile = ImuProfile::kLegacy;
    HeaderType header_type = HeaderType::kStandard;
    int imu_measurements_per_packet = 0;  // ACCEL32_GYRO32_NMEA only

    // Number of columns inside the window.
    int WindowColumns() const {
        return column_window_last >= column_window_first
                   ? column_window_last - column_window_first + 1
                   : columns_per_frame - column_window_first + column_window_last + 1;
    }
    // True when column v is inside the window (which may wrap past W - 1).
    bool InWindow(int v) const {
        return column_window_last >= column_window_first
                   ? v >= column_window_first && v <= column_window_last
                   : v >= column_window_first || v <= column_window_last;
    }
};

struct SensorInfo {
    std::string prod_line;  // e.g. "OS-1-32-G"; empty when the file does not say
    uint64_t prod_sn = 0;   // 0 when unknown (packets are then not checked against it)
    std::string build_rev;  // firmware, e.g. "v2.1.1"
    int fw_major = 0, fw_minor = 0, fw_patch = 0;  // parsed from build_rev; 0.0.0 when unknown
    uint32_t init_id = 0;         // initialization_id; 0 when unknown (packets not checked)
    std::string lidar_mode;       // e.g. "1024x10"
    double frame_rate_hz = 10.0;  // from lidar_mode
    std::optional<uint16_t> udp_port_lidar;  // absent from older metadata
    std::optional<uint16_t> udp_port_imu;
    DataFormat format;

    std::vector<double> beam_altitude_angles_deg;  // H entries (FW < 2.0: padded to 64)
    std::vector<double> beam_azimuth_angles_deg;
    double lidar_origin_to_beam_origin_mm = 0.0;
    // Translation parts in millimetres, as in the metadata. beam_to_lidar_transform is filled from
    // lidar_origin_to_beam_origin_mm (x) when the file has no such matrix (FW < 2.5).
    Eigen::Matrix4d beam_to_lidar_transform = Eigen::Matrix4d::Identity();
    Eigen::Matrix4d lidar_to_sensor_transform = Eigen::Matrix4d::Identity();
    Eigen::Matrix4d imu_to_sensor_transform = Eigen::Matrix4d::Identity();

    std::string source;  // the file it came from, for messages
};

}  // namespace bimslam::ouster
