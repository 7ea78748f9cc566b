// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "drivers/ouster/packet_format.hpp"

#include <gtest/gtest.h>

#include <random>

#include "algorithms/common/status.hpp"
#include "drivers/ouster/crc64.hpp"
#include "tests/support/ouster_fixtures.hpp"

namespace bimslam::ouster {
namespace {
namespace BIMSLAM_UNITY_ID {

// Crc64Xz is liblzma's on x86-64 and our table elsewhere (crc64.hpp): both are held to the
// definition, at every alignment.
TEST(Crc64, CheckValueAndAgreesWithBitwiseDefinition) {
    const char* check = "123456789";
    EXPECT_EQ(Crc64Xz(reinterpret_cast<const uint8_t*>(check), 9), 0x995DC9BBDF1939FAull);
    EXPECT_EQ(Crc64XzTable(reinterpret_cast<const uint8_t*>(check), 9), 0x995DC9BBDF1939FAull);
    std::mt19937 rng(3);
    for (size_t n : {0u, 1u, 7u, 8u, 9u, 63u, 6456u, 24888u}) {
        std::vector<uint8_t> data(n + 8);
        for (auto& b : data) b = static_cast<uint8_t>(rng());
        for (size_t offset : {0u, 1u, 3u, 7u}) {
            const uint8_t* p = data.data() + offset;
            uint64_t crc = ~0ull;  // the definition: reflected, bit by bit
            for (size_t i = 0; i < n; ++i) {
                crc ^= p[i];
                for (int k = 0; k < 8; ++k)
                    crc = (crc & 1) ? (crc >> 1) ^ 0xC96C5795D7870F42ull : crc >> 1;
            }
            EXPECT_EQ(Crc64Xz(p, n), ~crc) << n << " at +" << offset;
            EXPECT_EQ(Crc64XzTable(p, n), ~crc) << n << " at +" << offset;
        }
    }
}

TEST(PacketFormat, SizesOfTheSpec) {
    // specs/ouster-lidar.md: LEGACY H=16 3392, 32 6464, 64 12608, 128 24896; OS1-32 LEGACY 6464,
    // RNG19 6400, RNG15 2304, DUAL 8448.
    const std::pair<int, size_t> legacy[] = {{16, 3392}, {32, 6464}, {64, 12608}, {128, 24896}};
    for (const auto& [h, size] : legacy) {
        EXPECT_EQ(PacketFormat(fixtures::MakeSensor(LidarProfile::kLegacy, h)).lidar_packet_size(),
                  size);
    }
    EXPECT_EQ(
        PacketFormat(fixtures::MakeSensor(LidarProfile::kRng19Rfl8Sig16Nir16)).lidar_packet_size(),
        6400u);
    EXPECT_EQ(PacketFormat(fixtures::MakeSensor(LidarProfile::kRng15Rfl8Nir8)).lidar_packet_size(),
              2304u);
    EXPECT_EQ(PacketFormat(fixtures::MakeSensor(LidarProfile::kRng19Rfl8Sig16Nir16Dual))
                  .lidar_packet_size(),
              8448u);
    // The two shared captures of 8448 B: OS-0-32 DUAL and OS-0-128 RNG15.
    EXPECT_EQ(
        PacketFormat(fixtures::MakeSensor(LidarProfile::kRng15Rfl8Nir8, 128)).lidar_packet_size(),
        8448u);
    EXPECT_EQ(
        PacketFormat(fixtures::MakeSensor(LidarProfile::kRng15Rfl8Nir8Dual)).lidar_packet_size(),
        32u + 16 * (12 + 32 * 8) + 32);
    EXPECT_EQ(PacketFormat(fixtures::MakeSensor(LidarProfile::kLegacy)).imu_packet_size(), 48u);
}

TEST(PacketFormat, HeaderFieldsAtTheirBits) {
    for (HeaderType header : {HeaderType::kStandard, HeaderType::kFusa}) {
        SensorInfo info =
            fixtures::MakeSensor(LidarProfile::kRng19Rfl8Sig16Nir16, 32, 1024, header);
        info.prod_sn = 0xAB12345678ull;  // all 40 bits used
        info.init_id = 0xC0FFEE;
        const PacketEncoder enc(info);
        const LidarFrame frame = fixtures::MakeFrame(enc.format(), 0xFEDC, 1);
        std::vector<uint8_t> p(enc.format().lidar_packet_size());
        enc.EncodeLidarPacket(frame, 3, p.data());
        const PacketFormat& f = enc.format();
        EXPECT_EQ(f.PacketType(p.data()), 1u);
        EXPECT_EQ(f.FrameId(p.data()), 0xFEDCu);
        EXPECT_EQ(f.InitId(p.data()), 0xC0FFEEu);
        EXPECT_EQ(f.ProdSn(p.data()), 0xAB12345678ull);
        EXPECT_EQ(f.MeasurementId(f.Column(p.data(), 0)), 48);
        EXPECT_EQ(f.ColumnTimestamp(f.Column(p.data(), 1)), frame.timestamp[49]);
    }
    // STANDARD fixed bytes: packet_type 0..1, frame_id 2..3, init_id 4..6, prod_sn 7..11.
    SensorInfo info = fixtures::MakeSensor(LidarProfile::kRng19Rfl8Sig16Nir16);
    info.init_id = 0x030201;
    info.prod_sn = 0x0807060504ull;
    const PacketEncoder enc(info);
    const LidarFrame frame = fixtures::MakeFrame(enc.format(), 0x0A09, 2);
    std::vector<uint8_t> p(enc.format().lidar_packet_size());
    enc.EncodeLidarPacket(frame, 0, p.data());
    const uint8_t expected[] = {1, 0, 0x09, 0x0A, 1, 2, 3, 4, 5, 6, 7, 8};
    EXPECT_TRUE(std::equal(std::begin(expected), std::end(expected), p.begin()));
}

TEST(PacketFormat, RejectsImpossibleLayouts) {
    SensorInfo info = fixtures::MakeSensor(LidarProfile::kLegacy);
    info.format.columns_per_packet = 24;  // 1024 is not a multiple
    EXPECT_THROW(PacketFormat{info}, common::Error);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::ouster
