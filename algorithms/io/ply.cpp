// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/io/ply.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

#include "algorithms/common/status.hpp"
#include "algorithms/io/file_util.hpp"
#include "algorithms/io/pcd.hpp"
#include "algorithms/io/text_reader.hpp"

namespace bimslam::io {
namespace {
using common::Error;
using common::FileError;
using common::StatusCode;

// The scalar types of the spec ("Header" section) with their sized aliases (rply, Open3D).
struct TypeInfo {
    std::string_view name;
    std::string_view alias;
    uint32_t size;
    bool is_float;
    double min;
    double max;
};
constexpr TypeInfo kTypes[] = {
    {"char", "int8", 1, false, -128.0, 127.0},
    {"uchar", "uint8", 1, false, 0.0, 255.0},
    {"short", "int16", 2, false, -32768.0, 32767.0},
    {"ushort", "uint16", 2, false, 0.0, 65535.0},
    {"int", "int32", 4, false, -2147483648.0, 2147483647.0},
    {"uint", "uint32", 4, false, 0.0, 4294967295.0},
    {"float", "float32", 4, true, -std::numeric_limits<float>::max(),
     std::numeric_limits<float>::max()},
    {"double", "float64", 8, true, -std::numeric_limits<double>::max(),
     std::numeric_limits<double>::max()},
};
const TypeInfo& Info(PlyType t) { return kTypes[static_cast<int>(t)]; }

// Calls f with a value of the C++ type of t (the value itself is unused).
template <typename F>
auto Dispatch(PlyType t, F&& f) {
    switch (t) {
        case PlyType::kInt8:
            return f(int8_t{});
        case PlyType::kUint8:
            return f(uint8_t{});
        case PlyType::kInt16:
            return f(int16_t{});
        case PlyType::kUint16:
            return f(uint16_t{});
        case PlyType::kInt32:
            return f(int32_t{});
        case PlyType::kUint32:
            return f(uint32_t{});
        case PlyType::kFloat32:
            return f(float{});
        case PlyType::kFloat64:
            break;
    }
    return f(double{});
}

struct Property {
    std::string_view name;
    PlyType type = PlyType::kFloat32;
    bool is_list = false;
    PlyType count_type = PlyType::kUint8;
};

struct Element {
    std::string_view name;
    uint64_t count = 0;
    std::vector<Property> props;
    size_t line = 0;
};

enum class PlyFormat { kAscii, kBinaryLittleEndian, kBinaryBigEndian };

struct PlyHeader {
    PlyFormat format = PlyFormat::kAscii;
    std::vector<Element> elements;
};

// True when `v` is a value of type t: integral and in range for the integer types, finite for
// the float types.
bool Representable(double v, PlyType t) {
    const TypeInfo& info = Info(t);
    if (info.is_float) return std::isfinite(v) && v >= info.min && v <= info.max;
    return v >= info.min && v <= info.max && v == std::floor(v);
}

PlyType ParseType(const LineReader& r, std::string_view tok) {
    for (int i = 0; i < 8; ++i) {
        if (tok == kTypes[i].name || tok == kTypes[i].alias) return static_cast<PlyType>(i);
    }
    r.Fail("'" + std::string(tok.substr(0, 40)) + "' is not a PLY type");
}

PlyHeader ParsePlyHeader(LineReader& r) {
    std::string_view line;
    if (!r.Next(line) || line != "ply") r.Fail("not a PLY file (the first line must be 'ply')");
    PlyHeader h;
    bool have_format = false;
    std::vector<std::string_view> tok;
    for (;;) {
        if (!r.Next(line)) r.Fail("the header has no end_header line", StatusCode::kDataLoss);
        LineReader::Split(line, tok);
        if (tok.empty() || tok[0] == "comment" || tok[0] == "obj_info") continue;
        const std::string_view key = tok[0];
        if (key == "end_header") break;
        if (key == "format") {
            if (have_format) r.Fail("format appears twice");
            have_format = true;
            if (tok.size() != 3 || tok[2] != "1.0") r.Fail("expected 'format <encoding> 1.0'");
            if (tok[1] == "ascii") {
                h.format = PlyFormat::kAscii;
            } else if (tok[1] == "binary_little_endian") {
                h.format = PlyFormat::kBinaryLittleEndian;
            } else if (tok[1] == "binary_big_endian") {
                h.format = PlyFormat::kBinaryBigEndian;
            } else {
                r.Fail("unknown format '" + std::string(tok[1].substr(0, 40)) + "'");
            }
        } else if (key == "element") {
            if (tok.size() != 3) r.Fail("expected 'element <name> <count>'");
            for (const Element& e : h.elements) {
                if (e.name == tok[1]) r.Fail("element '" + std::string(tok[1]) + "' twice");
            }
            const int64_t n = r.ParseInt(tok[2], "element count");
            // Vertex indices are uint32 (common::TriangleMesh), so no element needs more.
            if (n < 0 || n > int64_t{std::numeric_limits<uint32_t>::max()}) {
                r.Fail("element count " + std::string(tok[2]) + " is outside [0, 2^32)");
            }
            h.elements.push_back(Element{tok[1], static_cast<uint64_t>(n), {}, r.line_number()});
        } else if (key == "property") {
            if (h.elements.empty()) r.Fail("property before any element");
            Property p;
            if (tok.size() == 5 && tok[1] == "list") {
                p.is_list = true;
                p.count_type = ParseType(r, tok[2]);
                if (Info(p.count_type).is_float) r.Fail("a list count must have an integer type");
                p.type = ParseType(r, tok[3]);
                p.name = tok[4];
            } else if (tok.size() == 3) {
                p.type = ParseType(r, tok[1]);
                p.name = tok[2];
            } else {
                r.Fail("expected 'property <type> <name>' or 'property list <type> <type> <name>'");
            }
            for (const Property& q : h.elements.back().props) {
                if (q.name == p.name) r.Fail("property '" + std::string(p.name) + "' twice");
            }
            h.elements.back().props.push_back(p);
        } else {
            r.Fail("unknown header keyword '" + std::string(key.substr(0, 40)) + "'");
        }
    }
    if (!have_format) r.Fail("the header has no format line");
    return h;
}

// Checks that every element fits in the bytes that follow the header, before allocating: an item
// takes at least its scalar sizes and list counts in binary, one character and one separator per
// value in ASCII.
void CheckSizes(const LineReader& r, const PlyHeader& h, size_t body_size) {
    uint64_t left = body_size + (h.format == PlyFormat::kAscii ? 1 : 0);
    for (const Element& e : h.elements) {
        uint64_t min = 0;
        for (const Property& p : e.props) {
            min += h.format == PlyFormat::kAscii ? 2 : Info(p.is_list ? p.count_type : p.type).size;
        }
        if (min > 0 && e.count > left / min) {
            throw FileError(StatusCode::kDataLoss, r.path(), e.line,
                            "element " + std::string(e.name) + " " + std::to_string(e.count) +
                                " needs more data than the " + std::to_string(body_size) +
                                " bytes after the header");
        }
        left -= e.count * min;
    }
}

// Reads values one at a time from either encoding; errors name the line in ASCII, no line in
// binary. No allocation per value.
class ValueReader {
public:
    ValueReader(LineReader& r, PlyFormat format) : r_(r), format_(format) {
        swap_ =
            (format == PlyFormat::kBinaryBigEndian) != (std::endian::native == std::endian::big);
        body_ = r.Rest();
    }

    void SetItem(const Element& e, uint64_t item) {
        element_ = &e;
        item_ = item;
    }

    double Read(PlyType t) { return format_ == PlyFormat::kAscii ? ReadAscii(t) : ReadBinary(t); }

    // Skips a value whose content does not matter (other elements, ignored properties).
    void Skip(PlyType t) {
        if (format_ == PlyFormat::kAscii) {
            NextToken();
        } else {
            Need(Info(t).size);
            pos_ += Info(t).size;
        }
    }

    // A list length (integer type, so Read's checks make it a non-negative integral value).
    uint64_t ReadCount(PlyType t) {
        const double n = Read(t);
        if (n < 0) Fail("list length " + FormatDouble(n) + " is negative");
        return static_cast<uint64_t>(n);
    }

    [[noreturn]] void Fail(const std::string& what,
                           StatusCode code = StatusCode::kParseError) const {
        const std::string msg = "element " + std::string(element_->name) + " item " +
                                std::to_string(item_) + ": " + what;
        if (format_ == PlyFormat::kAscii) r_.Fail(msg, code);
        throw FileError(code, r_.path(), 0, msg);
    }

    // ASCII: data after the last element is an error; binary: trailing bytes are ignored.
    void CheckEnd() {
        if (format_ != PlyFormat::kAscii) return;
        while (next_ == tok_.size()) {
            std::string_view line;
            if (!r_.Next(line)) return;
            LineReader::Split(line, tok_);
            next_ = 0;
        }
        r_.Fail("data after the last element");
    }

private:
    void Need(size_t n) {
        if (body_.size() - pos_ < n) Fail("the file ends here", StatusCode::kDataLoss);
    }

    std::string_view NextToken() {
        while (next_ == tok_.size()) {
            std::string_view line;
            if (!r_.Next(line)) Fail("the file ends here", StatusCode::kDataLoss);
            LineReader::Split(line, tok_);
            next_ = 0;
        }
        return tok_[next_++];
    }

    double ReadAscii(PlyType t) {
        std::string_view tok = NextToken();
        double v = 0.0;
        bool ok = false;
        if (t == PlyType::kFloat32) {
            float f = 0.0f;  // as float, so the shortest float text reads back exactly
            ok = FromChars(tok, f);
            v = f;
        } else if (t == PlyType::kFloat64) {
            ok = FromChars(tok, v);
        } else {
            int64_t i = 0;
            ok = FromChars(tok, i);
            v = static_cast<double>(i);
        }
        if (!ok || !Representable(v, t)) {
            Fail("'" + std::string(tok.substr(0, 40)) + "' is not a finite " +
                 std::string(Info(t).name));
        }
        return v;
    }

    double ReadBinary(PlyType t) {
        std::array<char, 8> b{};
        // PLY's largest type (double) has 8 bytes. The bound also shows GCC 12 for aarch64 that
        // the byte swap below stays inside b (its -Wstringop-overflow fired on std::reverse).
        const uint32_t size = std::min<uint32_t>(Info(t).size, b.size());
        Need(size);
        std::memcpy(b.data(), body_.data() + pos_, size);
        pos_ += size;
        if (swap_) std::reverse(b.begin(), b.begin() + size);
        const double v = Dispatch(t, [&b]<typename T>(T) {
            T x;
            std::memcpy(&x, b.data(), sizeof(T));
            return static_cast<double>(x);
        });
        if (!std::isfinite(v)) Fail(FormatDouble(v) + " is not finite");
        return v;
    }

    LineReader& r_;
    PlyFormat format_;
    bool swap_ = false;
    std::string_view body_;
    size_t pos_ = 0;
    std::vector<std::string_view> tok_;
    size_t next_ = 0;
    const Element* element_ = nullptr;
    uint64_t item_ = 0;
};

void SkipList(ValueReader& in, const Property& p) {
    const uint64_t n = in.ReadCount(p.count_type);
    for (uint64_t k = 0; k < n; ++k) in.Skip(p.type);
}

void ReadVertices(ValueReader& in, const Element& e, PlyData& out) {
    // Where each property goes: 0..2 = x y z, 3 + k = vertex_properties[k], -1 = skipped list.
    std::vector<int> target;
    for (const Property& p : e.props) {
        if (p.is_list) {
            target.push_back(-1);
        } else if (p.name == "x" || p.name == "y" || p.name == "z") {
            target.push_back(p.name[0] - 'x');
        } else {
            target.push_back(3 + static_cast<int>(out.vertex_properties.size()));
            out.vertex_properties.push_back(PlyProperty{std::string(p.name), p.type, {}});
            out.vertex_properties.back().values.resize(e.count);
        }
    }
    out.vertices.resize(e.count);
    for (uint64_t i = 0; i < e.count; ++i) {
        in.SetItem(e, i);
        for (size_t k = 0; k < e.props.size(); ++k) {
            const Property& p = e.props[k];
            if (target[k] < 0) {
                SkipList(in, p);
                continue;
            }
            const double v = in.Read(p.type);
            if (target[k] >= 3) {
                out.vertex_properties[target[k] - 3].values[i] = v;
                continue;
            }
            const float f = static_cast<float>(v);
            if (!std::isfinite(f)) in.Fail(std::string(p.name) + " overflows float");
            out.vertices[i][target[k]] = f;
        }
    }
}

void ReadFaces(ValueReader& in, const Element& e, uint64_t vertex_count, PlyData& out) {
    out.triangles.reserve(e.count);  // CheckSizes bounded e.count by the file size
    std::vector<uint32_t> corners;
    for (uint64_t i = 0; i < e.count; ++i) {
        in.SetItem(e, i);
        for (const Property& p : e.props) {
            if (p.name != "vertex_indices" && p.name != "vertex_index") {
                if (p.is_list) {
                    SkipList(in, p);
                } else {
                    in.Skip(p.type);
                }
                continue;
            }
            const uint64_t n = in.ReadCount(p.count_type);
            if (n < 3)
                in.Fail("a face needs at least 3 vertices, this one has " + std::to_string(n));
            corners.clear();
            for (uint64_t k = 0; k < n; ++k) {
                const double v = in.Read(p.type);
                if (v < 0 || v >= static_cast<double>(vertex_count)) {
                    in.Fail("vertex index " + FormatDouble(v) + " is out of range (" +
                            std::to_string(vertex_count) + " vertices)");
                }
                corners.push_back(static_cast<uint32_t>(v));
            }
            for (size_t k = 1; k + 1 < corners.size(); ++k) {  // fan triangulation
                out.triangles.push_back({corners[0], corners[k], corners[k + 1]});
            }
        }
    }
}

void StoreValue(std::string& out, PlyType t, double v) {
    Dispatch(t, [&out, v]<typename T>(T) {
        char b[sizeof(T)];
        const T x = static_cast<T>(v);  // Validate() checked that v is a value of T
        std::memcpy(b, &x, sizeof(T));
        if constexpr (std::endian::native == std::endian::big) std::reverse(b, b + sizeof(T));
        out.append(b, sizeof(T));
    });
}

void AppendText(std::string& out, PlyType t, double v) {
    std::array<char, 40> buf{};
    std::to_chars_result res{};
    if (t == PlyType::kFloat32) {
        res = std::to_chars(buf.data(), buf.data() + buf.size(), static_cast<float>(v));
    } else if (t == PlyType::kFloat64) {
        res = std::to_chars(buf.data(), buf.data() + buf.size(), v);
    } else {
        res = std::to_chars(buf.data(), buf.data() + buf.size(), static_cast<int64_t>(v));
    }
    out.append(buf.data(), res.ptr);
}

void Validate(const PlyData& data) {
    auto fail = [](const std::string& what) { throw Error(StatusCode::kInvalidArgument, what); };
    const size_t n = data.vertices.size();
    if (n > static_cast<size_t>(std::numeric_limits<int32_t>::max())) {
        fail("more vertices than a PLY 'int' index can address");
    }
    for (size_t i = 0; i < data.vertex_properties.size(); ++i) {
        const PlyProperty& p = data.vertex_properties[i];
        const bool bad_name = p.name.empty() || p.name == "x" || p.name == "y" || p.name == "z" ||
                              p.name.find_first_of(" \t\r\n") != std::string::npos;
        if (bad_name) fail("vertex property name '" + p.name + "' is empty, x/y/z or has spaces");
        for (size_t j = 0; j < i; ++j) {
            if (data.vertex_properties[j].name == p.name) fail("property '" + p.name + "' twice");
        }
        if (p.values.size() != n) {
            fail("property '" + p.name + "' has " + std::to_string(p.values.size()) +
                 " values for " + std::to_string(n) + " vertices");
        }
        for (size_t k = 0; k < n; ++k) {
            if (!Representable(p.values[k], p.type)) {
                fail("property '" + p.name + "' vertex " + std::to_string(k) + ": " +
                     FormatDouble(p.values[k]) + " is not a " + std::string(Info(p.type).name));
            }
        }
    }
    for (size_t i = 0; i < n; ++i) {
        if (!data.vertices[i].allFinite()) fail("vertex " + std::to_string(i) + " is not finite");
    }
    for (size_t i = 0; i < data.triangles.size(); ++i) {
        for (uint32_t v : data.triangles[i]) {
            if (v >= n) fail("triangle " + std::to_string(i) + " has vertex index out of range");
        }
    }
}

template <typename T>
T Rethrow(const std::filesystem::path& path, auto&& f) {
    try {
        return f();
    } catch (const FileError&) {
        throw;
    } catch (const Error& e) {
        throw FileError(e.code(), path.string(), 0, e.what());
    }
}
}  // namespace

const PlyProperty* PlyData::Find(std::string_view name) const {
    for (const PlyProperty& p : vertex_properties) {
        if (p.name == name) return &p;
    }
    return nullptr;
}

PlyData ParsePly(const std::string& name, std::string_view bytes) {
    LineReader reader(name, bytes);
    const PlyHeader h = ParsePlyHeader(reader);
    const Element* vertex = nullptr;
    for (const Element& e : h.elements) {
        if (e.name == "vertex") vertex = &e;
    }
    if (vertex == nullptr) reader.Fail("no vertex element");
    for (std::string_view axis : {"x", "y", "z"}) {
        const bool found = std::any_of(vertex->props.begin(), vertex->props.end(),
                                       [axis](const Property& p) { return p.name == axis; });
        if (!found) reader.Fail("the vertex element has no property " + std::string(axis));
    }
    for (const Element& e : h.elements) {
        // PCL writes "element face 0" without properties for point clouds.
        if (e.name != "face" || e.count == 0) continue;
        const bool found = std::any_of(e.props.begin(), e.props.end(), [](const Property& p) {
            return p.is_list && (p.name == "vertex_indices" || p.name == "vertex_index") &&
                   !Info(p.type).is_float;
        });
        if (!found) reader.Fail("the face element has no integer list vertex_indices");
    }
    CheckSizes(reader, h, reader.Rest().size());
    PlyData out;
    ValueReader in(reader, h.format);
    for (const Element& e : h.elements) {
        if (&e == vertex) {
            ReadVertices(in, e, out);
        } else if (e.name == "face" && e.count > 0) {
            ReadFaces(in, e, vertex->count, out);
        } else {
            for (uint64_t i = 0; i < e.count && !e.props.empty(); ++i) {
                in.SetItem(e, i);
                for (const Property& p : e.props) {
                    if (p.is_list) {
                        SkipList(in, p);
                    } else {
                        in.Skip(p.type);
                    }
                }
            }
        }
    }
    in.CheckEnd();
    return out;
}

PlyData ReadPly(const std::filesystem::path& path) {
    const std::string bytes = ReadFileToString(path);
    return ParsePly(path.string(), bytes);
}

std::string SerializePly(const PlyData& data, PlyEncoding encoding) {
    Validate(data);
    const bool ascii = encoding == PlyEncoding::kAscii;
    std::string out = "ply\nformat ";
    out += ascii ? "ascii" : "binary_little_endian";
    out += " 1.0\ncomment bimslam\nelement vertex " + std::to_string(data.vertices.size()) +
           "\nproperty float x\nproperty float y\nproperty float z\n";
    for (const PlyProperty& p : data.vertex_properties) {
        out += "property " + std::string(Info(p.type).name) + " " + p.name + "\n";
    }
    if (!data.triangles.empty()) {
        out += "element face " + std::to_string(data.triangles.size()) +
               "\nproperty list uchar int vertex_indices\n";
    }
    out += "end_header\n";
    for (size_t i = 0; i < data.vertices.size(); ++i) {
        for (int k = 0; k < 3; ++k) {
            if (ascii) {
                if (k > 0) out += ' ';
                AppendText(out, PlyType::kFloat32, data.vertices[i][k]);
            } else {
                StoreValue(out, PlyType::kFloat32, data.vertices[i][k]);
            }
        }
        for (const PlyProperty& p : data.vertex_properties) {
            if (ascii) {
                out += ' ';
                AppendText(out, p.type, p.values[i]);
            } else {
                StoreValue(out, p.type, p.values[i]);
            }
        }
        if (ascii) out += '\n';
    }
    for (const auto& tri : data.triangles) {
        if (ascii) {
            out += '3';
            for (uint32_t v : tri) {
                out += ' ';
                AppendText(out, PlyType::kInt32, v);
            }
            out += '\n';
        } else {
            StoreValue(out, PlyType::kUint8, 3);
            for (uint32_t v : tri) StoreValue(out, PlyType::kInt32, v);
        }
    }
    return out;
}

void WritePly(const std::filesystem::path& path, const PlyData& data, PlyEncoding encoding) {
    const std::string bytes =
        Rethrow<std::string>(path, [&] { return SerializePly(data, encoding); });
    WriteFileAtomic(path, bytes);
}

PlyData ToPly(const common::PointCloud& cloud) {
    if (!cloud.ChannelsConsistent()) {
        throw Error(StatusCode::kInvalidArgument, "point cloud channels differ in length");
    }
    PlyData out;
    out.vertices = cloud.xyz;
    if (cloud.HasIntensity()) {
        out.vertex_properties.push_back({"intensity", PlyType::kFloat32, {}});
        out.vertex_properties.back().values.assign(cloud.intensity.begin(), cloud.intensity.end());
    }
    if (cloud.HasRing()) {
        out.vertex_properties.push_back({"ring", PlyType::kUint16, {}});
        out.vertex_properties.back().values.assign(cloud.ring.begin(), cloud.ring.end());
    }
    if (cloud.HasTime()) {
        out.vertex_properties.push_back({"t", PlyType::kFloat32, {}});
        for (uint32_t ns : cloud.time_offset_ns) {
            out.vertex_properties.back().values.push_back(PcdNsToSeconds(ns));
        }
    }
    return out;
}

common::PointCloud PointCloudFromPly(const PlyData& data) {
    const size_t n = data.vertices.size();
    auto fail = [](StatusCode code, const std::string& what) { throw Error(code, what); };
    const PlyProperty* intensity = data.Find("intensity");
    const PlyProperty* ring = data.Find("ring");
    const PlyProperty* t = data.Find("t");
    for (const PlyProperty* p : {intensity, ring, t}) {
        if (p != nullptr && p->values.size() != n) {
            fail(StatusCode::kInvalidArgument,
                 "property '" + p->name + "' has " + std::to_string(p->values.size()) +
                     " values for " + std::to_string(n) + " vertices");
        }
    }
    common::PointCloud cloud;
    cloud.xyz = data.vertices;
    cloud.Resize(n, intensity != nullptr, ring != nullptr, t != nullptr);
    const bool t_seconds = t != nullptr && Info(t->type).is_float;
    for (size_t i = 0; i < n; ++i) {
        if (intensity != nullptr) {
            cloud.intensity[i] = static_cast<float>(intensity->values[i]);
            if (!std::isfinite(cloud.intensity[i])) {
                fail(StatusCode::kOutOfRange,
                     "vertex " + std::to_string(i) + ": intensity is not a finite float");
            }
        }
        if (ring != nullptr) {
            if (!Representable(ring->values[i], PlyType::kUint16)) {
                fail(StatusCode::kOutOfRange, "vertex " + std::to_string(i) + ": ring " +
                                                  FormatDouble(ring->values[i]) +
                                                  " is not an integer in [0, 65535]");
            }
            cloud.ring[i] = static_cast<uint16_t>(ring->values[i]);
        }
        if (t != nullptr) {
            const double v = t->values[i];
            const double ns = t_seconds ? v * 1e9 : v;
            if (!(ns > -0.5 && ns < 4294967295.5 && (t_seconds || ns == std::floor(ns)))) {
                fail(StatusCode::kOutOfRange, "vertex " + std::to_string(i) + ": t " +
                                                  FormatDouble(v) + (t_seconds ? " s" : " ns") +
                                                  " is outside [0, 4.294967295] s");
            }
            cloud.time_offset_ns[i] =
                static_cast<uint32_t>(t_seconds ? PcdSecondsToNs(v) : static_cast<int64_t>(v));
        }
    }
    return cloud;
}

PlyData ToPly(const common::TriangleMesh& mesh) {
    PlyData out;
    out.vertices = mesh.vertices;
    out.triangles = mesh.triangles;
    return out;
}

common::TriangleMesh MeshFromPly(const PlyData& data) {
    common::TriangleMesh mesh;
    mesh.vertices = data.vertices;
    mesh.triangles = data.triangles;
    if (!mesh.IndicesValid()) {
        throw Error(StatusCode::kOutOfRange, "a triangle has a vertex index out of range");
    }
    return mesh;
}

}  // namespace bimslam::io
