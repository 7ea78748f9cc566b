// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include <algorithm>
#include <optional>

#include "algorithms/common/status.hpp"
#include "algorithms/io/file_util.hpp"
#include "algorithms/io/g2o.hpp"
#include "algorithms/io/pcd.hpp"
#include "algorithms/io/session.hpp"
#include "algorithms/io/text_reader.hpp"

namespace bimslam::io {
namespace {
using common::FileError;
using common::StatusCode;
namespace fs = std::filesystem;

// A line-oriented file of the session, parsed by `parse(name, text)`: required ones must exist;
// in a recovered (not strict) session a missing file holds zero keyframes. The writer appends
// to these files (AppendFile), so a power cut can leave a recovered session's file ending in part
// of a line: that part is dropped and said in `notes`. A complete session's files were synced
// before its session.json, and a line cut there is an error.
template <typename Parser>
auto ReadPart(const fs::path& path, bool strict, bool required, Parser parse,
              std::vector<std::string>& notes)
    -> std::optional<decltype(parse(std::string(), std::string_view()))> {
    if (!fs::exists(path)) {
        if (required) {
            throw FileError(StatusCode::kNotFound, path.string(), 0,
                            "missing (every complete session has it)");
        }
        return std::nullopt;
    }
    std::string text = ReadFileToString(path);
    if (!strict && !text.empty() && text.back() != '\n') {
        const size_t whole = text.rfind('\n') + 1;  // 0 when no line is whole (npos + 1)
        notes.push_back(path.filename().string() + ": dropped its last " +
                        std::to_string(text.size() - whole) +
                        " bytes, a line cut off before its end");
        text.resize(whole);
    }
    return parse(path.string(), text);
}

// Contiguous Scans/NNNNNN.pcd (or SCDs) files from 0.
size_t CountContiguous(const fs::path& dir, fs::path (*path_of)(const fs::path&, size_t)) {
    size_t n = 0;
    while (fs::exists(path_of(dir, n))) ++n;
    return n;
}

[[noreturn]] void CountMismatch(const fs::path& path, size_t found, size_t expected,
                                const std::string& unit) {
    // The line named is the first missing one, or the first one too many.
    throw FileError(StatusCode::kDataLoss, path.string(), std::min(found, expected) + 1,
                    "holds " + std::to_string(found) + " " + unit + ", session.json says " +
                        std::to_string(expected));
}
}  // namespace

std::vector<int64_t> ReadTimes(const fs::path& path) {
    return ParseTimes(path.string(), ReadFileToString(path));
}

std::vector<int64_t> ParseTimes(const std::string& name, std::string_view text) {
    LineReader r(name, text);
    std::vector<int64_t> out;
    std::string_view line;
    std::vector<std::string_view> tok;
    while (r.Next(line)) {
        LineReader::Split(line, tok);
        if (tok.size() != 1) {
            r.Fail("expected one timestamp (seconds), found " + std::to_string(tok.size()) +
                   " values");
        }
        out.push_back(r.ParseSecondsToNs(tok[0], "time"));
    }
    return out;
}

DescriptorMatrix ReadScd(const fs::path& path, int expected_rings, int expected_sectors) {
    const std::string text = ReadFileToString(path);
    LineReader r(path.string(), text);
    std::vector<std::vector<float>> rows;
    std::string_view line;
    std::vector<std::string_view> tok;
    while (r.Next(line)) {
        LineReader::Split(line, tok);
        if (tok.empty()) continue;
        if (!rows.empty() && tok.size() != rows[0].size()) {
            r.Fail("ring has " + std::to_string(tok.size()) + " sectors, the first ring has " +
                   std::to_string(rows[0].size()));
        }
        if (expected_sectors > 0 && tok.size() != static_cast<size_t>(expected_sectors)) {
            r.Fail("ring has " + std::to_string(tok.size()) + " sectors, expected " +
                   std::to_string(expected_sectors));
        }
        if (expected_rings > 0 && rows.size() == static_cast<size_t>(expected_rings)) {
            r.Fail("more than the expected " + std::to_string(expected_rings) + " rings");
        }
        std::vector<float>& row = rows.emplace_back();
        for (size_t c = 0; c < tok.size(); ++c) {
            row.push_back(r.ParseFloat(tok[c], "cell (" + std::to_string(rows.size() - 1) + ", " +
                                                   std::to_string(c) + ")"));
        }
    }
    if (rows.empty() || (expected_rings > 0 && rows.size() != size_t(expected_rings))) {
        throw FileError(StatusCode::kParseError, path.string(), r.line_number(),
                        "holds " + std::to_string(rows.size()) + " rings, expected " +
                            (expected_rings > 0 ? std::to_string(expected_rings) : "at least 1"));
    }
    DescriptorMatrix d(rows.size(), rows[0].size());
    for (size_t i = 0; i < rows.size(); ++i) {
        for (size_t c = 0; c < rows[i].size(); ++c) d(i, c) = rows[i][c];
    }
    return d;
}

Session ReadSession(const fs::path& dir, const SessionReadOptions& options) {
    if (!fs::is_directory(dir)) {
        throw FileError(StatusCode::kNotFound, dir.string(), 0, "no such session folder");
    }
    Session s;
    const fs::path manifest_path = dir / "session.json";
    s.complete = fs::exists(manifest_path);
    if (s.complete) {
        s.manifest = ParseManifest(manifest_path.string(), ReadFileToString(manifest_path));
    } else if (!options.allow_recovery) {
        throw FileError(StatusCode::kDataLoss, manifest_path.string(), 0,
                        "missing: the session was cut off before it was finished");
    }
    const bool strict = s.complete;
    const bool odom_required = strict && s.manifest.source == "rig";

    auto times = ReadPart(dir / "times.txt", strict, strict, ParseTimes, s.notes);
    auto world = ReadPart(dir / "optimized_poses.txt", strict, strict, ParseKitti, s.notes);
    auto odom = ReadPart(dir / "odom_poses.txt", strict, odom_required, ParseKitti, s.notes);
    auto graph = ReadPart(dir / "singlesession_posegraph.g2o", strict, strict, ParseG2o, s.notes);
    auto trajectory = ReadPart(dir / "trajectory.tum", strict, strict, ParseTum, s.notes);
    const size_t scans = CountContiguous(dir, KeyframeCloudPath);
    const size_t scds = CountContiguous(dir, KeyframeDescriptorPath);

    size_t n = 0;
    if (strict) {
        n = s.manifest.counts.keyframes;
        const auto check = [n](const fs::path& p, size_t found, const char* unit) {
            if (found != n) CountMismatch(p, found, n, unit);
        };
        check(dir / "times.txt", times->size(), "timestamps");
        check(dir / "optimized_poses.txt", world->size(), "poses");
        if (odom) check(dir / "odom_poses.txt", odom->size(), "poses");
        check(dir / "singlesession_posegraph.g2o", graph->vertices.size(), "vertices");
        if (scans != n) {
            throw FileError(
                StatusCode::kDataLoss, KeyframeCloudPath(dir, std::min(scans, n)).string(), 0,
                scans < n ? "missing: session.json says " + std::to_string(n) + " keyframes"
                          : "one keyframe cloud too many: session.json says " + std::to_string(n) +
                                " keyframes");
        }
        if (scds != n) {
            throw FileError(
                StatusCode::kDataLoss, KeyframeDescriptorPath(dir, std::min(scds, n)).string(), 0,
                scds < n ? "missing: session.json says " + std::to_string(n) + " keyframes"
                         : "one descriptor too many: session.json says " + std::to_string(n) +
                               " keyframes");
        }
        if (trajectory->size() != s.manifest.counts.scans) {
            CountMismatch(dir / "trajectory.tum", trajectory->size(), s.manifest.counts.scans,
                          "scan poses");
        }
    } else {
        // A keyframe is complete when every file holds it; the writer's order makes that a prefix.
        n = std::min({times ? times->size() : 0, world ? world->size() : 0,
                      graph ? graph->vertices.size() : 0, scans, scds});
        if (odom) n = std::min(n, odom->size());
        s.notes.push_back("session.json is missing: recovered " + std::to_string(n) +
                          " complete keyframes (of " + std::to_string(std::max(scans, scds)) +
                          " keyframe files found)");
    }

    int rings = strict ? s.manifest.descriptor.rings : 0;
    int sectors = strict ? s.manifest.descriptor.sectors : 0;
    s.keyframes.resize(n);
    for (size_t i = 0; i < n; ++i) {
        SessionKeyframe& kf = s.keyframes[i];
        kf.stamp_ns = (*times)[i];
        kf.T_world_lidar = (*world)[i];
        if (odom) kf.T_odom_lidar = (*odom)[i];
        kf.descriptor = ReadScd(KeyframeDescriptorPath(dir, i), rings, sectors);
        rings = static_cast<int>(kf.descriptor.rows());  // recovered sessions: the first decides
        sectors = static_cast<int>(kf.descriptor.cols());
        if (options.load_clouds) {
            kf.cloud = ReadPcd(KeyframeCloudPath(dir, i));
            kf.cloud.stamp = common::SensorTime{kf.stamp_ns};  // per-point t counts from here
        }
    }
    if (graph) {
        for (const SessionEdge& e : graph->edges) {
            if (e.from < n && e.to < n) s.edges.push_back(e);
        }
        if (s.edges.size() != graph->edges.size()) {
            s.notes.push_back("dropped " + std::to_string(graph->edges.size() - s.edges.size()) +
                              " edges to keyframes that were not recovered");
        }
    }
    if (trajectory) s.trajectory = std::move(*trajectory);
    if (!strict) {
        s.manifest.counts.keyframes = n;
        s.manifest.counts.scans = s.trajectory.size();
        if (n > 0) {
            s.manifest.descriptor.rings = rings;
            s.manifest.descriptor.sectors = sectors;
        }
    }
    return s;
}

}  // namespace bimslam::io
