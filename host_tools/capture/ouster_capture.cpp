// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/capture/ouster_capture.hpp"

#include <limits>
#include <sstream>

#include "algorithms/common/status.hpp"
#include "drivers/ouster/metadata.hpp"

namespace bimslam::capture {
namespace {
using common::FileError;
using common::StatusCode;

std::string DescribePorts(const std::map<uint16_t, uint64_t>& ports) {
    std::ostringstream s;
    int shown = 0;
    for (const auto& [port, n] : ports) {
        if (shown++ == 4) {
            s << ", ...";
            break;
        }
        s << (shown > 1 ? ", " : "") << n << " on port " << port;
    }
    return s.str();
}
}  // namespace

ouster::SensorInfo LoadRecordingInfo(const io::CaptureFiles& files) {
    if (!files.metadata.empty()) return ouster::LoadMetadata(files.metadata);
    const net::RosPacketBag bag(files.packets);
    return ouster::ParseMetadata(files.packets.string() + ":" + bag.topics().metadata,
                                 bag.ReadMetadata());
}

OusterCapture::OusterCapture(const std::filesystem::path& recording, const ouster::SensorInfo& info,
                             const OusterCaptureOptions& options)
    : path_(recording), batcher_(info, options.batcher), imu_(info) {
    const size_t lidar_size = batcher_.format().lidar_packet_size();
    std::optional<uint16_t> lidar = options.lidar_port ? options.lidar_port : info.udp_port_lidar;
    imu_port_ = options.imu_port ? options.imu_port : info.udp_port_imu;
    const bool bag = net::LooksLikeRosBag(recording);
    if (bag) {
        // The topics tell the packets apart; the ports only label them.
        lidar = lidar.value_or(7502);
        imu_port_ = imu_port_.value_or(uint16_t(*lidar == 7503 ? 7502 : 7503));
    }
    if (!lidar) {
        const net::PortGuess guess =
            net::GuessPortsInCapture(recording, lidar_size, imu_.packet_size());
        ports_guessed_ = true;
        if (!guess.lidar_port) {
            const std::string drops = net::DescribeDrops(guess.extractor, false);
            throw FileError(StatusCode::kParseError, recording.string(), 0,
                            "no Ouster lidar packets: none of its " +
                                std::to_string(guess.datagrams) + " UDP datagrams (" +
                                std::to_string(guess.records) + " records" +
                                (drops.empty() ? "" : "; " + drops) + ") has the " +
                                std::to_string(lidar_size) + " bytes that " +
                                std::string(ToString(info.format.lidar_profile)) + " with " +
                                std::to_string(info.format.pixels_per_column) +
                                " pixels per column sends (metadata " + info.source + ")");
        }
        lidar = guess.lidar_port;
        if (!imu_port_) imu_port_ = guess.imu_port;
    }
    lidar_port_ = *lidar;
    net::PacketRecordingOptions ro;
    ro.extractor = options.extractor;
    ro.bag_lidar_port = lidar_port_;
    ro.bag_imu_port = imu_port_.value_or(0);
    recording_ = std::make_unique<net::PacketRecording>(recording, ro);
}

OusterCapture::~OusterCapture() = default;

void OusterCapture::Route(const net::UdpDatagram& d) {
    ++stats_.datagrams;
    last_arrival_ns_ = d.timestamp_ns;
    if (d.dst_port == lidar_port_) {
        ++stats_.lidar_packets;
        batcher_.AddPacket(d.payload.data(), d.payload.size(), d.timestamp_ns);
        ready_index_ = 0;
    } else if (imu_port_ && d.dst_port == *imu_port_) {
        ++stats_.imu_packets;
        ouster::ImuSample samples[64];
        const auto r = imu_.Decode(d.payload.data(), d.payload.size(), samples);
        stats_.imu_samples += r.samples;
        if (on_imu_) {
            for (size_t i = 0; i < r.samples; ++i) on_imu_(samples[i]);
        }
    } else {
        ++stats_.other_datagrams;
        ++stats_.other_ports[d.dst_port];
    }
}

const ouster::LidarFrame* OusterCapture::NextFrame() {
    for (;;) {
        if (ready_index_ < batcher_.ready().size()) return batcher_.ready()[ready_index_++];
        if (ended_) return nullptr;
        net::UdpDatagram d;
        if (recording_->Next(d)) {
            Route(d);
            continue;
        }
        // End of file: a capture that holds Ouster-sized packets on no port is no Ouster capture.
        ended_ = true;
        last_arrival_ns_ = std::numeric_limits<int64_t>::max();
        stats_.truncated = recording_->truncated();
        batcher_.Flush();
        ready_index_ = 0;
        const std::string drops = net::DescribeDrops(recording_->extractor_stats(), false);
        if (stats_.lidar_packets == 0 && stats_.other_datagrams > 0) {
            throw FileError(StatusCode::kParseError, path_.string(), 0,
                            "no packets on the lidar port " + std::to_string(lidar_port_) +
                                "; the capture holds UDP datagrams " +
                                DescribePorts(stats_.other_ports) + ": not this Ouster sensor" +
                                (drops.empty() ? "" : " (" + drops + ")"));
        }
        if (stats_.lidar_packets == 0 && !drops.empty()) {
            throw FileError(StatusCode::kParseError, path_.string(), 0,
                            "0 UDP datagrams from " +
                                std::to_string(recording_->extractor_stats().records) +
                                " records: " + drops);
        }
    }
}

}  // namespace bimslam::capture
