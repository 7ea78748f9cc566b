// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// A recording written as a folder of per-scan point clouds (cloud_folder.hpp's layout), with
// everything a peer odometry needs to run on exactly the input `bimslam odometry` sees and to be
// scored against the same truth (issue 17: "a benchmark mode that writes exactly what a peer
// odometry needs"):
//   DIR/000000.{pcd,ply,bin}  one file a frame of the recording, in the sensor frame; PCD and
//                              PLY carry intensity, ring and per-point time `t` (float32
//                              seconds since the scan start), KITTI .bin only x y z intensity;
//   DIR/times.txt              the scan starts, seconds, sensor clock (one a line);
//   DIR/imu.csv                the Ouster IMU in the sensor frame, when the recording has one
//                              (t_s, gyro rad/s, accel m/s^2; imu_csv.hpp);
//   DIR/ground_truth.tum       a simulated capture's ground truth, T_world_sensor at each scan
//                              start (TUM: t x y z qx qy qz qw), copied;
//   DIR/poses.txt              the same as KITTI odometry's poses (3x4 row-major, the first
//                              scan's frame as the origin), one a scan, when every scan has a
//                              ground-truth pose at its start.
// `bimslam odometry DIR` reads the folder back (its IMU too), which the tests use to prove that
// the export loses nothing the odometry needs.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>

#include "algorithms/common/point_cloud.hpp"
#include "algorithms/io/capture_files.hpp"
#include "host_tools/capture/ouster_capture.hpp"

namespace bimslam::replay {

struct CloudFolderExport {
    size_t scans = 0;
    size_t imu_samples = 0;
    bool ground_truth = false;  // ground_truth.tum copied
    bool kitti_poses = false;   // poses.txt written
    std::string note;           // why poses.txt is missing, when ground truth exists
};

// `format` is "pcd", "ply" or "bin". Throws common::Error (bad format) or FileError naming the
// file (unreadable recording, a recording without frames, a folder that cannot be written).
CloudFolderExport WriteCloudFolder(const io::CaptureFiles& recording, const std::string& format,
                                   const std::filesystem::path& dir,
                                   const capture::OusterCaptureOptions& options = {});

// A KITTI velodyne .bin: float32 x y z intensity per point, little-endian.
void WriteKittiBin(const std::filesystem::path& path, const common::PointCloud& cloud);

}  // namespace bimslam::replay
