// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/io/las.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <set>

#include "algorithms/common/status.hpp"
#include "algorithms/io/file_util.hpp"

namespace bimslam::io {
namespace {

// Every multi-byte field of LAS is little-endian; the project's targets (x86-64, aarch64) are too,
// so fields are copied as they are.
static_assert(std::endian::native == std::endian::little, "LAS fields are little-endian");

constexpr size_t kHeaderSize = 375;       // LAS 1.4 public header block (R15 Table 3)
constexpr size_t kVlrHeaderSize = 54;     // R15 Table 4
constexpr size_t kExtraBytesEntry = 192;  // R15 Table 24
constexpr size_t kFormat6Size = 30;       // R15 Table 12
constexpr uint16_t kExtraBytesRecordId = 4;
constexpr uint16_t kGlobalEncodingAdjustedGps = 1u << 0;
constexpr uint16_t kGlobalEncodingWkt = 1u << 4;  // "must be set" for formats 6-10 (R15 2.4)

[[noreturn]] void Invalid(const std::string& what) {
    throw common::Error(common::StatusCode::kInvalidArgument, "LAS: " + what);
}

template <typename T>
void Put(char* p, T v) {
    std::memcpy(p, &v, sizeof v);
}
void PutText(char* p, size_t field, std::string_view s, const char* what) {
    if (s.size() >= field) {
        Invalid(std::string(what) + " '" + std::string(s) + "' is longer than " +
                std::to_string(field - 1) + " characters");
    }
    std::memcpy(p, s.data(), s.size());  // the rest stays NUL
}

template <typename V>
void CheckLength(const V& v, size_t points, const char* what) {
    if (!v.empty() && v.size() != points) {
        Invalid(std::string(what) + " has " + std::to_string(v.size()) + " values for " +
                std::to_string(points) + " points");
    }
}

// The range of an integer type, as doubles (exact: every bound is an integer below 2^63, and the
// 64-bit types are limited to 2^53, where doubles stop being exact).
std::pair<double, double> IntegerRange(LasType t) {
    constexpr double k53 = 9007199254740992.0;
    switch (t) {
        case LasType::kUint8:
            return {0, 255};
        case LasType::kInt8:
            return {-128, 127};
        case LasType::kUint16:
            return {0, 65535};
        case LasType::kInt16:
            return {-32768, 32767};
        case LasType::kUint32:
            return {0, 4294967295.0};
        case LasType::kInt32:
            return {-2147483648.0, 2147483647.0};
        case LasType::kUint64:
            return {0, k53};
        case LasType::kInt64:
            return {-k53, k53};
        default:
            return {0, 0};
    }
}

bool IsFloat(LasType t) { return t == LasType::kFloat32 || t == LasType::kFloat64; }

void CheckField(const LasExtraField& f, size_t points) {
    const auto code = uint8_t(f.type);
    if (code < 1 || code > 10) Invalid("extra field '" + f.name + "' has no valid type");
    if (f.values.size() != points) {  // an empty map has fields of no values
        Invalid("extra field '" + f.name + "' has " + std::to_string(f.values.size()) +
                " values for " + std::to_string(points) + " points");
    }
    if (IsFloat(f.type)) {
        if (f.type == LasType::kFloat32) {
            for (double v : f.values) {
                if (std::isfinite(v) && std::abs(v) > std::numeric_limits<float>::max())
                    Invalid("extra field '" + f.name + "': " + std::to_string(v) +
                            " does not fit a float");
            }
        }
        return;
    }
    const std::pair<double, double> range = IntegerRange(f.type);  // clang 14 cannot capture
    const double lo = range.first, hi = range.second;              // structured bindings
    // In range first: then the cast is defined (and much cheaper than std::floor's call).
    const auto bad = [&](double v) { return !(v >= lo && v <= hi) || v != double(int64_t(v)); };
    for (double v : f.values) {
        if (bad(v))
            Invalid("extra field '" + f.name + "': " + std::to_string(v) +
                    " is not an integer its type holds");
    }
    if (f.no_data && bad(*f.no_data)) Invalid("extra field '" + f.name + "': bad no_data");
}

// values[first, last) as T at p, p + stride, ... (the type chosen once per block, not per value).
template <typename T>
void PutColumn(const std::vector<double>& values, size_t first, size_t last, char* p,
               size_t stride) {
    for (size_t i = first; i < last; ++i, p += stride) Put(p, T(values[i]));
}

void PutField(const LasExtraField& f, size_t first, size_t last, char* p, size_t stride) {
    const std::vector<double>& v = f.values;
    switch (f.type) {
        case LasType::kUint8:
            return PutColumn<uint8_t>(v, first, last, p, stride);
        case LasType::kInt8:
            return PutColumn<int8_t>(v, first, last, p, stride);
        case LasType::kUint16:
            return PutColumn<uint16_t>(v, first, last, p, stride);
        case LasType::kInt16:
            return PutColumn<int16_t>(v, first, last, p, stride);
        case LasType::kUint32:
            return PutColumn<uint32_t>(v, first, last, p, stride);
        case LasType::kInt32:
            return PutColumn<int32_t>(v, first, last, p, stride);
        case LasType::kUint64:
            return PutColumn<uint64_t>(v, first, last, p, stride);
        case LasType::kInt64:
            return PutColumn<int64_t>(v, first, last, p, stride);
        case LasType::kFloat32:
            return PutColumn<float>(v, first, last, p, stride);
        case LasType::kFloat64:
            return PutColumn<double>(v, first, last, p, stride);
    }
}

// One Extra Bytes descriptor (R15 Table 24): reserved[2], data_type, options, name[32],
// unused[4], no_data (8: int64/uint64 for integers, double for floats), 16 deprecated, min, 16,
// max, 16, scale, 16, offset, 16, description[32].
void PutDescriptor(char* p, const LasExtraField& f) {
    Put(p + 2, uint8_t(f.type));
    Put(p + 3, uint8_t(f.no_data ? 1 : 0));
    PutText(p + 4, 32, f.name, "extra field name");
    if (f.no_data) {
        if (IsFloat(f.type)) {
            Put(p + 40, *f.no_data);
        } else if (f.type == LasType::kUint8 || f.type == LasType::kUint16 ||
                   f.type == LasType::kUint32 || f.type == LasType::kUint64) {
            Put(p + 40, uint64_t(*f.no_data));
        } else {
            Put(p + 40, int64_t(*f.no_data));
        }
    }
    PutText(p + 160, 32, f.description, "extra field description");
}

// Where everything goes, found before anything is written: the record's layout, the offset and
// the coordinates' bounds (the header comes first in the file and holds them).
struct Layout {
    size_t length = kFormat6Size;  // bytes per point record
    std::vector<size_t> extra_at;  // each extra field's place in the record
    size_t data_at = kHeaderSize;  // where the point records start
    Eigen::Vector3d offset = Eigen::Vector3d::Zero();
    Eigen::Vector3i lo = Eigen::Vector3i::Zero(), hi = Eigen::Vector3i::Zero();  // counts
};

// A coordinate as counts of the scale from the offset, rounded to nearest (half away from zero;
// a cast instead of std::nearbyint's call, which took a third of the writer's time). `c` must be
// within int32 (Plan checks every coordinate's range once).
inline int32_t Round(double c) { return int32_t(c < 0 ? c - 0.5 : c + 0.5); }

// Throws unless every coordinate along axis `a`, in [lo, hi], fits int32 counts.
void CheckFits(const LasData& d, double lo, double hi, double offset, int a) {
    for (const double v : {lo, hi}) {
        const double c = (v - offset) / d.scale;
        if (!(c > -2147483648.5 && c < 2147483647.5)) {
            Invalid(std::string("a coordinate along ") + "xyz"[a] + " (" + std::to_string(v) +
                    ") does not fit int32 counts of " + std::to_string(d.scale) +
                    " m from the offset " + std::to_string(offset));
        }
    }
}

// The point records of points [first, last) into `out`.
void PutPoints(const LasData& d, const Layout& l, size_t first, size_t last, char* out) {
    const double inv = 1.0 / d.scale;
    for (size_t i = first; i < last; ++i) {
        char* r = out + (i - first) * l.length;
        for (int a = 0; a < 3; ++a) Put(r + 4 * a, Round((d.xyz[i][a] - l.offset[a]) * inv));
        Put(r + 12, d.intensity.empty() ? uint16_t(0) : d.intensity[i]);
        Put(r + 14, uint8_t(0x11));  // return 1 of 1
        Put(r + 15, uint8_t(0));     // classification flags, channel, scan direction, edge
        Put(r + 16, d.classification.empty() ? uint8_t(0) : d.classification[i]);
        Put(r + 17, d.user_data.empty() ? uint8_t(0) : d.user_data[i]);
        Put(r + 18, int16_t(0));  // scan angle: not known for a merged map
        Put(r + 20, d.point_source_id.empty() ? uint16_t(0) : d.point_source_id[i]);
        Put(r + 22, d.gps_time.empty() ? 0.0 : d.gps_time[i]);
    }
    // Extra fields column by column over the block (the block stays in cache).
    for (size_t k = 0; k < d.extra.size(); ++k) {
        PutField(d.extra[k], first, last, out + l.extra_at[k], l.length);
    }
}

void CheckData(const LasData& d) {
    const size_t n = d.size();
    CheckLength(d.intensity, n, "intensity");
    CheckLength(d.classification, n, "classification");
    CheckLength(d.user_data, n, "user_data");
    CheckLength(d.point_source_id, n, "point_source_id");
    CheckLength(d.gps_time, n, "gps_time");
    if (!(d.scale > 0) || !std::isfinite(d.scale)) Invalid("the scale must be positive");
    for (size_t i = 0; i < d.gps_time.size(); ++i) {
        if (!std::isfinite(d.gps_time[i]))
            Invalid("point " + std::to_string(i) + " has a non-finite time");
    }
    std::set<std::string> names;
    for (const LasExtraField& f : d.extra) {
        if (!names.insert(f.name).second) Invalid("extra field '" + f.name + "' appears twice");
        CheckField(f, n);
    }
}

// Checks the data and finds its layout and bounds (every coordinate counted once here).
Layout Plan(const LasData& d) {
    CheckData(d);
    Layout l;
    for (const LasExtraField& f : d.extra) {
        l.extra_at.push_back(l.length);
        l.length += LasTypeSize(f.type);
    }
    if (l.length > 65535) Invalid("a point record of " + std::to_string(l.length) + " bytes");
    if (!d.extra.empty()) l.data_at += kVlrHeaderSize + kExtraBytesEntry * d.extra.size();
    if (d.xyz.empty()) {
        l.offset = d.offset.value_or(Eigen::Vector3d::Zero());
        return l;
    }
    // The bounding box, one pass (rounding is monotonic: the box's corners' counts bound every
    // point's, and when they fit every point fits).
    Eigen::Vector3d lo = d.xyz[0], hi = d.xyz[0];
    for (const Eigen::Vector3d& p : d.xyz) {
        if (!p.allFinite()) Invalid("a coordinate is not finite");
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    // The offset: the minimum's whole metre unless given.
    l.offset = d.offset.value_or(Eigen::Vector3d(lo.array().floor()));
    const double inv = 1.0 / d.scale;
    for (int a = 0; a < 3; ++a) {
        CheckFits(d, lo[a], hi[a], l.offset[a], a);
        l.lo[a] = Round((lo[a] - l.offset[a]) * inv);
        l.hi[a] = Round((hi[a] - l.offset[a]) * inv);
    }
    return l;
}

// The public header block (R15 Table 3) and the Extra Bytes VLR: l.data_at bytes at h (zeroed).
void PutHeader(const LasData& d, const Layout& l, char* h) {
    std::memcpy(h, "LASF", 4);
    Put(h + 4, d.file_source_id);
    Put(h + 6, uint16_t(kGlobalEncodingWkt |
                        (d.adjusted_standard_gps_time ? kGlobalEncodingAdjustedGps : 0)));
    // 8..23: project GUID, left zero (optional).
    Put(h + 24, uint8_t(1));
    Put(h + 25, uint8_t(4));
    PutText(h + 26, 32, d.system_identifier, "system identifier");
    PutText(h + 58, 32, d.generating_software, "generating software");
    Put(h + 90, d.creation_day_of_year);
    Put(h + 92, d.creation_year);
    Put(h + 94, uint16_t(kHeaderSize));
    Put(h + 96, uint32_t(l.data_at));
    Put(h + 100, uint32_t(d.extra.empty() ? 0 : 1));
    Put(h + 104, uint8_t(6));
    Put(h + 105, uint16_t(l.length));
    // 107..130: legacy point counts, zero for formats 6-10 (R15 Table 3 notes).
    for (int a = 0; a < 3; ++a) {
        Put(h + 131 + 8 * a, d.scale);
        Put(h + 155 + 8 * a, l.offset[a]);
        Put(h + 179 + 16 * a, l.offset[a] + l.hi[a] * d.scale);  // max x, min x, max y, ...
        Put(h + 187 + 16 * a, l.offset[a] + l.lo[a] * d.scale);
    }
    // 227: waveform data, 235: first EVLR, 243: number of EVLRs: none.
    Put(h + 247, uint64_t(d.size()));
    Put(h + 255, uint64_t(d.size()));  // every point is return 1 (of 1)
    if (d.extra.empty()) return;
    char* v = h + kHeaderSize;
    PutText(v + 2, 16, "LASF_Spec", "user id");
    Put(v + 18, kExtraBytesRecordId);
    Put(v + 20, uint16_t(kExtraBytesEntry * d.extra.size()));
    PutText(v + 22, 32, "bimslam fields", "VLR description");
    for (size_t k = 0; k < d.extra.size(); ++k) {
        PutDescriptor(v + kVlrHeaderSize + k * kExtraBytesEntry, d.extra[k]);
    }
}

constexpr size_t kBlock = 4096;  // points encoded at a time: 180 kB of 44-byte records

}  // namespace

size_t LasTypeSize(LasType type) {
    switch (type) {
        case LasType::kUint8:
        case LasType::kInt8:
            return 1;
        case LasType::kUint16:
        case LasType::kInt16:
            return 2;
        case LasType::kUint32:
        case LasType::kInt32:
        case LasType::kFloat32:
            return 4;
        default:
            return 8;
    }
}

const LasExtraField* LasData::Find(std::string_view name) const {
    for (const LasExtraField& f : extra) {
        if (f.name == name) return &f;
    }
    return nullptr;
}

std::string SerializeLas(const LasData& d) {
    const Layout l = Plan(d);
    const size_t n = d.size();
    std::string out(l.data_at + n * l.length, '\0');
    PutHeader(d, l, out.data());
    for (size_t first = 0; first < n; first += kBlock) {
        PutPoints(d, l, first, std::min(n, first + kBlock),
                  out.data() + l.data_at + first * l.length);
    }
    return out;
}

// Streamed: the header, then 64 blocks of points at a time (11 MB of 44-byte records), so that
// a map of 10^7 points (440 MB) is never held in memory a second time; written past the page
// cache (Cache::kBypass), which took most of the time (algorithms/io/README.md, "Large files").
void WriteLas(const std::filesystem::path& path, const LasData& d) {
    try {
        const Layout l = Plan(d);
        std::string buffer(l.data_at, '\0');
        PutHeader(d, l, buffer.data());
        const size_t n = d.size(), chunk = 64 * kBlock;
        size_t next_point = 0;
        bool header = true;
        const auto next = [&]() -> std::string_view {
            if (header) {
                header = false;
                return buffer;
            }
            if (next_point >= n) return {};
            const size_t last = std::min(n, next_point + chunk);
            buffer.resize((last - next_point) * l.length);
            for (size_t first = next_point; first < last; first += kBlock) {
                PutPoints(d, l, first, std::min(last, first + kBlock),
                          buffer.data() + (first - next_point) * l.length);
            }
            next_point = last;
            return buffer;
        };
        WriteFileAtomic(path, next, Sync::kNow, Cache::kBypass);
    } catch (const common::FileError&) {
        throw;
    } catch (const common::Error& e) {
        throw common::FileError(common::StatusCode::kInvalidArgument, path.string(), 0, e.what());
    }
}

double UnixNsToAdjustedGpsSeconds(int64_t unix_ns) {
    using std::chrono::sys_days;
    using namespace std::chrono_literals;
    // The UTC days from which GPS - UTC grew by one second (IERS Bulletin C; 18 s since 2017).
    static const std::array<sys_days, 18> kLeaps = {
        sys_days{1981y / 7 / 1}, sys_days{1982y / 7 / 1}, sys_days{1983y / 7 / 1},
        sys_days{1985y / 7 / 1}, sys_days{1988y / 1 / 1}, sys_days{1990y / 1 / 1},
        sys_days{1991y / 1 / 1}, sys_days{1992y / 7 / 1}, sys_days{1993y / 7 / 1},
        sys_days{1994y / 7 / 1}, sys_days{1996y / 1 / 1}, sys_days{1997y / 7 / 1},
        sys_days{1999y / 1 / 1}, sys_days{2006y / 1 / 1}, sys_days{2009y / 1 / 1},
        sys_days{2012y / 7 / 1}, sys_days{2015y / 7 / 1}, sys_days{2017y / 1 / 1}};
    constexpr int64_t kNs = 1'000'000'000;
    const auto seconds_of = [](sys_days d) {
        return int64_t(
            std::chrono::duration_cast<std::chrono::seconds>(d.time_since_epoch()).count());
    };
    const int64_t gps_epoch = seconds_of(sys_days{1980y / 1 / 6});
    int64_t leap = 0;
    for (sys_days d : kLeaps) leap += unix_ns >= seconds_of(d) * kNs ? 1 : 0;
    const int64_t adjusted_ns = unix_ns - gps_epoch * kNs + leap * kNs - 1'000'000'000 * kNs;
    return double(adjusted_ns / kNs) + double(adjusted_ns % kNs) * 1e-9;
}

void SetLasCreationDate(LasData& data, int64_t unix_ns) {
    using namespace std::chrono;
    const sys_days day = floor<days>(sys_time<nanoseconds>(nanoseconds(unix_ns)));
    const year_month_day ymd(day);
    data.creation_year = uint16_t(int(ymd.year()));
    data.creation_day_of_year = uint16_t((day - sys_days(ymd.year() / 1 / 1)).count() + 1);
}

}  // namespace bimslam::io
