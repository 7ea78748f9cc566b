// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/mapping/map_inputs.hpp"

#include <algorithm>
#include <fstream>
#include <set>

#include "algorithms/common/status.hpp"
#include "drivers/ouster/metadata.hpp"
#include "host_tools/capture/ouster_capture.hpp"

namespace bimslam::mapping {
namespace fs = std::filesystem;
using common::FileError;
using common::StatusCode;

void CheckModelFile(const fs::path& model) {
    std::error_code ec;
    if (!fs::is_regular_file(model, ec)) {
        throw FileError(StatusCode::kNotFound, model.string(), 0, "no such file (the IFC model)");
    }
    // The header is within the first few kilobytes of any STEP file; the full parse (IFC++) comes
    // in the steps that need the geometry.
    std::ifstream in(model, std::ios::binary);
    std::string head(64 * 1024, '\0');
    in.read(head.data(), std::streamsize(head.size()));
    head.resize(size_t(in.gcount()));
    const size_t magic = head.find("ISO-10303-21;");
    const size_t first = head.find_first_not_of(" \t\r\n\xEF\xBB\xBF");
    if (magic == std::string::npos || magic != first) {
        throw FileError(StatusCode::kParseError, model.string(), 0,
                        "not an IFC model: no ISO-10303-21 (STEP) header");
    }
    std::string upper = head;
    std::transform(upper.begin(), upper.end(), upper.begin(), ::toupper);
    const size_t schema = upper.find("FILE_SCHEMA");
    const size_t end = upper.find(';', schema);
    if (schema == std::string::npos || end == std::string::npos ||
        upper.substr(schema, end - schema).find("'IFC") == std::string::npos) {
        throw FileError(StatusCode::kParseError, model.string(), 0,
                        "not an IFC model: its FILE_SCHEMA names no IFC schema");
    }
}

std::vector<RecordingInput> CheckRecordings(const std::vector<fs::path>& recordings) {
    std::vector<RecordingInput> out;
    std::set<std::string> used;
    for (const fs::path& r : recordings) {
        RecordingInput in;
        in.path = r;
        in.files = io::ResolveCapture(r);
        const ouster::SensorInfo info = capture::LoadRecordingInfo(in.files);
        // Throws naming the pcap when it holds no packet of this sensor's lidar packet size; and
        // a recording must give at least one frame (read up to the first, or to the end of a pcap
        // with none).
        capture::OusterCapture probe(in.files.packets, info);
        if (probe.NextFrame() == nullptr) {
            std::string ports;
            for (const auto& [port, n] : probe.stats().other_ports) {
                ports += (ports.empty() ? "" : ", ") + std::to_string(n) + " on port " +
                         std::to_string(port);
            }
            throw FileError(StatusCode::kParseError, in.files.packets.string(), 0,
                            "not an Ouster recording of the sensor in " + info.source +
                                ": no lidar frame on port " + std::to_string(probe.lidar_port()) +
                                (ports.empty() ? "" : " (UDP datagrams: " + ports + ")"));
        }
        const fs::path norm = r.lexically_normal();
        std::string name = in.files.folder
                               ? (norm.has_filename() ? norm.filename().string()
                                                      : norm.parent_path().filename().string())
                               : in.files.packets.stem().string();
        if (name.empty() || name == "." || name == "reference") name = "recording";
        std::string unique = name;
        for (int k = 2; !used.insert(unique).second; ++k) unique = name + "_" + std::to_string(k);
        in.name = unique;
        const fs::path dir = in.files.packets.parent_path();
        std::error_code ec;
        if (fs::is_regular_file(dir / "ground_truth.tum", ec))
            in.ground_truth = dir / "ground_truth.tum";
        if (fs::is_regular_file(dir / "changes.json", ec)) in.truth_changes = dir / "changes.json";
        out.push_back(std::move(in));
    }
    return out;
}

}  // namespace bimslam::mapping
