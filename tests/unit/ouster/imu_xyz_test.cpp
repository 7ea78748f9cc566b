// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "drivers/ouster/imu_packet.hpp"
#include "drivers/ouster/lidar_frame.hpp"
#include "drivers/ouster/xyz_lut.hpp"
#include "tests/support/ouster_fixtures.hpp"

namespace bimslam::ouster {
namespace {
namespace BIMSLAM_UNITY_ID {

// The spec's formula, evaluated directly for one pixel (specs/ouster-lidar.md, "Range -> XYZ").
Eigen::Vector3d Formula(const SensorInfo& s, int u, int v, double range_mm) {
    const int w = s.format.columns_per_frame;
    const double te = 2 * M_PI - v * 2 * M_PI / w;
    const double ta = -s.beam_azimuth_angles_deg[u] * M_PI / 180;
    const double phi = s.beam_altitude_angles_deg[u] * M_PI / 180;
    const Eigen::Vector3d dir(std::cos(te + ta) * std::cos(phi), std::sin(te + ta) * std::cos(phi),
                              std::sin(phi));
    const double n = s.beam_to_lidar_transform(0, 3), z0 = s.beam_to_lidar_transform(2, 3);
    const double d = z0 != 0 ? std::sqrt(n * n + z0 * z0) : n;
    const Eigen::Vector3d off(n * std::cos(te) - d * dir.x(), n * std::sin(te) - d * dir.y(),
                              -d * dir.z() + z0);
    const Eigen::Matrix3d R = s.lidar_to_sensor_transform.topLeftCorner<3, 3>();
    const Eigen::Vector3d t = s.lidar_to_sensor_transform.topRightCorner<3, 1>();
    return (range_mm * (R * dir) + R * off + t) * 0.001;
}

TEST(XyzLut, MatchesTheSpecFormulaIncludingBeamZOffsets) {
    SensorInfo s = fixtures::MakeSensor(LidarProfile::kLegacy, 32, 1024);
    for (double z0 : {0.0, 12.5}) {  // FW 2.5+ beam_to_lidar_transform may hold a z offset
        s.beam_to_lidar_transform(2, 3) = z0;
        const XyzLut<double> lut(s);
        const XyzLut<float> lut_f(s);
        std::mt19937 rng(1);
        std::vector<uint32_t> range(32 * 1024);
        for (auto& r : range) r = rng() % 120000;
        range[5] = 0;
        std::vector<Eigen::Vector3d> xyz(range.size());
        std::vector<Eigen::Vector3f> xyz_f(range.size());
        lut.Compute(range.data(), xyz.data());
        lut_f.Compute(range.data(), xyz_f.data());
        for (int i = 0; i < 2000; ++i) {
            const int u = rng() % 32, v = rng() % 1024;
            const size_t k = size_t(u) * 1024 + v;
            if (range[k] == 0) continue;
            EXPECT_LT((xyz[k] - Formula(s, u, v, range[k])).norm(), 1e-12);
            EXPECT_LT((xyz_f[k].cast<double>() - xyz[k]).norm(), 2e-5);  // 20 um at 120 m
        }
        EXPECT_EQ(xyz[5], Eigen::Vector3d::Zero());  // no return, no point
    }
}

TEST(XyzLut, GeometryIsPlausible) {
    // A beam at 0 deg altitude, column 0 points along the lidar's +x, which the default
    // lidar_to_sensor_transform turns to the sensor's -x.
    SensorInfo s = fixtures::MakeSensor(LidarProfile::kLegacy, 16, 1024);
    s.beam_altitude_angles_deg.assign(16, 0.0);
    s.beam_azimuth_angles_deg.assign(16, 0.0);
    const XyzLut<double> lut(s);
    const Eigen::Vector3d p = lut.offset(0, 0) + 10.0 * lut.direction(0, 0);
    EXPECT_NEAR(p.x(), -10.0, 1e-9);  // range measured from the beam origin, n = 15.8 mm out
    EXPECT_NEAR(p.y(), 0.0, 1e-9);
    EXPECT_NEAR(p.z(), 0.03618, 1e-9);
    // Column W/4 is a quarter turn clockwise seen from above (theta_e decreases with v).
    EXPECT_NEAR(lut.direction(0, 256).y(), 1.0, 1e-9);
}

TEST(Destagger, ShiftsEachRow) {
    const std::vector<int> shift = {0, 1, 3};
    const int in[] = {0, 1, 2, 3, 10, 11, 12, 13, 20, 21, 22, 23};
    int out[12];
    Destagger(in, 3, 4, shift, out);
    const int expected[] = {0, 1, 2, 3, 13, 10, 11, 12, 21, 22, 23, 20};
    EXPECT_TRUE(std::equal(out, out + 12, expected));
}

TEST(ImuDecoder, LegacyPacketsInSiUnitsAndTheSensorFrame) {
    SensorInfo s = fixtures::MakeSensor(LidarProfile::kLegacy);
    // Rotate the IMU by 90 deg about z to see the frame change.
    s.imu_to_sensor_transform.topLeftCorner<3, 3>() << 0, -1, 0, 1, 0, 0, 0, 0, 1;
    uint8_t p[48] = {};
    const uint64_t times[] = {111, 222, 333};
    std::memcpy(p, times, 24);
    const float a_g[] = {1.0f, 0.0f, -0.5f}, w_dps[] = {90.0f, 0.0f, 0.0f};
    std::memcpy(p + 24, a_g, 12);
    std::memcpy(p + 36, w_dps, 12);
    ImuDecoder dec(s);
    ImuSample out[1];
    const auto r = dec.Decode(p, 48, out);
    ASSERT_EQ(r.samples, 1u);
    EXPECT_EQ(out[0].time_ns, 222u);
    EXPECT_EQ(out[0].gyro_time_ns, 333u);
    EXPECT_NEAR(out[0].accel.y(), 9.80665, 1e-6);  // imu x -> sensor y
    EXPECT_NEAR(out[0].accel.z(), -9.80665 / 2, 1e-6);
    EXPECT_NEAR(out[0].gyro.y(), M_PI / 2, 1e-6);
    // The encoder inverts it.
    PacketEncoder enc(s);
    uint8_t back[48];
    enc.EncodeLegacyImuPacket(out[0], 111, back);
    EXPECT_EQ(0, std::memcmp(back, p, 48));
    // Wrong size and non-finite values are rejected and counted.
    EXPECT_EQ(dec.Decode(p, 47, out).rejected, ImuReject::kSize);
    const float nan = std::nanf("");
    std::memcpy(p + 28, &nan, 4);
    EXPECT_EQ(dec.Decode(p, 48, out).rejected, ImuReject::kNonFinite);
    EXPECT_EQ(dec.stats().packets, 3u);
    EXPECT_EQ(dec.stats().samples, 1u);
}

TEST(ImuDecoder, Accel32Gyro32NmeaPackets) {
    SensorInfo s = fixtures::MakeSensor(LidarProfile::kRng19Rfl8Sig16Nir16);
    s.format.imu_profile = ImuProfile::kAccel32Gyro32Nmea;
    s.format.imu_measurements_per_packet = 8;
    ImuDecoder dec(s);
    ASSERT_EQ(dec.packet_size(), 32u + 100 + 8 * 36 + 32);
    std::vector<uint8_t> p(dec.packet_size(), 0);
    const uint16_t type = 2;
    std::memcpy(p.data(), &type, 2);
    const uint32_t init = s.init_id;
    std::memcpy(p.data() + 4, &init, 3);
    for (int i = 0; i < 5; ++i) p[7 + i] = uint8_t(s.prod_sn >> (8 * i));
    for (int i = 0; i < 8; ++i) {
        uint8_t* q = p.data() + 132 + 36 * i;
        const uint64_t t = 1000 + i;
        const uint16_t status = i == 3 ? 0 : 1;  // one invalid sample
        const float a[] = {0.1f * i, 0, 9.8f}, w[] = {0, 0.01f, 0};
        std::memcpy(q, &t, 8);
        std::memcpy(q + 10, &status, 2);
        std::memcpy(q + 12, a, 12);
        std::memcpy(q + 24, w, 12);
    }
    ImuSample out[8];
    const auto r = dec.Decode(p.data(), p.size(), out);
    ASSERT_FALSE(r.rejected.has_value());
    ASSERT_EQ(r.samples, 7u);
    EXPECT_EQ(out[3].time_ns, 1004u);
    EXPECT_NEAR(out[0].accel.z(), 9.8, 1e-6);
    EXPECT_EQ(dec.stats().invalid_samples, 1u);
    p[0] = 1;
    EXPECT_EQ(dec.Decode(p.data(), p.size(), out).rejected, ImuReject::kPacketType);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::ouster
