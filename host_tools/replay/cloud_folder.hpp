// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// A folder of per-scan point clouds, the shape of public data sets (KITTI odometry's
// velodyne/*.bin, per-scan PCD or PLY exports), read as a recording for `bimslam odometry`:
//   DIR/ holds the scans, one file each, all .pcd, all .ply or all .bin (KITTI: float32 x y z
//   reflectance per point), in name order; and a times file: DIR/times.txt, else times.txt in
//   DIR's parent (KITTI: sequences/NN/velodyne/ beside sequences/NN/times.txt), one time in
//   seconds a line (the scan's start), line i for the i-th scan.
// An IMU file, imu.csv (imu_csv.hpp), in DIR or its parent, is the folder's IMU when present.
// Per-point time is used when the files have it (PCD/PLY field `t`: float seconds or integer
// nanoseconds since the scan start, io/pcd.hpp); otherwise the scans cannot be deskewed, and
// the caller says so. Readers are algorithms/io's; only the folder's layout is here.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "algorithms/common/point_cloud.hpp"

namespace bimslam::replay {

struct CloudFolder {
    std::filesystem::path dir;
    std::vector<std::filesystem::path> scans;  // name order
    std::vector<int64_t> stamps_ns;            // one per scan
    std::filesystem::path times;               // the times file read
    std::string extension;                     // ".pcd", ".ply" or ".bin"
    std::filesystem::path imu;                 // imu.csv, empty when there is none
};

// True for a folder that is not a capture folder (no lidar.pcap) and holds .pcd, .ply or .bin
// files. Reads the directory only.
bool IsCloudFolder(const std::filesystem::path& dir);

// Lists the scans and reads the times. Throws common::FileError naming the file: a missing times
// file (naming both places looked at), a times file of another length than the scans, times
// that decrease, a folder mixing formats.
CloudFolder ResolveCloudFolder(const std::filesystem::path& dir);

// One scan, stamped with its time; per-point time kept when the file has it. Throws
// common::FileError naming the file.
common::PointCloud ReadScanCloud(const CloudFolder& folder, size_t index);

// A KITTI velodyne .bin: float32 x y z reflectance per point, little-endian.
common::PointCloud ReadKittiBin(const std::filesystem::path& path);

}  // namespace bimslam::replay
