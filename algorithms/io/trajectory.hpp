// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Trajectories in the TUM format ("t x y z qx qy qz qw" per line, seconds and metres;
// https://cvg.cit.tum.de/data/datasets/rgbd-dataset/file_formats) and the KITTI format (the 12
// numbers of the row-major 3x4 matrix per line, no time).
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace bimslam::io {

// A pose as a TUM line holds it: kept exactly as read (the quaternion is not renormalised) so that
// reading what was written gives back the same bits.
struct StampedPose {
    int64_t stamp_ns = 0;  // nanoseconds; TUM files hold seconds, parsed exactly
    Eigen::Vector3d translation = Eigen::Vector3d::Zero();
    Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();

    static StampedPose FromIsometry(int64_t stamp_ns, const Eigen::Isometry3d& T);
    // The rigid transform, with the quaternion normalised.
    Eigen::Isometry3d Pose() const;
};

// TUM: '#' comment lines and blank lines are skipped. Quaternions must be of unit length within
// 1e-3; timestamps must not decrease. Throws common::FileError naming the file
// and line on anything else.
std::vector<StampedPose> ReadTum(const std::filesystem::path& path);
std::vector<StampedPose> ParseTum(const std::string& name, std::string_view text);
// Writes exact seconds ("s.nnnnnnnnn") and shortest round-trip numbers; atomic.
void WriteTum(const std::filesystem::path& path, const std::vector<StampedPose>& poses);
std::string SerializeTum(const std::vector<StampedPose>& poses);
// One pose's line of it (SerializeTum is these lines in order).
void AppendTumLine(std::string& out, const StampedPose& pose);

// KITTI: every line exactly 12 finite numbers whose 3x3 part is a rotation within 1e-4 (it is
// re-orthonormalised on read).
std::vector<Eigen::Isometry3d> ReadKitti(const std::filesystem::path& path);
std::vector<Eigen::Isometry3d> ParseKitti(const std::string& name, std::string_view text);
void WriteKitti(const std::filesystem::path& path, const std::vector<Eigen::Isometry3d>& poses);
std::string SerializeKitti(const std::vector<Eigen::Isometry3d>& poses);
void AppendKittiLine(std::string& out, const Eigen::Isometry3d& T);

}  // namespace bimslam::io
