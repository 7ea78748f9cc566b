// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// PCD v0.7 point cloud files
// (https://pointclouds.org/documentation/tutorials/pcd_file_format.html), the keyframe cloud format
// of specs/session-data.md, readable by PCL, Open3D and CloudCompare.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "algorithms/common/point_cloud.hpp"

namespace bimslam::io {

enum class PcdEncoding { kAscii, kBinary };

// Writes FIELDS x y z (float32), then intensity (float32), ring (uint16) and t (float32 seconds
// since cloud.stamp) for the channels the cloud has, with the header lines PCL writes (VERSION 0.7,
// VIEWPOINT 0 0 0 1 0 0 0, HEIGHT 1). Binary data is packed per point (x y z intensity ring t,
// 22 bytes with every channel) and bit-exact on read-back; ASCII uses the shortest exact decimal
// (PCL itself prints 8 significant digits, which does not round-trip a float). `t` is float32 as
// the spec says, so time offsets read back exactly below 15.6 ms only; see PcdSecondsToNs.
// Non-finite coordinates or intensities and inconsistent channels are rejected. Atomic
// (io/file_util.hpp). Throws common::FileError naming the file.
void WritePcd(const std::filesystem::path& path, const common::PointCloud& cloud,
              PcdEncoding encoding = PcdEncoding::kBinary);

// Reads ascii, binary and binary_compressed (LZF, what pcl::io::savePCDFileBinaryCompressed
// writes) PCD v0.7, and the v0.6/v0.5 headers without VERSION/VIEWPOINT lines (COLUMNS for FIELDS;
// SIZE 4, TYPE F and COUNT 1 when those lines are missing). Needs fields x, y, z; reads intensity,
// ring and t when present, converting any numeric SIZE/TYPE (only the first element of a field
// with COUNT > 1); skips other fields (normal_x, rgb, "_" padding, COUNT > 1 descriptors).
//   t: a float field is seconds since the scan start (ours, Velodyne-style drivers), an integer
//      field nanoseconds (ouster-ros "t", uint32); both must lie in [0, 2^32) ns.
//   ring: must be an integer value in [0, 65535].
// PCD has no is_dense flag: PCL keeps NaN placeholders only in organized clouds (HEIGHT > 1), so
// points with a non-finite x, y or z are dropped when HEIGHT > 1 and are an error when HEIGHT is
// 1. Any other non-finite intensity or t of a kept point is an error. The result has cloud.stamp 0
// (PCD does not store it). Trailing bytes after binary data are ignored (as PCL does); extra
// points in an ASCII body are an error.
// Throws common::FileError naming the file and, for header and ASCII body errors, the line.
// A header that promises more data than the file holds is an error before anything is allocated.
common::PointCloud ReadPcd(const std::filesystem::path& path);

// The same from bytes in memory; `name` is used in messages (for fuzzing and tests). Serialize
// throws common::Error (kInvalidArgument) on a cloud WritePcd would reject.
common::PointCloud ParsePcd(const std::string& name, std::string_view bytes);
std::string SerializePcd(const common::PointCloud& cloud, PcdEncoding encoding);

// The conversions of the `t` field: float32 seconds from nanoseconds (nearest float), and
// nanoseconds from seconds (nearest ns). float32 has 24 significant bits, so the round trip is
// exact below 2^-6 s = 15.6 ms and within 2^-24 * t + 0.5 ns above (<= 7 ns below 0.25 s).
float PcdNsToSeconds(uint32_t time_offset_ns);
int64_t PcdSecondsToNs(double seconds);

}  // namespace bimslam::io
