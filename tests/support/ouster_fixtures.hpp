// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Synthetic Ouster sensors and frames for tests, benchmarks and fuzz targets (no metadata file).
#pragma once

#include <gtest/gtest.h>

#include <random>
#include <type_traits>

#include "drivers/ouster/lidar_frame.hpp"
#include "drivers/ouster/packet_encoder.hpp"
#include "drivers/ouster/sensor_info.hpp"

namespace bimslam::ouster::fixtures {

// An OS1-32-like sensor (gradient beam table) in `profile`, 1024 columns unless said otherwise.
inline SensorInfo MakeSensor(LidarProfile profile, int h = 32, int w = 1024,
                             HeaderType header = HeaderType::kStandard) {
    SensorInfo s;
    s.prod_line = "OS-1-32-G";
    s.prod_sn = 992101000280;
    s.init_id = profile == LidarProfile::kLegacy ? 0 : 5431;
    // FW 3 sends CRC footers with the newer profiles; LEGACY is what FW 2.1 sends.
    s.build_rev = profile == LidarProfile::kLegacy ? "v2.1.1" : "v3.0.1";
    s.fw_major = profile == LidarProfile::kLegacy ? 2 : 3;
    s.fw_minor = profile == LidarProfile::kLegacy ? 1 : 0;
    s.fw_patch = 1;
    s.lidar_mode = std::to_string(w) + "x10";
    s.format.pixels_per_column = h;
    s.format.columns_per_frame = w;
    s.format.columns_per_packet = 16;
    s.format.column_window_first = 0;
    s.format.column_window_last = w - 1;
    s.format.lidar_profile = profile;
    s.format.header_type = header;
    s.format.pixel_shift_by_row.assign(h, 0);
    for (int u = 0; u < h; ++u) {
        s.beam_altitude_angles_deg.push_back(22.5 - 45.0 * u / (h - 1));
        s.beam_azimuth_angles_deg.push_back((u % 4 - 1.5) * 2.8);
        s.format.pixel_shift_by_row[u] = (u % 4) * 8;
    }
    s.lidar_origin_to_beam_origin_mm = 15.806;
    s.beam_to_lidar_transform(0, 3) = 15.806;
    s.lidar_to_sensor_transform << -1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1, 36.18, 0, 0, 0, 1;
    s.imu_to_sensor_transform << 1, 0, 0, 6.253, 0, 1, 0, -11.775, 0, 0, 1, 7.645, 0, 0, 0, 1;
    s.source = "synthetic " + std::string(ToString(profile));
    return s;
}

// A frame with random fields within each field's bits (RNG15 ranges in 8 mm steps), every column
// valid, timestamps 97.7 us apart.
inline LidarFrame MakeFrame(const PacketFormat& f, uint32_t frame_id, uint32_t seed) {
    std::mt19937 rng(seed);
    LidarFrame frame;
    frame.Reset(f);
    frame.frame_id = frame_id;
    for (int v = 0; v < frame.w; ++v) {
        frame.timestamp[v] = 1'000'000'000ull * frame_id + 97'656ull * v + 7;
        frame.measurement_id[v] = static_cast<uint16_t>(v);
        frame.status[v] = f.legacy() ? 0xFFFFFFFFu : 1u;
    }
    for (const FieldSpec& s : f.fields()) {
        for (size_t i = 0; i < static_cast<size_t>(frame.h) * frame.w; ++i) {
            const uint32_t value = (rng() & s.mask) * s.multiplier;
            frame.VisitField(s.field, [&](auto& image) {
                image[i] = static_cast<std::remove_reference_t<decltype(image[i])>>(value);
            });
        }
    }
    return frame;
}

// The packets of a frame, in order.
inline std::vector<std::vector<uint8_t>> Encode(const PacketEncoder& enc, const LidarFrame& frame) {
    std::vector<std::vector<uint8_t>> out;
    for (int k = 0; k < enc.packets_per_frame(); ++k) {
        out.emplace_back(enc.format().lidar_packet_size());
        enc.EncodeLidarPacket(frame, k, out.back().data());
    }
    return out;
}

// Every field of two SensorInfos but `source`, with gtest expectations.
inline void ExpectSameSensor(const SensorInfo& a, const SensorInfo& b) {
    EXPECT_EQ(a.prod_line, b.prod_line);
    EXPECT_EQ(a.prod_sn, b.prod_sn);
    EXPECT_EQ(a.build_rev, b.build_rev);
    EXPECT_EQ(a.fw_major * 10000 + a.fw_minor * 100 + a.fw_patch,
              b.fw_major * 10000 + b.fw_minor * 100 + b.fw_patch);
    EXPECT_EQ(a.init_id, b.init_id);
    EXPECT_EQ(a.lidar_mode, b.lidar_mode);
    EXPECT_EQ(a.frame_rate_hz, b.frame_rate_hz);
    EXPECT_EQ(a.udp_port_lidar, b.udp_port_lidar);
    EXPECT_EQ(a.udp_port_imu, b.udp_port_imu);
    const DataFormat &fa = a.format, &fb = b.format;
    EXPECT_EQ(fa.pixels_per_column, fb.pixels_per_column);
    EXPECT_EQ(fa.columns_per_packet, fb.columns_per_packet);
    EXPECT_EQ(fa.columns_per_frame, fb.columns_per_frame);
    EXPECT_EQ(fa.pixel_shift_by_row, fb.pixel_shift_by_row);
    EXPECT_EQ(fa.column_window_first, fb.column_window_first);
    EXPECT_EQ(fa.column_window_last, fb.column_window_last);
    EXPECT_EQ(fa.lidar_profile, fb.lidar_profile);
    EXPECT_EQ(fa.imu_profile, fb.imu_profile);
    EXPECT_EQ(fa.header_type, fb.header_type);
    EXPECT_EQ(fa.imu_measurements_per_packet, fb.imu_measurements_per_packet);
    EXPECT_EQ(a.beam_altitude_angles_deg, b.beam_altitude_angles_deg);
    EXPECT_EQ(a.beam_azimuth_angles_deg, b.beam_azimuth_angles_deg);
    EXPECT_EQ(a.lidar_origin_to_beam_origin_mm, b.lidar_origin_to_beam_origin_mm);
    EXPECT_EQ(a.beam_to_lidar_transform, b.beam_to_lidar_transform);
    EXPECT_EQ(a.lidar_to_sensor_transform, b.lidar_to_sensor_transform);
    EXPECT_EQ(a.imu_to_sensor_transform, b.imu_to_sensor_transform);
}

inline const LidarProfile kAllProfiles[] = {
    LidarProfile::kLegacy, LidarProfile::kRng19Rfl8Sig16Nir16, LidarProfile::kRng15Rfl8Nir8,
    LidarProfile::kRng19Rfl8Sig16Nir16Dual, LidarProfile::kRng15Rfl8Nir8Dual};

}  // namespace bimslam::ouster::fixtures
