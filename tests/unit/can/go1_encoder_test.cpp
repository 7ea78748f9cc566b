// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "drivers/can/go1_encoder.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "algorithms/common/status.hpp"
#include "drivers/can/crc8.hpp"
#include "drivers/can/go1_decoder.hpp"
#include "tests/unit/can/go1_stream.hpp"

namespace bimslam::can {
namespace {
namespace BIMSLAM_UNITY_ID {

using Frames = std::array<common::CanFrame, Go1Encoder::kMaxFramesPerTick>;

// (id, sent with every n-th sample; 0: the 5 ms messages, also sent on the tick between).
constexpr std::pair<uint32_t, int> kSchedule[] = {{0x140, 10}, {0x101, 2}, {0x130, 2}, {0x131, 2},
                                                  {0x0F0, 1},  {0x100, 1}, {0x112, 1}, {0x120, 1},
                                                  {0x110, 0},  {0x111, 0}};

std::vector<uint32_t> Ids(const Frames& f, size_t n) {
    std::vector<uint32_t> ids;
    for (size_t i = 0; i < n; ++i) ids.push_back(f[i].id);
    return ids;
}

TEST(Go1Encoder, SendsEachMessageOnItsCycleSlowestFirstWithOneCounterPerSample) {
    Go1EncoderConfig config;
    config.frame_spacing_ns = 230'000;
    Go1Encoder enc(config);
    EXPECT_EQ(enc.layout().tick_ns(), 5'000'000);
    EXPECT_EQ(enc.layout().sample_period_ns(), 10'000'000);
    std::mt19937 rng(1);
    Frames out;
    std::array<common::CanFrame, kGo1Messages> first_copy{};
    for (int tick = 0; tick < 60; ++tick) {
        const int64_t t = tick * 5'000'000;
        const int n = tick / 2;  // sample index
        const Go1Sample s = testing::RandomSample(rng, t);
        ASSERT_EQ(enc.sample_tick_next(), tick % 2 == 0);
        const size_t k = enc.Tick(&s, t, out);
        // Slowest first: 100 ms, then 20 ms, 10 ms and 5 ms; the tick between: 5 ms only.
        std::vector<uint32_t> want;
        for (const auto& [id, every] : kSchedule) {
            if (every == 0 || (tick % 2 == 0 && n % every == 0)) want.push_back(id);
        }
        if (tick % 2 == 0) {
            EXPECT_EQ(enc.counter(), n % 15);
        }
        ASSERT_EQ(Ids(out, k), want) << "tick " << tick;
        for (size_t i = 0; i < k; ++i) {
            const common::CanFrame& f = out[i];
            EXPECT_EQ(f.len, 8);
            EXPECT_FALSE(f.extended || f.fd || f.remote || f.error);
            EXPECT_EQ(f.timestamp_ns, t + static_cast<int64_t>(i) * 230'000);
            EXPECT_EQ(f.data[0], Go1FrameCrc(f.id, f.data.data()));
            EXPECT_EQ(f.data[1] & 0x0F, n % 15);  // the sample's alive counter
            const int m = enc.layout().IndexOf(f.id);
            if (tick % 2 == 0) {
                first_copy[m] = f;
            } else {
                EXPECT_EQ(f.data, first_copy[m].data);  // byte for byte
            }
        }
    }
    EXPECT_EQ(enc.stats().samples, 30u);
    EXPECT_EQ(enc.stats().frames, 30u * 6 + 15 * 3 + 3 + 30 * 2);
    EXPECT_EQ(enc.stats().clamped, 0u);
    EXPECT_EQ(enc.stats().sna, 0u);
}

TEST(Go1Encoder, NoSampleSendsNothingAndCountersStartWhereConfigured) {
    Go1EncoderConfig config;
    config.first_counter = 13;
    Go1Encoder enc(config);
    Frames out;
    EXPECT_EQ(enc.Tick(nullptr, 0, out), 0u);
    EXPECT_TRUE(enc.sample_tick_next());
    const Go1Sample s;
    EXPECT_EQ(enc.Tick(&s, 1, out), 10u);
    EXPECT_EQ(out[0].data[1] & 0x0F, 13);
    EXPECT_EQ(enc.Tick(nullptr, 2, out), 2u);  // the repeat does not need a sample
    EXPECT_EQ(enc.EncodeSample(s, 3, out), 6u);
    EXPECT_EQ(out[0].data[1] & 0x0F, 14);
    EXPECT_EQ(enc.EncodeSample(s, 4, out), 9u);  // no repeat tick in between: fine
    EXPECT_EQ(out[0].data[1] & 0x0F, 0);         // 15 is never sent
    enc.Reset();
    EXPECT_EQ(enc.counter(), 13);
    config.first_counter = 15;
    EXPECT_THROW(Go1Encoder{config}, common::Error);
    config.first_counter = 0;
    config.frame_spacing_ns = -1;
    EXPECT_THROW(config.Validate(), common::Error);
}

// Encodes one sample, decodes it, returns what came out.
Go1Sample RoundTrip(const Go1Sample& s, Go1Encoder& enc, Go1Decoder& dec) {
    Frames out;
    const size_t k = enc.EncodeSample(s, 0, out);
    Go1Sample got;
    int emitted = 0;
    for (size_t i = 0; i < k; ++i) {
        dec.Feed(out[i]);
        for (const Go1Sample& r : dec.ready()) got = r, ++emitted;
    }
    EXPECT_EQ(emitted, 1);
    return got;
}

TEST(Go1Encoder, ClampsOutOfRangeSendsSnaForNanAndInvalidGroups) {
    Go1Encoder enc;
    Go1Decoder dec;
    std::mt19937 rng(2);
    Go1Sample s = testing::RandomSample(rng, 0);
    s.vx = 50.0;                                           // beyond 32.767 m/s
    s.foot_force_raw[2] = 5000;                            // beyond 4094
    s.imu_temperature_c = -128;                            // beyond -127 (and the SNA pattern)
    s.gyro[1] = std::numeric_limits<double>::quiet_NaN();  // not available
    s.valid = kAllGroups & ~kGroupOdomXy;
    Go1Sample got = RoundTrip(s, enc, dec);
    EXPECT_EQ(enc.stats().clamped, 3u);
    EXPECT_EQ(enc.stats().sna, 1u + 2u);  // gyro y; PosX and PosY
    EXPECT_NEAR(got.vx, 32.767, 1e-9);
    EXPECT_EQ(got.foot_force_raw[2], 4094);
    EXPECT_EQ(got.imu_temperature_c, -127);
    EXPECT_TRUE(std::isnan(got.gyro[1]));
    EXPECT_NEAR(got.gyro[0], s.gyro[0], 0.0005 + 1e-9);
    EXPECT_TRUE(std::isnan(got.odom_x) && std::isnan(got.odom_y));
    // Groups with an SNA or a clear Valid bit arrive invalid; the others valid.
    EXPECT_EQ(got.valid, kAllGroups & ~(kGroupGyro | kGroupOdomXy));
    EXPECT_EQ(got.fresh, kAllGroups);
    EXPECT_EQ(dec.stats().not_valid, 1u);  // ODOM_XY's Valid bit
    EXPECT_EQ(dec.stats().sna, 1u + 2u);
    // A group without a Valid bit (GO1_FOOT): every value SNA, flags clear.
    s.gyro[1] = 0;
    s.valid = kAllGroups & ~kGroupFoot;
    Go1Encoder enc2;
    Go1Decoder dec2;
    got = RoundTrip(s, enc2, dec2);
    EXPECT_EQ(got.foot_force_raw, (std::array<uint16_t, 4>{4095, 4095, 4095, 4095}));
    EXPECT_EQ(got.foot_contact, (std::array<bool, 4>{}));
    EXPECT_EQ(got.valid, kAllGroups & ~kGroupFoot);
    EXPECT_EQ(dec2.stats().sna, 4u);
}

TEST(Go1Encoder, QuaternionIsNormalisedWithWNonNegative) {
    Go1Encoder enc;
    Go1Decoder dec;
    Go1Sample s;
    s.valid = kAllGroups;
    s.quat_wxyz = {-2.0, 0.0, 0.0, 2.0};  // not unit, w < 0
    Go1Sample got = RoundTrip(s, enc, dec);
    const double h = std::sqrt(0.5);
    EXPECT_NEAR(got.quat_wxyz[0], h, 1e-4);
    EXPECT_NEAR(got.quat_wxyz[3], -h, 2e-5);
    EXPECT_EQ(got.quat_wxyz[1], 0.0);
    EXPECT_TRUE(got.valid & kGroupQuat);
    s.quat_wxyz = {0, 0, 0, 0};  // no rotation at all: not available
    got = RoundTrip(s, enc, dec);
    EXPECT_TRUE(std::isnan(got.quat_wxyz[0]));
    EXPECT_FALSE(got.valid & kGroupQuat);
}

TEST(Go1Encoder, BridgeTimeIsMicrosecondsModulo2To32) {
    Go1Encoder enc;
    Go1Sample s;
    s.bridge_time_ns = (int64_t{1} << 32) * 1000 + 5'000'999;  // 2^32 us + 5000.999 us
    common::CanFrame f = enc.EncodeMessage(0, s, 0, 0);
    uint32_t us = 0;
    for (int i = 5; i >= 2; --i) us = (us << 8) | f.data[i];
    EXPECT_EQ(us, 5000u);
    s.bridge_time_ns = -1;  // floor: -1 us
    f = enc.EncodeMessage(0, s, 0, 0);
    us = 0;
    for (int i = 5; i >= 2; --i) us = (us << 8) | f.data[i];
    EXPECT_EQ(us, 0xFFFFFFFFu);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::can
