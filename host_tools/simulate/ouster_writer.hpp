// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// An Ouster sensor's UDP stream as a pcap (specs/ouster-lidar.md): lidar packets of the
// metadata's profile, encoded by drivers/ouster PacketEncoder (frame and measurement ids, LEGACY
// encoder counts, init_id, prod_sn, and the CRC-64 footer when the firmware is 3.x), and LEGACY
// IMU packets, in the order a host receives them: each lidar packet when its last column is
// measured, each IMU packet when it is sampled, both plus a fixed 60 us of link latency. Datagrams
// are cut into IPv4 fragments at MTU 1500 (NetworkSpec::fragment), as the sensor's link does, and
// lost with NetworkSpec::packet_loss, independently, drawn from the seed. A step of the sensor's
// clock (SensorSpec::clock_jump_s) moves the timestamps in the packets, not when they arrive.
#pragma once

#include <cstdint>
#include <random>
#include <span>
#include <vector>

#include "algorithms/simulation/lidar_simulator.hpp"
#include "drivers/net/pcap_writer.hpp"
#include "drivers/ouster/imu_packet.hpp"
#include "drivers/ouster/lidar_frame.hpp"
#include "drivers/ouster/packet_encoder.hpp"
#include "host_tools/simulate/scenario.hpp"

namespace bimslam::simulate {

struct OusterWriterStats {
    uint64_t lidar_packets = 0;  // written
    uint64_t imu_packets = 0;
    uint64_t lost_packets = 0;  // dropped by packet_loss
    uint64_t bytes = 0;         // UDP payload bytes written
};

class OusterWriter {
public:
    // `writer` (Ethernet link type) stays the caller's. host_minus_sensor_ns maps the sensor
    // clock to the capture's (host) time stamps.
    // The sensor's clock steps by jump_ns at jump_at_ns (its own clock; jump_ns 0: never).
    OusterWriter(const ouster::SensorInfo& info, net::PcapWriter& writer,
                 const NetworkSpec& network, uint64_t seed, int64_t host_minus_sensor_ns,
                 int64_t jump_at_ns = 0, int64_t jump_ns = 0);

    // Frame `index` of simulated ranges (the image's layout is the sensor's), whose column v was
    // measured at column_ns[v] (sensor clock), with the IMU samples measured up to the frame's
    // end (sorted by time), which are written interleaved in time order.
    void WriteFrame(uint32_t index, const simulation::ScanImage& image,
                    std::span<const uint64_t> column_ns, std::span<const ouster::ImuSample> imu);
    // IMU samples after the last frame.
    void WriteImu(std::span<const ouster::ImuSample> imu);

    const OusterWriterStats& stats() const { return stats_; }
    const ouster::PacketEncoder& encoder() const { return encoder_; }

private:
    void Send(int64_t sensor_ns, uint16_t port, std::span<const uint8_t> payload);
    void SendImuUpTo(std::span<const ouster::ImuSample> imu, size_t& next, int64_t sensor_ns);
    // What the sensor stamps at true time t (its clock after a step).
    uint64_t Stamp(uint64_t t) const {
        return jump_ns_ != 0 && int64_t(t) >= jump_at_ns_ ? uint64_t(int64_t(t) + jump_ns_) : t;
    }

    ouster::SensorInfo info_;
    ouster::PacketEncoder encoder_;
    net::PcapWriter& writer_;
    NetworkSpec network_;
    std::mt19937_64 loss_rng_;
    int64_t host_minus_sensor_ns_;
    int64_t jump_at_ns_, jump_ns_;
    uint32_t sensor_ip_, host_ip_;
    ouster::LidarFrame frame_;
    std::vector<uint8_t> packet_;
    std::array<uint8_t, 48> imu_packet_{};
    OusterWriterStats stats_;
};

// The sensor the scenario asks for: its metadata file, or the built-in `model` in the scenario's
// lidar mode and UDP profile, reporting firmware 3.0.1 (so that packets of the newer profiles
// carry a CRC-64). Throws common::Error naming the field for a mode or profile it cannot make,
// common::FileError for a bad metadata file, and for an IMU profile other than LEGACY.
ouster::SensorInfo SensorFor(const SensorSpec& spec);

}  // namespace bimslam::simulate
