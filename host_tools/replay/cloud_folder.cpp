// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/replay/cloud_folder.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <set>

#include "algorithms/common/status.hpp"
#include "algorithms/io/file_util.hpp"
#include "algorithms/io/pcd.hpp"
#include "algorithms/io/ply.hpp"
#include "algorithms/io/session.hpp"

namespace bimslam::replay {
namespace fs = std::filesystem;
using common::FileError;
using common::StatusCode;

namespace {
bool IsCloudFile(const fs::path& p) {
    const std::string e = p.extension().string();
    return e == ".pcd" || e == ".ply" || e == ".bin";
}
}  // namespace

bool IsCloudFolder(const fs::path& dir) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec) || fs::exists(dir / "lidar.pcap", ec)) return false;
    for (const auto& entry : fs::directory_iterator(dir, ec)) {
        if (entry.is_regular_file(ec) && IsCloudFile(entry.path())) return true;
    }
    return false;
}

CloudFolder ResolveCloudFolder(const fs::path& dir) {
    CloudFolder f;
    f.dir = dir;
    std::set<std::string> extensions;
    for (const auto& entry : fs::directory_iterator(dir)) {
        if (entry.is_regular_file() && IsCloudFile(entry.path())) {
            f.scans.push_back(entry.path());
            extensions.insert(entry.path().extension().string());
        }
    }
    if (f.scans.empty()) {
        throw FileError(StatusCode::kNotFound, dir.string(), 0,
                        "no .pcd, .ply or .bin scans in the folder");
    }
    if (extensions.size() > 1) {
        std::string list;
        for (const std::string& e : extensions) list += (list.empty() ? "" : ", ") + e;
        throw FileError(StatusCode::kInvalidArgument, dir.string(), 0,
                        "mixes scan formats (" + list + "): one format a folder");
    }
    f.extension = *extensions.begin();
    std::sort(f.scans.begin(), f.scans.end());
    const fs::path here = dir / "times.txt";
    const fs::path parent = dir.lexically_normal().parent_path() / "times.txt";
    if (fs::is_regular_file(here)) {
        f.times = here;
    } else if (!dir.lexically_normal().filename().empty() && fs::is_regular_file(parent)) {
        f.times = parent;
    } else {
        throw FileError(StatusCode::kNotFound, here.string(), 0,
                        "missing: a folder of " + std::to_string(f.scans.size()) +
                            " scans needs a times file (one time in seconds a line, the scan's "
                            "start), here or as " +
                            parent.string());
    }
    // The IMU file sits where the times file was found (KITTI-style layouts keep both in the
    // sequence folder).
    if (fs::is_regular_file(f.times.parent_path() / "imu.csv")) {
        f.imu = f.times.parent_path() / "imu.csv";
    }
    f.stamps_ns = io::ReadTimes(f.times);
    if (f.stamps_ns.size() != f.scans.size()) {
        throw FileError(StatusCode::kParseError, f.times.string(), 0,
                        std::to_string(f.stamps_ns.size()) + " times for the " +
                            std::to_string(f.scans.size()) + " " + f.extension + " scans of " +
                            dir.string() + ": expected one time a scan");
    }
    for (size_t i = 1; i < f.stamps_ns.size(); ++i) {
        if (f.stamps_ns[i] <= f.stamps_ns[i - 1]) {
            throw FileError(StatusCode::kParseError, f.times.string(), i + 1,
                            "times must increase (one scan after the other)");
        }
    }
    return f;
}

common::PointCloud ReadKittiBin(const fs::path& path) {
    const std::string bytes = io::ReadFileToString(path);
    if (bytes.size() % 16 != 0) {
        throw FileError(StatusCode::kParseError, path.string(), 0,
                        std::to_string(bytes.size()) +
                            " bytes: not a KITTI scan (float32 x y z reflectance, 16 bytes a "
                            "point)");
    }
    common::PointCloud cloud;
    const size_t n = bytes.size() / 16;
    cloud.Resize(n, /*with_intensity=*/true, false, false);
    for (size_t i = 0; i < n; ++i) {
        float v[4];
        std::memcpy(v, bytes.data() + 16 * i, 16);
        if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) {
            throw FileError(StatusCode::kParseError, path.string(), 0,
                            "point " + std::to_string(i) + " is not finite");
        }
        cloud.xyz[i] = Eigen::Vector3f(v[0], v[1], v[2]);
        cloud.intensity[i] = v[3];
    }
    return cloud;
}

common::PointCloud ReadScanCloud(const CloudFolder& folder, size_t index) {
    const fs::path& path = folder.scans.at(index);
    common::PointCloud cloud;
    if (folder.extension == ".pcd") {
        cloud = io::ReadPcd(path);
    } else if (folder.extension == ".ply") {
        try {
            cloud = io::PointCloudFromPly(io::ReadPly(path));
        } catch (const FileError&) {
            throw;
        } catch (const common::Error& e) {
            throw FileError(e.code(), path.string(), 0, e.what());
        }
    } else {
        cloud = ReadKittiBin(path);
    }
    cloud.stamp.ns = folder.stamps_ns[index];
    cloud.frame = "lidar";
    return cloud;
}

}  // namespace bimslam::replay
