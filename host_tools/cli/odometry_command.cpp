// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// bimslam odometry: a capture replayed through the on-board LiDAR odometry and keyframe
// selection, as fast as possible, into a session (host_tools/replay/capture_odometry.hpp).
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>

#include "algorithms/common/se3.hpp"
#include "algorithms/common/status.hpp"
#include "host_tools/cli/command.hpp"
#include "host_tools/replay/capture_odometry.hpp"

namespace bimslam::cli {
namespace {
namespace fs = std::filesystem;

struct OdometryArgs {
    std::string capture;
    std::string out;
    std::string can_log;
    bool no_can = false;
    bool no_imu = false;
    bool no_deskew = false;
    bool edge_features = false;
    double budget_ms = 50;
    bool budget_cpu = false;
    double duration_s = 0;
    std::vector<double> mount;  // x y z roll pitch yaw
    double time_offset_ms = 0;
    std::vector<double> imu_rotation_deg;  // roll pitch yaw
    bool overwrite = false;
    bool json = false;
    std::string scans_csv;
};

int Odometry(const OdometryArgs& a) {
    replay::CaptureOdometryOptions o;
    o.capture_dir = a.capture;
    o.session_dir = a.out;
    o.can_log = a.can_log;
    o.overwrite = a.overwrite;
    o.use_can = !a.no_can;
    o.use_imu = !a.no_imu;
    o.odometry.budget_ms = a.budget_ms;
    o.odometry.registration.cpu_time_budget = a.budget_cpu;
    o.odometry.preprocess.deskew = !a.no_deskew;
    o.odometry.edge_features = a.edge_features;
    o.max_duration_s = a.duration_s;
    if (!a.mount.empty()) {
        o.mount = common::PoseFromXyzRpyDeg({a.mount[0], a.mount[1], a.mount[2]},
                                            {a.mount[3], a.mount[4], a.mount[5]});
    }
    o.time_offset_ns = std::llround(a.time_offset_ms * 1e6);
    if (!a.imu_rotation_deg.empty()) {
        o.imu_rotation_rpy_deg = {a.imu_rotation_deg[0], a.imu_rotation_deg[1],
                                  a.imu_rotation_deg[2]};
    }
    const bool tty = !a.json && ::isatty(STDOUT_FILENO);
    std::ofstream csv;
    if (!a.scans_csv.empty()) {
        csv.open(a.scans_csv);
        if (!csv) {
            throw common::FileError(common::StatusCode::kIoError, a.scans_csv, 0,
                                    "cannot be written");
        }
        csv << "scan,stamp_ns,flags,check_reasons,points,correspondences,inliers,rms_m,"
               "correspondence_distance_m,motion_m,motion_deg,total_ms,deskew_rounds,budget_cut,"
               "height_share,height_sigma_m,unjudged\n";
    }
    o.on_scan = [tty, n = 0, &csv](const odometry::OdometryResult& r) mutable {
        if (csv.is_open()) {
            const odometry::RegistrationResult& g = r.registration;
            csv << n << "," << r.stamp_ns << "," << r.flags << "," << r.check_reasons << ","
                << g.points << "," << g.correspondences << "," << g.inliers << "," << g.rms << ","
                << r.correspondence_distance << "," << r.T_prev_lidar.translation().norm() << ","
                << common::RotationAngle(r.T_prev_lidar) * 180 / M_PI << "," << r.total_ms << ","
                << r.deskew_rounds << ",\"" << odometry::BudgetCutText(r.budget_cut) << "\","
                << g.axis_share << "," << r.height_sigma << "," << g.unjudged << "\n";
        }
        ++n;
        if (tty && n % 50 == 0) {
            std::cout << "\rscan " << n << "  (" << std::fixed << std::setprecision(1) << r.total_ms
                      << " ms)" << std::flush;
        }
    };
    const replay::CaptureOdometryReport rep = replay::RunCaptureOdometry(o);
    if (tty) std::cout << "\r";
    const double p50 = replay::Percentile(rep.scan_ms, 0.5);
    const double p99 = replay::Percentile(rep.scan_ms, 0.99);
    const double max = replay::Percentile(rep.scan_ms, 1.0);
    if (a.json) {
        nlohmann::json j = replay::ReportJson(rep);
        j["session"] = a.out;
        std::cout << j.dump(2) << "\n";
        return kExitOk;
    }
    for (const std::string& n : rep.notes) std::cout << "note      " << n << "\n";
    std::cout << std::fixed << std::setprecision(1);
    std::cout << "inputs    " << rep.scans << " scans (" << rep.incomplete_frames
              << " incomplete), " << rep.imu_samples << " IMU samples, " << rep.body_samples
              << " Go1 samples" << (rep.mount_from_capture ? ", mount from capture.json" : "")
              << "\n";
    std::cout << "odometry  " << rep.distance_m << " m in " << rep.capture_s << " s of capture, "
              << "run in " << rep.wall_s << " s (" << rep.capture_s / std::max(rep.wall_s, 1e-9)
              << "x real time)\n";
    std::cout << std::setprecision(2) << "per scan  p50 " << p50 << " ms, p99 " << p99
              << " ms, max " << max << " ms; over budget " << rep.over_budget << ", degenerate "
              << rep.degenerate << ", failed " << rep.failed << " (" << rep.check_failed
              << " by their checks), contradicted the gyro " << rep.contradicted_gyro
              << ", the legs " << rep.contradicted_legs << "\n";
    // The CPU time is the rig's odometry thread's work (decoding and writing are other threads
    // there); the wall time above also holds what else the machine runs.
    std::cout << "CPU/scan  p50 " << replay::Percentile(rep.scan_cpu_ms, 0.5) << " ms, p99 "
              << replay::Percentile(rep.scan_cpu_ms, 0.99) << " ms, max "
              << replay::Percentile(rep.scan_cpu_ms, 1.0)
              << " ms (odometry and keyframe selection: the rig's odometry thread)\n";
    std::cout << "trajectory " << rep.trust.Describe() << "\n";
    std::cout << "session   " << a.out << ": " << rep.keyframes
              << " keyframes, trajectory.tum with every scan\n";
    return kExitOk;
}

}  // namespace

void AddOdometryCommand(CLI::App& app, int& exit_code) {
    auto args = std::make_shared<OdometryArgs>();
    auto* cmd = app.add_subcommand(
        "odometry",
        "LiDAR odometry and keyframes of a capture into a session: the on-board algorithm, "
        "offline, as fast as possible");
    cmd->footer(
        "Runs algorithms/odometry and algorithms/keyframes, the code the rig runs on board.\n"
        "Reads CAPTURE_DIR/lidar.pcap and metadata.json, the Ouster IMU packets in the pcap,\n"
        "CAPTURE_DIR/go1_can.log when present (the Go1 motion prior) and capture.json's lidar\n"
        "mount when present; or X.pcap with X.json (else metadata.json) beside it; or a ROS 1\n"
        "bag recorded by ouster-ros (X.bag: <ns>/lidar_packets, <ns>/imu_packets, <ns>/metadata);\n"
        "or a folder of per-scan clouds (all .pcd, .ply or KITTI .bin, in name order) with\n"
        "times.txt (one scan start in seconds a line) in it or in its parent: per-point time\n"
        "(PCD/PLY field t) deskews; without it deskew is off, and the output says so.\n"
        "Writes SESSION/trajectory.tum (every scan, sensor clock) and the\n"
        "keyframes (Scans/, SCDs/, poses, singlesession_posegraph.g2o, session.json).\n"
        "Compare with ground truth:\n"
        "  bimslam evaluate --est SESSION/trajectory.tum --ref CAPTURE_DIR/ground_truth.tum");
    cmd->add_option("capture", args->capture,
                    "Capture folder (from the rig or bimslam simulate), a pcap with its "
                    "metadata JSON beside it (x.pcap + x.json, as the Ouster tools save them), "
                    "a ROS 1 bag from ouster-ros (.bag), or a folder of per-scan .pcd/.ply/.bin "
                    "clouds with times.txt")
        ->required();
    cmd->add_option("--can", args->can_log,
                    "Go1 CAN log (candump -l or pcap) to use instead of the folder's go1_can.log");
    cmd->add_option("-o,--output", args->out, "Session folder to write")->required();
    cmd->add_flag("--no-can", args->no_can, "Ignore go1_can.log (no Go1 motion prior)");
    cmd->add_flag("--no-imu", args->no_imu, "Ignore the Ouster IMU");
    cmd->add_flag("--no-deskew", args->no_deskew, "Register scans as they are, without deskew");
    cmd->add_flag("--edge-features", args->edge_features,
                  "Also register LOAM edge features point-to-line (off by default: measured "
                  "slower for 4 % less error, algorithms/odometry/README.md)");
    cmd->add_option("--budget-ms", args->budget_ms, "Time budget per scan")
        ->check(CLI::Range(1.0, 10000.0))
        ->capture_default_str();
    cmd->add_flag("--budget-cpu", args->budget_cpu,
                  "Count the budget in this thread's CPU time instead of wall time: on a machine "
                  "shared with other work the session then depends on the work, not on the load "
                  "(the rig counts wall time)");
    cmd->add_option("--duration", args->duration_s, "Stop after this many seconds of capture")
        ->check(CLI::NonNegativeNumber);
    cmd->add_option("--mount", args->mount,
                    "The lidar on the platform's base, T_base_lidar: X Y Z (m) ROLL PITCH YAW "
                    "(deg); overrides capture.json's (used by the Go1 prior and the self-filter)")
        ->expected(6)
        ->group("Calibration");
    cmd->add_option("--time-offset-ms", args->time_offset_ms,
                    "Added to every IMU and Go1 sample's time before it meets the scans (the "
                    "lidar-to-IMU/CAN latency)")
        ->check(CLI::Range(-1000.0, 1000.0))
        ->group("Calibration");
    cmd->add_option("--imu-rotation", args->imu_rotation_deg,
                    "ROLL PITCH YAW (deg) composed onto the metadata's IMU-to-sensor rotation")
        ->expected(3)
        ->group("Calibration");
    cmd->add_flag("--overwrite", args->overwrite, "Replace an existing session");
    cmd->add_flag("--json", args->json,
                  "Print the summary as JSON (verdict: trusted or untrusted, failed_stretches: "
                  "the scans and times that failed their registration checks; said apart, not "
                  "untrusting: height_unseen_stretches, the height the accelerometers' alone for "
                  "over 2 s, degenerate_stretches, some directions the prediction's for over "
                  "1 s, and height_ambiguous_stretches, the height seen again while the "
                  "accelerometers' was uncertain by over 7.5 cm: off by whole stair risers, may "
                  "be)");
    cmd->add_option(
        "--scans-csv", args->scans_csv,
        "Write every scan's registration evidence to this CSV (flags, check reasons, "
        "points, correspondences, inliers, rms, motion, time, deskew rounds, and the steps the "
        "budget cut: registration, gyro gate, other headings, start refinement, "
        "deskew round; with the IMU, the share of the registration's weights on surfaces "
        "facing up or down: under 0.01 the scan did not see the height; and the height's 1-sigma "
        "from the accelerometers' filter after the scan, m; unjudged: the correspondences on "
        "planes fitted through a line, which the checks leave out)");
    cmd->callback([args, &exit_code] { exit_code = Run([&] { return Odometry(*args); }); });
}

}  // namespace bimslam::cli
