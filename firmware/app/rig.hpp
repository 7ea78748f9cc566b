// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// bimslam-rig put together: the configuration turned into the modules, their queues and the
// thread table; start-up (mlockall, scheduling, sd_notify READY), the health thread (faults,
// rig_health_t, ouster_stats_t, rate-limited logs, the watchdog), and the orderly stop: the
// sources stop first, every queue is drained, the session is finished.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "algorithms/odometry/trajectory_trust.hpp"
#include "firmware/app/rig_config.hpp"

namespace bimslam::rig {

struct RunOptions {
    RigConfig config;
    // Replay: the recording (a capture folder or x.pcap + x.json); empty for live.
    std::string recording;
    double speed = 1.0;     // replay; 0: as fast as possible
    double duration_s = 0;  // > 0: stop after this long (live) or this much capture (replay)
    // Every LCM message published is also written here as an LCM log (lcm::LogFile): the
    // lossless record of the run's LCM output, which UDP multicast cannot promise. Empty: none.
    std::string lcm_log;
};

// One stage of the latency from a frame's last packet to its odometry_t on LCM (LatencyStages).
struct StageLatency {
    std::string name;
    double p50_ms = 0, p99_ms = 0, max_ms = 0;
};

struct RunSummary {
    std::string session_dir;  // the first session folder ("" without recording)
    uint64_t scans = 0, keyframes = 0, scans_dropped = 0, deadline_misses = 0;
    uint64_t keyframes_written = 0, keyframes_skipped_disk = 0;
    uint64_t lidar_packets = 0, imu_samples = 0, go1_samples = 0;
    uint64_t frames_incomplete = 0, columns_lost = 0, crc_failures = 0, silences = 0;
    uint64_t sensor_restarts = 0, clock_jumps = 0, can_timeouts = 0, can_e2e_errors = 0;
    uint64_t queue_drops = 0, can_late = 0, lcm_failures = 0, write_errors = 0;
    // Per thread that went stale at least once (FAULT_THREAD_STALLED): its name and how often.
    std::vector<std::pair<std::string, uint64_t>> threads_stalled;
    // The Go1 bridge's own word (CanCounters): samples sent with its link to the Go1 down,
    // STATUS frames not RUNNING, HighStates it lost, its last state (-1: no STATUS seen).
    uint64_t go1_bridge_link_down = 0, go1_bridge_not_running = 0, go1_bridge_lost = 0;
    int go1_bridge_state = -1;
    // Messages published per channel (lcmtypes/README.md), and the time a replay's output was
    // held back so that receivers keep up (lcm.replay_rate_mb_s).
    uint64_t lcm_odometry = 0, lcm_keyframes = 0, lcm_imu = 0, lcm_go1_state = 0;
    uint64_t lcm_rig_health = 0, lcm_ouster_stats = 0, lcm_logged = 0;
    double lcm_paced_s = 0;
    double latency_p50_ms = 0, latency_p99_ms = 0, latency_max_ms = 0;  // to LCM publication
    std::vector<StageLatency> latency_stages;  // the same by stage (the first hour of scans)
    double cpu_percent = 0;                    // of one core, over the run
    double rss_mb = 0;                         // at the end
    double wall_s = 0;
    std::vector<std::string> warnings;  // what was refused at start-up
    // The map package (localization.map): loaded, or why it was refused (FAULT_BIM_MAP).
    std::string bim_map, bim_map_error, bim_map_model;
    uint64_t bim_map_keyframes = 0, bim_map_storeys = 0, bim_map_bytes = 0;
    double bim_map_load_ms = 0;
    // The localiser's run (a package loaded): keyframes per state, its last state, seconds of
    // sensor time from the first keyframe to the first localised one (-1: never), CPU per
    // keyframe and share of one core, keyframes over localization.deadline_ms.
    uint64_t localization_keyframes = 0, localization_deadline_misses = 0, lcm_bim_pose = 0;
    std::vector<std::pair<std::string, uint64_t>> localization_states;
    std::string localization_final;
    double localization_time_to_localised_s = -1, localization_cpu_ms_p50 = 0,
           localization_cpu_ms_p99 = 0, localization_cpu_percent = 0;
    // The odometry's verdict over the run (trusted / untrusted, the failed stretches), as
    // `bimslam odometry` gives it; each session's share is its odometry_verdict.json.
    odometry::TrajectoryTrust trust;
    int stop_signal = 0;
};

// Runs until SIGINT/SIGTERM, the end of the recording or the duration. Throws common::Error /
// FileError for what cannot start (bad input: exit 2; resources: exit 1).
RunSummary RunRig(const RunOptions& options);

}  // namespace bimslam::rig
