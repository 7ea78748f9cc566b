// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The per-frame paths of drivers/can must not allocate once set up (DESIGN.md, "Hot path"):
// Go1Decoder::Feed/Tick/Flush, Go1Encoder::Tick, the signal codec and the CRC. Its binary links
// the counting operator new of tests/support/allocation_counter.hpp.
#include <gtest/gtest.h>

#include <array>
#include <random>
#include <vector>

#include "drivers/can/crc8.hpp"
#include "drivers/can/go1_decoder.hpp"
#include "drivers/can/go1_encoder.hpp"
#include "drivers/can/signal_codec.hpp"
#include "tests/support/allocation_counter.hpp"

namespace bimslam::can {
namespace {
namespace BIMSLAM_UNITY_ID {

TEST(HotPath, EncoderDecoderCodecAndCrcDoNotAllocate) {
    // Set-up may allocate: the DBC is parsed, the tables built.
    Go1Encoder encoder;
    Go1Decoder decoder;
    const MessageCodec codec(*Go1Dbc().FindMessage(0x100));
    std::mt19937 rng(1);
    Go1Sample sample;
    sample.valid = kAllGroups;
    std::array<common::CanFrame, Go1Encoder::kMaxFramesPerTick> out;
    std::vector<common::CanFrame> faults(4);
    const size_t before = test::Allocations();
    size_t samples = 0;
    double sink = 0;
    for (int tick = 0; tick < 4000; ++tick) {
        const int64_t t = int64_t{tick} * 5'000'000;
        sample.vx = (rng() % 1000) * 0.01;
        sample.valid = rng() % 50 == 0 ? 0 : kAllGroups;
        const size_t n = encoder.Tick(&sample, t, out);
        for (size_t i = 0; i < n; ++i) {
            common::CanFrame f = out[i];
            if (rng() % 40 == 0) f.data[3] ^= 0x04;   // CRC
            if (rng() % 80 == 0) f.len = 5;           // DLC
            if (rng() % 80 == 0) f.id = 0x7FF;        // foreign
            if (rng() % 200 == 0) f.data[1] ^= 0x03;  // counter (CRC catches it)
            if (rng() % 100 == 0) continue;           // lost
            samples += static_cast<size_t>(decoder.Feed(f).samples);
            if (rng() % 100 == 0) decoder.Feed(f);  // repeated
            sink += codec[3].Unpack(f.data.data());
            sink += Go1FrameCrc(f.id, f.data.data());
        }
        samples += static_cast<size_t>(decoder.Tick(t + 2'000'000));
        if (tick % 1000 == 999) samples += static_cast<size_t>(decoder.Tick(t + 500'000'000));
    }
    samples += static_cast<size_t>(decoder.Flush());
    EXPECT_EQ(test::Allocations() - before, 0u);
    EXPECT_GT(samples, 1500u);
    EXPECT_GT(decoder.stats().crc, 0u);
    EXPECT_GT(decoder.stats().timeout, 0u);
    EXPECT_NE(sink, 0.0);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::can
