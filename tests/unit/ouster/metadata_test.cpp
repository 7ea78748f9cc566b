// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Ouster metadata JSON (drivers/ouster/metadata.hpp): both layouts, every default of
// specs/ouster-lidar.md ("Metadata JSON"), every validation, and garbage that must come back as a
// FileError naming the file and the field, never as a crash.
#include "drivers/ouster/metadata.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <string_view>

#include "algorithms/common/status.hpp"
#include "drivers/ouster/builtin_sensor.hpp"
#include "tests/support/ouster_fixtures.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::ouster {
namespace {
namespace BIMSLAM_UNITY_ID {
using common::FileError;
using common::StatusCode;

// A flat ("legacy") file as FW 2.x writes it, shortened to 16 beams.
constexpr std::string_view kFlat = R"({
    "beam_altitude_angles": [15.0, 13.0, 11.0, 9.0, 7.0, 5.0, 3.0, 1.0,
                             -1.0, -3.0, -5.0, -7.0, -9.0, -11.0, -13.0, -15.5],
    "beam_azimuth_angles": [3.1, 1.0, -1.0, -3.1, 3.1, 1.0, -1.0, -3.1,
                            3.1, 1.0, -1.0, -3.1, 3.1, 1.0, -1.0, -3.25],
    "build_rev": "v2.1.1",
    "data_format": {
        "column_window": [0, 1023],
        "columns_per_frame": 1024,
        "columns_per_packet": 16,
        "pixel_shift_by_row": [12, 4, -4, -12, 12, 4, -4, -12, 12, 4, -4, -12, 12, 4, -4, -12],
        "pixels_per_column": 16,
        "udp_profile_imu": "LEGACY",
        "udp_profile_lidar": "RNG19_RFL8_SIG16_NIR16"
    },
    "hostname": "",
    "imu_to_sensor_transform": [1, 0, 0, 6.25, 0, 1, 0, -11.5, 0, 0, 1, 7.75, 0, 0, 0, 1],
    "initialization_id": 5431292,
    "lidar_mode": "1024x10",
    "lidar_origin_to_beam_origin_mm": 15.806,
    "lidar_to_sensor_transform": [-1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1, 38.195, 0, 0, 0, 1],
    "prod_line": "OS-1-16-U0",
    "prod_sn": "992146000760",
    "udp_port_imu": 7503,
    "udp_port_lidar": 7502
})";

// A nested file as FW 3.2 writes it: FUSA profile and headers, ACCEL32_GYRO32_NMEA IMU, a beam
// matrix with a z offset, a column window that wraps.
constexpr std::string_view kNested = R"({
    "beam_intrinsics": {
        "beam_altitude_angles": [45.0, 39.0, 33.0, 27.0, 21.0, 15.0, 9.0, 3.0,
                                 -3.0, -9.0, -15.0, -21.0, -27.0, -33.0, -39.0, -45.0],
        "beam_azimuth_angles": [-2.9, -2.8, -2.7, -2.6, -2.5, -2.4, -2.3, -2.2,
                                -2.1, -2.0, -1.9, -1.8, -1.7, -1.6, -1.5, -1.4],
        "beam_to_lidar_transform": [1, 0, 0, 27.67, 0, 1, 0, 0, 0, 0, 1, 1.5, 0, 0, 0, 1],
        "lidar_origin_to_beam_origin_mm": 27.67
    },
    "calibration_status": {"reflectivity": {"valid": true}},
    "config_params": {
        "lidar_mode": "512x20",
        "udp_port_imu": 0,
        "udp_port_lidar": 7777
    },
    "imu_data_format": {"imu_measurements_per_packet": 8, "imu_packets_per_frame": 8},
    "imu_intrinsics": {"imu_to_sensor_transform": [1, 0, 0, -2.441, 0, 1, 0, -9.725, 0, 0, 1, 7.533, 0, 0, 0, 1]},
    "lidar_data_format": {
        "column_window": [400, 100],
        "columns_per_frame": 512,
        "columns_per_packet": 32,
        "header_type": "FUSA",
        "pixel_shift_by_row": [3, 1, -1, -3, 3, 1, -1, -3, 3, 1, -1, -3, 3, 1, -1, -3],
        "pixels_per_column": 16,
        "udp_profile_imu": "ACCEL32_GYRO32_NMEA",
        "udp_profile_lidar": "FUSA_RNG15_RFL8_NIR8_DUAL"
    },
    "lidar_intrinsics": {"lidar_to_sensor_transform": [-1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1, 36.18, 0, 0, 0, 1]},
    "ouster-sdk": {"client_version": "ouster_client 0.11.0"},
    "sensor_info": {
        "build_rev": "v3.2.0-rc.1-17-gbc0879e",
        "initialization_id": 16777215,
        "prod_line": "OS-0-16-U1",
        "prod_sn": "122246000293"
    }
})";

// Where the value of the first "key": starts and ends in a document (brackets matched).
std::pair<size_t, size_t> ValueSpan(const std::string& doc, const std::string& key) {
    const size_t at = doc.find("\"" + key + "\": ");
    if (at == std::string::npos) return {std::string::npos, std::string::npos};
    const size_t begin = at + key.size() + 4;
    size_t end = begin;
    if (doc[begin] == '{' || doc[begin] == '[') {
        int depth = 0;
        do {
            depth += (doc[end] == '{' || doc[end] == '[') - (doc[end] == '}' || doc[end] == ']');
            ++end;
        } while (depth > 0);
    } else if (doc[begin] == '"') {
        end = doc.find('"', begin + 1) + 1;
    } else {
        end = doc.find_first_of(",}]\n", begin);
    }
    return {begin, end};
}

// The document with the value of "key" replaced by `value` (JSON text).
std::string Set(std::string_view doc_in, const std::string& key, const std::string& value) {
    std::string doc(doc_in);
    const auto [begin, end] = ValueSpan(doc, key);
    if (begin == std::string::npos) {
        ADD_FAILURE() << "test document has no key " << key;
        return doc;
    }
    return doc.replace(begin, end - begin, value);
}

// The document without the member "key" (and without the comma that would then dangle).
std::string Remove(std::string_view doc_in, const std::string& key) {
    std::string doc(doc_in);
    const size_t at = doc.find("\"" + key + "\": ");
    if (at == std::string::npos) {
        ADD_FAILURE() << "test document has no key " << key;
        return doc;
    }
    size_t end = ValueSpan(doc, key).second;
    const size_t next = doc.find_first_not_of(" \n", end);
    if (doc[next] == ',') {
        end = next + 1;
    } else {
        const size_t prev = doc.find_last_not_of(" \n", at - 1);
        if (doc[prev] == ',') return doc.erase(prev, end - prev);
    }
    return doc.erase(at, end - at);
}

// A member added at the top level.
std::string Add(std::string_view doc, const std::string& member) {
    std::string s(doc);
    return s.insert(1, member + ",");
}

// n comma-separated numbers first, first + step, ...
std::string Array(int n, double first, double step) {
    std::string s = "[";
    for (int i = 0; i < n; ++i) s += (i ? ", " : "") + std::to_string(first + step * i);
    return s + "]";
}

// The message of the FileError that parsing raises, or "accepted".
std::string ErrorOf(const std::string& text) {
    try {
        ParseMetadata("t.json", text);
    } catch (const FileError& e) {
        EXPECT_EQ(e.path(), "t.json");
        EXPECT_EQ(e.code(), StatusCode::kParseError);
        return e.detail();
    }
    return "accepted";
}

#define EXPECT_REJECTED(text, substring)                                            \
    do {                                                                            \
        const std::string message = ErrorOf(text);                                  \
        EXPECT_NE(message.find(substring), std::string::npos)                       \
            << "expected \"" << (substring) << "\" in the error, got: " << message; \
    } while (0)

Eigen::Matrix4d Rows(std::initializer_list<double> v) {
    Eigen::Matrix4d m;
    auto it = v.begin();
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) m(r, c) = *it++;
    return m;
}

TEST(Metadata, FlatLayoutFields) {
    const SensorInfo s = ParseMetadata("flat.json", std::string(kFlat));
    EXPECT_EQ(s.source, "flat.json");
    EXPECT_EQ(s.prod_line, "OS-1-16-U0");
    EXPECT_EQ(s.prod_sn, 992146000760u);
    EXPECT_EQ(s.build_rev, "v2.1.1");
    EXPECT_EQ(s.fw_major * 10000 + s.fw_minor * 100 + s.fw_patch, 20101);
    EXPECT_EQ(s.init_id, 5431292u);
    EXPECT_EQ(s.lidar_mode, "1024x10");
    EXPECT_EQ(s.frame_rate_hz, 10.0);
    EXPECT_EQ(s.udp_port_lidar, std::optional<uint16_t>(7502));
    EXPECT_EQ(s.udp_port_imu, std::optional<uint16_t>(7503));
    const DataFormat& f = s.format;
    EXPECT_EQ(f.pixels_per_column, 16);
    EXPECT_EQ(f.columns_per_frame, 1024);
    EXPECT_EQ(f.columns_per_packet, 16);
    EXPECT_EQ(f.pixel_shift_by_row,
              (std::vector<int>{12, 4, -4, -12, 12, 4, -4, -12, 12, 4, -4, -12, 12, 4, -4, -12}));
    EXPECT_EQ(f.column_window_first, 0);
    EXPECT_EQ(f.column_window_last, 1023);
    EXPECT_EQ(f.lidar_profile, LidarProfile::kRng19Rfl8Sig16Nir16);
    EXPECT_EQ(f.imu_profile, ImuProfile::kLegacy);
    EXPECT_EQ(f.header_type, HeaderType::kStandard);
    EXPECT_EQ(f.imu_measurements_per_packet, 0);
    ASSERT_EQ(s.beam_altitude_angles_deg.size(), 16u);
    EXPECT_EQ(s.beam_altitude_angles_deg.front(), 15.0);
    EXPECT_EQ(s.beam_altitude_angles_deg.back(), -15.5);
    EXPECT_EQ(s.beam_azimuth_angles_deg.back(), -3.25);
    EXPECT_EQ(s.lidar_origin_to_beam_origin_mm, 15.806);
    // No beam matrix before FW 2.5: identity with x = lidar_origin_to_beam_origin_mm.
    EXPECT_EQ(s.beam_to_lidar_transform,
              Rows({1, 0, 0, 15.806, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}));
    EXPECT_EQ(s.lidar_to_sensor_transform,
              Rows({-1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1, 38.195, 0, 0, 0, 1}));
    EXPECT_EQ(s.imu_to_sensor_transform,
              Rows({1, 0, 0, 6.25, 0, 1, 0, -11.5, 0, 0, 1, 7.75, 0, 0, 0, 1}));
}

TEST(Metadata, NestedLayoutFields) {
    const SensorInfo s = ParseMetadata("nested.json", std::string(kNested));
    EXPECT_EQ(s.prod_line, "OS-0-16-U1");
    EXPECT_EQ(s.prod_sn, 122246000293u);
    EXPECT_EQ(s.fw_major * 10000 + s.fw_minor * 100 + s.fw_patch, 30200);
    EXPECT_EQ(s.init_id, 16777215u);
    EXPECT_EQ(s.lidar_mode, "512x20");
    EXPECT_EQ(s.frame_rate_hz, 20.0);
    EXPECT_EQ(s.udp_port_lidar, std::optional<uint16_t>(7777));
    EXPECT_EQ(s.udp_port_imu, std::nullopt);  // 0: not given (as the SDK reads it)
    const DataFormat& f = s.format;
    EXPECT_EQ(f.pixels_per_column, 16);
    EXPECT_EQ(f.columns_per_frame, 512);
    EXPECT_EQ(f.columns_per_packet, 32);
    EXPECT_EQ(f.column_window_first, 400);
    EXPECT_EQ(f.column_window_last, 100);
    EXPECT_EQ(f.WindowColumns(), 213);
    EXPECT_EQ(f.lidar_profile, LidarProfile::kFusaRng15Rfl8Nir8Dual);
    EXPECT_EQ(f.imu_profile, ImuProfile::kAccel32Gyro32Nmea);
    EXPECT_EQ(f.header_type, HeaderType::kFusa);
    EXPECT_EQ(f.imu_measurements_per_packet, 8);
    EXPECT_EQ(s.beam_altitude_angles_deg.front(), 45.0);
    EXPECT_EQ(s.beam_azimuth_angles_deg.back(), -1.4);
    EXPECT_EQ(s.lidar_origin_to_beam_origin_mm, 27.67);
    EXPECT_EQ(s.beam_to_lidar_transform,
              Rows({1, 0, 0, 27.67, 0, 1, 0, 0, 0, 0, 1, 1.5, 0, 0, 0, 1}));
    EXPECT_EQ(s.lidar_to_sensor_transform(2, 3), 36.18);
    EXPECT_EQ(s.imu_to_sensor_transform(0, 3), -2.441);
    EXPECT_EQ(s.imu_to_sensor_transform(1, 3), -9.725);
}

TEST(Metadata, NoProfileIsLegacy) {
    const SensorInfo s =
        ParseMetadata("t", Remove(Remove(kFlat, "udp_profile_lidar"), "udp_profile_imu"));
    EXPECT_EQ(s.format.lidar_profile, LidarProfile::kLegacy);
    EXPECT_EQ(s.format.imu_profile, ImuProfile::kLegacy);
    EXPECT_EQ(s.format.header_type, HeaderType::kStandard);
}

TEST(Metadata, NoColumnWindowIsTheWholeFrame) {
    const SensorInfo s = ParseMetadata("t", Remove(kNested, "column_window"));
    EXPECT_EQ(s.format.column_window_first, 0);
    EXPECT_EQ(s.format.column_window_last, 511);
}

TEST(Metadata, NoPixelShiftIsZeros) {
    const SensorInfo s = ParseMetadata("t", Remove(kFlat, "pixel_shift_by_row"));
    EXPECT_EQ(s.format.pixel_shift_by_row, std::vector<int>(16, 0));
}

TEST(Metadata, BeamOriginByProductLine) {
    const std::string no_origin = Remove(kFlat, "lidar_origin_to_beam_origin_mm");
    const std::pair<const char*, double> cases[] = {
        {"\"OS-0-32-U1\"", 27.67}, {"\"OS-1-128\"", 15.806}, {"\"OS-2-128-U1\"", 13.762},
        {"\"OS-DOME-128\"", 0.0},  {"\"\"", 12.163},         {"\"OS1-64 gen1\"", 12.163},
    };
    for (const auto& [prod_line, mm] : cases) {
        const SensorInfo s = ParseMetadata("t", Set(no_origin, "prod_line", prod_line));
        EXPECT_EQ(s.lidar_origin_to_beam_origin_mm, mm) << prod_line;
        EXPECT_EQ(s.beam_to_lidar_transform(0, 3), mm) << prod_line;
        EXPECT_EQ(s.beam_to_lidar_transform(2, 3), 0.0) << prod_line;
    }
    // No prod_line at all: the gen-1 OS1 value.
    EXPECT_EQ(ParseMetadata("t", Remove(no_origin, "prod_line")).lidar_origin_to_beam_origin_mm,
              12.163);
    // An explicit matrix wins over the offset for the matrix; the offset stays as written.
    const SensorInfo n = ParseMetadata("t", Set(kNested, "lidar_origin_to_beam_origin_mm", "20"));
    EXPECT_EQ(n.lidar_origin_to_beam_origin_mm, 20.0);
    EXPECT_EQ(n.beam_to_lidar_transform(0, 3), 27.67);
}

TEST(Metadata, TransformDefaults) {
    const SensorInfo s = ParseMetadata(
        "t", Remove(Remove(kFlat, "lidar_to_sensor_transform"), "imu_to_sensor_transform"));
    EXPECT_EQ(s.lidar_to_sensor_transform,
              Rows({-1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1, 36.18, 0, 0, 0, 1}));
    EXPECT_EQ(s.imu_to_sensor_transform,
              Rows({1, 0, 0, 6.253, 0, 1, 0, -11.775, 0, 0, 1, 7.645, 0, 0, 0, 1}));
    const SensorInfo n = ParseMetadata(
        "t", Remove(Remove(kNested, "lidar_to_sensor_transform"), "imu_to_sensor_transform"));
    EXPECT_EQ(n.lidar_to_sensor_transform(2, 3), 36.18);
    EXPECT_EQ(n.imu_to_sensor_transform(1, 3), -11.775);
}

// FW < 2.0 (no data format): 64-pixel columns, 16 columns a packet, W from lidar_mode, and the
// SDK's gen-1 row shifts {3s, 2s, s, 0} with s = 3 W / 512.
std::string Firmware1(const std::string& mode) {
    std::string doc = Remove(kFlat, "data_format");
    doc = Set(doc, "beam_altitude_angles", Array(64, 16.6, -0.52));
    doc = Set(doc, "beam_azimuth_angles", Array(64, 3.1, -0.09));
    doc = Set(doc, "build_rev", "\"v1.13.0\"");
    return Set(doc, "lidar_mode", "\"" + mode + "\"");
}

TEST(Metadata, NoDataFormatIsFirmware1) {
    const std::tuple<const char*, int, double, int> modes[] = {
        {"512x10", 512, 10, 9},    {"512x20", 512, 20, 9},    {"1024x10", 1024, 10, 18},
        {"1024x20", 1024, 20, 18}, {"2048x10", 2048, 10, 36}, {"4096x5", 4096, 5, 72},
    };
    for (const auto& [mode, w, rate, shift0] : modes) {
        const SensorInfo s = ParseMetadata("t", Firmware1(mode));
        EXPECT_EQ(s.format.pixels_per_column, 64) << mode;
        EXPECT_EQ(s.format.columns_per_packet, 16) << mode;
        EXPECT_EQ(s.format.columns_per_frame, w) << mode;
        EXPECT_EQ(s.frame_rate_hz, rate) << mode;
        EXPECT_EQ(s.format.column_window_first, 0) << mode;
        EXPECT_EQ(s.format.column_window_last, w - 1) << mode;
        EXPECT_EQ(s.format.lidar_profile, LidarProfile::kLegacy);
        ASSERT_EQ(s.format.pixel_shift_by_row.size(), 64u);
        for (int u = 0; u < 64; ++u) {
            EXPECT_EQ(s.format.pixel_shift_by_row[size_t(u)], shift0 / 3 * (3 - u % 4)) << u;
        }
        EXPECT_EQ(s.fw_major, 1);
        EXPECT_EQ(s.fw_minor, 13);
    }
    // Such firmware pads the angle arrays to 64 even for a 16-beam sensor.
    EXPECT_REJECTED(Remove(kFlat, "data_format"),
                    "beam_altitude_angles: 16 entries, but pixels_per_column is 64 (no data");
    // Nested files of FW 1.x carry the sensor's error reply instead of a data format.
    std::string nested = Set(kNested, "lidar_data_format", "\"error: Command not recognized.\"");
    nested = Set(nested, "calibration_status", "\"error: Command not recognized.\"");
    nested = Remove(nested, "imu_data_format");
    nested = Set(nested, "beam_altitude_angles", Array(64, 16.6, -0.52));
    nested = Set(nested, "beam_azimuth_angles", Array(64, 3.1, -0.09));
    const SensorInfo n = ParseMetadata("t", nested);
    EXPECT_EQ(n.format.pixels_per_column, 64);
    EXPECT_EQ(n.format.columns_per_frame, 512);
    EXPECT_EQ(n.format.pixel_shift_by_row[0], 9);
}

TEST(Metadata, PortsAbsentOrZeroStayUnset) {
    const SensorInfo s =
        ParseMetadata("t", Remove(Remove(kFlat, "udp_port_lidar"), "udp_port_imu"));
    EXPECT_EQ(s.udp_port_lidar, std::nullopt);
    EXPECT_EQ(s.udp_port_imu, std::nullopt);
    EXPECT_EQ(ParseMetadata("t", Set(kFlat, "udp_port_lidar", "0")).udp_port_lidar, std::nullopt);
}

TEST(Metadata, HeaderTypeFollowsTheFusaProfile) {
    const std::string no_header = Remove(kNested, "header_type");
    EXPECT_EQ(ParseMetadata("t", no_header).format.header_type, HeaderType::kFusa);
    EXPECT_EQ(ParseMetadata("t", Set(no_header, "udp_profile_lidar", "\"RNG15_RFL8_NIR8\""))
                  .format.header_type,
              HeaderType::kStandard);
    EXPECT_EQ(ParseMetadata("t", Set(kNested, "header_type", "\"STANDARD\"")).format.header_type,
              HeaderType::kStandard);
}

TEST(Metadata, FirmwareVersionFromBuildRev) {
    const std::tuple<const char*, int, int, int> ok[] = {
        {"\"v2.1.1\"", 2, 1, 1},
        {"\"v2.2.0-rc.2-17-gbc0879e\"", 2, 2, 0},
        {"\"v1.14.0-beta.1-928-g6cccd78\"", 1, 14, 0},
        {"\"2.5.0-omega.8\"", 2, 5, 0},
        {"\"\"", 0, 0, 0},
    };
    for (const auto& [rev, major, minor, patch] : ok) {
        const SensorInfo s = ParseMetadata("t", Set(kFlat, "build_rev", rev));
        EXPECT_EQ(s.fw_major, major) << rev;
        EXPECT_EQ(s.fw_minor, minor) << rev;
        EXPECT_EQ(s.fw_patch, patch) << rev;
    }
    EXPECT_EQ(ParseMetadata("t", Remove(kFlat, "build_rev")).fw_major, 0);
    for (const char* bad : {"\"v2.1\"", "\"release\"", "\"v2..1\"", "\"v1234567.0.0\"", "\"v\""}) {
        EXPECT_REJECTED(Set(kFlat, "build_rev", bad), "build_rev: string");
    }
    EXPECT_REJECTED(Set(kFlat, "build_rev", "2.1"), "build_rev: must be a string");
}

// Each entry: a key of the document, its new value (nullptr: removed), a substring of the error.
struct BadField {
    const char* key;
    const char* value;
    const char* error;
};

void ExpectEachRejected(std::string_view doc, std::initializer_list<BadField> cases) {
    for (const BadField& c : cases) {
        SCOPED_TRACE(std::string(c.key) + " = " + (c.value ? c.value : "(removed)"));
        EXPECT_REJECTED(c.value ? Set(doc, c.key, c.value) : Remove(doc, c.key), c.error);
    }
}

TEST(Metadata, FlatValidationNamesTheField) {
    ExpectEachRejected(
        kFlat,
        {
            {"pixels_per_column", "33", "data_format.pixels_per_column: 33 is not one of 16, 32"},
            {"pixels_per_column", "\"16\"", "data_format.pixels_per_column: must be an integer"},
            {"pixels_per_column", "16.0", "data_format.pixels_per_column: must be an integer"},
            {"pixels_per_column", "32", "data_format.pixel_shift_by_row: 16 entries, but pix"},
            {"pixels_per_column", nullptr, "data_format.pixels_per_column: is missing"},
            {"columns_per_frame", "1000", "data_format.columns_per_frame: 1000 is not one of"},
            {"columns_per_frame", "2048", "data_format.columns_per_frame: 2048 does not match"},
            {"columns_per_frame", nullptr, "data_format.columns_per_frame: is missing"},
            {"columns_per_packet", "12", "data_format.columns_per_packet: 12 is not one of"},
            {"columns_per_packet", nullptr, "data_format.columns_per_packet: is missing"},
            {"column_window", "[0, 1024]", "data_format.column_window[1]: must be an integer in"},
            {"column_window", "[-1, 5]", "data_format.column_window[0]: must be an integer in"},
            {"column_window", "[0]", "data_format.column_window: 1 entries"},
            {"column_window", "\"all\"", "data_format.column_window: must be an array"},
            {"pixel_shift_by_row", Array(15, 0, 0).c_str(), "pixel_shift_by_row: 15 entries"},
            {"pixel_shift_by_row", "[1024, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]",
             "data_format.pixel_shift_by_row[0]: must be an integer in [-1023, 1023], not 1024"},
            {"udp_profile_lidar", "\"RNG99\"", "data_format.udp_profile_lidar: string \"RNG99\""},
            {"udp_profile_lidar", "\"FIVE_WORD_PIXEL\"", "udp_profile_lidar: string \"FIVE_"},
            {"udp_profile_lidar", "7", "data_format.udp_profile_lidar: must be a string"},
            {"udp_profile_imu", "\"IMU9\"", "data_format.udp_profile_imu: string \"IMU9\""},
            {"udp_profile_imu", "\"ACCEL32_GYRO32_NMEA\"",
             "imu_data_format.imu_measurements_per_packet: is missing"},
            {"data_format", "\"none\"", "data_format: must be an object, not string"},
            {"beam_altitude_angles", Array(15, 10, -1).c_str(), "beam_altitude_angles: 15 entr"},
            {"beam_azimuth_angles", Array(17, 1, 0).c_str(), "beam_azimuth_angles: 17 entries"},
            {"beam_altitude_angles", "[\"x\"]", "beam_altitude_angles[0]: must be a number, not"},
            {"beam_altitude_angles", "[[1, 2]]", "beam_altitude_angles[0]: must be a number"},
            {"beam_altitude_angles", nullptr, "beam_altitude_angles: is missing"},
            {"beam_altitude_angles", "null", "beam_altitude_angles: is missing"},
            {"beam_altitude_angles", Array(16, 0, 0).c_str(), "beam_altitude_angles: all 16 "},
            {"beam_azimuth_angles", Array(16, 0, 0).c_str(), "beam_azimuth_angles: all 16 entr"},
            {"beam_altitude_angles", Array(16, 95, -1).c_str(),
             "beam_altitude_angles[0]: 95.0 degrees is outside [-90, 90]"},
            {"beam_azimuth_angles", Array(16, 1, -20).c_str(), "beam_azimuth_angles[10]: -199"},
            {"lidar_to_sensor_transform", Array(15, 0, 0).c_str(),
             "lidar_to_sensor_transform: 15 entries, a row-major 4x4 matrix has 16"},
            {"lidar_to_sensor_transform", "[1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,1,1]",
             "lidar_to_sensor_transform: last row is 0 0 1 1, not 0 0 0 1"},
            {"imu_to_sensor_transform", "[1,0,0,\"a\", 0,1,0,0, 0,0,1,0, 0,0,0,1]",
             "imu_to_sensor_transform[3]: must be a number, not string \"a\""},
            {"lidar_origin_to_beam_origin_mm", "\"15\"", "lidar_origin_to_beam_origin_mm: must"},
            {"lidar_mode", "\"1024x30\"", "lidar_mode: string \"1024x30\" is not a lidar mode"},
            {"lidar_mode", "1024", "lidar_mode: must be a string"},
            {"lidar_mode", nullptr, "lidar_mode: is missing"},
            {"prod_line", "5", "prod_line: must be a string"},
            {"prod_sn", "\"99-21\"", "prod_sn: string \"99-21\" is not a serial number"},
            {"prod_sn", "\"1099511627776\"", "prod_sn: string \"1099511627776\" does not fit"},
            {"prod_sn", "-5", "prod_sn: must be an integer in [0, 1099511627775]"},
            {"prod_sn", "true", "prod_sn: must be a string, not true"},
            {"initialization_id", "-1", "initialization_id: must be an integer in [0, 16777215]"},
            {"initialization_id", "16777216", "initialization_id: must be an integer in [0, 16"},
            {"initialization_id", "5.5", "initialization_id: must be an integer in [0, 1677"},
            {"initialization_id", "\"5\"", "initialization_id: must be an integer in [0, 16777"},
            {"udp_port_lidar", "70000", "udp_port_lidar: must be an integer in [0, 65535]"},
            {"udp_port_imu", "-2", "udp_port_imu: must be an integer in [0, 65535]"},
        });
}

TEST(Metadata, NestedValidationNamesTheField) {
    ExpectEachRejected(
        kNested,
        {
            {"sensor_info", nullptr, "sensor_info: is missing; the nested layout has all of"},
            {"calibration_status", nullptr, "calibration_status: is missing"},
            {"config_params", "\"x\"", "config_params: must be an object, not string \"x\""},
            {"beam_intrinsics", "[]", "beam_intrinsics: must be an object, not an array of 0"},
            {"lidar_data_format", "5", "lidar_data_format: must be an object, not 5"},
            {"pixels_per_column", "200", "lidar_data_format.pixels_per_column: 200 is not one"},
            {"columns_per_frame", "1024",
             "lidar_data_format.columns_per_frame: 1024 does not "
             "match config_params.lidar_mode (512 columns)"},
            {"header_type", "\"WEIRD\"", "lidar_data_format.header_type: string \"WEIRD\""},
            {"lidar_mode", nullptr, "config_params.lidar_mode: is missing"},
            {"udp_port_lidar", "\"7502\"", "config_params.udp_port_lidar: must be an integer"},
            {"initialization_id", "16777216", "sensor_info.initialization_id: must be an inte"},
            {"prod_sn", "\"12a\"", "sensor_info.prod_sn: string \"12a\" is not a serial"},
            {"beam_to_lidar_transform", "[1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,2]",
             "beam_intrinsics.beam_to_lidar_transform: last row is 0 0 0 2"},
            {"beam_altitude_angles", Array(32, 10, -1).c_str(),
             "beam_intrinsics.beam_altitude_angles: 32 entries, but pixels_per_column is 16"},
            {"lidar_to_sensor_transform", "{}",
             "lidar_intrinsics.lidar_to_sensor_transform: must be an array, not an object"},
            {"imu_measurements_per_packet", "0",
             "imu_data_format.imu_measurements_per_packet: must be an integer in [1, 1815]"},
            {"imu_measurements_per_packet", nullptr,
             "imu_data_format.imu_measurements_per_packet: is missing"},
            {"imu_data_format", "\"x\"", "imu_data_format: must be an object"},
        });
}

TEST(Metadata, LayoutsMustNotMix) {
    EXPECT_REJECTED(Add(kNested, "\"lidar_mode\": \"1024x10\""),
                    "mixes the two metadata layouts: nested-layout sections (sensor_info, beam_"
                    "intrinsics, imu_intrinsics, lidar_intrinsics, config_params, lidar_data_"
                    "format, calibration_status) next to flat (legacy) layout fields (lidar_mode)");
    EXPECT_REJECTED(Add(kFlat, "\"calibration_status\": {}"),
                    "nested-layout sections (calibration_status) next to flat");
    EXPECT_REJECTED(Add(kFlat, "\"beam_intrinsics\": {}"), "(beam_intrinsics) next to flat");
    // Sections of the nested layout alone, but not all of them.
    EXPECT_REJECTED("{\"sensor_info\": {}, \"config_params\": {}}",
                    "beam_intrinsics: is missing; the nested layout");
    // Neither layout.
    EXPECT_REJECTED("{}", "not Ouster sensor metadata");
    EXPECT_REJECTED("{\"hostname\": \"os-1\", \"client_version\": \"x\"}",
                    "not Ouster sensor metadata");
    EXPECT_REJECTED("[1, 2]", "the top level must be a JSON object, not an array of 2");
    EXPECT_REJECTED("\"metadata\"", "the top level must be a JSON object, not string");
    EXPECT_REJECTED("null", "the top level must be a JSON object, not null");
}

TEST(Metadata, GarbageIsAFileErrorNamingTheFile) {
    for (const std::string& text :
         {std::string(), std::string("   \n"), std::string("nul"), std::string("{"),
          std::string("\xff\xfe{}", 4), std::string("{\"lidar_mode\": "), std::string("\0\0\0", 3),
          std::string("{\"a\": 1,}"), std::string("NaN"), std::string(100000, '['),
          Set(kFlat, "lidar_origin_to_beam_origin_mm", "-1e999")}) {
        EXPECT_NE(ErrorOf(text).find("not valid JSON"), std::string::npos) << text.substr(0, 20);
    }
    // Every truncation of a valid file.
    const std::string full(kNested);
    for (size_t n = 0; n < full.size(); ++n) {
        SCOPED_TRACE(n);
        // The error is at the end of the text: the line after its last newline (0 when empty).
        const auto line = n == 0 ? 0 : std::count(full.begin(), full.begin() + long(n), '\n') + 1;
        EXPECT_FILE_ERROR(ParseMetadata("cut.json", full.substr(0, n)), "cut.json", line);
    }
}

TEST(Metadata, SyntaxErrorsNameTheLine) {
    EXPECT_FILE_ERROR(ParseMetadata("s.json", "{\n\"a\": 1,\n\"b\": x\n}"), "s.json", 3);
    // JSON has no infinity, and a number beyond a double is refused as the file is read.
    EXPECT_NE(ErrorOf(Set(kFlat, "imu_to_sensor_transform", "[1e400]")).find("number overflow"),
              std::string::npos);
}

TEST(Metadata, MutatedFilesOnlyEverRaiseFileError) {
    constexpr std::string_view kJsonBytes{"{}[]\",:0123456789-.eE+ \ntrufalsn\0\xff", 34};
    static_assert(kJsonBytes.back() == '\xff');
    const auto counts = test::FuzzReader(
        "fuzz.json", {{std::string(kFlat), kFlat.size()}, {std::string(kNested), kNested.size()}},
        3000, 2024, kJsonBytes, [](const std::string& b) { ParseMetadata("fuzz.json", b); });
    EXPECT_GT(counts.rejected, 1000u);
    EXPECT_GT(counts.accepted, 100u);
}

TEST(Metadata, LoadReadsTheFileAndNamesIt) {
    test::TempDir dir;
    test::WriteBytes(dir / "m.json", std::string(kFlat));
    EXPECT_EQ(LoadMetadata(dir / "m.json").source, (dir / "m.json").string());
    test::WriteBytes(dir / "bad.json", Set(kFlat, "pixels_per_column", "3"));
    EXPECT_FILE_ERROR(LoadMetadata(dir / "bad.json"), (dir / "bad.json").string(), 0);
    try {
        LoadMetadata(dir / "absent.json");
        ADD_FAILURE() << "no error for a missing file";
    } catch (const FileError& e) {
        EXPECT_EQ(e.code(), StatusCode::kNotFound) << e.what();
        EXPECT_EQ(e.path(), (dir / "absent.json").string());
    }
    EXPECT_FILE_ERROR(LoadMetadata(dir.path()), dir.path().string(), 0);
}

TEST(Metadata, ProfileStringsRoundTrip) {
    for (const LidarProfile p :
         {LidarProfile::kLegacy, LidarProfile::kRng19Rfl8Sig16Nir16, LidarProfile::kRng15Rfl8Nir8,
          LidarProfile::kRng19Rfl8Sig16Nir16Dual, LidarProfile::kRng15Rfl8Nir8Dual,
          LidarProfile::kFusaRng15Rfl8Nir8Dual}) {
        EXPECT_EQ(ParseLidarProfile(ToString(p)), p) << ToString(p);
    }
    EXPECT_EQ(ToString(LidarProfile::kRng15Rfl8Nir8), "RNG15_RFL8_NIR8");
    EXPECT_EQ(ParseImuProfile("ACCEL32_GYRO32_NMEA"), ImuProfile::kAccel32Gyro32Nmea);
    EXPECT_EQ(ToString(ImuProfile::kLegacy), "LEGACY");
    EXPECT_EQ(ParseHeaderType("FUSA"), HeaderType::kFusa);
    EXPECT_EQ(ToString(HeaderType::kStandard), "STANDARD");
    EXPECT_EQ(ParseLidarProfile("legacy"), std::nullopt);  // the sensor's spelling only
    EXPECT_EQ(ParseImuProfile(""), std::nullopt);
    EXPECT_EQ(ParseHeaderType("STANDARD "), std::nullopt);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::ouster

namespace bimslam::ouster {
namespace {
namespace BIMSLAM_UNITY_ID {

TEST(Metadata, SerializedSyntheticSensorsReadBackTheSame) {
    for (LidarProfile p : fixtures::kAllProfiles) {
        SensorInfo info = fixtures::MakeSensor(p, 64, 2048);
        info.lidar_mode = "2048x10";
        info.udp_port_lidar = 7502;
        info.udp_port_imu = 7503;
        info.format.column_window_first = 1900;  // a wrapping window
        info.format.column_window_last = 99;
        info.beam_to_lidar_transform(2, 3) = 8.5;
        const SensorInfo back = ParseMetadata("s.json", SerializeMetadata(info));
        fixtures::ExpectSameSensor(info, back);
    }
    SensorInfo fusa =
        fixtures::MakeSensor(LidarProfile::kFusaRng15Rfl8Nir8Dual, 32, 1024, HeaderType::kFusa);
    fusa.format.imu_profile = ImuProfile::kAccel32Gyro32Nmea;
    fusa.format.imu_measurements_per_packet = 8;
    fixtures::ExpectSameSensor(fusa, ParseMetadata("f.json", SerializeMetadata(fusa)));
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::ouster

namespace bimslam::ouster {
namespace {
namespace BIMSLAM_UNITY_ID {

TEST(BuiltinSensor, IsAValidOs132InEveryMode) {
    for (const auto& [columns, rate] :
         {std::pair{512, 10}, std::pair{1024, 10}, std::pair{2048, 10}, std::pair{512, 20},
          std::pair{1024, 20}}) {
        const SensorInfo s = BuiltinOs1_32(LidarProfile::kRng19Rfl8Sig16Nir16, columns, rate);
        // It is what our own metadata parser accepts, unchanged.
        fixtures::ExpectSameSensor(s, ParseMetadata("builtin.json", SerializeMetadata(s)));
        EXPECT_EQ(s.format.pixel_shift_by_row.size(), 32u);
    }
    const SensorInfo s = BuiltinOs1_32(LidarProfile::kLegacy, 1024, 10);
    EXPECT_EQ(s.format.pixel_shift_by_row[0], 24);  // +4.23 deg = 24 columns after -4.23 deg
    EXPECT_EQ(s.format.pixel_shift_by_row[3], 0);
    EXPECT_THROW(BuiltinOs1_32(LidarProfile::kLegacy, 4096, 10), common::Error);
}

TEST(BuiltinSensor, EveryProductAndBeamCountIsValidWithItsFieldOfView) {
    const std::pair<const char*, double> products[] = {{"OS0", 90.0}, {"OS1", 45.0}, {"OS2", 22.5}};
    for (const auto& [product, fov] : products) {
        for (const int beams : {16, 32, 64, 128}) {
            const std::string model = std::string(product) + "-" + std::to_string(beams);
            const SensorInfo s = BuiltinOuster(model, LidarProfile::kRng19Rfl8Sig16Nir16, 1024, 10);
            fixtures::ExpectSameSensor(s, ParseMetadata("builtin.json", SerializeMetadata(s)));
            EXPECT_EQ(s.format.pixels_per_column, beams) << model;
            ASSERT_EQ(s.beam_altitude_angles_deg.size(), size_t(beams)) << model;
            EXPECT_DOUBLE_EQ(s.beam_altitude_angles_deg.front() - s.beam_altitude_angles_deg.back(),
                             fov)
                << model;
            EXPECT_EQ(s.prod_line,
                      "OS-" + std::string(1, product[2]) + "-" + std::to_string(beams) + "-U0");
        }
    }
    // OS1-32 is the original built-in sensor, unchanged.
    EXPECT_EQ(SerializeMetadata(BuiltinOuster("OS1-32")), SerializeMetadata(BuiltinOs1_32()));
    for (const char* bad : {"OS3-64", "OS1-48", "OS1", "os1-32", ""}) {
        EXPECT_THROW(BuiltinOuster(bad), common::Error) << bad;
    }
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::ouster
