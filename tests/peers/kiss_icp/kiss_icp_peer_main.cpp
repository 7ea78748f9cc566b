// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// kiss_icp_peer: KISS-ICP (PRBonn, Vizzo et al., RA-L 2023) run on a folder of per-scan clouds as
// `bimslam ouster export REC --all` writes it, so that it and `bimslam odometry` see the same
// scans and are scored against the same ground truth (issue 32, item 4).
//
// The folder is read with the reader `bimslam odometry` uses (host_tools/replay/cloud_folder.hpp),
// so both get the same points with the same per-point times. KISS-ICP runs with the defaults of
// its own apps (python/kiss_icp/config: max range 100 m, min range 0, deskew on, voxel size
// max_range / 100) on one thread (max_num_threads 1: TBB's global parallelism is then 1 and its
// parallel loops run on the calling thread).
//
// Timing: CLOCK_THREAD_CPUTIME_ID around each KissICP::RegisterFrame (deskew, voxelisation,
// registration, map update), nothing else: reading and converting the file are outside. The
// process's CPU time over the run is printed beside the sum, as a check that no other thread
// worked.
//
// The pose of a scan: KISS-ICP deskews every point to the time of the scan's last point
// (Preprocessing.cpp: exp((s - 1) * log(delta)) with s the time normalised to [0, 1]), so its pose
// is the sensor's at the sweep's end, and trajectory.tum stamps it there (scan start + largest
// point time). KISS-ICP's Python Ouster loader stamps it at the scan start instead; with
// `--stamp-at start` this driver does the same (a 0.1 s shift against the ground truth).
#include <time.h>

#include <CLI/CLI.hpp>
#include <Eigen/Core>
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "algorithms/common/status.hpp"
#include "algorithms/io/trajectory.hpp"
#include "host_tools/replay/capture_odometry.hpp"
#include "host_tools/replay/cloud_folder.hpp"
#include "kiss_icp/pipeline/KissICP.hpp"

#ifndef BIMSLAM_KISS_ICP_COMMIT
#define BIMSLAM_KISS_ICP_COMMIT "unknown"
#endif

namespace {

namespace fs = std::filesystem;
using bimslam::replay::Percentile;

double ClockMs(clockid_t clock) {
    timespec ts{};
    clock_gettime(clock, &ts);
    return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
}

struct Args {
    std::string folder;
    std::string out;
    double max_range = 100.0;
    double min_range = 0.0;
    bool no_deskew = false;
    std::string stamp_at = "end";
    bool json = false;
};

struct ScanFigures {
    std::vector<double> cpu_ms, wall_ms;
    std::vector<size_t> points;
    double registration_points = 0;  // summed over the scans: KISS-ICP's `source`
};

// The scan as KISS-ICP takes it: double points and per-point times (seconds since the scan
// start; KISS-ICP normalises them to the scan's own span). Empty times when the file has none.
void ToKiss(const bimslam::common::PointCloud& cloud, std::vector<Eigen::Vector3d>* points,
            std::vector<double>* times) {
    points->resize(cloud.size());
    for (size_t i = 0; i < cloud.size(); ++i) (*points)[i] = cloud.xyz[i].cast<double>();
    times->clear();
    if (!cloud.HasTime()) return;
    times->resize(cloud.size());
    for (size_t i = 0; i < cloud.size(); ++i) (*times)[i] = double(cloud.time_offset_ns[i]) * 1e-9;
}

nlohmann::json Summary(const Args& a, const kiss_icp::pipeline::KISSConfig& c, const ScanFigures& f,
                       double process_cpu_ms, bool had_times) {
    double cpu_sum = 0, mean_points = 0;
    for (const double ms : f.cpu_ms) cpu_sum += ms;
    for (const size_t n : f.points) mean_points += double(n);
    if (!f.points.empty()) mean_points /= double(f.points.size());
    return {{"peer", "kiss-icp"},
            {"kiss_icp_commit", BIMSLAM_KISS_ICP_COMMIT},
            {"folder", a.folder},
            {"scans", f.cpu_ms.size()},
            {"mean_points", mean_points},
            {"mean_registration_points",
             f.points.empty() ? 0.0 : f.registration_points / double(f.points.size())},
            {"voxel_size_m", c.voxel_size},
            {"max_range_m", c.max_range},
            {"min_range_m", c.min_range},
            {"deskew", c.deskew && had_times},
            {"threads", c.max_num_threads},
            {"stamp_at", a.stamp_at},
            {"scan_cpu_ms_p50", Percentile(f.cpu_ms, 0.5)},
            {"scan_cpu_ms_p99", Percentile(f.cpu_ms, 0.99)},
            {"scan_cpu_ms_max", Percentile(f.cpu_ms, 1.0)},
            {"scan_cpu_ms_sum", cpu_sum},
            {"scan_ms_p50", Percentile(f.wall_ms, 0.5)},
            {"scan_ms_p99", Percentile(f.wall_ms, 0.99)},
            {"process_cpu_ms", process_cpu_ms},
            {"trajectory", (fs::path(a.out) / "trajectory.tum").string()}};
}

int Run(const Args& a) {
    const bimslam::replay::CloudFolder folder = bimslam::replay::ResolveCloudFolder(a.folder);
    if (folder.scans.empty()) {
        throw bimslam::common::FileError(bimslam::common::StatusCode::kNotFound, a.folder, 0,
                                         "no scans in the folder");
    }
    kiss_icp::pipeline::KISSConfig config;  // KISS-ICP's own defaults, then its apps' choices:
    config.max_range = a.max_range;
    config.min_range = a.min_range;
    config.voxel_size = a.max_range / 100.0;  // python/kiss_icp/config/parser.py
    config.deskew = !a.no_deskew;
    config.max_num_threads = 1;
    kiss_icp::pipeline::KissICP kiss(config);

    fs::create_directories(a.out);
    std::ofstream per_scan(fs::path(a.out) / "scan_times.csv");
    per_scan << "scan,stamp_s,points,cpu_ms,wall_ms\n" << std::setprecision(9);
    std::vector<bimslam::io::StampedPose> trajectory;
    ScanFigures figures;
    std::vector<Eigen::Vector3d> points;
    std::vector<double> times;
    bool had_times = true;
    const double process_start = ClockMs(CLOCK_PROCESS_CPUTIME_ID);
    double read_cpu_ms = 0;
    for (size_t i = 0; i < folder.scans.size(); ++i) {
        const double read_start = ClockMs(CLOCK_THREAD_CPUTIME_ID);
        const bimslam::common::PointCloud cloud = bimslam::replay::ReadScanCloud(folder, i);
        ToKiss(cloud, &points, &times);
        read_cpu_ms += ClockMs(CLOCK_THREAD_CPUTIME_ID) - read_start;
        had_times = had_times && cloud.HasTime();

        const double wall0 = ClockMs(CLOCK_MONOTONIC);
        const double cpu0 = ClockMs(CLOCK_THREAD_CPUTIME_ID);
        const auto [deskewed, source] = kiss.RegisterFrame(points, times);
        const double cpu_ms = ClockMs(CLOCK_THREAD_CPUTIME_ID) - cpu0;
        const double wall_ms = ClockMs(CLOCK_MONOTONIC) - wall0;

        int64_t end_ns = 0;
        for (const uint32_t dt : cloud.time_offset_ns) end_ns = std::max(end_ns, int64_t(dt));
        const int64_t stamp = cloud.stamp.ns + (a.stamp_at == "end" ? end_ns : 0);
        trajectory.push_back(
            bimslam::io::StampedPose::FromIsometry(stamp, Eigen::Isometry3d(kiss.pose().matrix())));
        figures.cpu_ms.push_back(cpu_ms);
        figures.wall_ms.push_back(wall_ms);
        figures.points.push_back(cloud.size());
        figures.registration_points += double(source.size());
        per_scan << i << ',' << double(stamp) * 1e-9 << ',' << cloud.size() << ',' << cpu_ms << ','
                 << wall_ms << '\n';
    }
    // Everything the process did on any thread, less this thread's file reading: equal to the
    // registrations' sum when KISS-ICP ran on this thread alone.
    const double process_cpu_ms = ClockMs(CLOCK_PROCESS_CPUTIME_ID) - process_start - read_cpu_ms;
    bimslam::io::WriteTum(fs::path(a.out) / "trajectory.tum", trajectory);

    const nlohmann::json s = Summary(a, config, figures, process_cpu_ms, had_times);
    std::ofstream(fs::path(a.out) / "summary.json") << s.dump(2) << "\n";
    if (a.json) {
        std::cout << s.dump(2) << "\n";
        return 0;
    }
    std::cout << std::fixed << std::setprecision(2);
    std::cout << "kiss-icp  " << BIMSLAM_KISS_ICP_COMMIT << ", voxel " << config.voxel_size
              << " m, range " << config.min_range << "-" << config.max_range << " m, deskew "
              << (config.deskew && had_times ? "on" : "off") << ", 1 thread\n";
    if (!had_times) std::cout << "note      the clouds have no per-point time: no deskew\n";
    std::cout << "inputs    " << figures.cpu_ms.size() << " scans, "
              << s["mean_points"].get<double>() << " points a scan on average, "
              << s["mean_registration_points"].get<double>() << " registered\n";
    std::cout << "CPU/scan  p50 " << Percentile(figures.cpu_ms, 0.5) << " ms, p99 "
              << Percentile(figures.cpu_ms, 0.99) << " ms, max " << Percentile(figures.cpu_ms, 1.0)
              << " ms (RegisterFrame, this thread's CPU time)\n";
    std::cout << "wall/scan p50 " << Percentile(figures.wall_ms, 0.5) << " ms, p99 "
              << Percentile(figures.wall_ms, 0.99) << " ms\n";
    std::cout << "threads   process CPU " << process_cpu_ms << " ms against "
              << s["scan_cpu_ms_sum"].get<double>() << " ms on this thread\n";
    std::cout << "output    " << a.out << ": trajectory.tum (T_world_lidar at the sweep's "
              << a.stamp_at << "), scan_times.csv, summary.json\n";
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{
        "KISS-ICP (PRBonn) on a folder of per-scan clouds written by `bimslam ouster export "
        "--all`, on one thread: its trajectory (TUM, for bimslam evaluate) and the CPU time of "
        "each registration (tests/peers/kiss_icp/README.md)"};
    Args a;
    app.add_option("folder", a.folder, "folder of per-scan .pcd/.ply/.bin clouds with times.txt")
        ->required();
    app.add_option("-o,--output", a.out,
                   "folder to write trajectory.tum, scan_times.csv and summary.json into")
        ->required();
    app.add_option("--max-range", a.max_range,
                   "KISS-ICP's data.max_range (its default 100 m); the voxel size is a "
                   "hundredth of it")
        ->check(CLI::PositiveNumber);
    app.add_option("--min-range", a.min_range, "KISS-ICP's data.min_range (its default 0)")
        ->check(CLI::NonNegativeNumber);
    app.add_flag("--no-deskew", a.no_deskew, "KISS-ICP's data.deskew false");
    app.add_option("--stamp-at", a.stamp_at,
                   "stamp each pose at the sweep's end (where KISS-ICP's deskew puts it) or at "
                   "the scan start (as KISS-ICP's Python Ouster loader does)")
        ->check(CLI::IsMember({"end", "start"}));
    app.add_flag("--json", a.json, "print the summary as JSON");
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;
    }
    try {
        return Run(a);
    } catch (const bimslam::common::FileError& e) {
        std::cerr << "kiss_icp_peer: " << e.what() << "\n";
        return 2;
    } catch (const std::exception& e) {
        std::cerr << "kiss_icp_peer: " << e.what() << "\n";
        return 1;
    }
}
