// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// An Ouster recording read back as frames: a pcap or a ROS bag (drivers/net's PacketRecording)
// -> UDP datagrams -> lidar packets to FrameBatcher, IMU packets to ImuDecoder (drivers/ouster).
// The lidar and IMU ports come from the options, else the metadata, else a first pass over a
// pcap guesses them from payload sizes (specs/ouster-lidar.md, "Capture files"); a bag's topics
// say which packet is which, so its ports are only labels.
#pragma once

#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "algorithms/io/capture_files.hpp"
#include "drivers/net/ipv4.hpp"
#include "drivers/net/packet_recording.hpp"
#include "drivers/ouster/frame_batcher.hpp"
#include "drivers/ouster/imu_packet.hpp"
#include "drivers/ouster/sensor_info.hpp"

namespace bimslam::capture {

struct OusterCaptureOptions {
    std::optional<uint16_t> lidar_port;  // override the metadata
    std::optional<uint16_t> imu_port;
    ouster::BatcherConfig batcher;
    net::ExtractorConfig extractor;
};

struct OusterCaptureStats {
    uint64_t datagrams = 0;      // UDP datagrams after reassembly
    uint64_t lidar_packets = 0;  // datagrams on the lidar port
    uint64_t imu_packets = 0;    // datagrams on the IMU port
    uint64_t other_datagrams = 0;
    std::map<uint16_t, uint64_t> other_ports;  // port -> datagrams, for messages
    uint64_t imu_samples = 0;
    bool truncated = false;  // the file ends in the middle of a record
};

// The sensor of a recording (io::ResolveCapture): its metadata JSON, else (a bag) the bag's
// metadata topic. Throws common::FileError naming the file and what is wrong.
ouster::SensorInfo LoadRecordingInfo(const io::CaptureFiles& files);

class OusterCapture {
public:
    // Opens the capture (a pcap or a ROS bag of packets) and resolves the ports. Throws
    // common::FileError naming the file when it is unreadable or holds no packet of the
    // metadata's lidar packet size on any port (a capture of another sensor, or metadata of
    // another sensor mode).
    OusterCapture(const std::filesystem::path& recording, const ouster::SensorInfo& info,
                  const OusterCaptureOptions& options = {});
    ~OusterCapture();

    // The next emitted frame (complete or not), or nullptr at the end of the capture. Valid until
    // the next call. IMU samples met on the way go to the IMU callback.
    const ouster::LidarFrame* NextFrame();
    void OnImu(std::function<void(const ouster::ImuSample&)> callback) {
        on_imu_ = std::move(callback);
    }

    // Capture time of the last datagram read: the one that emitted the frames NextFrame returns,
    // or INT64_MAX once the end of the file emitted the last frame.
    int64_t last_arrival_ns() const { return last_arrival_ns_; }
    uint16_t lidar_port() const { return lidar_port_; }
    std::optional<uint16_t> imu_port() const { return imu_port_; }
    bool ports_guessed() const { return ports_guessed_; }
    const OusterCaptureStats& stats() const { return stats_; }
    const ouster::LidarStats& lidar_stats() const { return batcher_.stats(); }
    const ouster::ImuStats& imu_stats() const { return imu_.stats(); }
    const net::ExtractorStats& extractor_stats() const { return recording_->extractor_stats(); }
    // The bag's topics, nullptr for a pcap.
    const net::RosBagTopics* bag_topics() const {
        return recording_->bag() ? &recording_->bag()->topics() : nullptr;
    }
    const ouster::FrameBatcher& batcher() const { return batcher_; }

private:
    void Route(const net::UdpDatagram& d);

    std::filesystem::path path_;
    std::unique_ptr<net::PacketRecording> recording_;  // opened once the ports are known
    ouster::FrameBatcher batcher_;
    ouster::ImuDecoder imu_;
    uint16_t lidar_port_ = 0;
    std::optional<uint16_t> imu_port_;
    bool ports_guessed_ = false;
    bool ended_ = false;
    size_t ready_index_ = 0;  // frames of batcher_.ready() already returned
    int64_t last_arrival_ns_ = 0;
    std::function<void(const ouster::ImuSample&)> on_imu_;
    OusterCaptureStats stats_;
};

}  // namespace bimslam::capture
