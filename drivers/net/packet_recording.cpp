// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "drivers/net/packet_recording.hpp"

namespace bimslam::net {

PacketRecording::PacketRecording(const std::filesystem::path& path,
                                 const PacketRecordingOptions& options)
    : path_(path), extractor_(options.extractor) {
    if (LooksLikeRosBag(path)) {
        bag_ = std::make_unique<RosPacketBag>(path);
        bag_->SetPorts(options.bag_lidar_port, options.bag_imu_port);
    } else {
        pcap_.emplace(path);
    }
}

PacketRecording::~PacketRecording() = default;

bool PacketRecording::Next(UdpDatagram& out) {
    if (bag_) return bag_->Next(out);
    if (finished_) return false;
    PcapRecord record;
    while (pcap_->Next(record)) {
        if (extractor_.Feed(record, out)) return true;
    }
    extractor_.Finish();
    finished_ = true;
    return false;
}

uint64_t PacketRecording::records() const { return bag_ ? bag_->packets() : pcap_->records(); }

bool PacketRecording::truncated() const { return pcap_ && pcap_->truncated(); }

}  // namespace bimslam::net
