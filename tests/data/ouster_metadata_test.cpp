// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Every real Ouster metadata file of ../shared/data/ouster (specs/ouster-lidar.md, "Metadata
// JSON"): each accepted with the values it states or the spec's defaults, each malformed one
// rejected with a message naming the broken field. Labelled `data`: skips when the folder is
// absent.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "algorithms/common/status.hpp"
#include "drivers/ouster/metadata.hpp"
#include "tests/support/ouster_fixtures.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::ouster {
namespace {
namespace BIMSLAM_UNITY_ID {
namespace fs = std::filesystem;

constexpr bool kFlat = false, kNested = true;
constexpr LidarProfile kLegacy = LidarProfile::kLegacy, kRng19 = LidarProfile::kRng19Rfl8Sig16Nir16,
                       kRng15 = LidarProfile::kRng15Rfl8Nir8,
                       kDual = LidarProfile::kRng19Rfl8Sig16Nir16Dual;

// What each file must give. Values the file does not state are the defaults:
// - no data_format (FW < 2.0, and the Ouster Studio file): H = 64, 16 columns a packet, W from
//   lidar_mode, row shifts {18, 12, 6, 0} repeated at 1024 columns ({36, 24, 12, 0} at 2048);
// - no lidar_origin_to_beam_origin_mm: by prod_line as the SDK does ("OS-0-" 27.67, "OS-1-"
//   15.806; no prod_line: the gen-1 value 12.163). Gen-1 OS1s report "OS-1-64", so their FW 1.x
//   files get 15.806 although the same sensor's FW 2.x files state 12.163: the SDK does the same;
// - no transforms (Ouster Studio file): lidar_to_sensor z = 36.18, imu t = (6.253, -11.775, 7.645);
// - no ports: none (0 here); no initialization_id or prod_sn: 0.
struct Expected {
    const char* file;
    bool nested;
    int h, w;
    LidarProfile profile;
    int window_first, window_last;
    double beam_origin_mm;           // also beam_to_lidar_transform(0, 3)
    double lidar_to_sensor_z_mm;     // lidar_to_sensor_transform(2, 3); all rotate 180 deg about Z
    std::array<double, 3> imu_t_mm;  // imu_to_sensor_transform translation
    const char* fw;
    uint32_t init_id;
    uint64_t prod_sn;
    uint16_t udp_port_lidar;  // 0: none
    double first_altitude_deg;
    int first_pixel_shift;
};

// clang-format off
const Expected kMetadataFiles[] = {
    {"1_12_os1-991913000010-64.json", kNested, 64, 1024, kLegacy, 0, 1023, 15.806, 36.18, {6.253, -11.775, 7.645}, "1.12.0", 0, 991913000010, 60823, 16.729, 18},
    {"1_12_os1-991937000062-16A0_legacy.json", kFlat, 64, 1024, kLegacy, 0, 1023, 15.806, 36.18, {6.253, -11.775, 7.645}, "1.12.0", 0, 991937000062, 0, 16.509, 18},
    {"1_12_os1-991937000062-64_legacy.json", kFlat, 64, 1024, kLegacy, 0, 1023, 15.806, 36.18, {6.253, -11.775, 7.645}, "1.12.0", 0, 991937000062, 0, 16.509, 18},
    {"1_13_os1-991913000010-64.json", kNested, 64, 1024, kLegacy, 0, 1023, 15.806, 36.18, {6.253, -11.775, 7.645}, "1.13.0", 0, 991913000010, 7502, 16.729, 18},
    {"1_13_os1-991937000062-16A0_legacy.json", kFlat, 64, 1024, kLegacy, 0, 1023, 15.806, 36.18, {6.253, -11.775, 7.645}, "1.13.0", 0, 991937000062, 0, 0, 18},
    {"1_13_os1-991937000062-32A02_legacy.json", kFlat, 64, 1024, kLegacy, 0, 1023, 15.806, 36.18, {6.253, -11.775, 7.645}, "1.13.0", 0, 991937000062, 0, 0, 18},
    {"1_14_6cccd_os-882002000138-128_legacy.json", kFlat, 128, 1024, kLegacy, 0, 1023, 27.67, 36.18, {6.253, -11.775, 7.645}, "1.14.0", 0, 882002000138, 0, 46.2, 48},
    {"1_14_6cccd_os-882002000138-32U0_legacy.json", kFlat, 32, 1024, kLegacy, 0, 1023, 27.67, 36.18, {6.253, -11.775, 7.645}, "1.14.0", 0, 882002000138, 0, 43.9, 0},
    {"1_14_beta_os1-991937000062-16A0_legacy.json", kFlat, 16, 1024, kLegacy, 0, 1023, 15.806, 36.18, {6.253, -11.775, 7.645}, "1.14.0", 0, 991937000062, 0, 14.799, 0},
    {"1_14_beta_os1-991937000062-64_legacy.json", kFlat, 64, 1024, kLegacy, 0, 1023, 15.806, 36.18, {6.253, -11.775, 7.645}, "1.14.0", 0, 991937000062, 0, 16.509, 18},
    {"2_0_0_os1-991913000010-64.json", kNested, 64, 1024, kLegacy, 0, 1023, 12.163, 36.18, {6.253, -11.775, 7.645}, "2.0.0", 0, 991913000010, 55426, 16.729, 19},
    {"2_0_0_os1-992008000494-128_col_win_legacy.json", kFlat, 128, 2048, kLegacy, 2014, 2036, 15.806, 36.18, {6.253, -11.775, 7.645}, "2.0.0", 0, 992008000494, 0, 21.4764, 48},
    {"2_0_rc2_os-992011000121-32U0_legacy.json", kFlat, 32, 512, kLegacy, 0, 511, 15.806, 36.18, {6.253, -11.775, 7.645}, "2.0.0", 0, 992011000121, 0, 20.5477, 0},
    {"2_1_2_os1-991913000010-64.json", kNested, 64, 1024, kLegacy, 0, 1023, 12.163, 36.18, {6.253, -11.775, 7.645}, "2.1.2", 0, 991913000010, 7502, 16.729, 19},
    {"2_1_2_os1-991913000010-64_legacy.json", kFlat, 64, 1024, kLegacy, 0, 1023, 12.163, 36.18, {6.253, -11.775, 7.645}, "2.1.2", 0, 991913000010, 0, 16.729, 19},
    {"2_2_os-992119000444-128.json", kNested, 128, 1024, kLegacy, 0, 1023, 15.806, 36.18, {6.253, -11.775, 7.645}, "2.2.0", 7109745, 992119000444, 7502, 21.51, 24},
    {"2_2_os-992119000444-128_legacy.json", kFlat, 128, 1024, kLegacy, 0, 1023, 15.806, 36.18, {6.253, -11.775, 7.645}, "2.2.0", 7109745, 992119000444, 7502, 21.51, 24},
    {"2_3_1_os-992146000760-128.json", kNested, 128, 1024, kRng15, 0, 1023, 15.806, 36.18, {6.253, -11.775, 7.645}, "2.3.1", 5431287, 992146000760, 7502, 21.34, 24},
    {"2_3_1_os-992146000760-128_legacy.json", kFlat, 128, 1024, kRng15, 0, 1023, 15.806, 36.18, {6.253, -11.775, 7.645}, "2.3.1", 5431287, 992146000760, 7502, 21.34, 24},
    {"2_4_0_os-992146000760-128.json", kNested, 128, 1024, kRng19, 0, 1023, 15.806, 36.18, {6.253, -11.775, 7.645}, "2.4.0", 2573180, 992146000760, 7502, 21.34, 12},
    {"2_4_0_os-992146000760-128_legacy.json", kFlat, 128, 1024, kRng19, 0, 1023, 15.806, 36.18, {6.253, -11.775, 7.645}, "2.4.0", 2573180, 992146000760, 7502, 21.34, 12},
    {"2_5_0_os-992146000760-128.json", kNested, 128, 1024, kRng19, 912, 1022, 15.806, 36.18, {6.253, -11.775, 7.645}, "2.5.0", 8247301, 992146000760, 7502, 21.34, 12},
    {"2_5_0_os-992146000760-128_legacy.json", kFlat, 128, 1024, kRng19, 912, 1022, 15.806, 36.18, {6.253, -11.775, 7.645}, "2.5.0", 8247301, 992146000760, 7502, 21.34, 12},
    {"3_0_1_os-122246000293-128.json", kNested, 128, 1024, kDual, 0, 1023, 16.721, 38.195, {-2.441, -9.725, 7.533}, "3.0.1", 1629346, 122246000293, 7502, 20.47, 12},
    {"3_0_1_os-122246000293-128_legacy.json", kFlat, 128, 1024, kDual, 0, 1023, 16.721, 38.195, {-2.441, -9.725, 7.533}, "3.0.1", 1629346, 122246000293, 7502, 20.47, 12},
    {"ouster-studio-reduced-config-v1.json", kFlat, 64, 2048, kLegacy, 0, 2047, 12.163, 36.18, {6.253, -11.775, 7.645}, "0.0.0", 0, 0, 0, 21.45, 36},
};
// The metadata of the captures beside the pcaps.
const Expected kCaptureFiles[] = {
    {"OS-0-128-U1_v2.3.0_1024x10.json", kFlat, 128, 1024, kRng15, 0, 1023, 27.67, 36.18, {6.253, -11.775, 7.645}, "2.3.0", 5431292, 122150000150, 7502, 45.75, 64},
    {"OS-0-32-U1_v2.2.0_1024x10.json", kFlat, 32, 1024, kDual, 0, 1023, 27.67, 36.18, {6.253, -11.775, 7.645}, "2.2.0", 9599938, 992137000142, 7502, 43.88, 26},
    {"OS-1-32-G_v2.1.1_1024x10.json", kFlat, 32, 1024, kLegacy, 0, 1023, 15.806, 36.18, {6.253, -11.775, 7.645}, "2.1.1", 0, 992101000280, 0, 12.75, 0},
    {"OS-2-128-U1_v2.3.0_1024x10.json", kFlat, 128, 1024, kRng19, 0, 1023, 13.762, 78.296, {6.253, -11.775, 11.645}, "2.3.0", 5431293, 992210000957, 7502, 10.76, 12},
    {"empty_pcap.json", kNested, 128, 512, kDual, 0, 511, 27.397, 78.296, {-6.253, 11.775, 11.645}, "2.5.0", 7109746, 992305000159, 7502, 10.72, 3},
};
// clang-format on

// Why each deliberately broken file must be rejected: substrings of the message.
const std::map<std::string, std::vector<std::string>> kMalformedFiles = {
    {"complete_but_all_zeros_legacy.json", {"beam_altitude_angles: all 128 entries are 0"}},
    {"garbled_legacy_and_nonlegacy.json",
     {"mixes the two metadata layouts", "beam_intrinsics", "data_format"}},
    {"incomplete_data_format_legacy.json", {"data_format.columns_per_frame: is missing"}},
    {"incomplete_data_format_nonlegacy.json", {"lidar_data_format.pixels_per_column: is missing"}},
    {"incomplete_no_calref_nonlegacy.json", {"calibration_status: is missing"}},
    {"incomplete_no_sensor_info_nonlegacy.json", {"sensor_info: is missing"}},
    {"incorrect_nbeam_angles_legacy_113.json",
     {"beam_altitude_angles: 63 entries, but pixels_per_column is 64"}},
    {"legacy_with_calibration_status.json",
     {"mixes the two metadata layouts", "(calibration_status)", "beam_altitude_angles"}},
};

std::string Firmware(const SensorInfo& s) {
    return std::to_string(s.fw_major) + "." + std::to_string(s.fw_minor) + "." +
           std::to_string(s.fw_patch);
}

bool IsNested(const fs::path& path) {
    // The nested layout's files carry a "sensor_info" section; the flat ones never do.
    std::ifstream in(path);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    return text.find("\"sensor_info\"") != std::string::npos;
}

void ExpectFile(const fs::path& path, const Expected& e) {
    SCOPED_TRACE(path.string());
    SensorInfo s;
    try {
        s = LoadMetadata(path);
    } catch (const common::FileError& error) {
        ADD_FAILURE() << "rejected: " << error.what();
        return;
    }
    EXPECT_EQ(IsNested(path), e.nested);
    EXPECT_EQ(s.source, path.string());
    EXPECT_EQ(s.format.pixels_per_column, e.h);
    EXPECT_EQ(s.format.columns_per_frame, e.w);
    EXPECT_EQ(s.format.columns_per_packet, 16);
    EXPECT_EQ(s.format.lidar_profile, e.profile) << ToString(s.format.lidar_profile);
    EXPECT_EQ(s.format.column_window_first, e.window_first);
    EXPECT_EQ(s.format.column_window_last, e.window_last);
    EXPECT_EQ(s.format.pixel_shift_by_row.size(), size_t(e.h));
    if (!s.format.pixel_shift_by_row.empty()) {
        EXPECT_EQ(s.format.pixel_shift_by_row[0], e.first_pixel_shift);
    }
    EXPECT_EQ(s.beam_altitude_angles_deg.size(), size_t(e.h));
    EXPECT_EQ(s.beam_azimuth_angles_deg.size(), size_t(e.h));
    if (!s.beam_altitude_angles_deg.empty()) {
        EXPECT_EQ(s.beam_altitude_angles_deg[0], e.first_altitude_deg);
    }
    EXPECT_EQ(s.frame_rate_hz, 10.0);
    EXPECT_EQ(s.lidar_origin_to_beam_origin_mm, e.beam_origin_mm);
    Eigen::Matrix4d beam = Eigen::Matrix4d::Identity();
    beam(0, 3) = e.beam_origin_mm;
    EXPECT_EQ(s.beam_to_lidar_transform, beam) << s.beam_to_lidar_transform;
    Eigen::Matrix4d lidar = Eigen::Matrix4d::Identity();
    lidar(0, 0) = lidar(1, 1) = -1.0;
    lidar(2, 3) = e.lidar_to_sensor_z_mm;
    EXPECT_EQ(s.lidar_to_sensor_transform, lidar) << s.lidar_to_sensor_transform;
    Eigen::Matrix4d imu = Eigen::Matrix4d::Identity();
    imu.block<3, 1>(0, 3) << e.imu_t_mm[0], e.imu_t_mm[1], e.imu_t_mm[2];
    EXPECT_EQ(s.imu_to_sensor_transform, imu) << s.imu_to_sensor_transform;
    EXPECT_EQ(Firmware(s), e.fw);
    EXPECT_EQ(s.init_id, e.init_id);
    EXPECT_EQ(s.prod_sn, e.prod_sn);
    EXPECT_EQ(s.udp_port_lidar.value_or(0), e.udp_port_lidar);
}

TEST(MetadataData, EveryMetadataFileIsAccepted) {
    BIMSLAM_REQUIRE_SHARED_DATA(dir, "ouster/metadata");
    std::set<std::string> seen;
    for (const auto& entry : fs::directory_iterator(dir)) {
        if (!entry.is_regular_file()) continue;
        const std::string name = entry.path().filename().string();
        const auto e = std::find_if(std::begin(kMetadataFiles), std::end(kMetadataFiles),
                                    [&](const Expected& x) { return name == x.file; });
        if (e == std::end(kMetadataFiles)) {
            ADD_FAILURE() << name << " has no row in kMetadataFiles: add what it must give";
            continue;
        }
        ExpectFile(entry.path(), *e);
        seen.insert(name);
    }
    EXPECT_EQ(seen.size(), std::size(kMetadataFiles)) << "files of the table are missing";
}

TEST(MetadataData, CaptureMetadataIsAccepted) {
    BIMSLAM_REQUIRE_SHARED_DATA(dir, "ouster/metadata");
    for (const Expected& e : kCaptureFiles) ExpectFile(dir.parent_path() / e.file, e);
}

// The SDK's test data holds each recent file in both layouts ("x.json" and "x_legacy.json"):
// both must give the same sensor (ports aside: the flat FW 2.1 file has none).
TEST(MetadataData, BothLayoutsOfOneFileAgree) {
    BIMSLAM_REQUIRE_SHARED_DATA(dir, "ouster/metadata");
    int pairs = 0;
    for (const auto& entry : fs::directory_iterator(dir)) {
        const std::string name = entry.path().filename().string();
        const fs::path legacy = dir / (entry.path().stem().string() + "_legacy.json");
        if (name.ends_with("_legacy.json") || !fs::exists(legacy)) continue;
        SCOPED_TRACE(name);
        const SensorInfo a = LoadMetadata(entry.path()), b = LoadMetadata(legacy);
        EXPECT_EQ(a.prod_line, b.prod_line);
        EXPECT_EQ(a.prod_sn, b.prod_sn);
        EXPECT_EQ(a.build_rev, b.build_rev);
        EXPECT_EQ(a.init_id, b.init_id);
        EXPECT_EQ(a.lidar_mode, b.lidar_mode);
        EXPECT_EQ(a.format.pixels_per_column, b.format.pixels_per_column);
        EXPECT_EQ(a.format.columns_per_frame, b.format.columns_per_frame);
        EXPECT_EQ(a.format.pixel_shift_by_row, b.format.pixel_shift_by_row);
        EXPECT_EQ(a.format.column_window_first, b.format.column_window_first);
        EXPECT_EQ(a.format.column_window_last, b.format.column_window_last);
        EXPECT_EQ(a.format.lidar_profile, b.format.lidar_profile);
        EXPECT_EQ(a.beam_altitude_angles_deg, b.beam_altitude_angles_deg);
        EXPECT_EQ(a.beam_azimuth_angles_deg, b.beam_azimuth_angles_deg);
        EXPECT_EQ(a.beam_to_lidar_transform, b.beam_to_lidar_transform);
        EXPECT_EQ(a.lidar_to_sensor_transform, b.lidar_to_sensor_transform);
        EXPECT_EQ(a.imu_to_sensor_transform, b.imu_to_sensor_transform);
        ++pairs;
    }
    EXPECT_EQ(pairs, 6);  // FW 2.1.2, 2.2, 2.3.1, 2.4.0, 2.5.0, 3.0.1
}

TEST(MetadataData, EveryMalformedFileIsRejectedNamingTheField) {
    BIMSLAM_REQUIRE_SHARED_DATA(dir, "ouster/metadata/malformed");
    size_t seen = 0;
    for (const auto& entry : fs::directory_iterator(dir)) {
        const std::string name = entry.path().filename().string();
        const auto expected = kMalformedFiles.find(name);
        if (expected == kMalformedFiles.end()) {
            ADD_FAILURE() << name << " has no row in kMalformedFiles: say why it must fail";
            continue;
        }
        ++seen;
        try {
            LoadMetadata(entry.path());
            ADD_FAILURE() << name << " was accepted";
        } catch (const common::FileError& e) {
            EXPECT_EQ(e.path(), entry.path().string());
            EXPECT_EQ(e.code(), common::StatusCode::kParseError);
            for (const std::string& part : expected->second) {
                EXPECT_NE(e.detail().find(part), std::string::npos)
                    << name << ": expected \"" << part << "\" in: " << e.detail();
            }
        }
    }
    EXPECT_EQ(seen, kMalformedFiles.size()) << "files of the table are missing";
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::ouster

namespace bimslam::ouster {
namespace {
namespace BIMSLAM_UNITY_ID {

// What we write (the nested layout) reads back to the same sensor, for every real file.
TEST(MetadataData, SerializedMetadataReadsBackTheSame) {
    BIMSLAM_REQUIRE_SHARED_DATA(dir, "ouster/metadata");
    int files = 0;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
        if (!entry.is_regular_file()) continue;
        SCOPED_TRACE(entry.path().filename().string());
        const SensorInfo info = LoadMetadata(entry.path());
        const SensorInfo back = ParseMetadata("serialized", SerializeMetadata(info));
        fixtures::ExpectSameSensor(info, back);
        ++files;
    }
    EXPECT_GT(files, 20);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::ouster
