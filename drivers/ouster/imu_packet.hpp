// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Ouster IMU packets (specs/ouster-lidar.md, "IMU packets"), both layouts, converted to SI units
// and rotated into the sensor frame:
// - LEGACY (48 B, 100 Hz): u64 system, accelerometer and gyroscope times (ns, lidar clock), then
//   f32 ax ay az in g and f32 wx wy wz in deg/s;
// - ACCEL32_GYRO32_NMEA (FW 3.2+): 32 B header, 100 B NMEA block, N x 36 B samples (u64 time,
//   u16 measurement id, u16 status, f32 accel in m/s^2, f32 gyro in rad/s), 32 B footer (CRC-64).
// Only the rotation of imu_to_sensor_transform applies to these free vectors; the lever arm's
// centripetal term is left to the consumer, which knows the angular acceleration.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

#include "drivers/ouster/sensor_info.hpp"

namespace bimslam::ouster {

inline constexpr double kStandardGravity = 9.80665;  // m/s^2 per g (ISO 80000-3)

struct ImuSample {
    uint64_t time_ns = 0;       // sensor clock; the accelerometer's time for LEGACY
    uint64_t gyro_time_ns = 0;  // sensor clock
    Eigen::Vector3d accel = Eigen::Vector3d::Zero();  // m/s^2, sensor frame
    Eigen::Vector3d gyro = Eigen::Vector3d::Zero();   // rad/s, sensor frame
};

enum class ImuReject : uint8_t { kSize, kPacketType, kProdSn, kInitId, kCrc, kNonFinite };
inline constexpr int kNumImuRejects = 6;
std::string_view ToString(ImuReject r);

struct ImuStats {
    uint64_t packets = 0;
    uint64_t samples = 0;
    std::array<uint64_t, kNumImuRejects> rejected{};
    uint64_t invalid_samples = 0;  // NMEA layout: status bit 0 clear
};

class ImuDecoder {
public:
    explicit ImuDecoder(const SensorInfo& info);
    size_t packet_size() const { return packet_size_; }
    // Decodes one packet into `out` (up to out.size() samples); returns how many, or the reason
    // it was dropped. Never throws, never allocates.
    struct Result {
        size_t samples = 0;
        std::optional<ImuReject> rejected;
    };
    Result Decode(const uint8_t* p, size_t size, std::span<ImuSample> out);
    const ImuStats& stats() const { return stats_; }
    // As FrameBatcher::SetExpectedInitId, after a sensor restart.
    void SetExpectedInitId(uint32_t init_id) { info_.init_id = init_id; }

private:
    Result Drop(ImuReject r);
    SensorInfo info_;
    Eigen::Matrix3d R_sensor_imu_;
    size_t packet_size_;
    ImuStats stats_;
};

}  // namespace bimslam::ouster
