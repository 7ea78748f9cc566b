// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The health thread: once a period it reads every module's counters and every thread's
// heartbeat, turns them into the FAULT_* bits of rig_health_t (lcmtypes/bimslam/rig_health_t.lcm:
// a bit is active when its counter grew during the period or its condition holds now), logs each
// active fault at most once per log interval, queues rig_health_t and ouster_stats_t for the LCM
// thread, and feeds the systemd watchdog (WATCHDOG=1) only while every thread's heartbeat is
// fresh, with a STATUS line. A thread whose heartbeat is stale raises FAULT_THREAD_STALLED, named
// in the log and counted per thread (rig_health_t.thread_stalls, the exit summary).
#pragma once

#include <array>
#include <atomic>
#include <bimslam/ouster_stats_t.hpp>
#include <bimslam/rig_health_t.hpp>
#include <cstdint>
#include <string>
#include <vector>

#include "drivers/ouster/sensor_info.hpp"
#include "firmware/app/rig_config.hpp"
#include "firmware/modules/bim_localizer.hpp"
#include "firmware/modules/can_ingest.hpp"
#include "firmware/modules/lcm_bridge.hpp"
#include "firmware/modules/lidar_ingest.hpp"
#include "firmware/modules/odometry_worker.hpp"
#include "firmware/modules/session_recorder.hpp"
#include "firmware/runtime/process_stats.hpp"
#include "firmware/runtime/sd_notify.hpp"
#include "firmware/runtime/thread_table.hpp"

namespace bimslam::rig {

inline constexpr int kNumFaults = 22;  // rig_health_t::NUM_FAULTS
// "LIDAR_TIMEOUT", ... in bit order (the FAULT_* names without the prefix).
const char* FaultName(int bit);

// Whether thread i has not finished and its heartbeat is older than its stale time.
bool HeartbeatStale(runtime::ThreadTable& threads, size_t i, int64_t now_ns);
// Whether every thread that has not finished beat within its stale time.
bool HeartbeatsFresh(runtime::ThreadTable& threads, int64_t now_ns);

struct HealthInputs {
    runtime::ThreadTable& threads;
    const LidarIngest& ingest;
    const CanIngest* can;
    const OdometryWorker& worker;
    const SessionRecorder* recorder;
    const LcmPublisher& publisher;
    std::vector<const runtime::QueueBase*> queues;
    runtime::SpscQueue<bimslam::rig_health_t>& health_out;
    runtime::SpscQueue<bimslam::ouster_stats_t>& stats_out;
    runtime::SdNotifier& notifier;
    const RigConfig& config;
    const ouster::SensorInfo& info;
    const std::atomic<bool>& stop;
    bool replay;          // lossless: the LCM queues wait for room
    bool unpaced_replay;  // --speed max: using every core is the point, not CPU_OVERLOAD
    // Why the configured map package was refused (FAULT_BIM_MAP); empty: none refused.
    std::string bim_map_error = {};
    const BimLocalizer* localizer = nullptr;  // FAULT_BIM_LOST; nullptr: no package loaded
};

class Health {
public:
    explicit Health(HealthInputs inputs);
    void Run(runtime::ThreadStats& stats);
    // Times each thread's heartbeat went stale (one per episode), in thread-table order. Read it
    // after the health thread ended.
    const std::vector<uint64_t>& thread_stalls() const { return thread_stalls_; }

private:
    struct Snapshot;
    struct Faults;
    // One health period, in named steps: read the counters, find the faults, count and log them,
    // queue rig_health_t and ouster_stats_t, tell systemd.
    void Period(int64_t now_mono);
    Snapshot Read(int64_t now_mono) const;
    void DetectLidarFaults(const Snapshot& n, Faults& f) const;
    void DetectGo1Faults(const Snapshot& n, Faults& f) const;
    void DetectRigFaults(const Snapshot& n, Faults& f);
    void DetectStalledThreads(const Snapshot& n, Faults& f);
    void CountAndLog(const Faults& f, int64_t now_mono);
    void QueueHealth(const Snapshot& snapshot);
    void QueueOusterStats(const Snapshot& n);
    void NotifyStatus(const Snapshot& n);

    HealthInputs in_;
    int64_t start_mono_ = 0, start_rt_ = 0;
    int64_t last_mono_ = 0, last_rt_ = 0, last_cpu_ = 0;
    int64_t rt_minus_mono_ = 0;
    uint64_t latched_ = 0, active_ = 0;
    std::array<int64_t, kNumFaults> counts_{};
    std::vector<runtime::RateLimiter> limiters_;
    std::vector<int64_t> thread_cpu_;
    std::vector<uint64_t> thread_stalls_;
    std::vector<bool> thread_stale_;  // at the previous period
    // Counters at the previous period.
    IngestCounters last_ingest_{};
    CanCounters last_can_{};
    WorkerCounters last_worker_{};
    RecorderCounters last_recorder_{};
    LcmCounters last_lcm_{};
    uint64_t last_queue_drops_ = 0;
    std::vector<uint64_t> last_thread_misses_;
    // A replay's messages wait for room even while this thread is told to stop: the LCM thread
    // drains until it is done (Rig::StopInOrder).
    std::atomic<bool> never_{false};
};

}  // namespace bimslam::rig
