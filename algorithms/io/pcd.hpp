// PCD v0.7 point cloud files (https://pointclouds.org/documentation/tutorials/pcd_file_format.html),
// the keyframe cloud format of specs/session-data.md, readable by PCL, Open3D and CloudCompare.
#pragma once

#include <filesystem>
#include <string>

#include "algorithms/common/point_cloud.hpp"

namespace bimslam::io {

enum class PcdEncoding { kAscii, kBinary };

// Writes FIELDS x y z (float32), then intensity (float32), ring (uint16) and t (float32 seconds
// since cloud.stamp) for the channels the cloud has. Binary output is bit-exact on read-back;
// ASCII uses the shortest exact decimal. Atomic (io/file_util.hpp). Throws common::FileError.
void WritePcd(const std::filesystem::path& path, const common::PointCloud& cloud,
              PcdEncoding encoding = PcdEncoding::kBinary);

// Reads ascii and binary PCD v0.7 (and the v0.6 header without VERSION/VIEWPOINT lines). Needs
// fields x, y, z; reads intensity, ring and t when present, converting any numeric SIZE/TYPE;
// skips other fields (normal_x, rgb, "_" padding, COUNT > 1). Points with a non-finite xyz are
// dropped only when the header says the cloud is not dense; in a dense cloud they are an error.
// Throws common::FileError naming the file and, for header and ASCII body errors, the line.
// binary_compressed is rejected with a clear message.
common::PointCloud ReadPcd(const std::filesystem::path& path);

// The same from bytes in memory; `name` is used in messages (for fuzzing and tests).
common::PointCloud ParsePcd(const std::string& name, std::string_view bytes);
std::string SerializePcd(const common::PointCloud& cloud, PcdEncoding encoding);

}  // namespace bimslam::io
