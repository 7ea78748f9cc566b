// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// session.json (specs/session-data.md): every field checked on read, with the field named.
#include <cstdint>
#include <nlohmann/json.hpp>

#include "algorithms/common/status.hpp"
#include "algorithms/io/session.hpp"

namespace bimslam::io {
namespace {
using common::FileError;
using common::StatusCode;
using nlohmann::json;

// A field lookup that names the file and the dotted field path in its errors.
class Fields {
public:
    Fields(const std::string& file, const json& root) : file_(file), root_(root) {}

    const json& At(const std::string& path, json::value_t type) const {
        const json* node = &root_;
        size_t start = 0;
        while (start <= path.size()) {
            const size_t dot = std::min(path.find('.', start), path.size());
            const std::string key = path.substr(start, dot - start);
            if (!node->is_object() || !node->contains(key)) Fail(path, "is missing");
            node = &(*node)[key];
            start = dot + 1;
        }
        const bool number_ok = type == json::value_t::number_float && node->is_number();
        const bool uint_ok = type == json::value_t::number_unsigned && node->is_number_unsigned();
        if (node->type() != type && !number_ok && !uint_ok) {
            Fail(path, std::string("must be a ") + json(type).type_name() + ", not " +
                           node->type_name() + " " + Short(*node));
        }
        return *node;
    }
    std::string String(const std::string& path) const {
        return At(path, json::value_t::string).get<std::string>();
    }
    double Number(const std::string& path) const {
        return At(path, json::value_t::number_float).get<double>();
    }
    int64_t Unsigned(const std::string& path) const {
        const json& n = At(path, json::value_t::number_unsigned);
        if (n.get<uint64_t>() > (uint64_t{1} << 53)) Fail(path, "is implausibly large");
        return static_cast<int64_t>(n.get<uint64_t>());
    }
    bool Has(const std::string& key) const { return root_.contains(key); }

    [[noreturn]] void Fail(const std::string& path, const std::string& what) const {
        throw FileError(StatusCode::kParseError, file_, 0, "field '" + path + "' " + what);
    }

private:
    static std::string Short(const json& n) {
        std::string s = n.dump();
        return s.size() > 40 ? s.substr(0, 40) + "..." : s;
    }
    const std::string& file_;
    const json& root_;
};

size_t LineOfByte(const std::string& text, size_t byte) {
    size_t line = 1;
    for (size_t i = 0; i < std::min(byte, text.size()); ++i) line += text[i] == '\n';
    return line;
}
}  // namespace

std::string SerializeManifest(const SessionManifest& m) {
    json j;
    j["format"] = "bimslam-session";
    j["version"] = kSessionFormatVersion;
    j["source"] = m.source;
    j["created"] = m.created;
    j["sensor"] = {{"model", m.sensor.model},
                   {"beams", m.sensor.beams},
                   {"columns", m.sensor.columns},
                   {"metadata_file", m.sensor.metadata_file}};
    j["frames"] = {{"world", m.world_frame}};
    j["keyframe"] = {{"distance_m", m.keyframe.distance_m}, {"angle_deg", m.keyframe.angle_deg}};
    j["descriptor"] = {{"kind", m.descriptor.kind},
                       {"rings", m.descriptor.rings},
                       {"sectors", m.descriptor.sectors},
                       {"max_radius_m", m.descriptor.max_radius_m}};
    if (m.descriptor.kind == "indoor") {
        j["descriptor"]["cell_rule"] = {{"min_points", m.descriptor.min_points},
                                        {"min_z_span_m", m.descriptor.min_z_span_m},
                                        {"rule", m.descriptor.cell_rule}};
    }
    j["counts"] = {{"keyframes", m.counts.keyframes}, {"scans", m.counts.scans}};
    if (m.model) {
        j["model"] = {
            {"file", m.model->file}, {"sha256", m.model->sha256}, {"storeys", m.model->storeys}};
    }
    if (m.host_minus_sensor_ns) j["clocks"] = {{"host_minus_sensor_ns", *m.host_minus_sensor_ns}};
    return j.dump(2) + "\n";
}

SessionManifest ParseManifest(const std::string& name, const std::string& text) {
    json j;
    try {
        j = json::parse(text);
    } catch (const json::parse_error& e) {
        throw FileError(StatusCode::kParseError, name, LineOfByte(text, e.byte),
                        "not valid JSON (" + std::string(e.what()) + ")");
    }
    if (!j.is_object()) {
        throw FileError(StatusCode::kParseError, name, 0, "must hold a JSON object");
    }
    const Fields f(name, j);
    if (f.String("format") != "bimslam-session") {
        f.Fail("format", "is '" + f.String("format") + "', not 'bimslam-session'");
    }
    const int64_t version = f.Unsigned("version");
    if (version < 1 || version > kSessionFormatVersion) {
        f.Fail("version", "is " + std::to_string(version) + "; this build reads 1 to " +
                              std::to_string(kSessionFormatVersion));
    }
    SessionManifest m;
    m.source = f.String("source");
    if (m.source != "rig" && m.source != "bim" && m.source != "simulation") {
        f.Fail("source", "is '" + m.source + "', not one of rig, bim, simulation");
    }
    m.created = f.String("created");
    m.sensor.model = f.String("sensor.model");
    m.sensor.beams = static_cast<int>(f.Unsigned("sensor.beams"));
    m.sensor.columns = static_cast<int>(f.Unsigned("sensor.columns"));
    m.sensor.metadata_file = f.String("sensor.metadata_file");
    m.world_frame = f.String("frames.world");
    m.keyframe.distance_m = f.Number("keyframe.distance_m");
    m.keyframe.angle_deg = f.Number("keyframe.angle_deg");
    m.descriptor.kind = f.String("descriptor.kind");
    if (m.descriptor.kind != "indoor" && m.descriptor.kind != "outdoor") {
        f.Fail("descriptor.kind", "is '" + m.descriptor.kind + "', not indoor or outdoor");
    }
    m.descriptor.rings = static_cast<int>(f.Unsigned("descriptor.rings"));
    m.descriptor.sectors = static_cast<int>(f.Unsigned("descriptor.sectors"));
    if (m.descriptor.rings < 1 || m.descriptor.rings > 1000) {
        f.Fail("descriptor.rings", "must be in [1, 1000]");
    }
    if (m.descriptor.sectors < 1 || m.descriptor.sectors > 3600) {
        f.Fail("descriptor.sectors", "must be in [1, 3600]");
    }
    m.descriptor.max_radius_m = f.Number("descriptor.max_radius_m");
    if (m.descriptor.kind == "indoor") {
        m.descriptor.min_points = static_cast<int>(f.Unsigned("descriptor.cell_rule.min_points"));
        m.descriptor.min_z_span_m = f.Number("descriptor.cell_rule.min_z_span_m");
        const json& rule = j["descriptor"]["cell_rule"];
        m.descriptor.cell_rule =
            rule.contains("rule") ? f.String("descriptor.cell_rule.rule") : std::string("z_span");
        if (m.descriptor.cell_rule != "z_span" && m.descriptor.cell_rule != "z_stack") {
            f.Fail("descriptor.cell_rule.rule",
                   "is '" + m.descriptor.cell_rule + "', not z_span or z_stack");
        }
    }
    m.counts.keyframes = static_cast<size_t>(f.Unsigned("counts.keyframes"));
    m.counts.scans = static_cast<size_t>(f.Unsigned("counts.scans"));
    if (f.Has("model")) {
        SessionManifest::Model model;
        model.file = f.String("model.file");
        model.sha256 = f.String("model.sha256");
        for (const json& s : f.At("model.storeys", json::value_t::array)) {
            if (!s.is_string()) f.Fail("model.storeys", "must hold strings");
            model.storeys.push_back(s.get<std::string>());
        }
        m.model = model;
    }
    if (f.Has("clocks")) {
        const json& ns = f.At("clocks.host_minus_sensor_ns", json::value_t::number_float);
        if (!ns.is_number_integer() ||
            (ns.is_number_unsigned() && ns.get<uint64_t>() > uint64_t(INT64_MAX))) {
            f.Fail("clocks.host_minus_sensor_ns", "must be an integer of nanoseconds");
        }
        m.host_minus_sensor_ns = ns.get<int64_t>();
    }
    return m;
}

}  // namespace bimslam::io
