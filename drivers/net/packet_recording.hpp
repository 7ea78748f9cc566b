// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The UDP datagrams of a recording file, whatever its format: a pcap or pcapng (plain or .gz;
// PcapReader + UdpExtractor: link layers, IPv4 reassembly) or a ROS 1 bag of ouster-ros packet
// topics (RosPacketBag: each topic's messages given a port). Told apart by the file's content, so
// every reader of recordings (bimslam ouster info|export, odometry, map, ouster replay and
// bimslam-rig replay) takes both through this one class.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>

#include "drivers/net/ipv4.hpp"
#include "drivers/net/pcap_reader.hpp"
#include "drivers/net/ros_packet_bag.hpp"

namespace bimslam::net {

struct PacketRecordingOptions {
    ExtractorConfig extractor;  // pcap only
    // The ports a bag's lidar and IMU topics are given (a pcap carries its own).
    uint16_t bag_lidar_port = 7502;
    uint16_t bag_imu_port = 7503;
};

class PacketRecording {
public:
    // Opens the file. Throws common::FileError naming it when it cannot be opened or is neither a
    // pcap/pcapng nor a readable ROS bag of packets (RosPacketBag's messages).
    explicit PacketRecording(const std::filesystem::path& path,
                             const PacketRecordingOptions& options = {});
    ~PacketRecording();
    PacketRecording(const PacketRecording&) = delete;
    PacketRecording& operator=(const PacketRecording&) = delete;

    // The next datagram, or false at the end (a pcap's incomplete reassemblies are then dropped
    // and counted). `out.payload` stays valid until the next call. Pcap: does not allocate;
    // throws common::FileError on a corrupt record header. Bag: see RosPacketBag::Next.
    bool Next(UdpDatagram& out);

    bool is_bag() const { return bag_ != nullptr; }
    const RosPacketBag* bag() const { return bag_.get(); }
    // Pcap: what records gave no datagram and why (all zero for a bag).
    const ExtractorStats& extractor_stats() const { return extractor_.stats(); }
    // Pcap records, or bag messages, read so far.
    uint64_t records() const;
    // The file ended inside a record (pcap; a cut bag does not open).
    bool truncated() const;
    const std::filesystem::path& path() const { return path_; }

private:
    std::filesystem::path path_;
    std::optional<PcapReader> pcap_;
    std::unique_ptr<RosPacketBag> bag_;
    UdpExtractor extractor_;
    bool finished_ = false;
};

}  // namespace bimslam::net
