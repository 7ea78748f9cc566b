// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The reader of algorithms/io/las.hpp: LAS 1.4, point format 6, uncompressed (what WriteLas
// writes, and any such file of another writer). Layouts: ASPRS LAS 1.4 R15 Tables 3, 4, 12, 24.
#include <cstring>

#include "algorithms/common/status.hpp"
#include "algorithms/io/file_util.hpp"
#include "algorithms/io/las.hpp"

namespace bimslam::io {
namespace {

template <typename T>
T Get(const char* p) {
    T v;
    std::memcpy(&v, p, sizeof v);
    return v;
}

std::string Text(const char* p, size_t field) {
    size_t n = 0;
    while (n < field && p[n] != '\0') ++n;
    return std::string(p, n);
}

double GetValue(const char* p, LasType t) {
    switch (t) {
        case LasType::kUint8:
            return Get<uint8_t>(p);
        case LasType::kInt8:
            return Get<int8_t>(p);
        case LasType::kUint16:
            return Get<uint16_t>(p);
        case LasType::kInt16:
            return Get<int16_t>(p);
        case LasType::kUint32:
            return Get<uint32_t>(p);
        case LasType::kInt32:
            return Get<int32_t>(p);
        case LasType::kUint64:
            return double(Get<uint64_t>(p));
        case LasType::kInt64:
            return double(Get<int64_t>(p));
        case LasType::kFloat32:
            return Get<float>(p);
        case LasType::kFloat64:
            return Get<double>(p);
    }
    return 0;
}

class Parser {
public:
    Parser(const std::string& name, std::string_view bytes) : name_(name), b_(bytes) {}

    [[noreturn]] void Fail(const std::string& what) const {
        throw common::FileError(common::StatusCode::kInvalidArgument, name_, 0, what);
    }

    LasData Parse() {
        if (b_.size() < 375) Fail("too short for a LAS 1.4 header (" + Size(b_.size()) + ")");
        const char* h = b_.data();
        if (std::memcmp(h, "LASF", 4) != 0) Fail("not a LAS file (no 'LASF' signature)");
        if (h[24] != 1 || h[25] != 4) {
            Fail("LAS " + std::to_string(int(h[24])) + "." + std::to_string(int(h[25])) +
                 ": only LAS 1.4 is read");
        }
        const auto format = Get<uint8_t>(h + 104);
        if (format & 0xC0) Fail("compressed (LAZ) point data: only uncompressed LAS is read");
        if (format != 6) Fail("point format " + std::to_string(format) + ": only 6 is read");
        LasData d;
        d.file_source_id = Get<uint16_t>(h + 4);
        d.adjusted_standard_gps_time = (Get<uint16_t>(h + 6) & 1) != 0;
        d.system_identifier = Text(h + 26, 32);
        d.generating_software = Text(h + 58, 32);
        d.creation_day_of_year = Get<uint16_t>(h + 90);
        d.creation_year = Get<uint16_t>(h + 92);
        const size_t header_size = Get<uint16_t>(h + 94);
        const size_t data_at = Get<uint32_t>(h + 96);
        const size_t vlrs = Get<uint32_t>(h + 100);
        length_ = Get<uint16_t>(h + 105);
        if (header_size < 375) Fail("header size " + std::to_string(header_size) + " < 375");
        if (length_ < 30) Fail("point record length " + std::to_string(length_) + " < 30");
        if (data_at < header_size) {
            Fail("point data at byte " + std::to_string(data_at) + ", inside the header");
        }
        const Eigen::Vector3d scale(Get<double>(h + 131), Get<double>(h + 139),
                                    Get<double>(h + 147));
        d.offset =
            Eigen::Vector3d(Get<double>(h + 155), Get<double>(h + 163), Get<double>(h + 171));
        if (!(scale.array() > 0).all() || !scale.allFinite() || !d.offset->allFinite())
            Fail("scale or offset is not finite and positive");
        if (scale.x() != scale.y() || scale.x() != scale.z())
            Fail("different scales per axis are not held by LasData");
        d.scale = scale.x();
        const uint64_t n = Get<uint64_t>(h + 247);
        ReadVlrs(header_size, vlrs, data_at, &d);
        if (data_at > b_.size() || n > (b_.size() - data_at) / length_) {
            Fail("truncated: " + std::to_string(n) + " points of " + std::to_string(length_) +
                 " bytes from byte " + std::to_string(data_at) + " need more than the file's " +
                 Size(b_.size()));
        }
        ReadPoints(data_at, size_t(n), &d);
        return d;
    }

private:
    static std::string Size(size_t n) { return std::to_string(n) + " bytes"; }

    void ReadVlrs(size_t at, size_t count, size_t data_at, LasData* d) {
        for (size_t k = 0; k < count; ++k) {
            if (at + 54 > data_at || at + 54 > b_.size())
                Fail("VLR " + std::to_string(k) + " runs into the point data");
            const char* v = b_.data() + at;
            const size_t len = Get<uint16_t>(v + 20);
            if (at + 54 + len > data_at) Fail("VLR " + std::to_string(k) + " is truncated");
            if (Text(v + 2, 16) == "LASF_Spec" && Get<uint16_t>(v + 18) == 4) {
                ReadExtraBytes(v + 54, len, d);
            }
            at += 54 + len;
        }
    }

    // R15 Table 24; a data type of 0 is undocumented bytes, as many as `options` says.
    void ReadExtraBytes(const char* p, size_t len, LasData* d) {
        if (len % 192 != 0) Fail("Extra Bytes VLR of " + Size(len) + ", not a multiple of 192");
        size_t at = 30;
        for (size_t k = 0; k < len / 192; ++k, p += 192) {
            const auto type = Get<uint8_t>(p + 2);
            const auto options = Get<uint8_t>(p + 3);
            if (type > 10)
                Fail("extra bytes field " + std::to_string(k) + " has type " +
                     std::to_string(type) + " (deprecated arrays are not read)");
            if (type == 0) {
                at += options;
                continue;
            }
            LasExtraField f;
            f.type = LasType(type);
            f.name = Text(p + 4, 32);
            f.description = Text(p + 160, 32);
            if (options & 1) {
                f.no_data = type >= 9 ? Get<double>(p + 40)
                            : (type == 1 || type == 3 || type == 5 || type == 7)
                                ? double(Get<uint64_t>(p + 40))
                                : double(Get<int64_t>(p + 40));
            }
            extra_at_.push_back(at);
            at += LasTypeSize(f.type);
            d->extra.push_back(std::move(f));
        }
        if (at > length_) {
            Fail("extra bytes of " + std::to_string(at - 30) + " bytes do not fit a record of " +
                 std::to_string(length_));
        }
    }

    void ReadPoints(size_t data_at, size_t n, LasData* d) const {
        d->xyz.resize(n);
        d->intensity.resize(n);
        d->classification.resize(n);
        d->user_data.resize(n);
        d->point_source_id.resize(n);
        d->gps_time.resize(n);
        for (auto& f : d->extra) f.values.resize(n);
        const char* r = b_.data() + data_at;
        for (size_t i = 0; i < n; ++i, r += length_) {
            for (int a = 0; a < 3; ++a) {
                d->xyz[i][a] = (*d->offset)[a] + Get<int32_t>(r + 4 * a) * d->scale;
            }
            d->intensity[i] = Get<uint16_t>(r + 12);
            d->classification[i] = Get<uint8_t>(r + 16);
            d->user_data[i] = Get<uint8_t>(r + 17);
            d->point_source_id[i] = Get<uint16_t>(r + 20);
            d->gps_time[i] = Get<double>(r + 22);
            for (size_t k = 0; k < d->extra.size(); ++k) {
                d->extra[k].values[i] = GetValue(r + extra_at_[k], d->extra[k].type);
            }
        }
    }

    const std::string& name_;
    std::string_view b_;
    size_t length_ = 0;
    std::vector<size_t> extra_at_;
};

}  // namespace

LasData ParseLas(const std::string& name, std::string_view bytes) {
    return Parser(name, bytes).Parse();
}

LasData ReadLas(const std::filesystem::path& path) {
    return ParseLas(path.string(), ReadFileToString(path));
}

}  // namespace bimslam::io
