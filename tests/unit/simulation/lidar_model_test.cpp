// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/simulation/lidar_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "algorithms/common/status.hpp"
#include "drivers/ouster/builtin_sensor.hpp"
#include "drivers/ouster/xyz_lut.hpp"

// The test may link drivers/ouster (the layer rules bind libraries, not tests), so the model is
// checked against the driver's own XYZ table rather than a re-derivation of the formula.
namespace bimslam::simulation {
namespace {
namespace BIMSLAM_UNITY_ID {

TEST(LidarModel, DefaultOs1_32HasTheBuiltInTable) {
    const LidarModel m = LidarModel::DefaultOs1_32();
    ASSERT_EQ(m.beams(), 32);
    EXPECT_EQ(m.columns, 1024);
    EXPECT_EQ(m.frame_rate_hz, 10.0);
    EXPECT_EQ(m.pixels(), 32u * 1024u);
    EXPECT_DOUBLE_EQ(m.beam_altitude_deg.front(), 22.5);
    EXPECT_DOUBLE_EQ(m.beam_altitude_deg.back(), -22.5);
    for (int u = 1; u < 32; ++u) {  // uniform: 45 / 31 degrees apart
        EXPECT_NEAR(m.beam_altitude_deg[u - 1] - m.beam_altitude_deg[u], 45.0 / 31.0, 1e-12);
    }
    EXPECT_EQ(m.beam_azimuth_deg[0], 4.23);
    EXPECT_EQ(m.beam_azimuth_deg[3], -4.23);
    EXPECT_EQ(m.beam_origin_mm, 15.806);
    EXPECT_EQ(m.beam_z_mm, 0.0);
    EXPECT_NEAR(m.BeamOriginDistance(), 0.015806, 1e-15);
    EXPECT_EQ(m.lidar_to_sensor_transform(2, 3), 36.18);
    EXPECT_EQ(m.lidar_to_sensor_transform(0, 0), -1.0);
}

// Direction and Origin are the driver's XYZ table (specs/ouster-lidar.md "Range -> XYZ"): every
// pixel of every OS1 mode, and with a beam z offset (FW 2.5+ beam_to_lidar_transform).
TEST(LidarModel, EqualsTheDriversXyzTableForEveryPixel) {
    struct Mode {
        int columns, rate;
    };
    for (const Mode mode : {Mode{512, 10}, Mode{1024, 10}, Mode{2048, 10}, Mode{1024, 20}}) {
        for (const double z0 : {0.0, 7.5}) {
            ouster::SensorInfo info = ouster::BuiltinOs1_32(
                ouster::LidarProfile::kRng19Rfl8Sig16Nir16, mode.columns, mode.rate);
            info.beam_to_lidar_transform(2, 3) = z0;
            LidarModel m = LidarModel::DefaultOs1_32(mode.columns, mode.rate);
            m.beam_z_mm = z0;
            const ouster::XyzLut<double> lut(info);
            double worst = 0;
            for (int u = 0; u < m.beams(); ++u) {
                for (int v = 0; v < m.columns; ++v) {
                    worst = std::max(worst, (m.Direction(u, v) - lut.direction(u, v)).norm());
                    worst = std::max(worst, (m.Origin(u, v) - lut.offset(u, v)).norm());
                }
            }
            EXPECT_LT(worst, 1e-9) << mode.columns << "x" << mode.rate << " z0 " << z0;
            // The emission point is d along the ray from the table origin (d = |(n, z0)|).
            EXPECT_NEAR(m.BeamOriginDistance() * 1000, std::hypot(15.806, z0), 1e-12);
        }
    }
}

TEST(LidarModel, DirectionsAreUnitAndEmissionPointsOnTheBeamCircle) {
    const LidarModel m = LidarModel::DefaultOs1_32(512);
    const Eigen::Matrix3d R = m.lidar_to_sensor_transform.topLeftCorner<3, 3>();
    const Eigen::Vector3d t = m.lidar_to_sensor_transform.topRightCorner<3, 1>() * 0.001;
    for (int u = 0; u < m.beams(); ++u) {
        for (int v = 0; v < m.columns; v += 7) {
            EXPECT_NEAR(m.Direction(u, v).norm(), 1.0, 1e-12);
            // Origin + d * Direction, back in the lidar frame, lies on the circle of radius n in
            // the XY plane: the beam leaves the rotating optics there.
            const Eigen::Vector3d e =
                R.transpose() * (m.Origin(u, v) + m.BeamOriginDistance() * m.Direction(u, v) - t);
            EXPECT_NEAR(e.head<2>().norm(), 0.015806, 1e-12);
            EXPECT_NEAR(e.z(), 0.0, 1e-12);
        }
    }
}

TEST(LidarModel, ColumnTimes) {
    const LidarModel m = LidarModel::DefaultOs1_32(1024, 10);
    EXPECT_EQ(m.ColumnTimeOffsetNs(0), 0);
    EXPECT_EQ(m.ColumnTimeOffsetNs(1), 97656);  // spec: ~97.7 us apart in 1024x10
    EXPECT_EQ(m.ColumnTimeOffsetNs(1023), 99902344);
    EXPECT_EQ(LidarModel::DefaultOs1_32(512, 20).ColumnTimeOffsetNs(256), 25000000);
}

void ExpectInvalid(const LidarModel& m, const std::string& needle) {
    try {
        m.Validate();
        ADD_FAILURE() << "no error, expected one naming " << needle;
    } catch (const common::Error& e) {
        EXPECT_EQ(e.code(), common::StatusCode::kInvalidArgument);
        EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
}

TEST(LidarModel, ValidateNamesTheField) {
    LidarModel m = LidarModel::DefaultOs1_32();
    m.Validate();
    LidarModel bad = m;
    bad.beam_altitude_deg.clear();
    bad.beam_azimuth_deg.clear();
    ExpectInvalid(bad, "beam_altitude_deg.size()");
    bad = m;
    bad.beam_azimuth_deg.pop_back();
    ExpectInvalid(bad, "beam_azimuth_deg.size()");
    bad = m;
    bad.beam_altitude_deg[3] = NAN;
    ExpectInvalid(bad, "beam_altitude_deg[3]");
    bad = m;
    bad.beam_azimuth_deg[5] = 400;
    ExpectInvalid(bad, "beam_azimuth_deg[5]");
    bad = m;
    bad.columns = 0;
    ExpectInvalid(bad, "columns");
    bad = m;
    bad.frame_rate_hz = 0;
    ExpectInvalid(bad, "frame_rate_hz");
    bad = m;
    bad.beam_origin_mm = INFINITY;
    ExpectInvalid(bad, "beam_origin_mm");
    bad = m;
    bad.lidar_to_sensor_transform(0, 0) = 2;
    ExpectInvalid(bad, "lidar_to_sensor_transform");
    bad = m;
    bad.lidar_to_sensor_transform(3, 0) = 1;
    ExpectInvalid(bad, "lidar_to_sensor_transform[3]");
    EXPECT_THROW(LidarModel::DefaultOs1_32(0), common::Error);
    EXPECT_THROW(LidarModel::DefaultOs1_32(1024, -10), common::Error);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::simulation
