// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/localization/rig_map.hpp"

#include <zlib.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>
#include <optional>

#include "algorithms/common/status.hpp"
#include "algorithms/io/file_util.hpp"

namespace bimslam::localization {
namespace {
using common::FileError;
using common::StatusCode;
using nlohmann::json;

// Every number is little-endian (README, "The rig map format"); so are the targets.
static_assert(std::endian::native == std::endian::little, "the rig map is little-endian");

constexpr char kMagic[8] = {'B', 'S', 'R', 'I', 'G', 'M', 'A', 'P'};
constexpr size_t kHeaderBytes = 32;
constexpr size_t kSectionHeaderBytes = 16;
constexpr size_t kKeyframeBytes = 64;  // 7 doubles (t xyz, q wxyz), int32 storey, 4 reserved
constexpr size_t kSurfelBytes = 68;

constexpr uint32_t Tag(const char (&s)[5]) {
    return uint32_t(uint8_t(s[0])) | uint32_t(uint8_t(s[1])) << 8 | uint32_t(uint8_t(s[2])) << 16 |
           uint32_t(uint8_t(s[3])) << 24;
}

[[noreturn]] void Invalid(const std::string& what) {
    throw common::Error(StatusCode::kInvalidArgument, "rig map: " + what);
}

uint32_t Crc32(std::string_view bytes) {
    uLong crc = crc32(0L, Z_NULL, 0);
    // zlib takes uInt lengths: 1 GiB at a time.
    for (size_t at = 0; at < bytes.size(); at += size_t(1) << 30) {
        const size_t n = std::min(bytes.size() - at, size_t(1) << 30);
        crc = crc32(crc, reinterpret_cast<const Bytef*>(bytes.data() + at), uInt(n));
    }
    return uint32_t(crc);
}

template <typename T>
void Append(std::string& out, T v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof v);
    out.append(b, sizeof b);
}

void AppendSection(std::string& out, uint32_t tag, const std::string& payload) {
    Append(out, tag);
    Append(out, uint32_t(0));
    Append(out, uint64_t(payload.size()));
    out += payload;
    out.append((8 - payload.size() % 8) % 8, '\0');  // the next section 8-byte aligned
}

json MetaJson(const RigMap& m) {
    json storeys = json::array();
    for (const RigMapStorey& s : m.storeys) {
        storeys.push_back(
            {{"name", s.name}, {"global_id", s.global_id}, {"elevation_m", s.elevation_m}});
    }
    json levels = json::array();
    for (const registration::SurfelMap& l : m.levels) {
        levels.push_back({{"voxel_size_m", l.config().voxel_size},
                          {"min_points", l.config().min_points},
                          {"max_thickness_m", l.config().max_thickness},
                          {"surfels", l.size()}});
    }
    const io::SessionManifest::Descriptor& d = m.descriptor;
    return {{"format", "bimslam-rig-map"},
            {"version", kRigMapVersion},
            {"model", {{"file", m.model_file}, {"sha256", m.model_sha256}}},
            {"frame", m.frame},
            {"created", m.created},
            {"reference", m.reference},
            {"sensor",
             {{"model", m.sensor.model}, {"beams", m.sensor.beams}, {"columns", m.sensor.columns}}},
            {"descriptor",
             {{"kind", d.kind},
              {"rings", d.rings},
              {"sectors", d.sectors},
              {"max_radius_m", d.max_radius_m},
              {"min_points", d.min_points},
              {"min_z_span_m", d.min_z_span_m},
              {"cell_rule", d.cell_rule}}},
            {"storeys", storeys},
            {"keyframes", m.keyframes.size()},
            {"levels", levels}};
}

// SPAC: [{"name", "global_id", "storey", "z": [min, max], "xy": [x, y, x, y, ...]}, ...].
json SpacesJson(const RigMap& m) {
    json spaces = json::array();
    for (const RigMapSpace& s : m.spaces) {
        json xy = json::array();
        for (const Eigen::Vector2f& v : s.triangles) {
            xy.push_back(v.x());
            xy.push_back(v.y());
        }
        spaces.push_back({{"name", s.name},
                          {"global_id", s.global_id},
                          {"storey", s.storey},
                          {"z", {s.z_min, s.z_max}},
                          {"xy", xy}});
    }
    return spaces;
}

void CheckMap(const RigMap& m) {
    m.DescriptorConfig().Validate();  // throws common::Error naming the field
    const size_t n = m.keyframes.size();
    if (m.keyframe_storey.size() != n || m.descriptors.size() != n) {
        Invalid(std::to_string(n) + " keyframes, " + std::to_string(m.keyframe_storey.size()) +
                " storeys of keyframes and " + std::to_string(m.descriptors.size()) +
                " descriptors");
    }
    for (size_t k = 0; k < n; ++k) {
        if (!m.keyframes[k].matrix().allFinite()) Invalid("keyframe " + std::to_string(k));
        const int32_t s = m.keyframe_storey[k];
        if (s < -1 || s >= int32_t(m.storeys.size())) {
            Invalid("keyframe " + std::to_string(k) + ": storey " + std::to_string(s));
        }
        const scancontext::Descriptor& d = m.descriptors[k];
        if (d.rows() != m.descriptor.rings || d.cols() != m.descriptor.sectors) {
            Invalid("descriptor " + std::to_string(k) + " is not " +
                    std::to_string(m.descriptor.rings) + " x " +
                    std::to_string(m.descriptor.sectors));
        }
    }
    for (const registration::SurfelMap& l : m.levels) {
        if (!l.built()) Invalid("a surfel level is not built");
    }
    for (const RigMapSpace& s : m.spaces) {
        if (s.triangles.size() % 3 != 0 || s.storey < -1 || s.storey >= int32_t(m.storeys.size())) {
            Invalid("space '" + s.name + "': bad triangles or storey");
        }
    }
}

std::string KeyframesPayload(const RigMap& m) {
    std::string p;
    p.reserve(m.keyframes.size() * kKeyframeBytes);
    for (size_t k = 0; k < m.keyframes.size(); ++k) {
        const Eigen::Vector3d t = m.keyframes[k].translation();
        const Eigen::Quaterniond q(m.keyframes[k].rotation());
        for (const double v : {t.x(), t.y(), t.z(), q.w(), q.x(), q.y(), q.z()}) Append(p, v);
        Append(p, m.keyframe_storey[k]);
        Append(p, uint32_t(0));
    }
    return p;
}

std::string DescriptorsPayload(const RigMap& m) {
    std::string p;
    for (const scancontext::Descriptor& d : m.descriptors) {
        p.append(reinterpret_cast<const char*>(d.data()), size_t(d.size()) * sizeof(float));
    }
    return p;
}

std::string SurfelsPayload(const registration::SurfelMap& l) {
    std::string p;
    p.reserve(8 + l.size() * kSurfelBytes);
    Append(p, uint64_t(l.size()));
    for (size_t i = 0; i < l.size(); ++i) {
        const registration::Surfel& s = l.surfels()[i];
        const registration::SurfelMap::Place& at = l.places()[i];
        Append(p, at.key);
        Append(p, s.points);
        Append(p, at.bin);
        Append(p, uint8_t(s.porous ? 1 : 0));  // a padding byte before stop 74: 0, not porous
        p.append(2, '\0');
        for (const float v : {s.normal.x(), s.normal.y(), s.normal.z(), s.offset, s.centroid.x(),
                              s.centroid.y(), s.centroid.z(), s.thickness, s.axis.x(), s.axis.y(),
                              s.axis.z(), s.spread[0], s.spread[1]}) {
            Append(p, v);
        }
    }
    return p;
}

// Reads what the sections hold, each check naming the byte it is at.
class Parser {
public:
    Parser(const std::string& name, std::string_view bytes) : name_(name), bytes_(bytes) {}

    RigMap Parse();

private:
    [[noreturn]] void Fail(size_t at, const std::string& what) const {
        throw FileError(StatusCode::kParseError, name_, 0,
                        "at byte " + std::to_string(at) + ": " + what);
    }
    template <typename T>
    T Load(size_t at) const {
        T v;
        std::memcpy(&v, bytes_.data() + at, sizeof v);
        return v;
    }
    void CheckHeader() const;
    void ReadSections();
    void ReadMeta(RigMap& m) const;
    void ReadKeyframes(RigMap& m) const;
    void ReadDescriptors(RigMap& m) const;
    void ReadLevels(RigMap& m) const;
    void ReadSpaces(RigMap& m) const;
    std::string_view Section(uint32_t tag, size_t index = 0, size_t* at = nullptr) const;

    struct Entry {
        uint32_t tag;
        size_t at;  // payload's first byte
        size_t size;
    };
    std::string name_;
    std::string_view bytes_;
    std::vector<Entry> sections_;
    json meta_;
};

void Parser::CheckHeader() const {
    if (bytes_.size() < kHeaderBytes) {
        Fail(0, "the file holds " + std::to_string(bytes_.size()) +
                    " bytes: too short for a rig map's " + std::to_string(kHeaderBytes) +
                    "-byte header");
    }
    if (std::memcmp(bytes_.data(), kMagic, sizeof kMagic) != 0) {
        Fail(0, "not a bimslam rig map (the first 8 bytes are not \"BSRIGMAP\")");
    }
    if (Load<uint32_t>(28) != Crc32(bytes_.substr(0, 28)))
        Fail(28, "the header is damaged (CRC-32)");
    const uint32_t version = Load<uint32_t>(8);
    if (version != kRigMapVersion) {
        Fail(8, "rig map version " + std::to_string(version) + "; this build reads version " +
                    std::to_string(kRigMapVersion) +
                    " (make the package again with this build's "
                    "`bimslam rig-map`)");
    }
    const uint64_t size = Load<uint64_t>(16);
    if (size != bytes_.size()) {
        Fail(16, "the header says " + std::to_string(size) + " bytes, the file holds " +
                     std::to_string(bytes_.size()) + (size > bytes_.size() ? " (cut off)" : ""));
    }
    if (Load<uint32_t>(24) != Crc32(bytes_.substr(kHeaderBytes))) {
        Fail(kHeaderBytes, "the contents are damaged: their CRC-32 does not match the header's");
    }
}

void Parser::ReadSections() {
    const uint32_t count = Load<uint32_t>(12);
    size_t at = kHeaderBytes;
    for (uint32_t k = 0; k < count; ++k) {
        if (bytes_.size() - at < kSectionHeaderBytes) Fail(at, "a section header is cut off");
        const uint64_t size = Load<uint64_t>(at + 8);
        if (size > bytes_.size() - at - kSectionHeaderBytes) {
            Fail(at, "a section of " + std::to_string(size) + " bytes runs past the file's end");
        }
        sections_.push_back({Load<uint32_t>(at), at + kSectionHeaderBytes, size_t(size)});
        at += kSectionHeaderBytes + size_t(size);
        at += std::min((8 - at % 8) % 8, bytes_.size() - at);
    }
    if (at != bytes_.size()) Fail(at, "bytes after the last section");
}

std::string_view Parser::Section(uint32_t tag, size_t index, size_t* at) const {
    for (const Entry& e : sections_) {
        if (e.tag != tag || index-- > 0) continue;
        if (at != nullptr) *at = e.at;
        return bytes_.substr(e.at, e.size);
    }
    const char t[5] = {char(tag), char(tag >> 8), char(tag >> 16), char(tag >> 24), 0};
    Fail(kHeaderBytes, std::string("no section ") + t + (index > 0 ? " (surfel level)" : ""));
}

void Parser::ReadMeta(RigMap& m) const {
    size_t at = 0;
    const std::string_view text = Section(Tag("META"), 0, &at);
    try {
        const json j = json::parse(text);
        if (j.at("format") != "bimslam-rig-map") Fail(at, "META: format is not bimslam-rig-map");
        m.model_file = j.at("model").at("file").get<std::string>();
        m.model_sha256 = j.at("model").at("sha256").get<std::string>();
        m.frame = j.at("frame").get<std::string>();
        m.created = j.at("created").get<std::string>();
        m.reference = j.at("reference").get<std::string>();
        const json& s = j.at("sensor");
        m.sensor.model = s.at("model").get<std::string>();
        m.sensor.beams = s.at("beams").get<int>();
        m.sensor.columns = s.at("columns").get<int>();
        const json& d = j.at("descriptor");
        m.descriptor.kind = d.at("kind").get<std::string>();
        m.descriptor.rings = d.at("rings").get<int>();
        m.descriptor.sectors = d.at("sectors").get<int>();
        m.descriptor.max_radius_m = d.at("max_radius_m").get<double>();
        m.descriptor.min_points = d.at("min_points").get<int>();
        m.descriptor.min_z_span_m = d.at("min_z_span_m").get<double>();
        // Packages made before the z_stack rule name none: theirs is z_span.
        m.descriptor.cell_rule = d.value("cell_rule", std::string("z_span"));
        for (const json& st : j.at("storeys")) {
            m.storeys.push_back({st.at("name").get<std::string>(),
                                 st.at("global_id").get<std::string>(),
                                 st.at("elevation_m").get<double>()});
        }
        const size_t keyframes = j.at("keyframes").get<size_t>();
        const size_t bytes = Section(Tag("KEYF")).size();
        if (keyframes != bytes / kKeyframeBytes || bytes % kKeyframeBytes != 0) {
            Fail(at, "META says " + std::to_string(keyframes) + " keyframes, KEYF holds " +
                         std::to_string(bytes) + " bytes");
        }
        m.keyframe_storey.reserve(keyframes);
        for (const json& l : j.at("levels")) {
            registration::SurfelMapConfig c;
            c.voxel_size = l.at("voxel_size_m").get<double>();
            c.min_points = l.at("min_points").get<int>();
            c.max_thickness = l.at("max_thickness_m").get<double>();
            c.Validate();
            m.levels.emplace_back(c);  // replaced by the restored level (ReadLevels)
        }
    } catch (const FileError&) {
        throw;
    } catch (const std::exception& e) {  // json's and Validate's
        Fail(at, std::string("META: ") + e.what());
    }
    if (m.descriptor.kind != "indoor" && m.descriptor.kind != "outdoor") {
        Fail(at, "META: descriptor kind '" + m.descriptor.kind + "'");
    }
    if (!scancontext::ParseIndoorCellRule(m.descriptor.cell_rule)) {
        Fail(at, "META: descriptor cell rule '" + m.descriptor.cell_rule + "'");
    }
    try {
        m.DescriptorConfig().Validate();
    } catch (const common::Error& e) {
        Fail(at, std::string("META: descriptor: ") + e.what());
    }
}

void Parser::ReadKeyframes(RigMap& m) const {
    size_t at = 0;
    const std::string_view p = Section(Tag("KEYF"), 0, &at);
    const size_t n = p.size() / kKeyframeBytes;
    m.keyframes.reserve(n);
    for (size_t k = 0; k < n; ++k) {
        const size_t r = at + k * kKeyframeBytes;
        double v[7];
        std::memcpy(v, bytes_.data() + r, sizeof v);
        const Eigen::Quaterniond q(v[3], v[4], v[5], v[6]);
        if (!std::all_of(v, v + 7, [](double x) { return std::isfinite(x); }) ||
            std::abs(q.norm() - 1) > 1e-6) {
            Fail(r, "keyframe " + std::to_string(k) + ": not a finite rigid pose");
        }
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
        T.linear() = q.normalized().toRotationMatrix();
        T.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
        m.keyframes.push_back(T);
        const int32_t storey = Load<int32_t>(r + 56);
        if (storey < -1 || storey >= int32_t(m.storeys.size())) {
            Fail(r + 56, "keyframe " + std::to_string(k) + ": storey " + std::to_string(storey) +
                             " of " + std::to_string(m.storeys.size()));
        }
        m.keyframe_storey.push_back(storey);
    }
}

void Parser::ReadDescriptors(RigMap& m) const {
    size_t at = 0;
    const std::string_view p = Section(Tag("DESC"), 0, &at);
    const size_t cells = size_t(m.descriptor.rings) * size_t(m.descriptor.sectors);
    if (p.size() != m.keyframes.size() * cells * sizeof(float)) {
        Fail(at, "DESC holds " + std::to_string(p.size()) + " bytes, not " +
                     std::to_string(m.keyframes.size()) + " descriptors of " +
                     std::to_string(m.descriptor.rings) + " x " +
                     std::to_string(m.descriptor.sectors));
    }
    m.descriptors.resize(m.keyframes.size());
    for (size_t k = 0; k < m.descriptors.size(); ++k) {
        scancontext::Descriptor& d = m.descriptors[k];
        d.resize(m.descriptor.rings, m.descriptor.sectors);
        std::memcpy(d.data(), p.data() + k * cells * sizeof(float), cells * sizeof(float));
        if (!d.allFinite()) Fail(at + k * cells * sizeof(float), "descriptor " + std::to_string(k));
    }
}

void Parser::ReadLevels(RigMap& m) const {
    for (size_t level = 0; level < m.levels.size(); ++level) {
        size_t at = 0;
        const std::string_view p = Section(Tag("SURF"), level, &at);
        const uint64_t n = p.size() >= 8 ? Load<uint64_t>(at) : 0;
        if (p.size() < 8 || n != (p.size() - 8) / kSurfelBytes || (p.size() - 8) % kSurfelBytes) {
            Fail(at, "surfel level " + std::to_string(level) + ": " + std::to_string(p.size()) +
                         " bytes do not hold the count they give");
        }
        std::vector<registration::Surfel> surfels(n);
        std::vector<registration::SurfelMap::Place> places(n);
        for (size_t i = 0; i < n; ++i) {
            const size_t r = at + 8 + i * kSurfelBytes;
            places[i].key = Load<uint64_t>(r);
            registration::Surfel& s = surfels[i];
            s.points = Load<uint32_t>(r + 8);
            places[i].bin = Load<uint8_t>(r + 12);
            const uint8_t porous = Load<uint8_t>(r + 13);
            if (porous > 1) {
                Fail(r + 13, "surfel " + std::to_string(i) + " of level " + std::to_string(level) +
                                 ": porous flag " + std::to_string(porous) + ", not 0 or 1");
            }
            s.porous = porous == 1;
            float v[13];
            std::memcpy(v, bytes_.data() + r + 16, sizeof v);
            if (!std::all_of(v, v + 13, [](float x) { return std::isfinite(x); })) {
                Fail(r, "surfel " + std::to_string(i) + " of level " + std::to_string(level) +
                            " is not finite");
            }
            s.normal = Eigen::Vector3f(v[0], v[1], v[2]);
            s.offset = v[3];
            s.centroid = Eigen::Vector3f(v[4], v[5], v[6]);
            s.thickness = v[7];
            s.axis = Eigen::Vector3f(v[8], v[9], v[10]);
            s.spread[0] = v[11];
            s.spread[1] = v[12];
        }
        try {
            m.levels[level] = registration::SurfelMap::Restore(
                m.levels[level].config(), std::move(surfels), std::move(places));
        } catch (const common::Error& e) {
            Fail(at, "surfel level " + std::to_string(level) + ": " + e.what());
        }
    }
}

// The optional SPAC section (a package without spaces has none).
void Parser::ReadSpaces(RigMap& m) const {
    for (const Entry& e : sections_) {
        if (e.tag != Tag("SPAC")) continue;
        try {
            for (const json& s : json::parse(bytes_.substr(e.at, e.size))) {
                RigMapSpace sp;
                sp.name = s.at("name").get<std::string>();
                sp.global_id = s.at("global_id").get<std::string>();
                sp.storey = s.at("storey").get<int32_t>();
                sp.z_min = s.at("z").at(0).get<float>();
                sp.z_max = s.at("z").at(1).get<float>();
                const json& xy = s.at("xy");
                if (xy.size() % 6 != 0)
                    Fail(e.at, "SPAC: space '" + sp.name + "': " + std::to_string(xy.size()) +
                                   " numbers are not whole triangles");
                for (size_t i = 0; i + 1 < xy.size(); i += 2) {
                    sp.triangles.emplace_back(xy[i].get<float>(), xy[i + 1].get<float>());
                }
                if (sp.storey < -1 || sp.storey >= int32_t(m.storeys.size())) {
                    Fail(e.at,
                         "SPAC: space '" + sp.name + "': storey " + std::to_string(sp.storey));
                }
                m.spaces.push_back(std::move(sp));
            }
        } catch (const FileError&) {
            throw;
        } catch (const std::exception& x) {
            Fail(e.at, std::string("SPAC: ") + x.what());
        }
    }
}

RigMap Parser::Parse() {
    CheckHeader();
    ReadSections();
    RigMap m;
    ReadMeta(m);
    ReadKeyframes(m);
    ReadDescriptors(m);
    ReadLevels(m);
    ReadSpaces(m);
    return m;
}

}  // namespace

scancontext::ScanContextConfig RigMap::DescriptorConfig() const {
    const bool indoor = descriptor.kind == "indoor";
    scancontext::ScanContextConfig c = indoor ? scancontext::ScanContextConfig::Indoor()
                                              : scancontext::ScanContextConfig::Outdoor();
    c.num_rings = descriptor.rings;
    c.num_sectors = descriptor.sectors;
    c.max_radius = descriptor.max_radius_m;
    if (indoor) {
        c.indoor_min_points = descriptor.min_points;
        c.indoor_min_z_span = descriptor.min_z_span_m;
        c.indoor_rule = *scancontext::ParseIndoorCellRule(descriptor.cell_rule);
    }
    return c;
}

int SpaceAt(const RigMap& map, const Eigen::Vector3d& p) {
    const Eigen::Vector2f q(float(p.x()), float(p.y()));
    const auto cross = [](const Eigen::Vector2f& a, const Eigen::Vector2f& b) {
        return a.x() * b.y() - a.y() * b.x();
    };
    for (size_t s = 0; s < map.spaces.size(); ++s) {
        const RigMapSpace& sp = map.spaces[s];
        if (p.z() < sp.z_min || p.z() > sp.z_max) continue;
        for (size_t t = 0; t + 2 < sp.triangles.size(); t += 3) {
            const Eigen::Vector2f &a = sp.triangles[t], &b = sp.triangles[t + 1],
                                  &c = sp.triangles[t + 2];
            const float d1 = cross(b - a, q - a), d2 = cross(c - b, q - b),
                        d3 = cross(a - c, q - c);
            const bool neg = d1 < 0 || d2 < 0 || d3<0, pos = d1> 0 || d2 > 0 || d3 > 0;
            if (!(neg && pos)) return int(s);
        }
    }
    return -1;
}

int32_t StoreyAt(const std::vector<RigMapStorey>& storeys, double z) {
    int32_t found = -1;
    for (size_t s = 0; s < storeys.size(); ++s) {
        if (storeys[s].elevation_m <= z) found = int32_t(s);
    }
    return found;
}

std::string SerializeRigMap(const RigMap& m) {
    CheckMap(m);
    std::string body;
    AppendSection(body, Tag("META"), MetaJson(m).dump(1));
    AppendSection(body, Tag("KEYF"), KeyframesPayload(m));
    AppendSection(body, Tag("DESC"), DescriptorsPayload(m));
    for (const registration::SurfelMap& l : m.levels) {
        AppendSection(body, Tag("SURF"), SurfelsPayload(l));
    }
    if (!m.spaces.empty()) AppendSection(body, Tag("SPAC"), SpacesJson(m).dump());
    std::string out(kMagic, sizeof kMagic);
    Append(out, kRigMapVersion);
    Append(out, uint32_t(3 + m.levels.size() + (m.spaces.empty() ? 0 : 1)));
    Append(out, uint64_t(kHeaderBytes + body.size()));
    Append(out, Crc32(body));
    Append(out, Crc32(out));
    return out + body;
}

void WriteRigMap(const std::filesystem::path& path, const RigMap& map) {
    std::string bytes;
    try {
        bytes = SerializeRigMap(map);
    } catch (const common::Error& e) {
        throw FileError(StatusCode::kInvalidArgument, path.string(), 0, e.what());
    }
    io::WriteFileAtomic(path, bytes);
}

RigMap ParseRigMap(const std::string& name, std::string_view bytes) {
    return Parser(name, bytes).Parse();
}

RigMap ReadRigMap(const std::filesystem::path& path, size_t max_bytes) {
    std::error_code ec;
    const uintmax_t size = std::filesystem::file_size(path, ec);
    if (!ec && size > max_bytes) {
        throw FileError(StatusCode::kParseError, path.string(), 0,
                        std::to_string(size) + " bytes: more than the " +
                            std::to_string(max_bytes) + " a rig map may hold");
    }
    return ParseRigMap(path.string(), io::ReadFileToString(path));
}

}  // namespace bimslam::localization
