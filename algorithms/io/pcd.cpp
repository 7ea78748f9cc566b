// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/io/pcd.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "algorithms/common/status.hpp"
#include "algorithms/io/file_util.hpp"
#include "algorithms/io/text_reader.hpp"

namespace bimslam::io {
namespace {
using common::Error;
using common::FileError;
using common::StatusCode;

// PCD TYPE letters: I signed integer, U unsigned integer, F floating point.
enum class Kind : uint8_t { kInt, kUint, kFloat };

struct Field {
    std::string_view name;  // points into the file bytes
    uint32_t size = 4;      // v0.5 files may leave out SIZE/TYPE/COUNT: PCL defaults to F4 x1
    Kind kind = Kind::kFloat;
    uint32_t count = 1;
};

// The channels of common::PointCloud that a PCD field can fill.
enum Channel : int { kX, kY, kZ, kIntensity, kRing, kT, kChannelCount };
constexpr std::array<std::string_view, kChannelCount> kChannelNames = {"x",         "y",    "z",
                                                                       "intensity", "ring", "t"};

enum class DataKind { kAscii, kBinary, kBinaryCompressed };

struct PcdHeader {
    std::vector<Field> fields;
    uint64_t points = 0;
    bool organized = false;
    DataKind data = DataKind::kBinary;
    std::array<int, kChannelCount> channel{-1, -1, -1, -1, -1, -1};  // field index per channel
};

constexpr uint64_t kMaxDimension = std::numeric_limits<uint32_t>::max();  // PCL's uint32 width
constexpr uint32_t kMaxCount = 1u << 20;  // far above any descriptor (FPFH 33, SHOT 352)

// PCD dimension values of <= 32 bits convert to double exactly; 64-bit integers beyond 2^53 are
// rounded, which only matters for values that are out of range for every channel anyway.
double LoadBinary(const char* p, uint32_t size, Kind kind) {
    auto load = [p]<typename T>(T) {
        T v;
        std::memcpy(&v, p, sizeof(T));  // unaligned: PCD packs fields without padding
        return static_cast<double>(v);
    };
    if (kind == Kind::kFloat) return size == 4 ? load(float{}) : load(double{});
    if (kind == Kind::kInt) {
        return size == 1   ? load(int8_t{})
               : size == 2 ? load(int16_t{})
               : size == 4 ? load(int32_t{})
                           : load(int64_t{});
    }
    return size == 1   ? load(uint8_t{})
           : size == 2 ? load(uint16_t{})
           : size == 4 ? load(uint32_t{})
                       : load(uint64_t{});
}

// One ASCII value as its declared type. "nan" is accepted here: whether it is allowed depends on
// the channel and on the cloud being organized (see Sink::Store).
double ParseAscii(const LineReader& reader, std::string_view token, const Field& f) {
    auto what = [&f] { return "field '" + std::string(f.name) + "'"; };
    if (f.kind == Kind::kFloat) {
        if (f.size == 4) {
            float v = 0.0f;  // parsed as float so that the shortest float text reads back exactly
            if (FromChars(token, v)) return v;
        } else {
            double v = 0.0;
            if (FromChars(token, v)) return v;
        }
        reader.Fail(what() + ": '" + std::string(token.substr(0, 40)) + "' is not a number");
    }
    const int bits = static_cast<int>(f.size) * 8;
    if (f.kind == Kind::kInt) {
        int64_t v = 0;
        const int64_t lim = bits == 64 ? std::numeric_limits<int64_t>::max() : (1ll << (bits - 1));
        if (FromChars(token, v) && (bits == 64 || (v >= -lim && v < lim))) {
            return static_cast<double>(v);
        }
    } else {
        uint64_t v = 0;
        if (FromChars(token, v) && (bits == 64 || v < (1ull << bits))) {
            return static_cast<double>(v);
        }
    }
    reader.Fail(what() + ": '" + std::string(token.substr(0, 40)) + "' is not a " +
                (f.kind == Kind::kInt ? "signed" : "unsigned") + " " + std::to_string(bits) +
                "-bit integer");
}

// Converts channel values into the cloud; no allocation per point.
class Sink {
public:
    static constexpr int kOk = -1;
    static constexpr int kDropped = -2;

    Sink(common::PointCloud& cloud, const PcdHeader& h) : cloud_(cloud), organized_(h.organized) {
        for (int c = 0; c < kChannelCount; ++c) has_[c] = h.channel[c] >= 0;
        t_is_seconds_ = has_[kT] && h.fields[h.channel[kT]].kind == Kind::kFloat;
    }

    // Called by each body reader once it has checked that the data can hold `points` points, so
    // a lying header never causes a large allocation.
    void Allocate(uint64_t points) {
        cloud_.Resize(points, has_[kIntensity], has_[kRing], has_[kT]);
    }

    // Stores one point; returns kOk, kDropped, or the channel whose value is invalid.
    int Store(const std::array<double, kChannelCount>& v) {
        const Eigen::Vector3f p(static_cast<float>(v[kX]), static_cast<float>(v[kY]),
                                static_cast<float>(v[kZ]));
        if (!p.allFinite()) {
            if (organized_) return kDropped;  // PCL's NaN placeholder of an organized cloud
            for (int c = kX; c <= kZ; ++c) {
                if (!std::isfinite(p[c])) return c;
            }
        }
        if (has_[kIntensity] && !std::isfinite(static_cast<float>(v[kIntensity]))) {
            return kIntensity;
        }
        if (has_[kRing] &&
            !(v[kRing] >= 0.0 && v[kRing] <= 65535.0 && v[kRing] == std::floor(v[kRing]))) {
            return kRing;
        }
        int64_t t_ns = 0;
        if (has_[kT]) {
            const double ns = t_is_seconds_ ? v[kT] * 1e9 : v[kT];
            if (!(ns > -0.5 && ns < 4294967295.5)) return kT;
            t_ns = t_is_seconds_ ? PcdSecondsToNs(v[kT]) : static_cast<int64_t>(v[kT]);
        }
        cloud_.xyz[n_] = p;
        if (has_[kIntensity]) cloud_.intensity[n_] = static_cast<float>(v[kIntensity]);
        if (has_[kRing]) cloud_.ring[n_] = static_cast<uint16_t>(v[kRing]);
        if (has_[kT]) cloud_.time_offset_ns[n_] = static_cast<uint32_t>(t_ns);
        ++n_;
        return kOk;
    }

    std::string Describe(int c, double v) const {
        const std::string head = std::string(kChannelNames[c]) + " = " + FormatDouble(v);
        if (c <= kZ) {
            return head + " is not a finite float (allowed as a NaN placeholder only in an " +
                   "organized cloud, HEIGHT > 1)";
        }
        if (c == kIntensity) return head + " is not a finite float";
        if (c == kRing) return head + " is not an integer in [0, 65535]";
        return head + (t_is_seconds_ ? " s" : " ns") + " is outside [0, 4.294967295] s";
    }

    void Finish() {
        cloud_.Resize(n_, false, false, false);  // shrinking: drops the skipped NaN points
    }

private:
    common::PointCloud& cloud_;
    bool organized_;
    bool t_is_seconds_ = false;
    std::array<bool, kChannelCount> has_{};
    size_t n_ = 0;
};

uint64_t ParseUnsigned(const LineReader& r, std::string_view tok, std::string_view what,
                       uint64_t max) {
    const int64_t v = r.ParseInt(tok, what);
    if (v < 0 || static_cast<uint64_t>(v) > max) {
        r.Fail(std::string(what) + " " + std::string(tok) + " is outside [0, " +
               std::to_string(max) + "]");
    }
    return static_cast<uint64_t>(v);
}

void CheckTypes(const LineReader& r, const std::vector<Field>& fields) {
    for (const Field& f : fields) {
        const bool ok = f.kind == Kind::kFloat
                            ? (f.size == 4 || f.size == 8)
                            : (f.size == 1 || f.size == 2 || f.size == 4 || f.size == 8);
        if (!ok) {
            r.Fail("field '" + std::string(f.name) + "': TYPE " + "IUF"[static_cast<int>(f.kind)] +
                   " with SIZE " + std::to_string(f.size) +
                   " is not a PCD type (I/U 1 2 4 8, F 4 8)");
        }
    }
}

// The header, up to and including the DATA line (tutorial section "PCD file format").
PcdHeader ParsePcdHeader(LineReader& r) {
    PcdHeader h;
    std::vector<std::string_view> tok;
    std::string_view line;
    bool have_fields = false, have_size = false, have_type = false, have_count = false;
    bool have_width = false, have_height = false, have_points = false, have_data = false;
    uint64_t width = 0, height = 1;
    auto per_field = [&](std::string_view key) {
        if (!have_fields) r.Fail(std::string(key) + " before FIELDS");
        if (tok.size() - 1 != h.fields.size()) {
            r.Fail(std::string(key) + " has " + std::to_string(tok.size() - 1) + " entries for " +
                   std::to_string(h.fields.size()) + " fields");
        }
    };
    auto once = [&](bool& seen, std::string_view key) {
        if (seen) r.Fail(std::string(key) + " appears twice");
        seen = true;
    };
    while (!have_data && r.Next(line)) {
        LineReader::Split(line, tok);
        if (tok.empty() || tok[0].front() == '#') continue;
        const std::string_view key = tok[0];
        if (key == "VERSION") {
            if (tok.size() != 2) r.Fail("VERSION needs one value");
        } else if (key == "FIELDS" || key == "COLUMNS") {  // COLUMNS: v0.5
            once(have_fields, "FIELDS");
            if (tok.size() < 2) r.Fail("FIELDS lists no field");
            for (size_t i = 1; i < tok.size(); ++i) {
                if (tok[i] != "_") {
                    for (const Field& f : h.fields) {
                        if (f.name == tok[i]) r.Fail("field '" + std::string(tok[i]) + "' twice");
                    }
                }
                h.fields.push_back(Field{tok[i]});
            }
        } else if (key == "SIZE") {
            once(have_size, key);
            per_field(key);
            for (size_t i = 1; i < tok.size(); ++i) {
                h.fields[i - 1].size = static_cast<uint32_t>(ParseUnsigned(r, tok[i], "SIZE", 8));
            }
            if (have_type) CheckTypes(r, h.fields);
        } else if (key == "TYPE") {
            once(have_type, key);
            per_field(key);
            for (size_t i = 1; i < tok.size(); ++i) {
                const std::string_view t = tok[i];
                if (t != "I" && t != "U" && t != "F") {
                    r.Fail("TYPE '" + std::string(t.substr(0, 40)) + "' is not I, U or F");
                }
                h.fields[i - 1].kind = t == "I"   ? Kind::kInt
                                       : t == "U" ? Kind::kUint
                                                  : Kind::kFloat;
            }
            if (have_size) CheckTypes(r, h.fields);
        } else if (key == "COUNT") {
            once(have_count, key);
            per_field(key);
            for (size_t i = 1; i < tok.size(); ++i) {
                h.fields[i - 1].count =
                    static_cast<uint32_t>(ParseUnsigned(r, tok[i], "COUNT", kMaxCount));
                if (h.fields[i - 1].count == 0) r.Fail("COUNT 0");
            }
        } else if (key == "WIDTH" || key == "HEIGHT" || key == "POINTS") {
            if (tok.size() != 2) r.Fail(std::string(key) + " needs one value");
            const uint64_t v = ParseUnsigned(r, tok[1], key, kMaxDimension);
            if (key == "WIDTH") {
                once(have_width, key);
                width = v;
            } else if (key == "HEIGHT") {
                once(have_height, key);
                height = v;
            } else {
                once(have_points, key);
                h.points = v;
            }
        } else if (key == "VIEWPOINT") {  // the sensor pose; a cloud here is in its own frame
            if (tok.size() != 8) r.Fail("VIEWPOINT needs 7 numbers (tx ty tz qw qx qy qz)");
            for (size_t i = 1; i < 8; ++i) r.ParseDouble(tok[i], "VIEWPOINT");
        } else if (key == "DATA") {
            have_data = true;
            if (tok.size() != 2) r.Fail("DATA needs one value");
            if (tok[1] == "ascii") {
                h.data = DataKind::kAscii;
            } else if (tok[1] == "binary") {
                h.data = DataKind::kBinary;
            } else if (tok[1] == "binary_compressed") {
                h.data = DataKind::kBinaryCompressed;
            } else {
                r.Fail("DATA '" + std::string(tok[1].substr(0, 40)) +
                       "' is not ascii, binary or binary_compressed");
            }
        } else {
            r.Fail(r.line_number() == 1 && key != "#"
                       ? "not a PCD file (unknown header line '" + std::string(key.substr(0, 40)) +
                             "')"
                       : "unknown header keyword '" + std::string(key.substr(0, 40)) + "'");
        }
    }
    if (!have_data) r.Fail("the header has no DATA line", StatusCode::kDataLoss);
    if (!have_fields) r.Fail("the header has no FIELDS line");
    CheckTypes(r, h.fields);
    // v0.6 files may give only POINTS, or only WIDTH and HEIGHT; PCL requires them to agree.
    if (!have_width && !have_points) r.Fail("the header has neither WIDTH nor POINTS");
    if (!have_width) width = h.points / std::max<uint64_t>(height, 1);
    if (!have_points) h.points = width * height;
    if (width * height != h.points) {
        r.Fail("WIDTH " + std::to_string(width) + " x HEIGHT " + std::to_string(height) +
               " != POINTS " + std::to_string(h.points));
    }
    h.organized = height > 1;
    for (int c = 0; c < kChannelCount; ++c) {
        for (size_t i = 0; i < h.fields.size(); ++i) {
            if (h.fields[i].name == kChannelNames[c]) h.channel[c] = static_cast<int>(i);
        }
    }
    for (int c = kX; c <= kZ; ++c) {
        if (h.channel[c] < 0) {
            r.Fail("no field '" + std::string(kChannelNames[c]) + "' (x, y and z are required)");
        }
    }
    return h;
}

// liblzf's lzf_decompress (the LZF that PCL bundles as pcl::lzfDecompress), with every read and
// write bounds-checked. Returns the number of bytes written, or npos on malformed input.
size_t LzfDecompress(std::string_view in, char* out, size_t out_len) {
    size_t ip = 0, op = 0;
    while (ip < in.size()) {
        const unsigned ctrl = static_cast<uint8_t>(in[ip++]);
        if (ctrl < (1u << 5)) {  // literal run of ctrl + 1 bytes
            const size_t len = ctrl + 1;
            if (op + len > out_len || ip + len > in.size()) return std::string_view::npos;
            std::memcpy(out + op, in.data() + ip, len);
            op += len;
            ip += len;
        } else {  // back reference: length (ctrl >> 5) + 2, distance from the low 13 bits
            size_t len = ctrl >> 5;
            size_t back = (ctrl & 0x1f) << 8;
            if (ip >= in.size()) return std::string_view::npos;
            if (len == 7) {
                len += static_cast<uint8_t>(in[ip++]);
                if (ip >= in.size()) return std::string_view::npos;
            }
            back += static_cast<uint8_t>(in[ip++]) + 1;
            len += 2;
            if (back > op || op + len > out_len) return std::string_view::npos;
            for (size_t k = 0; k < len; ++k, ++op) out[op] = out[op - back];  // may overlap
        }
    }
    return op;
}

struct Source {
    const char* base = nullptr;
    size_t stride = 0;
    uint32_t size = 4;
    Kind kind = Kind::kFloat;
};

// `load(channel, bytes)` gives a channel's value as double, each point's checked by the sink.
template <class Load>
void ReadBinaryPointsWith(const std::string& name, const PcdHeader& h,
                          const std::array<Source, kChannelCount>& src, Sink& sink, Load load) {
    std::array<double, kChannelCount> v{};
    for (size_t i = 0; i < h.points; ++i) {
        for (int c = 0; c < kChannelCount; ++c) {
            if (h.channel[c] >= 0) v[c] = load(c, src[c].base + i * src[c].stride);
        }
        const int bad = sink.Store(v);
        if (bad >= 0) {
            throw FileError(StatusCode::kParseError, name, 0,
                            "point " + std::to_string(i) + ": " + sink.Describe(bad, v[bad]));
        }
    }
}

template <typename T>
double LoadAs(const char* p) {
    T v;
    std::memcpy(&v, p, sizeof(T));  // unaligned: PCD packs fields without padding
    return static_cast<double>(v);
}

void ReadBinaryPoints(const std::string& name, const PcdHeader& h,
                      const std::array<Source, kChannelCount>& src, Sink& sink) {
    // The fields WritePcd writes (float32, ring uint16) are loaded without choosing a
    // conversion per value: a session's keyframe clouds are read by the thousand.
    bool written_by_us = true;
    for (int c = 0; c < kChannelCount; ++c) {
        const Kind kind = c == kRing ? Kind::kUint : Kind::kFloat;
        const uint32_t size = c == kRing ? 2 : 4;
        if (h.channel[c] >= 0 && (src[c].kind != kind || src[c].size != size)) {
            written_by_us = false;
        }
    }
    if (written_by_us) {
        ReadBinaryPointsWith(name, h, src, sink, [](int c, const char* p) {
            return c == kRing ? LoadAs<uint16_t>(p) : LoadAs<float>(p);
        });
    } else {
        ReadBinaryPointsWith(name, h, src, sink, [&src](int c, const char* p) {
            return LoadBinary(p, src[c].size, src[c].kind);
        });
    }
}

void ReadBinary(const std::string& name, const PcdHeader& h, std::string_view body, Sink& sink) {
    std::array<Source, kChannelCount> src{};
    uint64_t offset = 0;
    std::array<uint64_t, kChannelCount> field_offset{};
    for (size_t i = 0; i < h.fields.size(); ++i) {
        for (int c = 0; c < kChannelCount; ++c) {
            if (h.channel[c] == static_cast<int>(i)) field_offset[c] = offset;
        }
        offset += uint64_t{h.fields[i].size} * h.fields[i].count;
    }
    const uint64_t point_size = offset;  // >= 1: at least x y z
    if (body.size() / point_size < h.points) {
        throw FileError(StatusCode::kDataLoss, name, 0,
                        "POINTS " + std::to_string(h.points) + " of " + std::to_string(point_size) +
                            " bytes need " + std::to_string(h.points * point_size) +
                            " bytes of binary data, the file has " + std::to_string(body.size()));
    }
    for (int c = 0; c < kChannelCount; ++c) {
        if (h.channel[c] < 0) continue;
        const Field& f = h.fields[h.channel[c]];
        src[c] = Source{body.data() + field_offset[c], point_size, f.size, f.kind};
    }
    sink.Allocate(h.points);
    ReadBinaryPoints(name, h, src, sink);
}

// binary_compressed (PCL's PCDWriter::writeBinaryCompressed): uint32 compressed size, uint32
// uncompressed size, then LZF data that expands to one block per field (all x, then all y, ...),
// "_" padding fields left out.
void ReadCompressed(const std::string& name, const PcdHeader& h, std::string_view body,
                    Sink& sink) {
    auto fail = [&name](const std::string& what) {
        throw FileError(StatusCode::kDataLoss, name, 0, "binary_compressed data: " + what);
    };
    if (body.size() < 8) fail("shorter than its 8-byte size header");
    uint32_t compressed = 0, uncompressed = 0;
    std::memcpy(&compressed, body.data(), 4);
    std::memcpy(&uncompressed, body.data() + 4, 4);
    uint64_t point_size = 0;
    for (const Field& f : h.fields) {
        if (f.name != "_") point_size += uint64_t{f.size} * f.count;
    }
    const uint64_t expected = h.points * point_size;
    if (uncompressed != expected) {
        fail("uncompressed size " + std::to_string(uncompressed) + " != POINTS x point size " +
             std::to_string(expected));
    }
    if (compressed > body.size() - 8) {
        fail("compressed size " + std::to_string(compressed) + " but only " +
             std::to_string(body.size() - 8) + " bytes follow");
    }
    // An LZF token of 3 bytes expands to at most 264: a larger claim is a lie, caught before
    // allocating.
    if (expected > uint64_t{compressed} * 88) fail("uncompressed size too large for its input");
    std::vector<char> buf(expected);
    if (LzfDecompress(body.substr(8, compressed), buf.data(), buf.size()) != expected) {
        fail("corrupt LZF stream");
    }
    std::array<Source, kChannelCount> src{};
    uint64_t block = 0;
    for (size_t i = 0; i < h.fields.size(); ++i) {
        const Field& f = h.fields[i];
        if (f.name == "_") continue;
        for (int c = 0; c < kChannelCount; ++c) {
            if (h.channel[c] == static_cast<int>(i)) {
                src[c] = Source{buf.data() + block, uint64_t{f.size} * f.count, f.size, f.kind};
            }
        }
        block += h.points * f.size * f.count;
    }
    sink.Allocate(h.points);
    ReadBinaryPoints(name, h, src, sink);
}

void ReadAscii(LineReader& r, const PcdHeader& h, Sink& sink) {
    std::array<size_t, kChannelCount> token{};
    size_t tokens = 0;
    for (size_t i = 0; i < h.fields.size(); ++i) {
        for (int c = 0; c < kChannelCount; ++c) {
            if (h.channel[c] == static_cast<int>(i)) token[c] = tokens;
        }
        tokens += h.fields[i].count;
    }
    // Each point takes at least one character and one separator per value.
    if (h.points > 0 && (r.Rest().size() + 1) / (2 * tokens) < h.points) {
        r.Fail("POINTS " + std::to_string(h.points) + " needs more ASCII data than the " +
                   std::to_string(r.Rest().size()) + " bytes that follow",
               StatusCode::kDataLoss);
    }
    sink.Allocate(h.points);
    std::vector<std::string_view> tok;
    std::array<double, kChannelCount> v{};
    std::string_view line;
    uint64_t n = 0;
    while (r.Next(line)) {
        LineReader::Split(line, tok);
        if (tok.empty()) continue;
        if (n == h.points) r.Fail("more points than POINTS " + std::to_string(h.points));
        if (tok.size() != tokens) {
            r.Fail("expected " + std::to_string(tokens) + " values (the sum of COUNT), found " +
                   std::to_string(tok.size()));
        }
        for (int c = 0; c < kChannelCount; ++c) {
            if (h.channel[c] >= 0) v[c] = ParseAscii(r, tok[token[c]], h.fields[h.channel[c]]);
        }
        const int bad = sink.Store(v);
        if (bad >= 0) r.Fail(sink.Describe(bad, v[bad]));
        ++n;
    }
    if (n < h.points) {
        r.Fail("the file ends after " + std::to_string(n) + " of POINTS " +
                   std::to_string(h.points) + " points",
               StatusCode::kDataLoss);
    }
}

void AppendNumber(std::string& out, auto v) {
    std::array<char, 32> buf{};
    const auto res = std::to_chars(buf.data(), buf.data() + buf.size(), v);
    out.append(buf.data(), res.ptr);
}

template <typename T>
void AppendRaw(char*& p, T v) {
    std::memcpy(p, &v, sizeof(T));
    p += sizeof(T);
}
}  // namespace

float PcdNsToSeconds(uint32_t time_offset_ns) {
    return static_cast<float>(static_cast<double>(time_offset_ns) / 1e9);
}

int64_t PcdSecondsToNs(double seconds) { return std::llround(seconds * 1e9); }

common::PointCloud ParsePcd(const std::string& name, std::string_view bytes) {
    LineReader reader(name, bytes);
    const PcdHeader h = ParsePcdHeader(reader);
    common::PointCloud cloud;
    Sink sink(cloud, h);
    switch (h.data) {
        case DataKind::kAscii:
            ReadAscii(reader, h, sink);
            break;
        case DataKind::kBinary:
            ReadBinary(name, h, reader.Rest(), sink);
            break;
        case DataKind::kBinaryCompressed:
            ReadCompressed(name, h, reader.Rest(), sink);
            break;
    }
    sink.Finish();
    return cloud;
}

common::PointCloud ReadPcd(const std::filesystem::path& path) {
    const std::string bytes = ReadFileToString(path);
    return ParsePcd(path.string(), bytes);
}

std::string SerializePcd(const common::PointCloud& cloud, PcdEncoding encoding) {
    if (!cloud.ChannelsConsistent()) {
        throw Error(StatusCode::kInvalidArgument,
                    "point cloud channels differ in length from its " +
                        std::to_string(cloud.size()) + " points");
    }
    const size_t n = cloud.size();
    for (size_t i = 0; i < n; ++i) {
        // The reader rejects these in an unorganized cloud, so writing them would make a file
        // this project cannot read back.
        if (!cloud.xyz[i].allFinite() ||
            (cloud.HasIntensity() && !std::isfinite(cloud.intensity[i]))) {
            throw Error(StatusCode::kInvalidArgument,
                        "point " + std::to_string(i) + " has a non-finite coordinate or intensity");
        }
    }
    const bool has_i = cloud.HasIntensity(), has_r = cloud.HasRing(), has_t = cloud.HasTime();
    // Header lines as PCL's PCDWriter::generateHeader writes them.
    std::string out = "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z";
    out += std::string(has_i ? " intensity" : "") + (has_r ? " ring" : "") + (has_t ? " t" : "");
    out += std::string("\nSIZE 4 4 4") + (has_i ? " 4" : "") + (has_r ? " 2" : "") +
           (has_t ? " 4" : "");
    out += std::string("\nTYPE F F F") + (has_i ? " F" : "") + (has_r ? " U" : "") +
           (has_t ? " F" : "");
    out += std::string("\nCOUNT 1 1 1") + (has_i ? " 1" : "") + (has_r ? " 1" : "") +
           (has_t ? " 1" : "");
    out += "\nWIDTH " + std::to_string(n) + "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " +
           std::to_string(n) + "\n";
    if (encoding == PcdEncoding::kBinary) {
        out += "DATA binary\n";
        const size_t point_size = 12 + (has_i ? 4 : 0) + (has_r ? 2 : 0) + (has_t ? 4 : 0);
        const size_t start = out.size();
        out.resize(start + n * point_size);
        char* p = out.data() + start;
        for (size_t i = 0; i < n; ++i) {  // packed per point (AoS), no padding, as PCL does
            std::memcpy(p, cloud.xyz[i].data(), 12);
            p += 12;
            if (has_i) AppendRaw(p, cloud.intensity[i]);
            if (has_r) AppendRaw(p, cloud.ring[i]);
            if (has_t) AppendRaw(p, PcdNsToSeconds(cloud.time_offset_ns[i]));
        }
        return out;
    }
    out += "DATA ascii\n";
    out.reserve(out.size() + n * 60);
    for (size_t i = 0; i < n; ++i) {
        for (int k = 0; k < 3; ++k) {
            if (k > 0) out += ' ';
            AppendNumber(out, cloud.xyz[i][k]);
        }
        if (has_i) {
            out += ' ';
            AppendNumber(out, cloud.intensity[i]);
        }
        if (has_r) {
            out += ' ';
            AppendNumber(out, cloud.ring[i]);
        }
        if (has_t) {
            out += ' ';
            AppendNumber(out, PcdNsToSeconds(cloud.time_offset_ns[i]));
        }
        out += '\n';
    }
    return out;
}

void WritePcd(const std::filesystem::path& path, const common::PointCloud& cloud,
              PcdEncoding encoding) {
    std::string bytes;
    try {
        bytes = SerializePcd(cloud, encoding);
    } catch (const FileError&) {
        throw;
    } catch (const Error& e) {
        throw FileError(e.code(), path.string(), 0, e.what());
    }
    WriteFileAtomic(path, bytes);
}

}  // namespace bimslam::io
