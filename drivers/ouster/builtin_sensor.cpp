#include "drivers/ouster/builtin_sensor.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "algorithms/common/status.hpp"

namespace bimslam::ouster {

SensorInfo BuiltinOs1_32(LidarProfile profile, int columns, int rate_hz) {
    const bool ok = (rate_hz == 10 && (columns == 512 || columns == 1024 || columns == 2048)) ||
                    (rate_hz == 20 && (columns == 512 || columns == 1024));
    if (!ok) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            "no OS1 lidar mode " + std::to_string(columns) + "x" +
                                std::to_string(rate_hz) +
                                " (512x10, 1024x10, 2048x10, 512x20, 1024x20)");
    }
    SensorInfo s;
    s.prod_line = "OS-1-32-U0";
    s.prod_sn = 122000000032;
    s.build_rev = "v2.5.0";
    s.fw_major = 2;
    s.fw_minor = 5;
    s.init_id = 4242;
    s.lidar_mode = std::to_string(columns) + "x" + std::to_string(rate_hz);
    s.frame_rate_hz = rate_hz;
    s.udp_port_lidar = 7502;
    s.udp_port_imu = 7503;
    DataFormat& f = s.format;
    f.pixels_per_column = 32;
    f.columns_per_packet = 16;
    f.columns_per_frame = columns;
    f.column_window_first = 0;
    f.column_window_last = columns - 1;
    f.lidar_profile = profile;
    const double column_azimuth_deg[4] = {4.23, 1.41, -1.41, -4.23};
    for (int u = 0; u < 32; ++u) {
        s.beam_altitude_angles_deg.push_back(22.5 - 45.0 * u / 31.0);
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
    // OS1 beam origin offset and the spec's default lidar and IMU transforms.
    s.lidar_origin_to_beam_origin_mm = 15.806;
    s.beam_to_lidar_transform = Eigen::Matrix4d::Identity();
    s.beam_to_lidar_transform(0, 3) = 15.806;
    s.lidar_to_sensor_transform << -1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1, 36.18, 0, 0, 0, 1;
    s.imu_to_sensor_transform << 1, 0, 0, 6.253, 0, 1, 0, -11.775, 0, 0, 1, 7.645, 0, 0, 0, 1;
    s.source = "built-in OS-1-32";
    return s;
}

}  // namespace bimslam::ouster
