// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/bim/lidar_from_metadata.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <string>
#include <vector>

#include "algorithms/common/status.hpp"
#include "algorithms/simulation/lidar_simulator.hpp"
#include "drivers/ouster/builtin_sensor.hpp"
#include "drivers/ouster/metadata.hpp"
#include "drivers/ouster/xyz_lut.hpp"
#include "tests/support/test_support.hpp"
#include "tests/unit/simulation/box_room.hpp"

namespace bimslam::bim {
namespace {
namespace BIMSLAM_UNITY_ID {

using simulation::LidarModel;

void ExpectSameModel(const LidarModel& a, const LidarModel& b) {
    EXPECT_EQ(a.beam_altitude_deg, b.beam_altitude_deg);
    EXPECT_EQ(a.beam_azimuth_deg, b.beam_azimuth_deg);
    EXPECT_EQ(a.columns, b.columns);
    EXPECT_EQ(a.frame_rate_hz, b.frame_rate_hz);
    EXPECT_EQ(a.beam_origin_mm, b.beam_origin_mm);
    EXPECT_EQ(a.beam_z_mm, b.beam_z_mm);
    EXPECT_EQ(a.lidar_to_sensor_transform, b.lidar_to_sensor_transform);
}

// Expects `statement` to throw common::FileError naming `file`.
#define EXPECT_ERROR_NAMES_FILE(statement, file)                        \
    try {                                                               \
        statement;                                                      \
        ADD_FAILURE() << "no error from " #statement;                   \
    } catch (const common::FileError& e) {                              \
        EXPECT_EQ(e.path(), (file).string()) << e.what();               \
        EXPECT_EQ(std::string(e.what()).rfind((file).string(), 0), 0u); \
    }

// The metadata JSON the Ouster tools would save for `info`, written to `dir`.
std::filesystem::path WriteMetadata(const test::TempDir& dir, const ouster::SensorInfo& info,
                                    const std::string& name = "lidar.json") {
    const std::filesystem::path path = dir / name;
    test::WriteBytes(path, ouster::SerializeMetadata(info));
    return path;
}

TEST(LidarFromMetadata, BuiltInOs1_32EqualsTheDefaultModel) {
    const test::TempDir dir;
    struct Mode {
        int columns, rate;
    };
    for (const Mode mode :
         {Mode{512, 10}, Mode{1024, 10}, Mode{2048, 10}, Mode{512, 20}, Mode{1024, 20}}) {
        const ouster::SensorInfo info = ouster::BuiltinOs1_32(
            ouster::LidarProfile::kRng19Rfl8Sig16Nir16, mode.columns, mode.rate);
        const LidarModel expected = LidarModel::DefaultOs1_32(mode.columns, mode.rate);
        ExpectSameModel(LidarModelFromSensorInfo(info), expected);
        // Through the metadata JSON and the driver's parser: the same numbers.
        ExpectSameModel(LidarModelFromMetadataFile(WriteMetadata(dir, info)), expected);
    }
}

// A sensor unlike the built-in one in every field the model takes: 64 irregular beams, a beam z
// offset (FW 2.5+ beam_to_lidar_transform), a tilted lidar_to_sensor_transform, 2048x10.
ouster::SensorInfo IrregularSensor() {
    ouster::SensorInfo info =
        ouster::BuiltinOs1_32(ouster::LidarProfile::kRng19Rfl8Sig16Nir16, 2048, 10);
    info.prod_line = "OS-1-64";
    info.format.pixels_per_column = 64;
    info.beam_altitude_angles_deg.clear();
    info.beam_azimuth_angles_deg.clear();
    info.format.pixel_shift_by_row.clear();
    for (int u = 0; u < 64; ++u) {
        info.beam_altitude_angles_deg.push_back(21.0 - 0.66 * u + 0.07 * std::sin(u));
        info.beam_azimuth_angles_deg.push_back((u % 4 - 1.5) * 2.9 + 0.03 * std::cos(3 * u));
        info.format.pixel_shift_by_row.push_back(12 * (u % 4));
    }
    info.beam_to_lidar_transform(0, 3) = 15.806;
    info.beam_to_lidar_transform(2, 3) = 9.25;
    Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
    T.topLeftCorner<3, 3>() = (Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(0.02, Eigen::Vector3d::UnitX()))
                                  .toRotationMatrix();
    T.topRightCorner<3, 1>() = Eigen::Vector3d(4.0, -3.0, 36.18);
    info.lidar_to_sensor_transform = T;
    return info;
}

TEST(LidarFromMetadata, TakesEveryFieldFromTheMetadata) {
    const test::TempDir dir;
    const ouster::SensorInfo info = IrregularSensor();
    const LidarModel m = LidarModelFromMetadataFile(WriteMetadata(dir, info));
    const ouster::SensorInfo parsed = ouster::LoadMetadata(dir / "lidar.json");
    EXPECT_EQ(m.beams(), 64);
    EXPECT_EQ(m.columns, 2048);
    EXPECT_EQ(m.frame_rate_hz, 10.0);
    EXPECT_EQ(m.beam_altitude_deg, parsed.beam_altitude_angles_deg);
    EXPECT_EQ(m.beam_azimuth_deg, parsed.beam_azimuth_angles_deg);
    EXPECT_EQ(m.beam_origin_mm, 15.806);
    EXPECT_EQ(m.beam_z_mm, 9.25);
    EXPECT_TRUE(m.lidar_to_sensor_transform.isApprox(info.lidar_to_sensor_transform, 1e-15));
    // The model's rays are the driver's XYZ table of the same metadata.
    const ouster::XyzLut<double> lut(parsed);
    double worst = 0;
    for (int u = 0; u < m.beams(); ++u) {
        for (int v = 0; v < m.columns; ++v) {
            worst = std::max(worst, (m.Direction(u, v) - lut.direction(u, v)).norm());
            worst = std::max(worst, (m.Origin(u, v) - lut.offset(u, v)).norm());
        }
    }
    EXPECT_LT(worst, 1e-9);
}

TEST(LidarFromMetadata, ErrorsNameTheFile) {
    const test::TempDir dir;
    const std::filesystem::path missing = dir / "missing.json";
    EXPECT_ERROR_NAMES_FILE(LidarModelFromMetadataFile(missing), missing);
    const std::filesystem::path broken = dir / "broken.json";
    test::WriteBytes(broken, "{\n  \"lidar_mode\": \n");
    EXPECT_ERROR_NAMES_FILE(LidarModelFromMetadataFile(broken), broken);
    // Metadata the driver accepts but the simulator cannot use: a lidar_to_sensor_transform that
    // scales (the driver checks only its last row).
    ouster::SensorInfo scaled = ouster::BuiltinOs1_32();
    scaled.lidar_to_sensor_transform(0, 0) = -2.0;
    const std::filesystem::path path = WriteMetadata(dir, scaled, "scaled.json");
    EXPECT_FILE_ERROR(LidarModelFromMetadataFile(path), path.string(), 0);
    try {
        LidarModelFromMetadataFile(path);
    } catch (const common::FileError& e) {
        EXPECT_EQ(e.code(), common::StatusCode::kInvalidArgument);
        EXPECT_NE(e.detail().find("lidar_to_sensor_transform"), std::string::npos) << e.what();
    }
    // From a SensorInfo the message starts with its source.
    scaled.source = "capture.json";
    try {
        LidarModelFromSensorInfo(scaled);
        ADD_FAILURE() << "no error";
    } catch (const common::Error& e) {
        EXPECT_EQ(std::string(e.what()).rfind("capture.json: LidarModel.", 0), 0u) << e.what();
    }
}

// The key round trip: a simulated range image, decoded by the driver's XYZ table of the same
// metadata, gives the ray-cast points, which lie on the room's walls.
TEST(LidarFromMetadata, SimulatedRangesDecodeWithTheDriverOntoTheWalls) {
    const test::TempDir dir;
    const test::BoxRoom room({0, 0, 0}, {6, 4, 3});
    const simulation::Scene scene(room.mesh, room.ids);
    simulation::NoiseModel noise = simulation::NoiseModel::Noiseless();
    noise.range_resolution_mm = 1;
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(2.4, 1.6, 1.1);
    T.linear() = (Eigen::AngleAxisd(0.6, Eigen::Vector3d::UnitZ()) *
                  Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitX()))
                     .toRotationMatrix();
    for (const ouster::SensorInfo& info : {ouster::BuiltinOs1_32(), IrregularSensor()}) {
        const std::filesystem::path path = WriteMetadata(dir, info);
        const LidarModel model = LidarModelFromMetadataFile(path);
        simulation::ScanImage img;
        const simulation::ScanStats stats =
            simulation::SimulateScan(scene, model, T, noise, 1, &img);
        ASSERT_EQ(stats.returns, model.pixels());

        const ouster::SensorInfo parsed = ouster::LoadMetadata(path);
        const ouster::XyzLut<double> lut(parsed);
        ASSERT_EQ(lut.h(), img.h);
        ASSERT_EQ(lut.w(), img.w);
        std::vector<Eigen::Vector3d> xyz(img.range_mm.size());
        lut.Compute(img.range_mm.data(), xyz.data());
        double worst_wall = 0, worst_cast = 0;
        for (int u = 0; u < img.h; ++u) {
            for (int v = 0; v < img.w; ++v) {
                const size_t i = img.Index(u, v);
                const Eigen::Vector3d p = T * xyz[i];  // sensor frame to the room
                ASSERT_TRUE(room.Contains(p, 1e-3)) << p.transpose();
                worst_wall = std::max(worst_wall, room.DistanceToWalls(p));
                // The ray-cast point itself: the analytic exit of the same ray.
                const Eigen::Vector3d o = T * model.Origin(u, v);
                const Eigen::Vector3d d = T.linear() * model.Direction(u, v);
                const test::BoxRoom::Exit e = room.Cast(o, d);
                worst_cast = std::max(worst_cast, (p - (o + e.t * d)).norm());
                if (e.margin > 1e-4) {
                    ASSERT_EQ(img.element_id[i], test::BoxRoom::kIdBase + e.wall);
                }
            }
        }
        EXPECT_LE(worst_wall, 1e-3) << info.prod_line;
        EXPECT_LE(worst_cast, 1e-3) << info.prod_line;
    }
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::bim
