// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// A recording's UDP datagrams sent again on a real socket at the recorded pace: the bench
// stand-in for a sensor (`bimslam ouster replay`: an Ouster's lidar and IMU packets to a rig
// running `bimslam-rig live`). Datagrams are read from the pcap (drivers/net: any link layer,
// IPv4 fragments reassembled) or ROS bag (its topics given the bag ports), those of the selected
// destination ports are sent to `to`, each at its capture time scaled by 1/speed from the start, in
// sendmmsg batches of the datagrams due together.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <string>

namespace bimslam::capture {

struct UdpReplayOptions {
    std::filesystem::path recording;  // a pcap, or a ROS bag of ouster-ros packet topics
    uint16_t bag_lidar_port = 7502, bag_imu_port = 7503;  // the "recorded" ports of a bag's topics
    uint32_t to_ip = 0x7F000001;                          // host byte order
    // Recorded destination port -> port to send to. Datagrams to other ports are skipped.
    std::map<uint16_t, uint16_t> ports;
    double speed = 1.0;  // 0: as fast as possible
    std::string bind_address = "0.0.0.0";
    uint16_t bind_port = 0;
    double max_duration_s = 0;             // > 0: stop after this much capture time
    std::function<void(double)> progress;  // capture seconds sent so far, about once a second
};

struct UdpReplayReport {
    uint64_t records = 0, datagrams = 0, sent = 0, skipped = 0, failed = 0, bytes = 0;
    double capture_s = 0, wall_s = 0;
    double max_late_ms = 0;  // the worst lag behind the recorded schedule
};

// Throws common::FileError for an unreadable recording, common::Error for a socket that cannot be
// set up.
UdpReplayReport ReplayUdp(const UdpReplayOptions& options);

}  // namespace bimslam::capture
