// bimslam demo: the main job end to end on data the project makes itself. It grows with every
// issue; for now: walk a synthetic office storey twice and record it as an Ouster capture (pcap +
// metadata), decode the capture with the driver, keep keyframes with Scan Context descriptors,
// write them as a session, read the session back and check it bit for bit, and recognise the
// places of the second lap among the keyframes of the first.
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "algorithms/common/se3.hpp"
#include "algorithms/common/status.hpp"
#include "algorithms/io/session.hpp"
#include "algorithms/scancontext/candidate_index.hpp"
#include "algorithms/scancontext/descriptor.hpp"
#include "drivers/ouster/builtin_sensor.hpp"
#include "drivers/ouster/metadata.hpp"
#include "host_tools/capture/ouster_capture.hpp"
#include "host_tools/cli/command.hpp"
#include "host_tools/cli/demo_capture.hpp"
#include "host_tools/cli/demo_scene.hpp"

namespace bimslam::cli {
namespace {
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct DemoOptions {
    std::string out = "demo_output";
    bool overwrite = false;
    int columns = 1024;
    int laps = 2;
};

double Seconds(Clock::time_point since) {
    return std::chrono::duration<double>(Clock::now() - since).count();
}

double Yaw(const Eigen::Isometry3d& T) { return std::atan2(T.linear()(1, 0), T.linear()(0, 0)); }

std::string FixedString(double v) {
    std::ostringstream s;
    s << std::fixed << std::setprecision(1) << v;
    return s.str();
}

double WrapAngle(double a) { return std::remainder(a, 2.0 * M_PI); }

uintmax_t FolderBytes(const fs::path& dir) {
    uintmax_t bytes = 0;
    for (const auto& e : fs::recursive_directory_iterator(dir)) {
        if (e.is_regular_file()) bytes += e.file_size();
    }
    return bytes;
}

// Bit-identical xyz, intensity and ring. The per-point time is stored as float32 seconds
// (specs/session-data.md), exact to a few ns only: its largest error goes to max_t_error_ns.
bool SameCloud(const common::PointCloud& a, const common::PointCloud& b, int64_t& max_t_error_ns) {
    if (a.size() != b.size() || a.time_offset_ns.size() != b.time_offset_ns.size()) return false;
    for (size_t i = 0; i < a.time_offset_ns.size(); ++i) {
        max_t_error_ns = std::max<int64_t>(
            max_t_error_ns, std::abs(int64_t(a.time_offset_ns[i]) - int64_t(b.time_offset_ns[i])));
    }
    return a.xyz == b.xyz && a.intensity == b.intensity && a.ring == b.ring;
}

int RunDemo(const DemoOptions& opt) {
    const auto t_start = Clock::now();
    const fs::path out = opt.out;
    const fs::path session_dir = out / "session";
    const fs::path capture_dir = out / "capture";
    if ((fs::exists(session_dir) || fs::exists(capture_dir)) && !opt.overwrite) {
        throw common::FileError(common::StatusCode::kAlreadyExists, out.string(), 0,
                                "holds an earlier demo; pass --overwrite or choose another --out");
    }
    fs::remove_all(capture_dir);
    fs::create_directories(capture_dir);

    // 1. The walk, recorded as an Ouster capture: pcap + metadata, as a real rig would save.
    const DemoScene scene = DemoScene::Office();
    const double lap_m = scene.LoopLength();
    const double speed = 1.0, sensor_z = 0.6;  // a Go1's pace and lidar height
    // The low-data-rate profile (8 mm range steps) keeps the demo's capture near 0.25 GB.
    const ouster::SensorInfo sensor =
        ouster::BuiltinOs1_32(ouster::LidarProfile::kRng15Rfl8Nir8, opt.columns, 10);
    const int frames_per_lap = static_cast<int>(lap_m / speed * sensor.frame_rate_hz);
    std::vector<Eigen::Isometry3d> poses;
    for (int lap = 0; lap < opt.laps; ++lap) {
        const double offset = 0.25 * lap;  // later laps walk beside the first
        for (int k = 0; k < frames_per_lap; ++k) {
            poses.push_back(scene.PoseAt(k * speed / sensor.frame_rate_hz, offset, sensor_z));
        }
    }
    std::cout << std::fixed << std::setprecision(1);
    std::cout << "bimslam demo: synthetic office storey (" << scene.walls.size()
              << " wall faces), walked " << opt.laps << " times (" << lap_m << " m a lap)\n";
    const auto t_capture = Clock::now();
    const DemoCapture capture = WriteDemoCapture(scene, poses, sensor, capture_dir, 0.01, 7);
    std::cout << "  captured " << poses.size() << " frames of a built-in OS-1-32 "
              << ToString(sensor.format.lidar_profile) << " " << sensor.lidar_mode << ": "
              << capture.packets << " lidar packets in IPv4 fragments, "
              << fs::file_size(capture.pcap) / 1e6 << " MB, in " << Seconds(t_capture)
              << " s\n           " << capture.pcap.string() << " + "
              << capture.metadata.filename().string() << "\n";

    // 2. Decode it like any real recording; keep keyframes (1 m / 10 deg, on the true poses
    //    until the LiDAR odometry exists) with indoor Scan Context descriptors.
    const auto t_decode = Clock::now();
    const ouster::SensorInfo info = ouster::LoadMetadata(capture.metadata);
    capture::OusterCapture reader(capture.pcap, info);
    const scancontext::ScanContextConfig sc = scancontext::ScanContextConfig::Indoor();
    scancontext::DescriptorBuilder builder(sc);
    io::SessionManifest manifest;
    manifest.source = "simulation";
    manifest.world_frame = "world";
    manifest.sensor = {info.prod_line, info.format.pixels_per_column, info.format.columns_per_frame,
                       capture.metadata.string()};
    manifest.descriptor = {"indoor",      sc.num_rings,         sc.num_sectors,
                           sc.max_radius, sc.indoor_min_points, sc.indoor_min_z_span};
    io::SessionWriter writer(session_dir, manifest, {.overwrite = opt.overwrite});
    std::vector<io::SessionKeyframe> keyframes;
    std::vector<int> lap_of;
    Eigen::Isometry3d last_key = Eigen::Isometry3d::Identity();
    size_t frames = 0, points = 0, keyframe_points = 0;
    common::PointCloud cloud;
    while (const ouster::LidarFrame* frame = reader.NextFrame()) {
        const size_t k = frames++;
        if (k >= poses.size() || frame->frame_id != (k & 0xFFFF)) {
            throw common::Error(common::StatusCode::kInternal,
                                "decoded frame " + std::to_string(frame->frame_id) +
                                    " where frame " + std::to_string(k) + " was recorded");
        }
        const Eigen::Isometry3d& T = poses[k];
        const auto stamp = static_cast<int64_t>(frame->start_ns);
        writer.AddScanPose(io::StampedPose::FromIsometry(stamp, T));
        ouster::ToPointCloud(*frame, &cloud);
        points += cloud.size();
        const Eigen::Isometry3d rel = common::Between(last_key, T);
        if (!keyframes.empty() && common::TranslationNorm(rel) < 1.0 &&
            common::RotationAngle(rel) < 10.0 * M_PI / 180.0) {
            continue;
        }
        io::SessionKeyframe kf;
        kf.stamp_ns = stamp;
        kf.T_world_lidar = T;
        kf.cloud = cloud;
        builder.Build(kf.cloud, &kf.descriptor);
        keyframe_points += kf.cloud.size();
        const size_t i = writer.AddKeyframe(kf);
        if (i > 0) {
            // Odometry edge from the ground truth, 1 cm / 0.1 deg standard deviation.
            io::SessionEdge e{uint32_t(i - 1), uint32_t(i),
                              common::Between(keyframes.back().T_world_lidar, T),
                              common::Matrix6d::Identity()};
            e.information.diagonal() << 1e4, 1e4, 1e4, 3.3e5, 3.3e5, 3.3e5;
            writer.AddEdge(e);
        }
        last_key = T;
        keyframes.push_back(std::move(kf));
        lap_of.push_back(static_cast<int>(k) / frames_per_lap);
    }
    writer.Finish();
    const double decode_s = Seconds(t_decode);
    const auto& ls = reader.lidar_stats();
    std::cout << "  decoded  " << frames << " frames (" << ls.frames_complete << " complete, "
              << ls.TotalRejected() << " packets rejected, " << reader.extractor_stats().reassembled
              << " datagrams reassembled), " << points / std::max<size_t>(frames, 1)
              << " points a frame\n"
              << "  kept     " << keyframes.size() << " keyframes (1 m / 10 deg), "
              << keyframe_points << " points, indoor Scan Context each; decoding, describing and "
              << "writing took " << decode_s << " s\n"
              << "  wrote    " << session_dir.string() << "  (" << FolderBytes(session_dir) / 1e6
              << " MB)\n";
    if (frames != poses.size() || ls.frames_complete != poses.size()) {
        throw common::Error(common::StatusCode::kInternal,
                            "the capture gave back " + std::to_string(ls.frames_complete) +
                                " complete frames of " + std::to_string(poses.size()));
    }

    // 3. Read the session back and compare everything.
    const auto t_read = Clock::now();
    const io::Session s = io::ReadSession(session_dir);
    size_t identical = 0;
    int64_t max_t_error_ns = 0;
    for (size_t i = 0; i < std::min(s.keyframes.size(), keyframes.size()); ++i) {
        const auto& a = keyframes[i];
        const auto& b = s.keyframes[i];
        identical += a.stamp_ns == b.stamp_ns &&
                     a.T_world_lidar.matrix() == b.T_world_lidar.matrix() &&
                     a.descriptor == b.descriptor && SameCloud(a.cloud, b.cloud, max_t_error_ns);
    }
    const bool read_ok = s.complete && identical == keyframes.size() &&
                         s.keyframes.size() == keyframes.size() && max_t_error_ns <= 8;
    std::cout << "  read     " << s.keyframes.size() << " keyframes, " << s.edges.size()
              << " edges, " << s.trajectory.size() << " scan poses in " << Seconds(t_read) << " s; "
              << identical << "/" << keyframes.size()
              << " keyframes bit-identical (points, descriptor, pose, time); per-point times "
                 "within "
              << max_t_error_ns << " ns (float32 seconds in PCD)\n";

    // 4. Place recognition: later laps against the first.
    scancontext::CandidateIndex index(sc);
    std::vector<size_t> first_lap;
    for (size_t i = 0; i < s.keyframes.size(); ++i) {
        if (lap_of[i] == 0) {
            first_lap.push_back(i);
            if (!index.Add(s.keyframes[i].descriptor).ok()) return kExitFailure;
        }
    }
    index.Build();
    int queries = 0, found = 0;
    double yaw_err_sum = 0.0;
    for (size_t i = 0; i < s.keyframes.size(); ++i) {
        if (lap_of[i] == 0) continue;
        ++queries;
        const auto match = index.Query(s.keyframes[i].descriptor);
        if (!match) continue;
        const auto& ref = s.keyframes[first_lap[match->index]].T_world_lidar;
        const auto& qry = s.keyframes[i].T_world_lidar;
        if ((ref.translation() - qry.translation()).norm() > 2.0) continue;
        ++found;
        yaw_err_sum += std::abs(WrapAngle(match->yaw - (Yaw(qry) - Yaw(ref))));
    }
    std::cout << "  matched  " << found << "/" << queries
              << " keyframes of the later laps to a first-lap keyframe within 2 m by Scan Context"
              << (found
                      ? ", mean yaw error " + FixedString(yaw_err_sum / found * 180 / M_PI) + " deg"
                      : "")
              << "\n";
    std::cout << "results in " << out.string() << "/:\n"
              << "  capture/  lidar.pcap + metadata.json   (bimslam ouster info "
              << capture.pcap.string() << ")\n"
              << "  session/  keyframes, poses, descriptors (bimslam session info "
              << session_dir.string() << "; layout in algorithms/io/README.md)\n"
              << "demo " << (read_ok ? "finished" : "FAILED") << " in " << Seconds(t_start)
              << " s\n";
    return read_ok ? kExitOk : kExitFailure;
}

}  // namespace

void AddDemoCommand(CLI::App& app, int& exit_code) {
    auto opt = std::make_shared<DemoOptions>();
    CLI::App* demo = app.add_subcommand(
        "demo",
        "Run the main job end to end on a building and a walk the project generates "
        "itself, and print what it did and where the results are.");
    demo->add_option("--out,-o", opt->out, "output folder")->capture_default_str();
    demo->add_flag("--overwrite", opt->overwrite, "replace the results of an earlier demo");
    demo->add_option("--columns", opt->columns, "columns per scan (512, 1024 or 2048)")
        ->check(CLI::IsMember({512, 1024, 2048}))
        ->capture_default_str();
    demo->add_option("--laps", opt->laps, "laps of the walk (the first is the reference)")
        ->check(CLI::Range(1, 10))
        ->capture_default_str();
    demo->callback([opt, &exit_code] { exit_code = Run([&] { return RunDemo(*opt); }); });
}

}  // namespace bimslam::cli
