// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/replay/cloud_folder_writer.hpp"

#include <cstdio>
#include <cstring>
#include <map>

#include "algorithms/common/status.hpp"
#include "algorithms/io/file_util.hpp"
#include "algorithms/io/pcd.hpp"
#include "algorithms/io/ply.hpp"
#include "algorithms/io/text_reader.hpp"
#include "algorithms/io/trajectory.hpp"
#include "algorithms/pipeline/scan_pipeline.hpp"
#include "host_tools/replay/imu_csv.hpp"

namespace bimslam::replay {
namespace fs = std::filesystem;
using common::StatusCode;

void WriteKittiBin(const fs::path& path, const common::PointCloud& cloud) {
    std::string bytes(16 * cloud.size(), '\0');
    for (size_t i = 0; i < cloud.size(); ++i) {
        const float v[4] = {cloud.xyz[i].x(), cloud.xyz[i].y(), cloud.xyz[i].z(),
                            cloud.HasIntensity() ? cloud.intensity[i] : 0.0f};
        std::memcpy(bytes.data() + 16 * i, v, sizeof(v));
    }
    io::WriteFileAtomic(path, bytes);
}

namespace {

// poses.txt: the ground truth at each scan's start (the simulator writes one pose a scan, stamped
// with the scan's start), relative to the first. Empty with `note` set when a scan has none.
std::vector<Eigen::Isometry3d> KittiPoses(const std::vector<io::StampedPose>& truth,
                                          const std::vector<int64_t>& stamps, std::string* note) {
    std::map<int64_t, Eigen::Isometry3d> by_stamp;
    for (const io::StampedPose& p : truth) by_stamp[p.stamp_ns] = p.Pose();
    std::vector<Eigen::Isometry3d> poses;
    for (const int64_t t : stamps) {
        const auto it = by_stamp.find(t);
        if (it == by_stamp.end()) {
            *note = "no ground-truth pose at scan time " + io::FormatNsAsSeconds(t) +
                    ": poses.txt not written (ground_truth.tum is, for time-based matching)";
            return {};
        }
        poses.push_back(it->second);
    }
    const Eigen::Isometry3d first_inv = poses.front().inverse();
    for (Eigen::Isometry3d& T : poses) T = first_inv * T;
    return poses;
}

}  // namespace

CloudFolderExport WriteCloudFolder(const io::CaptureFiles& files, const std::string& format,
                                   const fs::path& dir,
                                   const capture::OusterCaptureOptions& options) {
    if (format != "pcd" && format != "ply" && format != "bin") {
        throw common::Error(StatusCode::kInvalidArgument,
                            "cloud format '" + format + "': expected pcd, ply or bin");
    }
    const ouster::SensorInfo info = capture::LoadRecordingInfo(files);
    capture::OusterCapture cap(files.packets, info, options);
    std::vector<odometry::ImuMeasurement> imu;
    cap.OnImu([&imu](const ouster::ImuSample& s) { imu.push_back(pipeline::ImuFromOuster(s)); });
    fs::create_directories(dir);
    CloudFolderExport out;
    std::string times;
    std::vector<int64_t> stamps;
    common::PointCloud cloud;
    while (const ouster::LidarFrame* frame = cap.NextFrame()) {
        ouster::ToPointCloud(*frame, &cloud);
        char name[32];
        std::snprintf(name, sizeof(name), "%06zu.%s", out.scans++, format.c_str());
        if (format == "pcd") {
            io::WritePcd(dir / name, cloud);
        } else if (format == "ply") {
            io::WritePly(dir / name, io::ToPly(cloud));
        } else {
            WriteKittiBin(dir / name, cloud);
        }
        times += io::FormatNsAsSeconds(cloud.stamp.ns) + "\n";
        stamps.push_back(cloud.stamp.ns);
    }
    if (out.scans == 0) {
        throw common::FileError(StatusCode::kNotFound, files.packets.string(), 0,
                                "no frames: nothing to export");
    }
    io::WriteFileAtomic(dir / "times.txt", times);
    if (!imu.empty()) {
        WriteImuCsv(dir / "imu.csv", imu);
        out.imu_samples = imu.size();
    }
    // A simulated capture's truth lies beside its capture.json.
    const fs::path truth = files.capture_json.empty()
                               ? fs::path()
                               : files.capture_json.parent_path() / "ground_truth.tum";
    if (!truth.empty() && fs::is_regular_file(truth)) {
        fs::copy_file(truth, dir / "ground_truth.tum", fs::copy_options::overwrite_existing);
        out.ground_truth = true;
        const std::vector<Eigen::Isometry3d> poses =
            KittiPoses(io::ReadTum(truth), stamps, &out.note);
        if (!poses.empty()) {
            io::WriteKitti(dir / "poses.txt", poses);
            out.kitti_poses = true;
        }
    }
    return out;
}

}  // namespace bimslam::replay
