// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The per-scan join of the on-board mapping: decoded sensor data in, odometry, keyframes and the
// session's records out. `bimslam odometry` (host_tools/replay) and `bimslam-rig`
// (firmware/modules/odometry_module) run this one class, so they cannot drift apart; they differ
// only in threads, pacing and I/O (README.md).
//
// Layering: the one algorithms library that may use drivers, and only the decoders
// (drivers/ouster, drivers/can; never drivers/net): its inputs are their outputs (a LidarFrame
// with its per-column times and arrival times, an ImuSample, a Go1Sample). No threads, no I/O,
// no allocation per scan after the first (the pending rings are allocated here, the clouds keep
// their capacity).
//
// Order of inputs. Everything is tied to arrival order, so that a threaded caller and a
// single-threaded one hand the odometry the same samples before each scan:
// - Ouster IMU samples come from the same stream as the lidar packets: a scan gets every IMU
//   sample that arrived before the packet that emitted its frame (ScanInput::imu_before, a count
//   of AddImu calls since the start), which holds only if the caller adds them in arrival order
//   (the rig's live ingest reads its two sockets so: firmware/modules/lidar_ingest.cpp, LiveTurn);
// - Go1 samples come from another stream (CAN): a scan gets every sample received (Go1Sample::
//   host_time_ns, the receive time of the frame that completed it) up to the arrival of the
//   packet that emitted its frame (ScanInput::emitted_arrival_ns). A caller must have added them
//   all before Process (the rig waits for its CAN ingest to pass that time).
//
// Clocks (as the capture folder's header says): scans and Ouster IMU samples in the sensor clock;
// Go1 samples in the host clock of their receive, dated back by SampleAge to the bridge's receive
// of the HighState. The host-minus-sensor offset is estimated from the lidar packets: the
// smallest (arrival of a frame's last packet - sensor time of its last valid column) seen so far,
// i.e. the offset plus the smallest network latency. Go1 times move to the sensor clock with it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "algorithms/common/point_cloud.hpp"
#include "algorithms/io/session.hpp"
#include "algorithms/keyframes/keyframe_selector.hpp"
#include "algorithms/odometry/lidar_odometry.hpp"
#include "drivers/can/go1_sample.hpp"
#include "drivers/ouster/imu_packet.hpp"
#include "drivers/ouster/lidar_frame.hpp"
#include "drivers/ouster/sensor_info.hpp"

namespace bimslam::pipeline {

struct ScanPipelineConfig {
    odometry::LidarOdometryConfig odometry;
    keyframes::KeyframeConfig keyframes;
    // Samples held until their scan: 1024 is 10 s of Ouster IMU or Go1 samples; the oldest is
    // dropped (and counted) when a caller adds more than that between two scans.
    size_t pending_capacity = 1024;
    // A scan whose sensor time goes back by more than this, or forward by more than
    // clock_jump_forward_s, is a clock jump (a sensor restart or a step of its time source):
    // counted, the odometry and the clock offset start again.
    double clock_jump_back_s = 0.05;
    double clock_jump_forward_s = 5.0;

    // Throws common::Error naming the field and value.
    void Validate() const;
};

// A scan as an ingest hands it over: the frame's points and what the join needs of the frame.
struct ScanInput {
    common::PointCloud cloud;  // lidar (Ouster sensor) frame, stamped at the scan start
    bool complete = true;      // every column of the window arrived
    int64_t frame_id = 0;
    int64_t last_column_ns = -1;     // sensor time of the last valid column (-1: none)
    int64_t last_arrival_ns = 0;     // arrival (host clock) of the frame's last packet, 0: unknown
    int64_t emitted_arrival_ns = 0;  // arrival of the packet (or end of stream) that emitted it
    uint64_t imu_before = 0;         // AddImu calls that precede it (see the header)
};

// Fills `out` from a frame the batcher emitted at `emitted_arrival_ns`, with `imu_before` IMU
// samples before it; out->cloud keeps its capacity (ouster::ToPointCloud).
void FrameToScan(const ouster::LidarFrame& frame, int64_t emitted_arrival_ns, uint64_t imu_before,
                 ScanInput* out);

// An Ouster IMU sample for the odometry: the gyroscope's time, sensor frame, SI units.
odometry::ImuMeasurement ImuFromOuster(const ouster::ImuSample& s);

// A Go1 sample with its two host times.
struct BodyInput {
    int64_t received_ns = 0;  // receive of the CAN frame that completed the sample
    int64_t measured_ns = 0;  // the bridge's receive of the HighState: received - SampleAge
    odometry::BodyMotionSample sample;  // t_ns set by the pipeline (sensor clock)
};
BodyInput BodyFromGo1(const can::Go1Sample& s);

// What Process made of one scan; valid until the next Process.
struct ScanOutput {
    uint64_t scan_index = 0;  // 0-based, every scan given to Process
    int64_t stamp_ns = 0;     // the scan start (sensor clock), trajectory.tum's time
    const odometry::OdometryResult* odometry = nullptr;
    bool complete = true;
    bool clock_jump = false;      // the odometry was started again at this scan
    bool keyframe = false;        // this scan became keyframe `keyframe_index`
    uint64_t keyframe_index = 0;  // of the keyframes since the start (or the last clock jump)
    const io::SessionKeyframe* keyframe_data = nullptr;  // when keyframe
    const io::SessionEdge* edge = nullptr;               // from the previous keyframe, if any
};

struct ScanPipelineStats {
    uint64_t scans = 0;
    uint64_t incomplete_scans = 0;
    uint64_t keyframes = 0;
    uint64_t imu_samples = 0;      // given to the odometry
    uint64_t body_samples = 0;     // given to the odometry
    uint64_t pending_dropped = 0;  // samples dropped because a pending ring was full
    uint64_t clock_jumps = 0;
    // failed: registration failed (too few correspondences) or failed its own evidence
    // (kCheckFailed, counted in check_failed too).
    uint64_t over_budget = 0, degenerate = 0, failed = 0, not_converged = 0;
    uint64_t check_failed = 0;
    uint64_t contradicted_gyro = 0;    // scans that turned against the gyro (kContradictsGyro)
    uint64_t contradicted_legs = 0;    // the Go1's legs against the LiDAR (kContradictsLegs)
    double distance_m = 0;             // along the odometry trajectory
    int64_t host_minus_sensor_ns = 0;  // the current estimate (0 before the first frame)
    bool offset_known = false;
};

class ScanPipeline {
public:
    explicit ScanPipeline(const ScanPipelineConfig& config);

    // Inputs in arrival order within each stream. Never throw, never allocate.
    void AddImu(const odometry::ImuMeasurement& m);
    void AddBody(const BodyInput& b);

    // One scan: the pending samples that precede it go to the odometry, then the scan; a
    // keyframe when the selector takes it. Never throws; allocates nothing after the first
    // keyframe of a given cloud size (LidarOdometry's and KeyframeSelector's own promises).
    const ScanOutput& Process(const ScanInput& scan);

    const ScanPipelineStats& stats() const { return stats_; }
    const odometry::LidarOdometry& odometry() const { return *odometry_; }
    const ScanPipelineConfig& config() const { return config_; }
    uint64_t imu_added() const { return imu_added_; }

private:
    struct PendingBody {
        int64_t received_ns;
        int64_t measured_ns;
        odometry::BodyMotionSample sample;
    };
    void Restart();

    ScanPipelineConfig config_;
    std::optional<odometry::LidarOdometry> odometry_;
    std::optional<keyframes::KeyframeSelector> selector_;
    // Pending rings (allocated once).
    std::vector<odometry::ImuMeasurement> imu_;
    size_t imu_head_ = 0, imu_count_ = 0;
    uint64_t imu_added_ = 0;      // sequence number of the next AddImu
    uint64_t imu_first_seq_ = 0;  // sequence number of imu_[imu_head_]
    std::vector<PendingBody> body_;
    size_t body_head_ = 0, body_count_ = 0;

    int64_t offset_ns_ = 0;
    bool offset_known_ = false;
    bool have_last_stamp_ = false;
    int64_t last_stamp_ns_ = 0;
    Eigen::Vector3d last_position_ = Eigen::Vector3d::Zero();
    ScanOutput out_;
    ScanPipelineStats stats_;
};

// session.json of a rig session recorded with this sensor and keyframe rule.
io::SessionManifest MakeSessionManifest(const ouster::SensorInfo& info,
                                        const std::string& metadata_file,
                                        const keyframes::KeyframeConfig& keyframes);

// The scan's records into a session: its pose in trajectory.tum, and its keyframe and edge when
// it is one. Throws what io::SessionWriter throws (I/O: not for the hot path).
void WriteScan(const ScanOutput& out, io::SessionWriter& writer);

}  // namespace bimslam::pipeline
