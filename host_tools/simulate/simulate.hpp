// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// `bimslam simulate`: a capture of a walk through a (changed) building, written as a real rig
// would record it. CAPTURE_DIR receives:
//   lidar.pcap          Ouster lidar + IMU UDP packets (ouster_writer.hpp)
//   metadata.json       the sensor's metadata, Ouster layout
//   go1_can.log/.pcap   the Go1 bridge's CAN frames, candump -l and link type 227 (Go1 only)
//   ground_truth.tum    T_bim_sensor at column 0 of every lidar frame, stamped in the sensor clock
//   ground_truth_storeys.csv  (storey: all) per frame: the storey under it, on a flight or not
//   changes.json        the ground truth of the scene edits (world.hpp), changes/*.ply
//   scenario.yaml       the scenario as run (defaults filled in)
//   capture.json        the manifest: files, clocks, sensor, mount, IMU biases, odometry errors
//
// Clocks: trajectory time t (s) starts at 0. Sensor clock (lidar and IMU timestamps, ground
// truth) = kSensorBootNs + t; host clock (pcap and candump stamps) = sensor clock +
// host_minus_sensor_ns; the bridge's clock (GO1_SYNC BridgeTime) = kBridgeBootNs + t.
#pragma once

#include <filesystem>
#include <functional>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "algorithms/simulation/body_trajectory.hpp"
#include "algorithms/simulation/lidar_model.hpp"
#include "host_tools/bim/bim_model.hpp"
#include "host_tools/simulate/beam_hits.hpp"
#include "host_tools/simulate/scenario.hpp"

namespace bimslam::simulate {

inline constexpr int64_t kSensorBootNs = 42'000'000'000;  // up 42 s at t = 0
// The host clock at t = 0 (UNIX epoch) unless the scenario's `date` says: 2023-11-14T22:13:20Z.
inline constexpr int64_t kDefaultStartNs = 1'700'000'000'000'000'000;
inline constexpr int64_t kHostMinusSensorNs = kDefaultStartNs - kSensorBootNs;
// The host clock at t = 0 of this scenario's capture (its `date`, else kDefaultStartNs), and the
// host clock minus the sensor's.
int64_t CaptureStartNs(const Scenario& s);
inline int64_t HostMinusSensorNs(const Scenario& s) { return CaptureStartNs(s) - kSensorBootNs; }
inline constexpr int64_t kBridgeBootNs = 17'000'000'000;

struct CaptureReport {
    std::filesystem::path dir;
    double duration_s = 0;         // captured
    double walk_length_m = 0;      // of the walk (all laps)
    double captured_length_m = 0;  // of it in the captured duration
    size_t laps = 1;
    bool starts_outside = false;
    std::string storey;  // walked, or where a building walk starts (empty: no storeys)
    std::vector<std::string> storeys;            // walked, in the order first entered
    size_t flights_walked = 0;                   // flights of stairs walked, each way counted
    std::vector<std::string> unreached_storeys;  // storey: all: floors the stairs do not reach
    size_t frames = 0;
    uint64_t lidar_packets = 0, imu_packets = 0, lost_packets = 0;
    uint64_t can_frames = 0;
    uint64_t pcap_bytes = 0;  // lidar.pcap's size
    size_t added_objects = 0, removed_elements = 0, moved_elements = 0, people = 0;
    // The beams on what the HitWatch named (SimulateCapture's `watch`), by its key or GlobalId.
    std::map<std::string, size_t> watched_hits;
    double wall_s = 0;               // time the simulation took
    std::vector<std::string> notes;  // for the user (Walk::notes)
};

// The rolling shutter: the sensor's pose at each column of the frame that starts at trajectory
// time t0, column v at t0 + LidarModel::ColumnTimeOffsetNs(v). `poses` holds lidar.columns.
void ColumnPoses(const simulation::BodyTrajectory& trajectory,
                 const Eigen::Isometry3d& T_base_sensor, const simulation::LidarModel& lidar,
                 double t0, std::span<Eigen::Isometry3d> poses);

// Simulates `scenario` in `model` (already loaded; `model_sha256` is recorded in the manifest)
// into `dir` (created; files in it are replaced). `progress` gets the fraction done; the beams on
// what `watch` names go into the report only (the files do not depend on it). Throws
// common::Error naming the scenario field for what cannot be simulated, common::FileError for
// files that cannot be read or written.
CaptureReport SimulateCapture(const Scenario& scenario, const bim::BimModel& model,
                              const std::string& model_sha256, const std::filesystem::path& dir,
                              const std::function<void(double)>& progress = {},
                              const HitWatch& watch = {});

}  // namespace bimslam::simulate
