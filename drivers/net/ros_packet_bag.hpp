// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// A ROS 1 bag of raw sensor packets, as ouster-ros records them, read with the ROS library itself
// (Debian's rosbag_storage: rosbag::Bag and rosbag::View), not a parser of our own.
//
// ouster-ros publishes every UDP payload of the sensor as one message of `ouster_ros/PacketMsg`
// (`uint8[] buf`; ouster_sensor_msgs/PacketMsg in later releases, the same definition) on
// `<ns>/lidar_packets` and `<ns>/imu_packets`, and the sensor's metadata JSON as a
// `std_msgs/String` on `<ns>/metadata` (latched, once). The namespace varies (`/os_node`,
// `/os_node0`, `/ouster`, ...), so topics are found by their message definition's MD5 (the
// package name varies, the definition does not) and their name's suffix; a bag with several
// sensors is refused, naming the candidates.
//
// The packets come out as UdpDatagrams, so the code after the source is the pcap's: the lidar
// topic's messages on the lidar port, the IMU topic's on the IMU port (set by the caller from the
// metadata), each stamped with its bag record time (the host's receive time, as a pcap's capture
// time; PacketMsg has no header stamp). Reading allocates inside the library (its message index,
// chunk buffers): a recording's replay, never the live path.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "drivers/net/ipv4.hpp"

namespace bimslam::net {

// True when the file starts with the ROS bag 2.0 version line ("#ROSBAG V2.0\n").
bool LooksLikeRosBag(const std::filesystem::path& path);

struct RosBagTopics {
    std::string lidar;     // the lidar packet topic
    std::string imu;       // the IMU packet topic, empty when the bag has none
    std::string metadata;  // the metadata topic, empty when the bag has none
    std::vector<std::pair<std::string, std::string>> all;  // every topic and its type, sorted
    uint64_t lidar_messages = 0, imu_messages = 0;
};

class RosPacketBag {
public:
    // Opens the bag, reads its index and finds the topics. Throws common::FileError naming the
    // file when it is not a readable bag (truncated, not indexed, not a bag) or holds no lidar
    // packet topic (listing the topics it does hold) or several.
    explicit RosPacketBag(const std::filesystem::path& path);
    ~RosPacketBag();
    RosPacketBag(const RosPacketBag&) = delete;
    RosPacketBag& operator=(const RosPacketBag&) = delete;

    const RosBagTopics& topics() const { return topics_; }
    // The sensor's metadata JSON: the first message on the metadata topic. Throws
    // common::FileError naming the file and its topics when the bag has none.
    std::string ReadMetadata() const;

    // The destination ports given to the two topics' packets (default: Ouster's 7502 and 7503).
    void SetPorts(uint16_t lidar_port, uint16_t imu_port);
    // The next lidar or IMU packet in record-time order; false at the end. `out.payload` stays
    // valid until the next call. Throws common::FileError naming the file when a chunk cannot be
    // read.
    bool Next(UdpDatagram& out);
    // Packets returned so far.
    uint64_t packets() const { return packets_; }
    const std::filesystem::path& path() const { return path_; }

private:
    struct State;
    std::filesystem::path path_;
    RosBagTopics topics_;
    std::unique_ptr<State> state_;
    uint16_t lidar_port_ = 7502, imu_port_ = 7503;
    uint64_t packets_ = 0;
};

}  // namespace bimslam::net
