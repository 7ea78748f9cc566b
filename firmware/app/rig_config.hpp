// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The configuration of bimslam-rig: one struct with every default, a schema that says of each
// YAML key its type, default, range and unit, and the loader that applies a YAML file to it.
// A file is read strictly: an unknown key, a wrong type or a value out of range is a
// common::FileError naming the file, the line and the key's full path (exit 2). --print-config
// prints the effective configuration in the same YAML, every key with its unit and range.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace bimslam::rig {

// Scheduling of one thread of the thread table (firmware/runtime/README.md).
struct ThreadConfig {
    int priority = 0;  // SCHED_FIFO 1..99; 0: the normal scheduler
    int cpu = -1;      // the CPU it is pinned to; -1: any
};

struct RigConfig {
    // sensor: the Ouster.
    std::string metadata;        // its metadata JSON (live; replay takes the recording's)
    std::string sensor_address;  // accept packets from this address only ("": any)
    std::string bind_address = "0.0.0.0";
    int lidar_port = 0;                  // 0: the metadata's udp_port_lidar (else 7502)
    int imu_port = 0;                    // 0: the metadata's udp_port_imu (else 7503)
    int receive_buffer_bytes = 8 << 20;  // SO_RCVBUF request
    double sensor_timeout_s = 0.5;       // no packet for this long: FAULT_LIDAR_TIMEOUT

    // can: the Go1 (through bimslam-go1-bridge).
    std::string can_source = "socketcan";  // socketcan | lcm | log | none
    std::string can_interface = "can0";
    std::string can_log;                              // can_source log (replay --can)
    std::string can_lcm_channel = "BIMSLAM_GO1_CAN";  // can_source lcm (the bridge's --lcm)
    double can_wait_ms = 20;  // how long a scan waits for the CAN ingest to reach its time

    // odometry (algorithms/odometry, algorithms/keyframes).
    double budget_ms = 50;
    double deadline_ms = 100;  // from a frame's last packet to its odometry message
    bool use_imu = true;
    bool deskew = true;
    bool edge_features = false;
    // The lidar on the Go1's body, T_base_lidar: x y z (m), roll pitch yaw (deg).
    std::vector<double> mount = {0.05, 0.0, 0.28, 0.0, 0.0, 0.0};
    double keyframe_distance_m = 1.0;
    double keyframe_angle_deg = 10.0;

    // session: where sessions go, one new folder per start.
    bool record = true;
    std::string session_root = "/var/lib/bimslam/sessions";
    double min_free_mb = 1024;  // below this free space keyframe clouds are no longer written

    // lcm.
    std::string lcm_url = "udpm://239.255.76.67:7667?ttl=0";
    bool publish_keyframes = true;
    bool publish_imu = true;
    bool publish_go1_state = true;
    // A replay's LCM output is paced to this rate (lcm_bridge.hpp, PublishPacer) so that
    // receivers keep up; live runs are never paced.
    double lcm_replay_rate_mb_s = 32;
    double lcm_replay_messages_per_s = 2000;

    // queues (items; a full queue drops the new item and counts it).
    int scan_queue = 3;
    int imu_queue = 512;
    int body_queue = 512;
    int publish_queue = 64;
    int keyframe_queue = 8;

    // localization: the building's model on board (issue 35; algorithms/localization).
    std::string bim_map;                  // the map package (bimslam rig-map); "": none
    std::string bim_model_sha256;         // the model the package must be of; "": any
    double localizer_deadline_ms = 1000;  // a keyframe's relocalisation, CPU time
    double bim_lost_fault_s = 30;  // unlocalised this long after a localisation: FAULT_BIM_LOST
    // Where the walk starts, [x, y] or [x, y, radius] in model metres (radius 3 m when absent);
    // empty: unknown (localization::StartHint, RelocalizerConfig::start).
    std::vector<double> bim_near;

    // runtime.
    bool lock_memory = true;
    ThreadConfig ingest{80, -1}, can{70, -1}, odometry{60, -1}, writer{0, -1}, lcm{0, -1},
        health{0, -1}, localizer{0, -1};
    double health_period_s = 1.0;  // rig_health_t, ouster_stats_t, the watchdog, the logs
    double log_interval_s = 10.0;  // the same fault is logged at most this often

    // Set by the command line, not the file.
    bool handheld = false;  // no CAN: LiDAR + Ouster IMU
};

// One key of the schema (the YAML path, e.g. "sensor.lidar_port").
struct ConfigKey {
    std::string path;
    std::string type;   // int | number | bool | string | enum | vector
    std::string unit;   // "" for none
    std::string range;  // "[1, 99]", "socketcan | lcm | log | none", ...
    std::string doc;
};
const std::vector<ConfigKey>& ConfigSchema();

// Applies a YAML file on top of `config`. Throws common::FileError (path, line, key) on an
// unreadable file, bad YAML, an unknown key, a wrong type or a value out of range.
void LoadConfigFile(const std::filesystem::path& path, RigConfig& config);
// Checks the relations between keys; throws common::Error naming the keys.
void ValidateConfig(const RigConfig& config);
// The effective configuration as YAML, each key with a comment: unit, range, what it is.
std::string PrintConfig(const RigConfig& config);

}  // namespace bimslam::rig
