// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The hot path (per packet) must not allocate after the first frame (DESIGN.md, "Hot path").
// Its binary links the counting operator new of tests/support/allocation_counter.hpp.
#include <gtest/gtest.h>

#include "drivers/ouster/frame_batcher.hpp"
#include "drivers/ouster/imu_packet.hpp"
#include "tests/support/allocation_counter.hpp"
#include "tests/support/ouster_fixtures.hpp"

namespace bimslam::ouster {
namespace {
namespace BIMSLAM_UNITY_ID {

TEST(HotPath, BatcherAndImuDecoderDoNotAllocateAfterTheFirstFrame) {
    for (LidarProfile profile : fixtures::kAllProfiles) {
        const SensorInfo info = fixtures::MakeSensor(profile);
        const PacketEncoder enc(info, true);
        std::vector<std::vector<uint8_t>> packets;
        for (uint32_t id = 0; id < 4; ++id) {
            const auto p = fixtures::Encode(enc, fixtures::MakeFrame(enc.format(), id, id));
            packets.insert(packets.end(), p.begin(), p.end());
        }
        FrameBatcher b(info);
        for (size_t i = 0; i < 64; ++i) b.AddPacket(packets[i].data(), packets[i].size());
        const size_t before = test::Allocations();
        size_t frames = 0;
        for (size_t i = 64; i < packets.size(); ++i) {
            frames += b.AddPacket(packets[i].data(), packets[i].size()).frames;
            if (i % 7 == 0) b.AddPacket(packets[i].data(), 10);  // rejections too
        }
        EXPECT_EQ(test::Allocations() - before, 0u) << ToString(profile);
        EXPECT_EQ(frames, 3u);
    }
    const SensorInfo info = fixtures::MakeSensor(LidarProfile::kLegacy);
    ImuDecoder imu(info);
    PacketEncoder enc(info);
    uint8_t packet[48];
    enc.EncodeLegacyImuPacket(ImuSample{}, 0, packet);
    ImuSample samples[4];
    const size_t before = test::Allocations();
    for (int i = 0; i < 100; ++i) imu.Decode(packet, sizeof(packet), samples);
    EXPECT_EQ(test::Allocations() - before, 0u);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::ouster
