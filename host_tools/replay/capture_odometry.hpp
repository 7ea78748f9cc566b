// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// A recording (a capture folder as the rig records and `bimslam simulate` writes it, or a pcap
// with its metadata JSON as the Ouster tools save them: algorithms/io/capture_files.hpp) replayed
// through the on-board LiDAR odometry and keyframe selection, as fast as the machine goes, into a
// session (specs/session-data.md). The same library code as the rig; only the reading of files is
// here.
//
// Clocks. Scans and Ouster IMU samples are stamped by the sensor; Go1 samples by the host (the
// candump stamps). The host-minus-sensor offset is estimated from the lidar packets themselves:
// the smallest (pcap arrival - sensor time of the packet's last column) seen so far, i.e. the
// offset plus the smallest network latency. A Go1 sample is dated at its candump stamp minus its
// SampleAge (the bridge's receive of the HighState), then moved to the sensor clock.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "algorithms/keyframes/keyframe_selector.hpp"
#include "algorithms/odometry/lidar_odometry.hpp"
#include "algorithms/odometry/trajectory_trust.hpp"

namespace bimslam::replay {

struct CaptureOdometryOptions {
    // A capture folder, or a pcap with its metadata JSON (io::ResolveCapture).
    std::filesystem::path capture_dir;
    std::filesystem::path can_log;      // overrides the folder's go1_can.log
    std::filesystem::path session_dir;  // empty: no session written (benchmarks)
    bool overwrite = false;
    bool use_can = true;                     // go1_can.log when present
    bool use_imu = true;                     // the Ouster IMU packets in lidar.pcap
    odometry::LidarOdometryConfig odometry;  // T_base_lidar is taken from capture.json if there
    keyframes::KeyframeConfig keyframes;
    double max_duration_s = 0;  // > 0: stop after this much capture time
    // Calibration the odometry is given: a rig's own (a real recording has no capture.json), or a
    // deliberately wrong one, to measure what a calibration error costs (algorithms/odometry/
    // README.md, "Rotated and miscalibrated mounts").
    std::optional<Eigen::Isometry3d> mount;  // T_base_lidar; overrides capture.json's mount
    int64_t time_offset_ns = 0;              // added to every IMU and Go1 sample's time
    // Composed onto the metadata's IMU-to-sensor rotation: R_sensor_imu * R(roll, pitch, yaw).
    Eigen::Vector3d imu_rotation_rpy_deg = Eigen::Vector3d::Zero();
    // Called after every scan (progress, figures); may be empty.
    std::function<void(const odometry::OdometryResult&)> on_scan;
};

struct CaptureOdometryReport {
    size_t scans = 0;
    size_t keyframes = 0;
    size_t incomplete_frames = 0;
    size_t imu_samples = 0;
    size_t body_samples = 0;          // Go1 samples given to the odometry
    bool used_can = false;            // go1_can.log present and read
    bool mount_from_capture = false;  // T_base_lidar from capture.json
    std::vector<double> scan_ms;      // per scan, total time in LidarOdometry::Process
    // Per scan, this thread's CPU time in ScanPipeline::Process: the work of the rig's odometry
    // thread (odometry and keyframe selection). Decoding the packets and writing the session are
    // other threads on the rig (firmware/app/README.md), so they are not in it.
    std::vector<double> scan_cpu_ms;
    // Per scan, the stages of that time (OdometryResult::preprocess_ms, register_ms, map_ms) and
    // the work: registration points, outer iterations, map points inserted.
    std::vector<double> preprocess_ms, register_ms, map_ms;
    double mean_registration_points = 0, mean_iterations = 0, mean_map_points = 0;
    // failed: too few correspondences, or the registration failed its own evidence
    // (check_failed, algorithms/odometry/registration_check.hpp).
    size_t over_budget = 0, degenerate = 0, failed = 0, not_converged = 0, check_failed = 0;
    odometry::TrajectoryTrust trust;  // the failed scans in stretches, the run's verdict
    size_t contradicted_gyro = 0;     // scans that turned against the gyro (kContradictsGyro)
    size_t contradicted_legs = 0;     // the Go1's legs against the LiDAR (kContradictsLegs)
    double distance_m = 0;            // along the odometry trajectory
    double capture_s = 0;             // sensor time from the first to the last scan
    double wall_s = 0;                // this run
    int64_t host_minus_sensor_ns = 0;
    std::vector<std::string> notes;  // what was missing or skipped, for the user
};

// The p-quantile (0..1) of v, nearest rank; 0 for none.
double Percentile(std::vector<double> v, double p);

// Throws common::Error / FileError naming the file on missing or bad input (exit 2 material).
CaptureOdometryReport RunCaptureOdometry(const CaptureOdometryOptions& options);

// The report's figures as `bimslam odometry --json` prints them and `bimslam map` keeps them
// (odometry/<recording>.json): counts, the per-scan time's percentiles (wall and CPU, by stage),
// the failures and the run's verdict with its stretches; not the per-scan times themselves.
nlohmann::json ReportJson(const CaptureOdometryReport& report);

}  // namespace bimslam::replay
