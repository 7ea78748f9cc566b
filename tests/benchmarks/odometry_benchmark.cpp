// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The LiDAR odometry end to end on simulated captures of the sample building, as `bimslam
// odometry` runs it (host_tools/replay/capture_odometry.hpp): the capture is simulated first
// (not timed), then replayed as fast as possible on one thread (the odometry has no threads of
// its own and Ceres runs with 1), so every timing below is one core's.
//
// BM_OdometryAccuracy/platform:P/seconds:S/edges:E  (P 0 = Go1 with its CAN log, 1 = handheld;
// E 1 = LOAM edge features on, the measurement behind their default of off)
//   The session is written, then its trajectory.tum is evaluated against the capture's
//   ground_truth.tum with se3 alignment (host_tools/evaluation, as `bimslam evaluate`). The timed
//   part is the replay only. Counters: APE translation rmse/max (cm), APE rotation rmse (deg),
//   RPE over 1 m of path (cm), KITTI drift over 10 m (%), distance (m, ground truth), per-scan
//   time p50/p99/max (ms, wall, LidarOdometry::Process), odo_cpu_ms_* (CPU time of the rig's
//   odometry thread's work per scan: ScanPipeline::Process, odometry and keyframe selection),
//   scans over budget and degenerate, and realtime_x (capture seconds per second of replay,
//   session writing included).
//
// BM_OdometryAccuracy/.../imu:I  (I 0 = without the Ouster IMU, as `bimslam odometry --no-imu`;
//   the Go1 then keeps its CAN prior, the handheld has none: LiDAR only)
//
// BM_OdometrySensor/sensor:K/platform:P/seconds:S  (K 0 = OS1-32, 1 = OS0-64, 2 = OS1-128, the
// simulator's built-in sensors (drivers/ouster BuiltinOuster), 1024x10)
//   Time per scan for each sensor, with the accuracy kept: the same counters, plus the thread's
//   CPU time between consecutive scans (cpu_ms_*: packet decoding, the odometry and the session
//   writing, which the rig spreads over three threads; odo_cpu_ms_* is the odometry's alone;
//   measured with CLOCK_THREAD_CPUTIME_ID, so a machine shared with other work inflates it less
//   than the wall time) and the worst scan of the first second (first_s_ms_max, wall: the map is
//   empty and the voxel sizes not yet adapted there).
//
// BM_OdometryCalibration/platform:P/mount:M/error:E/seed:S  (issue 17: a yardstick the odometry
// did not build)
//   60 s captures with the sensor mounted level (M 0, the default), pitched 15 deg (M 1) or
//   yawed 90 deg (M 2) on the base, replayed with the calibration the capture was made with
//   (E 0) or with one realistic error in what the odometry is given: the mount off by 1 cm
//   (E 1) or by 1 deg (E 2), the IMU's rotation off by 1 deg (E 3), the IMU and CAN clocks off by
//   1 ms (E 4), all four at once (E 5). Every error points along (1, 1, 1)/sqrt(3): a translation
//   of 1 cm, a rotation of 1 deg about that axis. The same counters as BM_OdometryAccuracy;
//   each capture is simulated once and shared by its six error cases.
//
// BM_OdometryMemory/seconds:S  (opt-in: BIMSLAM_BENCH_LONG=1)
//   A long Go1 capture (the coverage walk repeated; ~4.3 MB of pcap per captured second, so ~7.7 GB
//   for 30 min) replayed without writing a session: the process's resident memory after 5 minutes
//   of capture and at the end, its peak during the replay, and the local map's size at the end;
//   also the accuracy over the whole walk (se3 alignment), from the poses kept in memory.
#include <benchmark/benchmark.h>
#include <malloc.h>
#include <time.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include "algorithms/io/capture_files.hpp"
#include "algorithms/io/trajectory.hpp"
#include "host_tools/bim/ifc_model.hpp"
#include "host_tools/bim/sample_building.hpp"
#include "host_tools/evaluation/trajectory_metrics.hpp"
#include "host_tools/replay/capture_odometry.hpp"
#include "host_tools/simulate/simulate.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::replay {
namespace {
namespace fs = std::filesystem;
using simulate::Platform;

// The default scenario of `platform`, `seconds` long (the walk repeats when it is shorter),
// simulated in the sample building into dir/capture. The model is freed before returning.
simulate::CaptureReport Simulate(const test::TempDir& dir, Platform platform, double seconds,
                                 const std::string& sensor = "OS1-32", uint64_t seed = 1,
                                 const Eigen::Vector3d& mount_rpy_deg = Eigen::Vector3d::Zero()) {
    const fs::path ifc = dir / "building.ifc";
    bim::WriteSampleBuilding(ifc);
    const bim::BimModel model = bim::LoadIfc(ifc);
    simulate::Scenario s = simulate::DefaultScenario(platform);
    s.duration_s = seconds;
    s.sensor.model = sensor;
    s.seed = seed;
    s.sensor.mount_rpy_deg = mount_rpy_deg;
    return simulate::SimulateCapture(s, model, "", dir / "capture");
}

double ThreadCpuMs() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}

// The accuracy and time counters every case reports.
void SetCounters(benchmark::State& state, const CaptureOdometryReport& rep,
                 const evaluation::EvaluationResult& e) {
    state.counters["ape_trans_rmse_cm"] = 100.0 * e.ape_trans_m.rmse;
    state.counters["ape_trans_max_cm"] = 100.0 * e.ape_trans_m.max;
    state.counters["ape_rot_rmse_deg"] = e.ape_rot_deg.rmse;
    state.counters["rpe_trans_rmse_cm"] = 100.0 * e.rpe_trans_m.rmse;  // per 1 m of path
    state.counters["drift_pct"] = e.drift_percent;
    state.counters["distance_m"] = e.distance_m;  // ground truth, matched poses
    state.counters["scan_ms_p50"] = Percentile(rep.scan_ms, 0.5);
    state.counters["scan_ms_p99"] = Percentile(rep.scan_ms, 0.99);
    state.counters["scan_ms_max"] = Percentile(rep.scan_ms, 1.0);
    // The rig's odometry thread: CPU time in ScanPipeline::Process (odometry and keyframe
    // selection; the rig decodes and writes on other threads).
    state.counters["odo_cpu_ms_p50"] = Percentile(rep.scan_cpu_ms, 0.5);
    state.counters["odo_cpu_ms_p99"] = Percentile(rep.scan_cpu_ms, 0.99);
    state.counters["odo_cpu_ms_max"] = Percentile(rep.scan_cpu_ms, 1.0);
    state.counters["over_budget"] = double(rep.over_budget);
    state.counters["degenerate"] = double(rep.degenerate);
    state.counters["failed"] = double(rep.failed);
    state.counters["scans"] = double(rep.scans);
    state.counters["matched"] = double(e.matched);
    state.counters["keyframes"] = double(rep.keyframes);
    state.counters["realtime_x"] = rep.capture_s / std::max(rep.wall_s, 1e-9);
}

// The session's trajectory.tum against the capture's ground truth, SE(3)-aligned.
evaluation::EvaluationResult Evaluate(const fs::path& session, const fs::path& capture) {
    evaluation::EvaluationConfig config;
    config.align = evaluation::Alignment::kSe3;
    return evaluation::EvaluateFiles(session / "trajectory.tum", capture / "ground_truth.tum",
                                     config);
}

void BM_OdometryAccuracy(benchmark::State& state) {
    const bool handheld = state.range(0) == 1;
    test::TempDir tmp;
    const simulate::CaptureReport sim =
        Simulate(tmp, handheld ? Platform::kHandheld : Platform::kGo1, double(state.range(1)));

    CaptureOdometryOptions o;
    o.capture_dir = sim.dir;
    o.session_dir = tmp / "session";
    o.overwrite = true;
    o.use_can = !handheld;  // as `bimslam odometry --no-can` for a handheld capture
    o.use_imu = state.range(3) == 1;
    o.odometry.edge_features = state.range(2) == 1;
    // The budget in CPU time: the accuracy must not depend on what else the machine runs.
    o.odometry.registration.cpu_time_budget = true;
    CaptureOdometryReport rep;
    for (auto _ : state) rep = RunCaptureOdometry(o);

    SetCounters(state, rep, Evaluate(o.session_dir, sim.dir));
    state.SetLabel(std::string(handheld ? "handheld" : "go1+can") + (o.use_imu ? "" : ", no imu") +
                   (o.odometry.edge_features ? ", edge features" : ""));
}
BENCHMARK(BM_OdometryAccuracy)
    ->Args({0, 180, 0, 1})
    ->Args({1, 180, 0, 1})
    ->Args({0, 180, 1, 1})
    ->Args({1, 180, 1, 1})
    ->Args({0, 180, 0, 0})
    ->Args({1, 180, 0, 0})
    ->Args({1, 180, 1, 0})
    ->ArgNames({"platform", "seconds", "edges", "imu"})
    ->Unit(benchmark::kSecond)
    ->Iterations(1);

void BM_OdometrySensor(benchmark::State& state) {
    static const char* const kSensors[] = {"OS1-32", "OS0-64", "OS1-128"};
    const char* sensor = kSensors[state.range(0)];
    const bool handheld = state.range(1) == 1;
    test::TempDir tmp;
    const simulate::CaptureReport sim = Simulate(
        tmp, handheld ? Platform::kHandheld : Platform::kGo1, double(state.range(2)), sensor);

    CaptureOdometryOptions o;
    o.capture_dir = sim.dir;
    o.session_dir = tmp / "session";
    o.overwrite = true;
    o.use_can = !handheld;
    std::vector<double> cpu_ms;
    double last = 0, first_s_max = 0;
    int64_t first_ns = -1;
    o.on_scan = [&](const odometry::OdometryResult& r) {
        const double now = ThreadCpuMs();
        if (first_ns < 0) {
            first_ns = r.stamp_ns;
        } else {
            cpu_ms.push_back(now - last);
        }
        last = now;
        if (double(r.stamp_ns - first_ns) < 1e9) first_s_max = std::max(first_s_max, r.total_ms);
    };
    CaptureOdometryReport rep;
    for (auto _ : state) {
        cpu_ms.clear();
        first_ns = -1;
        rep = RunCaptureOdometry(o);
    }
    SetCounters(state, rep, Evaluate(o.session_dir, sim.dir));
    state.counters["cpu_ms_p50"] = Percentile(cpu_ms, 0.5);
    state.counters["cpu_ms_p99"] = Percentile(cpu_ms, 0.99);
    state.counters["cpu_ms_max"] = Percentile(cpu_ms, 1.0);
    state.counters["first_s_ms_max"] = first_s_max;
    state.SetLabel(std::string(sensor) + (handheld ? ", handheld" : ", go1+can"));
}
BENCHMARK(BM_OdometrySensor)
    ->ArgsProduct({{0, 1, 2}, {0, 1}, {60}})
    ->ArgNames({"sensor", "platform", "seconds"})
    ->Unit(benchmark::kSecond)
    ->Iterations(1);

void BM_OdometryCalibration(benchmark::State& state) {
    const bool handheld = state.range(0) == 1;
    const int mount = int(state.range(1)), error = int(state.range(2));
    const uint64_t seed = uint64_t(state.range(3));
    static const Eigen::Vector3d kMounts[] = {{0, 0, 0}, {0, 15, 0}, {0, 0, 90}};
    // One capture per platform, mount and seed, kept for the error cases that follow it.
    static std::map<std::tuple<bool, int, uint64_t>, std::unique_ptr<test::TempDir>> captures;
    std::unique_ptr<test::TempDir>& dir = captures[{handheld, mount, seed}];
    if (!dir) {
        dir = std::make_unique<test::TempDir>();
        Simulate(*dir, handheld ? Platform::kHandheld : Platform::kGo1, 60, "OS1-32", seed,
                 kMounts[mount]);
    }
    const fs::path capture = *dir / "capture";
    const Eigen::Vector3d axis = Eigen::Vector3d::Ones().normalized();
    const Eigen::Matrix3d R_error = Eigen::AngleAxisd(M_PI / 180.0, axis).toRotationMatrix();
    const Eigen::Vector3d ypr_deg = R_error.eulerAngles(2, 1, 0) * (180.0 / M_PI);

    CaptureOdometryOptions o;
    o.capture_dir = capture;
    o.session_dir = *dir / "session";
    o.overwrite = true;
    o.use_can = !handheld;
    o.odometry.registration.cpu_time_budget = true;
    Eigen::Isometry3d T_base_lidar = *io::ReadCaptureMount(capture / "capture.json");
    if (error == 1 || error == 5) T_base_lidar.translation() += 0.01 * axis;
    if (error == 2 || error == 5) T_base_lidar.linear() = T_base_lidar.linear() * R_error;
    o.mount = T_base_lidar;
    if (error == 3 || error == 5) o.imu_rotation_rpy_deg = ypr_deg.reverse();
    if (error == 4 || error == 5) o.time_offset_ns = 1'000'000;
    CaptureOdometryReport rep;
    for (auto _ : state) rep = RunCaptureOdometry(o);

    SetCounters(state, rep, Evaluate(o.session_dir, capture));
    static const char* const kErrors[] = {"exact",     "mount 1 cm", "mount 1 deg",
                                          "imu 1 deg", "clock 1 ms", "all four"};
    static const char* const kMountNames[] = {"level", "pitched 15", "yawed 90"};
    state.SetLabel(std::string(handheld ? "handheld" : "go1+can") + ", " + kMountNames[mount] +
                   ", " + kErrors[error]);
}
BENCHMARK(BM_OdometryCalibration)
    ->ArgsProduct({{0, 1}, {0}, {0, 1, 2, 3, 4, 5}, {1, 2}})
    ->ArgsProduct({{0, 1}, {1, 2}, {0, 5}, {1, 2}})
    ->ArgNames({"platform", "mount", "error", "seed"})
    ->Unit(benchmark::kSecond)
    ->Iterations(1);

// VmRSS (current) and VmHWM (peak) of this process, MB (10^6 bytes).
struct Memory {
    double rss_mb = 0;
    double hwm_mb = 0;
};
Memory ReadMemory() {
    Memory m;
    std::ifstream in("/proc/self/status");
    std::string line;
    while (std::getline(in, line)) {
        const auto kb = [&line] { return std::stod(line.substr(line.find(':') + 1)) * 1e3 / 1e6; };
        if (line.starts_with("VmRSS:")) m.rss_mb = kb();
        if (line.starts_with("VmHWM:")) m.hwm_mb = kb();
    }
    return m;
}

// Resets VmHWM to the current VmRSS (Linux >= 4.0: "5" to /proc/self/clear_refs). False when
// the kernel refused.
bool ResetPeak() {
    {
        std::ofstream out("/proc/self/clear_refs");
        out << "5";
        out.flush();
        if (!out) return false;
    }
    const Memory m = ReadMemory();
    return m.hwm_mb <= m.rss_mb + 1.0;
}

void BM_OdometryMemory(benchmark::State& state) {
    if (std::getenv("BIMSLAM_BENCH_LONG") == nullptr) {
        state.SkipWithError(
            "opt-in: set BIMSLAM_BENCH_LONG=1 (simulates 30 min of capture: 7.7 GB of pcap in a "
            "temporary folder, about 2.5 min)");
        for (auto _ : state) {
        }
        return;
    }
    test::TempDir tmp;
    const simulate::CaptureReport sim = Simulate(tmp, Platform::kGo1, double(state.range(0)));
    // The simulation's peak is not the odometry's: give its freed memory back to the system and
    // start the peak again. When the kernel does not allow the reset, VmHWM would be the
    // simulation's peak, so peak_rss_mb is then the largest VmRSS sampled every 10 scans.
    const double sim_peak_mb = ReadMemory().hwm_mb;
    // The estimated poses, for the accuracy over the whole walk (64 bytes a scan: ~1.2 MB of the
    // RSS at the end is theirs, not the odometry's; the ground truth's as much is in
    // rss_mb_before).
    const std::vector<io::StampedPose> truth = io::ReadTum(sim.dir / "ground_truth.tum");
    std::vector<io::StampedPose> poses;
    poses.reserve(truth.size() + 16);
    ::malloc_trim(0);
    const bool peak_reset = ResetPeak();
    const Memory before = ReadMemory();

    CaptureOdometryOptions o;
    o.capture_dir = sim.dir;  // no session_dir: nothing written
    int64_t first_ns = -1;
    size_t scans = 0, map_voxels = 0, map_points = 0;
    bool at_5min = false;
    Memory mem_5min, mem_end;
    double sampled_peak_mb = before.rss_mb;
    o.on_scan = [&](const odometry::OdometryResult& r) {
        if (first_ns < 0) first_ns = r.stamp_ns;
        ++scans;
        map_voxels = r.map_voxels;
        map_points = r.map_points;
        poses.push_back(io::StampedPose::FromIsometry(r.stamp_ns, r.T_odom_lidar));
        // Every 10 scans, and every scan of the last second (sim.frames scans are coming).
        if (scans % 10 == 0 || scans + 10 >= sim.frames) {
            mem_end = ReadMemory();
            sampled_peak_mb = std::max(sampled_peak_mb, mem_end.rss_mb);
        }
        if (!at_5min && double(r.stamp_ns - first_ns) * 1e-9 >= 300.0) {
            at_5min = true;
            mem_5min = ReadMemory();
        }
    };
    CaptureOdometryReport rep;
    for (auto _ : state) rep = RunCaptureOdometry(o);
    const evaluation::EvaluationResult e = evaluation::Evaluate(poses, truth, {});

    state.counters["rss_mb_before"] = before.rss_mb;
    state.counters["rss_mb_at_5min"] = mem_5min.rss_mb;
    state.counters["rss_mb_at_end"] = mem_end.rss_mb;
    state.counters["peak_rss_mb"] = peak_reset ? mem_end.hwm_mb : sampled_peak_mb;
    state.counters["peak_rss_sampled_mb"] = sampled_peak_mb;
    state.counters["peak_reset"] = peak_reset ? 1 : 0;
    state.counters["sim_peak_rss_mb"] = sim_peak_mb;
    state.counters["map_voxels_at_end"] = double(map_voxels);
    state.counters["map_points_at_end"] = double(map_points);
    state.counters["scans"] = double(rep.scans);
    state.counters["capture_s"] = rep.capture_s;
    state.counters["distance_m"] = rep.distance_m;
    state.counters["pcap_GB"] = double(sim.pcap_bytes) / 1e9;
    state.counters["realtime_x"] = rep.capture_s / std::max(rep.wall_s, 1e-9);
    state.counters["scan_ms_p99"] = Percentile(rep.scan_ms, 0.99);
    state.counters["scan_ms_max"] = Percentile(rep.scan_ms, 1.0);
    state.counters["failed"] = double(rep.failed);
    state.counters["over_budget"] = double(rep.over_budget);
    state.counters["degenerate"] = double(rep.degenerate);
    state.counters["ape_trans_rmse_cm"] = 100.0 * e.ape_trans_m.rmse;
    state.counters["ape_trans_max_cm"] = 100.0 * e.ape_trans_m.max;
    state.counters["ape_rot_rmse_deg"] = e.ape_rot_deg.rmse;
    state.counters["drift_pct"] = e.drift_percent;
}
BENCHMARK(BM_OdometryMemory)
    ->Args({1800})
    ->ArgNames({"seconds"})
    ->Unit(benchmark::kSecond)
    ->Iterations(1);

}  // namespace
}  // namespace bimslam::replay

BENCHMARK_MAIN();
