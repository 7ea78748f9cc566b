// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The odometry thread: scans from the lidar ingest, Ouster IMU and Go1 samples from their
// queues, through pipeline::ScanPipeline (the same join `bimslam odometry` runs), out to the LCM
// thread (odometry per scan, keyframes) and the session writer (every scan's pose, keyframes).
//
// Before a scan it waits, at most can_wait_ns (live) or until the CAN recording has passed it
// (a replay, lossless at any speed), for the CAN ingest's progress to reach the scan's arrival, so
// the scan gets the Go1 samples a single-threaded replay gives it. Deadline: a scan's odometry must
// be handed to LCM within deadline_ns of its last packet; a later one is a deadline miss.
#pragma once

#include <atomic>
#include <cstdint>
#include <vector>

#include "algorithms/odometry/trajectory_trust.hpp"
#include "algorithms/pipeline/scan_pipeline.hpp"
#include "firmware/modules/can_ingest.hpp"
#include "firmware/modules/rig_types.hpp"
#include "firmware/runtime/seqlock.hpp"
#include "firmware/runtime/thread_table.hpp"

namespace bimslam::rig {

struct OdometryWorkerConfig {
    pipeline::ScanPipelineConfig pipeline;
    int64_t can_wait_ns = 20'000'000;
    int64_t deadline_ns = 100'000'000;
    bool lossless = false;  // a replay (any speed): wait for the CAN log, never drop
    bool record = true;     // false: no session writer consumes poses and keyframes
};

struct WorkerCounters {
    uint64_t scans = 0, keyframes = 0;
    uint64_t deadline_misses = 0;
    uint64_t can_late = 0;  // scans processed before the CAN ingest reached them
    uint64_t over_budget = 0, degenerate = 0, failed = 0;
    uint64_t clock_jumps = 0;
    uint64_t outputs_dropped = 0;  // odometry/pose/keyframe items the full queues refused
    uint64_t incomplete = 0;
    int64_t last_solve_ns = 0;
    uint32_t last_flags = 0;
    double distance_m = 0;
};

struct WorkerQueues {
    runtime::SpscQueue<ScanSlot>& scans;
    runtime::SpscQueue<ImuItem>& imu;
    runtime::SpscQueue<BodyItem>& bodies;
    runtime::SpscQueue<OdometryItem>& odometry_out;
    runtime::SpscQueue<KeyframeItem>& keyframes_lcm;
    runtime::SpscQueue<KeyframeItem>& keyframes_session;
    runtime::SpscQueue<PoseItem>& poses;
    runtime::Wakeup& wakeup;  // notified by the three input queues
    // The localiser thread's keyframes (a map package loaded); nullptr: none.
    runtime::SpscQueue<KeyframeItem>* keyframes_localizer = nullptr;
};

class OdometryWorker {
public:
    OdometryWorker(const OdometryWorkerConfig& config, WorkerQueues queues,
                   const CanIngest* can);  // can: nullptr without CAN

    // Until `stop` and the ingest finished (`inputs_done`) with nothing left to process.
    void Run(runtime::ThreadStats& stats, const std::atomic<bool>& stop,
             const std::atomic<bool>& inputs_done);

    WorkerCounters counters() const { return counters_.Load(); }
    // Every scan's flags in stretches, the run's verdict (as `bimslam odometry` gives it); read
    // after Run returns.
    const odometry::TrajectoryTrust& trust() const { return trust_; }

private:
    bool ProcessOne(runtime::ThreadStats& stats, const std::atomic<bool>& stop);
    void DrainImu();

    OdometryWorkerConfig config_;
    WorkerQueues q_;
    const CanIngest* can_;
    pipeline::ScanPipeline pipeline_;
    uint32_t segment_ = 0;
    bool height_ambiguous_ = false;  // a scan since the last keyframe flagged kHeightAmbiguous
    WorkerCounters c_;
    runtime::Seqlock<WorkerCounters> counters_;
    odometry::TrajectoryTrust trust_;
    int64_t first_stamp_ns_ = -1;     // the run's first scan's stamp: TrajectoryTrust's seconds
    std::atomic<bool> never_{false};  // a replay's outputs wait for room until pushed
};

}  // namespace bimslam::rig
