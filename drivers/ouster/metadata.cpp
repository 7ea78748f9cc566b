// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Ouster metadata JSON, both layouts (specs/ouster-lidar.md, "Metadata JSON: two layouts").
//
// Both layouts are first mapped onto one set of logical fields (Layout), each carrying the dotted
// path it has in this file; the checks and defaults then exist once, and every message names the
// field as the file spells it. Where the spec is silent we follow the Ouster SDK's parser
// (ouster_client types.cpp / metadata.cpp), for facts only.
#include "drivers/ouster/metadata.hpp"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string_view>
#include <vector>

#include "algorithms/common/status.hpp"

namespace bimslam::ouster {
namespace {
using common::FileError;
using common::StatusCode;
using nlohmann::json;

// The nested layout's sections. A nested file has all seven (the SDK's is_new_format rule); the
// first five are objects, while lidar_data_format and calibration_status may hold the error
// string FW 1.x answered with ("error: Command not recognized.").
constexpr std::array<std::string_view, 7> kNestedSections{
    "sensor_info",   "beam_intrinsics",   "imu_intrinsics",     "lidar_intrinsics",
    "config_params", "lidar_data_format", "calibration_status",
};
constexpr size_t kNestedObjectSections = 5;
// Top-level keys only the flat layout has (the nested layout keeps them inside its sections).
constexpr std::array<std::string_view, 14> kFlatFields{
    "beam_altitude_angles",
    "beam_azimuth_angles",
    "lidar_origin_to_beam_origin_mm",
    "beam_to_lidar_transform",
    "lidar_to_sensor_transform",
    "imu_to_sensor_transform",
    "lidar_mode",
    "data_format",
    "prod_line",
    "prod_sn",
    "build_rev",
    "initialization_id",
    "udp_port_lidar",
    "udp_port_imu",
};

// The lidar modes the SDK knows (lidar_mode_strings): columns per frame and frames per second.
struct LidarMode {
    int columns;
    int rate_hz;
};
constexpr std::array<LidarMode, 6> kLidarModes{
    {{512, 10}, {512, 20}, {1024, 10}, {1024, 20}, {2048, 10}, {4096, 5}}};

constexpr uint64_t kMaxProdSn = (uint64_t{1} << 40) - 1;  // packet header prod_sn is 40 bits
constexpr int64_t kMaxInitId = (int64_t{1} << 24) - 1;    // packet header init_id is 24 bits
// An ACCEL32_GYRO32_NMEA packet is 164 B + 36 B per sample and must fit one UDP datagram.
constexpr int64_t kMaxImuSamples = (65507 - 164) / 36;

// Defaults of the spec ("Metadata JSON", defaults), equal to the SDK's.
Eigen::Matrix4d DefaultLidarToSensor() {
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    m(0, 0) = -1.0;  // 180 degrees about Z
    m(1, 1) = -1.0;
    m(2, 3) = 36.18;
    return m;
}
Eigen::Matrix4d DefaultImuToSensor() {
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    m.block<3, 1>(0, 3) << 6.253, -11.775, 7.645;
    return m;
}
// By product line, as the SDK's default_lidar_origin_to_beam_origin: a prod_line that names no
// known family gets the gen-1 OS1 value; OS-DOME has no offset (SDK parse_legacy).
double DefaultBeamOriginMm(const std::string& prod_line) {
    if (prod_line.starts_with("OS-0-")) return 27.67;
    if (prod_line.starts_with("OS-1-")) return 15.806;
    if (prod_line.starts_with("OS-2-")) return 13.762;
    if (prod_line.starts_with("OS-DOME-")) return 0.0;
    return 12.163;
}

std::string Printable(std::string_view s, size_t max = 60) {
    std::string out;
    for (const char c : s.substr(0, max)) {
        const auto u = static_cast<unsigned char>(c);
        out += (u < 0x20 || u == 0x7f) ? '?' : c;
    }
    if (s.size() > max) out += "...";
    return out;
}

// A value for messages. Containers are only described: dumping them would recurse as deep as
// the input nests.
std::string Describe(const json& v) {
    switch (v.type()) {
        case json::value_t::array:
            return "an array of " + std::to_string(v.size());
        case json::value_t::object:
            return "an object";
        case json::value_t::string:
            return "string \"" + Printable(v.get_ref<const std::string&>()) + "\"";
        case json::value_t::number_float:
            // dump() would print a non-finite number as null.
            if (!std::isfinite(v.get<double>())) return v.get<double>() > 0 ? "inf" : "-inf";
            return v.dump();
        default:
            return v.dump();  // integer, boolean, null
    }
}

// A value in the document and its dotted path. `value` is null when the key is absent or JSON
// null: the SDK treats both as "not given".
struct JsonField {
    const json* value = nullptr;
    std::string path;
    explicit operator bool() const { return value != nullptr; }
};

JsonField Child(const JsonField& parent, std::string_view key) {
    JsonField f;
    f.path = parent.path.empty() ? std::string(key) : parent.path + "." + std::string(key);
    if (parent && parent.value->is_object()) {
        const auto it = parent.value->find(std::string(key));
        if (it != parent.value->end() && !it->is_null()) f.value = &*it;
    }
    return f;
}

// Typed reads that throw FileError naming the file and the field.
class Reader {
public:
    explicit Reader(const std::string& file) : file_(file) {}

    [[noreturn]] void Fail(const std::string& message) const {
        throw FileError(StatusCode::kParseError, file_, 0, message);
    }
    [[noreturn]] void Fail(const JsonField& f, const std::string& what) const {
        Fail(f.path + ": " + what);
    }

    const json& Required(const JsonField& f) const {
        if (!f) Fail(f, "is missing");
        return *f.value;
    }
    const json& Object(const JsonField& f) const {
        const json& v = Required(f);
        if (!v.is_object()) Fail(f, "must be an object, not " + Describe(v));
        return v;
    }
    std::string String(const JsonField& f) const {
        const json& v = Required(f);
        if (!v.is_string()) Fail(f, "must be a string, not " + Describe(v));
        return v.get<std::string>();
    }
    double Number(const JsonField& f) const {
        const json& v = Required(f);
        if (!v.is_number()) Fail(f, "must be a number, not " + Describe(v));
        const double d = v.get<double>();
        // nlohmann refuses overflowing numbers while parsing; kept so no caller can get inf.
        if (!std::isfinite(d)) Fail(f, "must be finite, not " + Describe(v));
        return d;
    }
    int64_t Integer(const JsonField& f, int64_t lo, int64_t hi) const {
        const json& v = Required(f);
        bool ok = false;
        int64_t i = 0;
        if (v.is_number_unsigned()) {
            ok = v.get<uint64_t>() <= static_cast<uint64_t>(hi);
            i = ok ? static_cast<int64_t>(v.get<uint64_t>()) : 0;
        } else if (v.is_number_integer()) {
            i = v.get<int64_t>();
            ok = i <= hi;
        }
        if (!ok || i < lo) {
            Fail(f, "must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                        "], not " + Describe(v));
        }
        return i;
    }
    // Elements of an array, with their paths ("field[3]").
    std::vector<JsonField> Items(const JsonField& f) const {
        const json& v = Required(f);
        if (!v.is_array()) Fail(f, "must be an array, not " + Describe(v));
        std::vector<JsonField> items;
        for (size_t i = 0; i < v.size(); ++i) {
            items.push_back({&v[i], f.path + "[" + std::to_string(i) + "]"});
        }
        return items;
    }
    std::vector<double> Numbers(const JsonField& f) const {
        std::vector<double> out;
        for (const JsonField& item : Items(f)) out.push_back(Number(item));
        return out;
    }
    // A row-major 4x4 with translation in mm; the last row must be 0 0 0 1 (a rigid transform).
    Eigen::Matrix4d Transform(const JsonField& f) const {
        const std::vector<double> v = Numbers(f);
        if (v.size() != 16) {
            Fail(f, std::to_string(v.size()) + " entries, a row-major 4x4 matrix has 16");
        }
        Eigen::Matrix4d m;
        for (int r = 0; r < 4; ++r) {
            for (int c = 0; c < 4; ++c) m(r, c) = v[static_cast<size_t>(4 * r + c)];
        }
        if (m(3, 0) != 0.0 || m(3, 1) != 0.0 || m(3, 2) != 0.0 || m(3, 3) != 1.0) {
            std::ostringstream row;
            row << m(3, 0) << " " << m(3, 1) << " " << m(3, 2) << " " << m(3, 3);
            Fail(f, "last row is " + row.str() + ", not 0 0 0 1");
        }
        return m;
    }

private:
    const std::string& file_;
};

// Where each logical field lives in this file's layout.
struct Layout {
    JsonField altitude, azimuth, beam_origin_mm, beam_to_lidar, lidar_to_sensor, imu_to_sensor;
    JsonField lidar_mode, prod_line, prod_sn, build_rev, init_id, port_lidar, port_imu;
    JsonField data_format;  // absent: firmware before 2.0 (no data format; spec defaults)
    JsonField imu_data_format;
};

std::string Join(const std::vector<std::string>& v) {
    std::string s;
    for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
    return s;
}

Layout DetectLayout(const Reader& r, const json& root) {
    if (!root.is_object()) r.Fail("the top level must be a JSON object, not " + Describe(root));
    std::vector<std::string> nested, missing, flat;
    for (const auto key : kNestedSections) {
        (root.contains(std::string(key)) ? nested : missing).emplace_back(key);
    }
    for (const auto key : kFlatFields) {
        if (root.contains(std::string(key))) flat.emplace_back(key);
    }
    if (!nested.empty() && !flat.empty()) {
        r.Fail("mixes the two metadata layouts: nested-layout sections (" + Join(nested) +
               ") next to flat (legacy) layout fields (" + Join(flat) +
               "); a file has one layout or the other");
    }
    if (!nested.empty() && !missing.empty()) {
        r.Fail(missing.front() + ": is missing; the nested layout has all of " +
               "sensor_info, beam_intrinsics, imu_intrinsics, lidar_intrinsics, config_params, " +
               "lidar_data_format, calibration_status (missing: " + Join(missing) + ")");
    }
    const JsonField top{&root, ""};
    Layout l;
    l.imu_data_format = Child(top, "imu_data_format");
    if (nested.empty()) {
        if (flat.empty()) {
            r.Fail(
                "not Ouster sensor metadata: none of the flat layout's fields (lidar_mode, "
                "beam_altitude_angles, ...) and none of the nested layout's sections "
                "(sensor_info, config_params, ...)");
        }
        l.altitude = Child(top, "beam_altitude_angles");
        l.azimuth = Child(top, "beam_azimuth_angles");
        l.beam_origin_mm = Child(top, "lidar_origin_to_beam_origin_mm");
        l.beam_to_lidar = Child(top, "beam_to_lidar_transform");
        l.lidar_to_sensor = Child(top, "lidar_to_sensor_transform");
        l.imu_to_sensor = Child(top, "imu_to_sensor_transform");
        l.lidar_mode = Child(top, "lidar_mode");
        l.prod_line = Child(top, "prod_line");
        l.prod_sn = Child(top, "prod_sn");
        l.build_rev = Child(top, "build_rev");
        l.init_id = Child(top, "initialization_id");
        l.port_lidar = Child(top, "udp_port_lidar");
        l.port_imu = Child(top, "udp_port_imu");
        l.data_format = Child(top, "data_format");
        return l;
    }
    for (size_t i = 0; i < kNestedObjectSections; ++i) r.Object(Child(top, kNestedSections[i]));
    const JsonField sensor = Child(top, "sensor_info"), beams = Child(top, "beam_intrinsics"),
                    config = Child(top, "config_params");
    l.altitude = Child(beams, "beam_altitude_angles");
    l.azimuth = Child(beams, "beam_azimuth_angles");
    l.beam_origin_mm = Child(beams, "lidar_origin_to_beam_origin_mm");
    l.beam_to_lidar = Child(beams, "beam_to_lidar_transform");
    l.lidar_to_sensor = Child(Child(top, "lidar_intrinsics"), "lidar_to_sensor_transform");
    l.imu_to_sensor = Child(Child(top, "imu_intrinsics"), "imu_to_sensor_transform");
    l.lidar_mode = Child(config, "lidar_mode");
    l.prod_line = Child(sensor, "prod_line");
    l.prod_sn = Child(sensor, "prod_sn");
    l.build_rev = Child(sensor, "build_rev");
    l.init_id = Child(sensor, "initialization_id");
    l.port_lidar = Child(config, "udp_port_lidar");
    l.port_imu = Child(config, "udp_port_imu");
    l.data_format = Child(top, "lidar_data_format");
    // FW 1.x had no data format and wrote its error reply there: same as absent.
    if (l.data_format && l.data_format.value->is_string()) l.data_format.value = nullptr;
    return l;
}

// "v2.1.1", "v2.2.0-rc.2-17-gbc0879e", "v1.14.0-beta.1-928-g6cccd78": major.minor.patch first.
bool ParseFirmware(const std::string& s, int* major, int* minor, int* patch) {
    size_t i = (!s.empty() && (s[0] == 'v' || s[0] == 'V')) ? 1 : 0;
    int* parts[3] = {major, minor, patch};
    for (int k = 0; k < 3; ++k) {
        if (k > 0) {
            if (i >= s.size() || s[i] != '.') return false;
            ++i;
        }
        const size_t start = i;
        int value = 0;
        while (i < s.size() && s[i] >= '0' && s[i] <= '9' && i - start < 6) {
            value = value * 10 + (s[i] - '0');
            ++i;
        }
        if (i == start || (i < s.size() && s[i] >= '0' && s[i] <= '9')) return false;
        *parts[k] = value;
    }
    return true;
}

uint64_t ParseProdSn(const Reader& r, const JsonField& f) {
    const json& v = r.Required(f);
    if (v.is_number_integer()) return static_cast<uint64_t>(r.Integer(f, 0, kMaxProdSn));
    const std::string s = r.String(f);
    uint64_t sn = 0;
    for (const char c : s) {
        if (c < '0' || c > '9') r.Fail(f, Describe(v) + " is not a serial number (digits only)");
        sn = sn * 10 + static_cast<uint64_t>(c - '0');
        if (sn > kMaxProdSn) {
            r.Fail(f, Describe(v) + " does not fit the 40-bit prod_sn of the packet header");
        }
    }
    return sn;  // "" (seen in real files' neighbours) is unknown: 0
}

std::optional<uint16_t> ParsePort(const Reader& r, const JsonField& f) {
    if (!f) return std::nullopt;
    // 0 is what the SDK stores for "not given" (parse_legacy: asInt() of an absent key).
    const int64_t port = r.Integer(f, 0, 65535);
    if (port == 0) return std::nullopt;
    return static_cast<uint16_t>(port);
}

// No data format (FW < 2.0): the SDK's default_data_format. Those sensors send 64-pixel columns
// whatever their beam count, 16 columns a packet, and stagger gen-1 OS1 beams in a 4-row pattern
// of 3 * W / 512 columns per step ({18, 12, 6, 0} at 1024 columns).
DataFormat DefaultDataFormat(int columns) {
    DataFormat f;
    f.pixels_per_column = 64;
    f.columns_per_packet = 16;
    f.columns_per_frame = columns;
    const int step = 3 * columns / 512;
    for (int u = 0; u < f.pixels_per_column; ++u)
        f.pixel_shift_by_row.push_back(step * (3 - u % 4));
    f.column_window_first = 0;
    f.column_window_last = columns - 1;
    return f;
}

DataFormat ParseDataFormat(const Reader& r, const JsonField& df, const JsonField& mode_field,
                           int mode_columns) {
    r.Object(df);
    DataFormat f;
    const auto one_of = [&](const JsonField& field, int64_t v, std::initializer_list<int> allowed) {
        if (std::find(allowed.begin(), allowed.end(), v) != allowed.end()) return;
        std::string list;
        for (const int a : allowed) list += (list.empty() ? "" : ", ") + std::to_string(a);
        r.Fail(field, std::to_string(v) + " is not one of " + list);
    };
    const JsonField h = Child(df, "pixels_per_column"), cpp = Child(df, "columns_per_packet"),
                    w = Child(df, "columns_per_frame");
    f.pixels_per_column = static_cast<int>(r.Integer(h, 0, 1 << 20));
    one_of(h, f.pixels_per_column, {16, 32, 64, 128});
    f.columns_per_frame = static_cast<int>(r.Integer(w, 0, 1 << 20));
    one_of(w, f.columns_per_frame, {512, 1024, 2048, 4096});
    if (f.columns_per_frame != mode_columns) {
        r.Fail(w, std::to_string(f.columns_per_frame) + " does not match " + mode_field.path +
                      " (" + std::to_string(mode_columns) + " columns)");
    }
    f.columns_per_packet = static_cast<int>(r.Integer(cpp, 0, 1 << 20));
    one_of(cpp, f.columns_per_packet, {8, 16, 32, 64});  // all of them divide every W above

    const JsonField shift = Child(df, "pixel_shift_by_row");
    if (shift) {
        const std::vector<JsonField> items = r.Items(shift);
        if (items.size() != static_cast<size_t>(f.pixels_per_column)) {
            r.Fail(shift, std::to_string(items.size()) + " entries, but pixels_per_column is " +
                              std::to_string(f.pixels_per_column));
        }
        const int w1 = f.columns_per_frame - 1;
        for (const JsonField& item : items) {
            f.pixel_shift_by_row.push_back(static_cast<int>(r.Integer(item, -w1, w1)));
        }
    } else {
        // The SDK's parse_data_format fills zeros when the row shifts are not given.
        f.pixel_shift_by_row.assign(static_cast<size_t>(f.pixels_per_column), 0);
    }

    f.column_window_first = 0;
    f.column_window_last = f.columns_per_frame - 1;
    const JsonField window = Child(df, "column_window");
    if (window) {
        const std::vector<JsonField> ends = r.Items(window);
        if (ends.size() != 2) {
            r.Fail(window, std::to_string(ends.size()) + " entries, a column window has 2");
        }
        f.column_window_first = static_cast<int>(r.Integer(ends[0], 0, f.columns_per_frame - 1));
        f.column_window_last = static_cast<int>(r.Integer(ends[1], 0, f.columns_per_frame - 1));
    }

    const JsonField lidar_profile = Child(df, "udp_profile_lidar");
    if (lidar_profile) {
        const auto p = ParseLidarProfile(r.String(lidar_profile));
        if (!p) r.Fail(lidar_profile, Describe(*lidar_profile.value) + " is not a known profile");
        f.lidar_profile = *p;
    }
    const JsonField imu_profile = Child(df, "udp_profile_imu");
    if (imu_profile) {
        const auto p = ParseImuProfile(r.String(imu_profile));
        if (!p) r.Fail(imu_profile, Describe(*imu_profile.value) + " is not a known profile");
        f.imu_profile = *p;
    }
    // header_type exists from FW 3.2; before, the FUSA profile implied FUSA headers (SDK).
    const JsonField header = Child(df, "header_type");
    if (header) {
        const auto t = ParseHeaderType(r.String(header));
        if (!t) r.Fail(header, Describe(*header.value) + " is not STANDARD or FUSA");
        f.header_type = *t;
    } else if (f.lidar_profile == LidarProfile::kFusaRng15Rfl8Nir8Dual) {
        f.header_type = HeaderType::kFusa;
    }
    return f;
}

// Beam angles: exactly H finite entries within range, not all zero (the SDK refuses all-zero
// arrays: "cannot all be zeros", the mark of an uncalibrated or blanked sensor).
std::vector<double> ParseAngles(const Reader& r, const JsonField& f, int pixels_per_column,
                                bool default_format, double limit_deg) {
    std::vector<double> angles = r.Numbers(f);
    if (angles.size() != static_cast<size_t>(pixels_per_column)) {
        r.Fail(f, std::to_string(angles.size()) + " entries, but pixels_per_column is " +
                      std::to_string(pixels_per_column) +
                      (default_format ? " (no data format: firmware before 2.0 sends 64-pixel "
                                        "columns and pads the angles to 64)"
                                      : ""));
    }
    for (size_t i = 0; i < angles.size(); ++i) {
        if (std::abs(angles[i]) > limit_deg) {
            r.Fail(f.path + "[" + std::to_string(i) + "]: " + Describe(*r.Items(f)[i].value) +
                   " degrees is outside [-" + std::to_string(static_cast<int>(limit_deg)) + ", " +
                   std::to_string(static_cast<int>(limit_deg)) + "]");
        }
    }
    if (std::all_of(angles.begin(), angles.end(), [](double a) { return a == 0.0; })) {
        r.Fail(f, "all " + std::to_string(angles.size()) +
                      " entries are 0 (an uncalibrated or blanked sensor)");
    }
    return angles;
}

SensorInfo Parse(const Reader& r, const std::string& name, const json& root) {
    const Layout l = DetectLayout(r, root);
    SensorInfo info;
    info.source = name;

    // "WxR": columns per frame and frame rate.
    info.lidar_mode = r.String(l.lidar_mode);
    const auto mode = std::find_if(kLidarModes.begin(), kLidarModes.end(), [&](const auto& m) {
        return info.lidar_mode == std::to_string(m.columns) + "x" + std::to_string(m.rate_hz);
    });
    if (mode == kLidarModes.end()) {
        r.Fail(l.lidar_mode, Describe(*l.lidar_mode.value) +
                                 " is not a lidar mode (512x10, 512x20, 1024x10, 1024x20, "
                                 "2048x10, 4096x5)");
    }
    info.frame_rate_hz = mode->rate_hz;

    if (l.prod_line) info.prod_line = r.String(l.prod_line);
    if (l.prod_sn) info.prod_sn = ParseProdSn(r, l.prod_sn);
    if (l.build_rev) {
        info.build_rev = r.String(l.build_rev);
        if (!info.build_rev.empty() &&
            !ParseFirmware(info.build_rev, &info.fw_major, &info.fw_minor, &info.fw_patch)) {
            r.Fail(l.build_rev,
                   Describe(*l.build_rev.value) + " is not a firmware version like v2.1.1");
        }
    }
    if (l.init_id) info.init_id = static_cast<uint32_t>(r.Integer(l.init_id, 0, kMaxInitId));
    info.udp_port_lidar = ParsePort(r, l.port_lidar);
    info.udp_port_imu = ParsePort(r, l.port_imu);

    const bool default_format = !l.data_format;
    info.format = default_format ? DefaultDataFormat(mode->columns)
                                 : ParseDataFormat(r, l.data_format, l.lidar_mode, mode->columns);
    if (l.imu_data_format) {
        const JsonField n = Child(l.imu_data_format, "imu_measurements_per_packet");
        r.Object(l.imu_data_format);
        if (n)
            info.format.imu_measurements_per_packet =
                static_cast<int>(r.Integer(n, 1, kMaxImuSamples));
    }
    if (info.format.imu_profile != ImuProfile::kAccel32Gyro32Nmea) {
        info.format.imu_measurements_per_packet = 0;
    } else if (info.format.imu_measurements_per_packet == 0) {
        r.Fail(
            "imu_data_format.imu_measurements_per_packet: is missing; the "
            "ACCEL32_GYRO32_NMEA IMU profile needs it");
    }

    const int h = info.format.pixels_per_column;
    info.beam_altitude_angles_deg = ParseAngles(r, l.altitude, h, default_format, 90.0);
    info.beam_azimuth_angles_deg = ParseAngles(r, l.azimuth, h, default_format, 180.0);

    info.lidar_origin_to_beam_origin_mm =
        l.beam_origin_mm ? r.Number(l.beam_origin_mm) : DefaultBeamOriginMm(info.prod_line);
    if (l.beam_to_lidar) {
        info.beam_to_lidar_transform = r.Transform(l.beam_to_lidar);
    } else {
        // FW < 2.5 has no matrix: the beam origin is offset along x only (SDK, spec XYZ table).
        info.beam_to_lidar_transform = Eigen::Matrix4d::Identity();
        info.beam_to_lidar_transform(0, 3) = info.lidar_origin_to_beam_origin_mm;
    }
    info.lidar_to_sensor_transform =
        l.lidar_to_sensor ? r.Transform(l.lidar_to_sensor) : DefaultLidarToSensor();
    info.imu_to_sensor_transform =
        l.imu_to_sensor ? r.Transform(l.imu_to_sensor) : DefaultImuToSensor();
    return info;
}

size_t LineOfByte(const std::string& text, size_t byte) {
    size_t line = 1;
    for (size_t i = 0; i < std::min(byte, text.size()); ++i) line += text[i] == '\n';
    return line;
}

}  // namespace

SensorInfo ParseMetadata(const std::string& name, const std::string& json_text) {
    json root;
    try {
        root = json::parse(json_text);
    } catch (const json::exception& e) {
        // A syntax error (parse_error, which knows where) or a number too large for a double
        // (out_of_range 406: so no number we read below can be infinite). Drop nlohmann's
        // "[json.exception.parse_error.101] " tag; keep where and why.
        std::string what = e.what();
        const size_t tag = what.find("] ");
        if (tag != std::string::npos) what = what.substr(tag + 2);
        const auto* syntax = dynamic_cast<const json::parse_error*>(&e);
        const size_t line = (syntax == nullptr || json_text.empty())
                                ? 0
                                : LineOfByte(json_text, syntax->byte == 0 ? 0 : syntax->byte - 1);
        throw FileError(StatusCode::kParseError, name, line,
                        "not valid JSON: " + Printable(what, 200));
    }
    const Reader reader(name);
    try {
        return Parse(reader, name, root);
    } catch (const json::exception& e) {
        // Every access above is type-checked first; this is a guard, not a path.
        throw FileError(StatusCode::kParseError, name, 0,
                        std::string("unexpected JSON structure: ") + Printable(e.what(), 200));
    }
}

SensorInfo LoadMetadata(const std::filesystem::path& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) {
        throw FileError(StatusCode::kIoError, path.string(), 0, "is a folder, not a file");
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        const int err = errno;
        throw FileError(
            std::filesystem::exists(path, ec) ? StatusCode::kIoError : StatusCode::kNotFound,
            path.string(), 0, std::string("cannot open: ") + std::strerror(err));
    }
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) throw FileError(StatusCode::kIoError, path.string(), 0, "read failed");
    return ParseMetadata(path.string(), text.str());
}

}  // namespace bimslam::ouster
