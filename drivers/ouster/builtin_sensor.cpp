// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "drivers/ouster/builtin_sensor.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "algorithms/common/status.hpp"

namespace bimslam::ouster {

SensorInfo BuiltinOs1_32(LidarProfile profile, int columns, int rate_hz) {
    return BuiltinOuster("OS1-32", profile, columns, rate_hz);
}

SensorInfo BuiltinOuster(const std::string& model, LidarProfile profile, int columns, int rate_hz) {
    // "OS<p>-<beams>"
    const int product =
        model.size() >= 5 && model.starts_with("OS") && model[3] == '-' ? model[2] - '0' : -1;
    const std::string beam_text = model.size() >= 5 ? model.substr(4) : "";
    const int beams = beam_text == "16"    ? 16
                      : beam_text == "32"  ? 32
                      : beam_text == "64"  ? 64
                      : beam_text == "128" ? 128
                                           : 0;
    if (product < 0 || product > 2 || beams == 0) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            "no built-in sensor '" + model +
                                "' (OS0, OS1 or OS2 with 16, 32, 64 or 128 beams: OS1-32, OS0-64, "
                                "OS1-128, ...)");
    }
    const bool ok = (rate_hz == 10 && (columns == 512 || columns == 1024 || columns == 2048)) ||
                    (rate_hz == 20 && (columns == 512 || columns == 1024));
    if (!ok) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            "no " + model + " lidar mode " + std::to_string(columns) + "x" +
                                std::to_string(rate_hz) +
                                " (512x10, 1024x10, 2048x10, 512x20, 1024x20)");
    }
    SensorInfo s;
    constexpr double kFovDeg[3] = {90.0, 45.0, 22.5};
    constexpr double kBeamOriginMm[3] = {27.67, 15.806, 13.762};
    s.prod_line = "OS-" + std::to_string(product) + "-" + std::to_string(beams) + "-U0";
    s.prod_sn = 122000000000 + 1000 * product + beams;
    s.build_rev = "v2.5.0";
    s.fw_major = 2;
    s.fw_minor = 5;
    s.init_id = 4242;
    s.lidar_mode = std::to_string(columns) + "x" + std::to_string(rate_hz);
    s.frame_rate_hz = rate_hz;
    s.udp_port_lidar = 7502;
    s.udp_port_imu = 7503;
    DataFormat& f = s.format;
    f.pixels_per_column = beams;
    f.columns_per_packet = 16;
    f.columns_per_frame = columns;
    f.column_window_first = 0;
    f.column_window_last = columns - 1;
    f.lidar_profile = profile;
    const double column_azimuth_deg[4] = {4.23, 1.41, -1.41, -4.23};
    const double fov = kFovDeg[product];
    for (int u = 0; u < beams; ++u) {
        s.beam_altitude_angles_deg.push_back(fov / 2 - fov * u / (beams - 1));
        s.beam_azimuth_angles_deg.push_back(column_azimuth_deg[u % 4]);
    }
    // Destaggering shifts each row by its azimuth offset in columns, counted from the smallest
    // (the rule the OS1's own pixel_shift_by_row follows).
    const double min_az =
        *std::min_element(s.beam_azimuth_angles_deg.begin(), s.beam_azimuth_angles_deg.end());
    for (double az : s.beam_azimuth_angles_deg) {
        f.pixel_shift_by_row.push_back(
            static_cast<int>(std::lround((az - min_az) * columns / 360.0)));
    }
    // The product's beam origin offset and the spec's default lidar and IMU transforms.
    s.lidar_origin_to_beam_origin_mm = kBeamOriginMm[product];
    s.beam_to_lidar_transform = Eigen::Matrix4d::Identity();
    s.beam_to_lidar_transform(0, 3) = kBeamOriginMm[product];
    s.lidar_to_sensor_transform << -1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1, 36.18, 0, 0, 0, 1;
    s.imu_to_sensor_transform << 1, 0, 0, 6.253, 0, 1, 0, -11.775, 0, 0, 1, 7.645, 0, 0, 0, 1;
    s.source = "built-in OS-" + std::to_string(product) + "-" + std::to_string(beams);
    return s;
}

}  // namespace bimslam::ouster
