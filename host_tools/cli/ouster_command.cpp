// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// bimslam ouster info | export: what an Ouster capture holds, and one frame of it as arrays.
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>

#include "algorithms/common/status.hpp"
#include "algorithms/io/capture_files.hpp"
#include "algorithms/io/file_util.hpp"
#include "algorithms/io/npy.hpp"
#include "algorithms/io/pcd.hpp"
#include "drivers/ouster/metadata.hpp"
#include "drivers/ouster/xyz_lut.hpp"
#include "host_tools/capture/ouster_capture.hpp"
#include "host_tools/cli/command.hpp"
#include "host_tools/replay/cloud_folder_writer.hpp"

namespace bimslam::cli {
namespace {
namespace fs = std::filesystem;
using common::FileError;
using common::StatusCode;

struct OusterOptions {
    std::string pcap;
    std::string meta;  // default: the pcap's name with .json
    std::optional<uint16_t> lidar_port, imu_port;
    bool json = false;
    std::string out;
    int frame = 0;
    bool all = false;            // export: every frame as a cloud folder
    std::string format = "pcd";  // export --all: pcd, ply or bin
    bool overwrite = false;
};

// The recording as every command takes it (io::ResolveCapture: a capture folder, x.pcap with
// x.json or metadata.json beside it, a ROS bag), --meta overriding its metadata.
io::CaptureFiles Files(const OusterOptions& o) {
    try {
        return io::ResolveCapture(o.pcap, o.meta);
    } catch (const FileError& e) {
        if (!o.meta.empty() || e.path() != o.pcap) throw;
        throw FileError(e.code(), e.path(), e.line(), e.detail() + "; pass --meta JSON");
    }
}

capture::OusterCaptureOptions CaptureOptions(const OusterOptions& o) {
    capture::OusterCaptureOptions c;
    c.lidar_port = o.lidar_port;
    c.imu_port = o.imu_port;
    return c;
}

int Info(const OusterOptions& o) {
    const io::CaptureFiles files = Files(o);
    const ouster::SensorInfo info = capture::LoadRecordingInfo(files);
    capture::OusterCapture cap(files.packets, info, CaptureOptions(o));
    uint64_t first_id = 0, last_id = 0, n = 0;
    while (const ouster::LidarFrame* f = cap.NextFrame()) {
        if (n++ == 0) first_id = f->frame_id;
        last_id = f->frame_id;
    }
    const auto& ls = cap.lidar_stats();
    const auto& cs = cap.stats();
    nlohmann::json rejected = nlohmann::json::object();
    for (int r = 0; r < ouster::kNumRejects; ++r) {
        rejected[std::string(ToString(static_cast<ouster::Reject>(r)))] = ls.rejected[r];
    }
    nlohmann::json imu_rejected = nlohmann::json::object();
    for (int r = 0; r < ouster::kNumImuRejects; ++r) {
        imu_rejected[std::string(ToString(static_cast<ouster::ImuReject>(r)))] =
            cap.imu_stats().rejected[r];
    }
    const auto& es = cap.extractor_stats();
    const net::RosBagTopics* bag = cap.bag_topics();
    nlohmann::json j = {
        {"file", files.packets.string()},
        {"format", bag ? "rosbag" : "pcap"},
        {"metadata", info.source},
        {"prod_line", info.prod_line},
        {"prod_sn", info.prod_sn},
        {"firmware", info.build_rev},
        {"profile", std::string(ToString(info.format.lidar_profile))},
        {"pixels_per_column", info.format.pixels_per_column},
        {"columns_per_frame", info.format.columns_per_frame},
        {"columns_per_packet", info.format.columns_per_packet},
        {"lidar_port", cap.lidar_port()},
        {"imu_port", cap.imu_port() ? nlohmann::json(*cap.imu_port()) : nlohmann::json(nullptr)},
        {"ports_guessed", cap.ports_guessed()},
        {"datagrams", cs.datagrams},
        {"lidar_packets", cs.lidar_packets},
        {"imu_packets", cs.imu_packets},
        {"other_datagrams", cs.other_datagrams},
        {"lidar_packets_accepted", ls.accepted},
        {"frames_complete", ls.frames_complete},
        {"frames_incomplete", ls.frames_incomplete},
        {"columns_lost", ls.columns_lost},
        {"sensor_restarts", ls.sensor_restarts},
        {"crc_checked", ls.crc_checked},
        {"rejected", rejected},
        {"imu_samples", cs.imu_samples},
        {"imu_rejected", imu_rejected},
        {"first_frame_id", n ? nlohmann::json(first_id) : nlohmann::json(nullptr)},
        {"last_frame_id", n ? nlohmann::json(last_id) : nlohmann::json(nullptr)},
        {"ip_fragments", es.fragments},
        {"ip_reassembled", es.reassembled},
        {"ip_incomplete", es.timed_out_datagrams + es.incomplete_at_end +
                              es.evicted_datagrams_limit + es.evicted_datagrams_bytes},
        {"truncated", cs.truncated},
    };
    if (bag) {
        const auto topic = [](const std::string& t) {
            return t.empty() ? nlohmann::json(nullptr) : nlohmann::json(t);
        };
        j["bag_topics"] = {
            {"lidar", bag->lidar}, {"imu", topic(bag->imu)}, {"metadata", topic(bag->metadata)}};
    }
    if (o.json) {
        std::cout << j.dump(2) << "\n";
        return kExitOk;
    }
    std::cout << "capture     " << files.packets.string()
              << (cs.truncated ? "  (cut off mid-packet)" : "") << "\n";
    if (bag) {
        std::cout << "ROS bag     lidar " << bag->lidar << ", imu "
                  << (bag->imu.empty() ? "none" : bag->imu) << ", metadata "
                  << (bag->metadata.empty() ? "none" : bag->metadata) << "\n";
    }
    std::cout << "sensor      " << info.prod_line << " sn " << info.prod_sn << " " << info.build_rev
              << ", " << ToString(info.format.lidar_profile) << ", "
              << info.format.pixels_per_column << " x " << info.format.columns_per_frame
              << "  (metadata " << info.source << ")\n"
              << "ports       lidar " << cap.lidar_port() << ", imu "
              << (cap.imu_port() ? std::to_string(*cap.imu_port()) : "none")
              << (cap.ports_guessed() ? " (guessed from packet sizes)" : "")
              << (bag ? " (labels given to the bag's topics)" : "") << "\n"
              << "datagrams   " << cs.datagrams << ": " << cs.lidar_packets << " lidar, "
              << cs.imu_packets << " imu, " << cs.other_datagrams << " other";
    if (es.reassembled > 0) std::cout << " (" << es.reassembled << " from IPv4 fragments)";
    std::cout << "\n";
    if (n == 0) {
        std::cout << "frames      no frames\n";
    } else {
        std::cout << "frames      " << ls.frames_complete << " complete, " << ls.frames_incomplete
                  << " incomplete (" << ls.columns_lost << " columns lost), ids " << first_id
                  << " .. " << last_id << "\n";
    }
    std::cout << "rejected    " << ls.TotalRejected();
    for (const auto& [cause, count] : rejected.items()) {
        if (count.get<uint64_t>() > 0) std::cout << "  " << cause << ": " << count;
    }
    std::cout << "\nimu         " << cs.imu_samples << " samples\n";
    return kExitOk;
}

template <typename T>
void WriteArray(const fs::path& dir, const std::string& name, const T* data,
                std::vector<size_t> shape) {
    io::WriteNpy(dir / (name + ".npy"), io::NpyArray::From(data, std::move(shape)));
}

// export --all: the peer-benchmark folder (host_tools/replay/cloud_folder_writer.hpp).
int ExportAll(const OusterOptions& o, const io::CaptureFiles& files) {
    const replay::CloudFolderExport e =
        replay::WriteCloudFolder(files, o.format, o.out, CaptureOptions(o));
    std::cout << "exported " << e.scans << " scans (" << o.format << ", per-point time"
              << (o.format == "bin" ? " not in KITTI .bin" : " t") << ") and times.txt";
    if (e.imu_samples > 0) std::cout << ", " << e.imu_samples << " IMU samples in imu.csv";
    if (e.ground_truth) std::cout << ", ground_truth.tum";
    if (e.kitti_poses) std::cout << ", poses.txt (KITTI)";
    std::cout << " to " << o.out << "/\n";
    if (!e.note.empty()) std::cout << "note: " << e.note << "\n";
    std::cout << "replay it: bimslam odometry " << o.out << " -o SESSION\n";
    return kExitOk;
}

int Export(const OusterOptions& o) {
    const io::CaptureFiles files = Files(o);
    const ouster::SensorInfo info = capture::LoadRecordingInfo(files);
    const fs::path out = o.out;
    if (fs::exists(out) && !fs::is_empty(out) && !o.overwrite) {
        throw FileError(
            StatusCode::kAlreadyExists, out.string(), 0,
            "already exists and is not empty; pass --overwrite or choose another --out");
    }
    if (o.all) return ExportAll(o, files);
    capture::OusterCapture cap(files.packets, info, CaptureOptions(o));
    int seen = 0;
    const ouster::LidarFrame* frame = nullptr;
    while ((frame = cap.NextFrame()) != nullptr) {
        if (frame->complete && seen++ == o.frame) break;
    }
    if (frame == nullptr) {
        throw FileError(StatusCode::kNotFound, files.packets.string(), 0,
                        seen == 0 ? std::string("no frames: the capture holds no complete frame")
                                  : "has " + std::to_string(seen) + " complete frames; --frame " +
                                        std::to_string(o.frame) + " is beyond them");
    }
    fs::create_directories(out);
    const size_t h = frame->h, w = frame->w;
    nlohmann::json fields = nlohmann::json::array();
    for (int k = 0; k < ouster::kNumFields; ++k) {
        const auto field = static_cast<ouster::Field>(k);
        const void* data = frame->FieldData(field);
        if (!data) continue;
        const std::string name(ToString(field));
        switch (ouster::TypeOf(field)) {
            case ouster::FieldType::kU32:
                WriteArray(out, name, static_cast<const uint32_t*>(data), {h, w});
                break;
            case ouster::FieldType::kU16:
                WriteArray(out, name, static_cast<const uint16_t*>(data), {h, w});
                break;
            case ouster::FieldType::kU8:
                WriteArray(out, name, static_cast<const uint8_t*>(data), {h, w});
                break;
        }
        fields.push_back(name);
    }
    WriteArray(out, "TIMESTAMP", frame->timestamp.data(), {w});
    WriteArray(out, "MEASUREMENT_ID", frame->measurement_id.data(), {w});
    WriteArray(out, "STATUS", frame->status.data(), {w});
    // XYZ in double from the spec's lookup table, not the float one of the hot path.
    const ouster::XyzLut<double> lut(info);
    std::vector<Eigen::Vector3d> xyz(h * w);
    lut.Compute(frame->range.data(), xyz.data());
    WriteArray(out, "xyz", xyz.data()->data(), {h, w, 3});
    common::PointCloud cloud;
    ouster::ToPointCloud(*frame, &cloud);
    io::WritePcd(out / "cloud.pcd", cloud);
    const nlohmann::json j = {{"source", files.packets.string()},
                              {"metadata", info.source},
                              {"frame_index", o.frame},
                              {"frame_id", frame->frame_id},
                              {"profile", std::string(ToString(info.format.lidar_profile))},
                              {"H", h},
                              {"W", w},
                              {"fields", fields},
                              {"columns_received", frame->columns_received},
                              {"packets", frame->packets},
                              {"points", cloud.size()},
                              {"start_ns", frame->start_ns}};
    io::WriteFileAtomic(out / "frame.json", j.dump(2) + "\n");
    std::cout << "exported frame " << frame->frame_id << " (complete frame " << o.frame << ", " << h
              << " x " << w << ", " << cloud.size() << " points) to " << out.string()
              << "/: " << fields.size() << " field images, TIMESTAMP, MEASUREMENT_ID, STATUS, "
              << "xyz.npy, cloud.pcd, frame.json\n";
    return kExitOk;
}

void AddCommon(CLI::App* cmd, OusterOptions& o) {
    cmd->add_option("RECORDING", o.pcap,
                    "a capture (.pcap, .pcapng, optionally .gz), a capture folder, or a ROS 1 bag "
                    "from ouster-ros (.bag: lidar/IMU packet topics and the metadata topic)")
        ->required();
    cmd->add_option("--meta", o.meta,
                    "sensor metadata JSON (default: RECORDING with .json, else metadata.json "
                    "beside it; a bag's own metadata topic)");
    cmd->add_option("--lidar-port", o.lidar_port, "lidar UDP port (default: metadata, or guessed)");
    cmd->add_option("--imu-port", o.imu_port, "IMU UDP port (default: metadata, or guessed)");
}

}  // namespace

void AddOusterCommands(CLI::App& app, int& exit_code) {
    CLI::App* ouster = app.add_subcommand("ouster", "Ouster captures: inspect, export frames");
    ouster->require_subcommand(1);
    auto info_opt = std::make_shared<OusterOptions>();
    CLI::App* info = ouster->add_subcommand(
        "info", "Decode a capture; print its sensor, packets, frames and rejections by cause");
    AddCommon(info, *info_opt);
    info->add_flag("--json", info_opt->json, "machine-readable output");
    info->callback([info_opt, &exit_code] { exit_code = Run([&] { return Info(*info_opt); }); });

    auto exp_opt = std::make_shared<OusterOptions>();
    CLI::App* exp = ouster->add_subcommand(
        "export",
        "Write one complete frame as .npy arrays (SDK dtypes), cloud.pcd and frame.json; or, with "
        "--all, every frame as per-scan clouds for a peer odometry");
    AddCommon(exp, *exp_opt);
    exp->add_option("--out,-o", exp_opt->out, "output folder")->required();
    exp->add_option("--frame", exp_opt->frame, "which complete frame, 0 = the first")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    exp->add_flag("--all", exp_opt->all,
                  "every frame as a folder of per-scan clouds with times.txt, imu.csv and, for a "
                  "simulated capture, ground_truth.tum and KITTI poses.txt: exactly the input "
                  "and the truth a peer odometry needs (`bimslam odometry` reads it back)");
    exp->add_option("--format", exp_opt->format,
                    "with --all: pcd, ply (both with per-point "
                    "time t) or bin (KITTI: x y z intensity)")
        ->check(CLI::IsMember({"pcd", "ply", "bin"}))
        ->capture_default_str();
    exp->add_flag("--overwrite", exp_opt->overwrite, "write into a non-empty output folder");
    exp->callback([exp_opt, &exit_code] { exit_code = Run([&] { return Export(*exp_opt); }); });
    AddOusterReplayCommand(*ouster, exit_code);
}

}  // namespace bimslam::cli
