// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The lidar ingest thread: Ouster lidar and IMU datagrams -> FrameBatcher / ImuDecoder -> scans
// (point clouds with their arrival times) and IMU samples for the odometry thread, IMU samples
// for LCM. The datagrams come from the sensor's UDP ports (live: two net::UdpSource sockets) or
// from a recording (replay: a pcap or a ROS bag read by drivers/net's PacketRecording and paced
// by its capture or record times); the code after the source is the same. Per datagram nothing
// allocates, throws or logs: faults are counted in IngestCounters, which the health thread reads.
//
// Arrival clock: live, each datagram's kernel receive time (CLOCK_REALTIME) moved to
// CLOCK_MONOTONIC, so that a step of the wall clock does not reorder anything; replay, its
// capture time. The CAN ingest uses the same clock, so the odometry can order the two.
//
// Sensor restart: packets with another init_id than expected are rejected; when 64 in a row
// carry the same new init_id, it is adopted (counted as a restart) and batching resumes.
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

#include "drivers/ouster/sensor_info.hpp"
#include "firmware/modules/rig_types.hpp"
#include "firmware/runtime/seqlock.hpp"
#include "firmware/runtime/thread_table.hpp"

namespace bimslam::rig {

struct LidarIngestConfig {
    // Live: the sockets. Replay: the recording, a pcap or a ROS bag (non-empty selects replay);
    // a bag's lidar and IMU topics are given lidar_port and imu_port.
    std::string bind_address = "0.0.0.0";
    std::string sensor_address;
    uint16_t lidar_port = 7502;
    uint16_t imu_port = 7503;
    int receive_buffer_bytes = 8 << 20;
    std::filesystem::path recording;
    int64_t sensor_timeout_ns = 500'000'000;
    bool publish_imu = true;
};

// Cumulative counters (trivially copyable, for a Seqlock).
struct IngestCounters {
    uint64_t lidar_datagrams = 0, imu_datagrams = 0, other_datagrams = 0, bytes = 0;
    ouster::LidarStats lidar;
    ouster::ImuStats imu;
    uint64_t scans_queued = 0, scans_dropped = 0;
    uint64_t imu_dropped = 0;
    uint64_t silences = 0;         // the sensor fell silent for longer than the timeout
    uint64_t init_id_changes = 0;  // sensor restarts adopted
    uint64_t ip_bad_checksum = 0, ip_dropped = 0;
    uint64_t socket_errors = 0;
    uint64_t clock_backwards = 0;     // arrival times that went back (kept in order)
    int64_t last_packet_mono_ns = 0;  // 0: none yet
    uint32_t init_id = 0;
    bool finished = false;  // the recording ended
};

class LidarIngest {
public:
    // Opens the sockets (live) or the recording (replay); throws common::Error / FileError
    // naming what could not be opened.
    LidarIngest(const LidarIngestConfig& config, const ouster::SensorInfo& info,
                runtime::SpscQueue<ScanSlot>& scans, runtime::SpscQueue<ImuItem>& imu,
                runtime::SpscQueue<OusterImuItem>& imu_lcm, ReplayClock* replay);
    ~LidarIngest();

    // The thread body: until `stop`, or the end of the recording.
    void Run(runtime::ThreadStats& stats, const std::atomic<bool>& stop);

    IngestCounters counters() const { return counters_.Load(); }
    // The first capture time of the recording (replay), for the shared replay clock.
    int64_t first_capture_ns() const;
    // One line for the start-up log (sockets, receive buffers, ports).
    const std::string& description() const { return description_; }
    std::string receive_buffer_warning() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    runtime::Seqlock<IngestCounters> counters_;
    std::string description_;
};

}  // namespace bimslam::rig
