// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Go1 CAN decode + end-to-end checks + sample assembly on one core, over a realistic in-memory
// stream: what Go1Encoder sends for 5 s of random HighState samples (a tick every 5 ms, 960
// frames/s). Target: >= 9 M frames/s (1000x a 9000 frames/s bus). items_per_second counts frames;
// x_realtime compares with the 960 frames/s the bridge sends. Also the encoder and the CRC alone.
#include <benchmark/benchmark.h>

#include <array>
#include <random>
#include <vector>

#include "drivers/can/crc8.hpp"
#include "drivers/can/go1_decoder.hpp"
#include "drivers/can/go1_encoder.hpp"

namespace bimslam::can {
namespace {

constexpr int kSeconds = 5;

Go1Sample Sample(std::mt19937& rng, int64_t t) {
    auto u = [&](double lo, double hi) {
        return std::uniform_real_distribution<double>(lo, hi)(rng);
    };
    Go1Sample s;
    s.valid = kAllGroups;
    s.bridge_time_ns = t;
    s.sample_age_us = 300;
    s.vx = u(-2, 2);
    s.vy = u(-1, 1);
    s.yaw_rate = u(-1, 1);
    s.body_height = 0.3;
    for (auto& g : s.gyro) g = u(-3, 3);
    for (auto& a : s.accel) a = u(-15, 15);
    s.quat_wxyz = {0.9, 0.1, -0.3, 0.2};
    for (auto& f : s.foot_force_raw) f = static_cast<uint16_t>(rng() % 4000);
    s.odom_x = u(-50, 50);
    s.odom_y = u(-50, 50);
    s.odom_yaw = u(-3, 3);
    s.battery_soc = 80;
    return s;
}

const std::vector<common::CanFrame>& Stream() {
    static const std::vector<common::CanFrame> frames = [] {
        std::mt19937 rng(1);
        Go1EncoderConfig config;
        config.frame_spacing_ns = 230'000;
        Go1Encoder enc(config);
        std::vector<common::CanFrame> out;
        std::array<common::CanFrame, Go1Encoder::kMaxFramesPerTick> tick;
        Go1Sample s;
        for (int64_t k = 0; k < kSeconds * 200; ++k) {
            const int64_t t = k * 5'000'000;
            if (enc.sample_tick_next()) s = Sample(rng, t);
            const size_t n = enc.Tick(&s, t, tick);
            out.insert(out.end(), tick.begin(), tick.begin() + static_cast<ptrdiff_t>(n));
        }
        return out;
    }();
    return frames;
}

void Report(benchmark::State& state, size_t frames) {
    state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(frames));
    const double per_second = static_cast<double>(frames) / kSeconds;
    state.counters["x_realtime"] = benchmark::Counter(
        static_cast<double>(state.iterations()) * kSeconds, benchmark::Counter::kIsRate);
    state.SetLabel(std::to_string(frames) + " frames, " + std::to_string(int(per_second)) +
                   " frames/s stream");
}

// Feed only: CRC, counters, assembly, emission.
void BM_DecodeStream(benchmark::State& state) {
    const auto& frames = Stream();
    Go1Decoder dec;
    size_t samples = 0;
    for (auto _ : state) {
        dec.Reset();
        for (const common::CanFrame& f : frames) {
            samples += static_cast<size_t>(dec.Feed(f).samples);
            benchmark::DoNotOptimize(dec.ready().data());
        }
    }
    if (dec.stats().samples != kSeconds * 100u || dec.stats().Faults() != 0) {
        state.SkipWithError("the stream did not decode cleanly");
    }
    benchmark::DoNotOptimize(samples);
    Report(state, frames.size());
}
BENCHMARK(BM_DecodeStream);

// As the rig runs it: Feed plus a Tick every millisecond.
void BM_DecodeStreamWithTick(benchmark::State& state) {
    const auto& frames = Stream();
    Go1Decoder dec;
    for (auto _ : state) {
        dec.Reset();
        int64_t next_tick = 0;
        for (const common::CanFrame& f : frames) {
            while (next_tick <= f.timestamp_ns) {
                dec.Tick(next_tick);
                next_tick += 1'000'000;
            }
            dec.Feed(f);
            benchmark::DoNotOptimize(dec.ready().data());
        }
    }
    Report(state, frames.size());
}
BENCHMARK(BM_DecodeStreamWithTick);

void BM_Encode(benchmark::State& state) {
    std::mt19937 rng(2);
    const Go1Sample s = Sample(rng, 0);
    Go1Encoder enc;
    std::array<common::CanFrame, Go1Encoder::kMaxFramesPerTick> out;
    size_t frames = 0;
    int64_t t = 0;
    for (auto _ : state) {
        frames += enc.Tick(&s, t, out);
        t += 5'000'000;
        benchmark::DoNotOptimize(out.data());
    }
    state.SetItemsProcessed(static_cast<int64_t>(frames));
    state.SetLabel("items = frames");
}
BENCHMARK(BM_Encode);

void BM_Go1FrameCrc(benchmark::State& state) {
    const auto& frames = Stream();
    uint32_t acc = 0;
    for (auto _ : state) {
        for (const common::CanFrame& f : frames) acc += Go1FrameCrc(f.id, f.data.data());
    }
    benchmark::DoNotOptimize(acc);
    state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(frames.size()));
}
BENCHMARK(BM_Go1FrameCrc);

}  // namespace
}  // namespace bimslam::can

BENCHMARK_MAIN();
