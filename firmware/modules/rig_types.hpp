// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// What the rig's threads hand each other through their queues (firmware/runtime/spsc_queue.hpp),
// and the replay clock they share. Every slot is constructed once at start-up with its buffers
// reserved; the threads fill and read them in place.
#pragma once

#include <atomic>
#include <cstdint>
#include <limits>
#include <optional>

#include "algorithms/io/session.hpp"
#include "algorithms/odometry/lidar_odometry.hpp"
#include "algorithms/pipeline/scan_pipeline.hpp"
#include "drivers/can/go1_decoder.hpp"
#include "drivers/ouster/frame_batcher.hpp"
#include "drivers/ouster/imu_packet.hpp"
#include "firmware/runtime/spsc_queue.hpp"
#include "firmware/runtime/wakeup.hpp"

namespace bimslam::rig {

inline constexpr int64_t kEndOfStream = std::numeric_limits<int64_t>::max();

// When a scan passed each stage from its last packet to its odometry_t on LCM (CLOCK_MONOTONIC
// ns): the latency and its breakdown by stage in the summary (firmware/app/README.md).
struct ScanTimes {
    int64_t last_packet = 0;    // the frame's last packet reached the rig (kernel receive time)
    int64_t ingested = 0;       // the ingest thread took that packet up
    int64_t queued = 0;         // the scan assembled and in the scan queue
    int64_t started = 0;        // the odometry thread took the scan (after any wait for CAN)
    int64_t odometry_done = 0;  // ScanPipeline::Process returned (odometry, keyframe selection)
    int64_t handed = 0;         // the odometry queued for the LCM thread
    // The odometry thread's CPU time from `started` to `odometry_done`: the odometry stage less
    // this is time the thread waited for a CPU (a loaded machine, a higher priority).
    int64_t odometry_cpu_ns = 0;
};

// A frame's points and what the join needs, plus when it passed the ingest's stages.
struct ScanSlot {
    pipeline::ScanInput scan;
    ScanTimes times;  // last_packet, ingested, queued
};

struct ImuItem {
    odometry::ImuMeasurement measurement;
};

struct BodyItem {
    pipeline::BodyInput body;
};

// Pacing of a replay: capture time t is handed on at start_mono + (t - start_capture) / speed.
// Lidar and CAN recordings share it (both are stamped by the capturing host's clock).
struct ReplayClock {
    // A replay loses nothing at any speed: its producers wait for room in every queue
    // (SpscQueue::BeginPushWaiting), where a live run drops and counts.
    double speed = 1.0;                                   // 0: as fast as possible
    std::atomic<int64_t> start_capture_ns{kEndOfStream};  // the earlier first stamp of the two
    int64_t start_mono_ns = 0;
    // Sleeps until capture time t is due; returns the monotonic time it handed on at.
    int64_t WaitFor(int64_t capture_ns, const std::atomic<bool>& stop) const;
    bool unpaced() const { return speed <= 0; }
};

// A scan's odometry for the LCM thread.
struct OdometryItem {
    odometry::OdometryResult result;
    uint64_t scan_index = 0;
    int64_t scan_end_ns = 0;
    bool complete = true;
    bool keyframe = false;
    bool reset = false;
    ScanTimes times;  // every stage up to `handed`
};

// A keyframe for the session writer or the LCM thread.
struct KeyframeItem {
    io::SessionKeyframe keyframe;
    std::optional<io::SessionEdge> edge;
    uint64_t keyframe_index = 0;  // of the selector, in its segment
    uint64_t scan_index = 0;
    uint32_t segment = 0;  // a clock jump starts a new segment (a new session folder)
    // The odometry flagged its height ambiguous (odometry::kHeightAmbiguous) at a scan since the
    // previous keyframe, this one's included: for the localiser (Relocalizer::AddKeyframe).
    bool height_ambiguous = false;
};

struct PoseItem {
    io::StampedPose pose;
    uint32_t segment = 0;
    // The scan's odometry verdict, for the session's odometry_verdict.json (SessionRecorder feeds
    // them to its odometry::TrajectoryTrust): the scan's index, seconds since the run's first
    // scan, OdometryResult flags and check reasons.
    uint64_t scan_index = 0;
    double t_s = 0;
    uint32_t flags = 0, check_reasons = 0;
};

// The localiser's step on one keyframe, for the session writer (trajectory_bim_live.tum,
// localization_states.csv).
struct BimStepItem {
    int64_t keyframe_stamp_ns = 0;  // sensor clock: the keyframe's scan
    uint32_t segment = 0;
    uint8_t state = 0;  // localization::RelocalizerState
    bool localised = false;
    Eigen::Isometry3d T_bim_odom = Eigen::Isometry3d::Identity();
    uint32_t consistent_loops = 0, hypotheses = 0;
    int32_t storey = -1;
};

// The Go1 state for LCM: the sample and the decoder's counters when it was emitted.
struct Go1Item {
    can::Go1Sample sample;
    can::Go1DecoderStats stats;
    uint16_t timed_out = 0;
};

// The Ouster IMU sample for LCM (sensor frame, SI units).
struct OusterImuItem {
    ouster::ImuSample sample;
    uint64_t sequence = 0;
};

}  // namespace bimslam::rig
