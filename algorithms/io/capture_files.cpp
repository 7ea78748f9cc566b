// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/io/capture_files.hpp"

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "algorithms/common/se3.hpp"
#include "algorithms/common/status.hpp"

namespace bimslam::io {
namespace fs = std::filesystem;
using common::FileError;
using common::StatusCode;

CaptureFiles ResolveCapture(const fs::path& recording, const fs::path& metadata) {
    if (!metadata.empty() && !fs::is_regular_file(metadata)) {
        throw FileError(StatusCode::kNotFound, metadata.string(), 0, "no such metadata file");
    }
    CaptureFiles f;
    f.metadata = metadata;
    if (fs::is_directory(recording)) {
        f.folder = true;
        f.packets = recording / "lidar.pcap";
        if (f.metadata.empty()) f.metadata = recording / "metadata.json";
        for (const fs::path& p : {f.packets, f.metadata}) {
            if (!fs::is_regular_file(p)) {
                throw FileError(StatusCode::kNotFound, p.string(), 0,
                                "missing (a capture folder holds lidar.pcap and metadata.json; "
                                "or give a pcap with its metadata JSON beside it, or a ROS bag)");
            }
        }
        if (fs::is_regular_file(recording / "go1_can.log")) f.can_log = recording / "go1_can.log";
        if (fs::is_regular_file(recording / "capture.json")) {
            f.capture_json = recording / "capture.json";
        }
        return f;
    }
    if (!fs::is_regular_file(recording)) {
        throw FileError(StatusCode::kNotFound, recording.string(), 0,
                        "no such file or folder (expected a capture folder, a pcap with its "
                        "metadata JSON, or a ROS bag)");
    }
    f.packets = recording;
    // A bag carries its metadata as a topic (read by whoever opens the bag).
    f.bag = recording.extension() == ".bag";
    if (f.bag || !f.metadata.empty()) return f;
    // x.pcap -> x.json (x.pcap.gz -> x.json too), as the Ouster tools save them.
    fs::path stem = recording;
    if (stem.extension() == ".gz") stem.replace_extension();
    const fs::path beside = fs::path(stem).replace_extension(".json");
    const fs::path folder = recording.parent_path() / "metadata.json";
    for (const fs::path& candidate : {beside, folder}) {
        if (fs::is_regular_file(candidate)) {
            f.metadata = candidate;
            return f;
        }
    }
    throw FileError(StatusCode::kNotFound, recording.string(), 0,
                    "no metadata: looked for " + beside.string() + " and " + folder.string());
}

std::optional<Eigen::Isometry3d> ReadCaptureMount(const fs::path& path) {
    std::ifstream in(path);
    if (!in) return std::nullopt;
    std::stringstream text;
    text << in.rdbuf();
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(text.str());
    } catch (const nlohmann::json::exception& e) {
        throw FileError(StatusCode::kParseError, path.string(), 0, e.what());
    }
    const auto sensor = j.find("sensor");
    if (sensor == j.end() || !sensor->is_object() || !sensor->contains("T_base_sensor")) {
        return std::nullopt;
    }
    const nlohmann::json& m = (*sensor)["T_base_sensor"];
    if (!m.is_array() || m.size() != 16 ||
        !std::all_of(m.begin(), m.end(), [](const auto& x) { return x.is_number(); })) {
        throw FileError(StatusCode::kParseError, path.string(), 0,
                        "sensor.T_base_sensor: expected 16 numbers (row-major 4x4)");
    }
    Eigen::Matrix4d M;
    for (int i = 0; i < 16; ++i) M(i / 4, i % 4) = m[size_t(i)].get<double>();
    Eigen::Isometry3d T;
    T.matrix() = M;
    if (!common::IsValidRigid(T, 1e-6)) {
        throw FileError(StatusCode::kParseError, path.string(), 0,
                        "sensor.T_base_sensor is not a rigid transform");
    }
    return T;
}

}  // namespace bimslam::io
