// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The inverse of the decoder: frames to byte-exact Ouster packets of any profile
// (specs/ouster-lidar.md), for the capture simulator and for tests. Headers carry the metadata's
// init_id and prod_sn, LEGACY columns their frame id and encoder count, and packets of the newer
// profiles a CRC-64 footer when asked (FW 3.x) or zero (FW 2.x).
#pragma once

#include <cstddef>
#include <cstdint>

#include "drivers/ouster/imu_packet.hpp"
#include "drivers/ouster/lidar_frame.hpp"
#include "drivers/ouster/packet_format.hpp"
#include "drivers/ouster/sensor_info.hpp"

namespace bimslam::ouster {

class PacketEncoder {
public:
    explicit PacketEncoder(const SensorInfo& info, bool fill_crc = false);

    const PacketFormat& format() const { return format_; }
    int packets_per_frame() const;

    // Packet k of `frame` (columns k * columns_per_packet ...): headers from the frame's
    // per-column arrays, pixels from its field images (values beyond a field's bits are
    // truncated; RNG15 ranges are floored to 8 mm). `out` must hold lidar_packet_size() bytes.
    void EncodeLidarPacket(const LidarFrame& frame, int k, uint8_t* out) const;

    // A LEGACY IMU packet (48 B): sample in the sensor frame and SI units back to the IMU frame,
    // g and deg/s. `sys_time_ns` is the packet's system time.
    void EncodeLegacyImuPacket(const ImuSample& sample, uint64_t sys_time_ns, uint8_t* out) const;

private:
    SensorInfo info_;
    PacketFormat format_;
    bool fill_crc_;
};

}  // namespace bimslam::ouster
