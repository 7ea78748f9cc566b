// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Decode + batch + XYZ of OS1-32 1024x10 frames from packets held in memory, on one core
// (issue target: <= 0.2 ms per frame, i.e. > 500x real time at 10 Hz), against a plain memcpy of
// the same bytes. Synthetic frames from PacketEncoder, so the figures need no shared data; the
// real OS-1-32 capture too when ../shared/data is there.
#include <benchmark/benchmark.h>

#include <cstring>
#include <random>

#include "drivers/net/ipv4.hpp"
#include "drivers/net/pcap_reader.hpp"
#include "drivers/ouster/frame_batcher.hpp"
#include "drivers/ouster/metadata.hpp"
#include "drivers/ouster/packet_encoder.hpp"
#include "tests/support/ouster_fixtures.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::ouster {
namespace {

struct Stream {
    SensorInfo info;
    std::vector<std::vector<uint8_t>> packets;  // 10 frames
    size_t bytes = 0;
};

Stream MakeStream(LidarProfile profile) {
    Stream s;
    s.info = fixtures::MakeSensor(profile);
    s.info.build_rev = "v2.3.0";  // no CRC footers, as the FW 2.x sensors send
    s.info.fw_major = 2;
    const PacketEncoder enc(s.info);
    std::mt19937 rng(1);
    for (uint32_t id = 0; id < 10; ++id) {
        LidarFrame f = fixtures::MakeFrame(enc.format(), id, id);
        // Indoor ranges (0.5 - 30 m) with 10 % no-returns, as a real scan has.
        for (auto& r : f.range) r = (rng() % 10 == 0) ? 0 : 500 + rng() % 29500;
        if (!f.range.empty() && enc.format().fields()[0].multiplier == 8) {
            for (auto& r : f.range) r &= ~7u;
        }
        for (const auto& p : fixtures::Encode(enc, f)) {
            s.packets.push_back(p);
            s.bytes += p.size();
        }
    }
    return s;
}

void BM_DecodeBatchXyz(benchmark::State& state) {
    const auto profile = static_cast<LidarProfile>(state.range(0));
    const bool xyz = state.range(1) != 0;
    const Stream s = MakeStream(profile);
    FrameBatcher b(s.info, {.check_crc = false, .compute_xyz = xyz});
    size_t frames = 0;
    for (auto _ : state) {
        b.Reset();  // the same ten frames again are new frames, not late ones
        for (const auto& p : s.packets) frames += b.AddPacket(p.data(), p.size()).frames;
    }
    if (frames != size_t(10 * state.iterations())) state.SkipWithError("frames were not emitted");
    state.SetItemsProcessed(int64_t(frames));
    state.SetBytesProcessed(int64_t(state.iterations() * s.bytes));
    // Printed as a time: the seconds one frame takes.
    state.counters["per_frame"] = benchmark::Counter(
        double(frames), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
    state.SetLabel(std::string(ToString(profile)) + (xyz ? " +xyz" : " no xyz"));
}
BENCHMARK(BM_DecodeBatchXyz)
    ->ArgsProduct({{int(LidarProfile::kLegacy), int(LidarProfile::kRng19Rfl8Sig16Nir16),
                    int(LidarProfile::kRng15Rfl8Nir8), int(LidarProfile::kRng19Rfl8Sig16Nir16Dual)},
                   {1}})
    ->Args({int(LidarProfile::kLegacy), 0})
    ->Unit(benchmark::kMicrosecond);

// The real OS-1-32-G capture of ../shared/data (one LEGACY frame), held in memory.
void BM_RealCaptureOs132(benchmark::State& state) {
    const auto data = bimslam::test::SharedDataDir();
    const std::string name = "ouster/OS-1-32-G_v2.1.1_1024x10";
    if (!data || !std::filesystem::exists(*data / (name + ".pcap"))) {
        state.SkipWithError("../shared/data/ouster is absent");
        return;
    }
    const SensorInfo info = LoadMetadata(*data / (name + ".json"));
    std::vector<std::vector<uint8_t>> packets;
    net::PcapReader reader(*data / (name + ".pcap"));
    net::UdpExtractor extractor;
    net::PcapRecord record;
    net::UdpDatagram d;
    while (reader.Next(record)) {
        if (extractor.Feed(record, d)) packets.emplace_back(d.payload.begin(), d.payload.end());
    }
    FrameBatcher b(info);
    size_t frames = 0;
    for (auto _ : state) {
        b.Reset();
        for (const auto& p : packets) frames += b.AddPacket(p.data(), p.size()).frames;
    }
    state.counters["per_frame"] = benchmark::Counter(
        double(frames), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
    state.SetLabel("LEGACY +xyz, real capture");
}
BENCHMARK(BM_RealCaptureOs132)->Unit(benchmark::kMicrosecond);

// The floor: copying the same packet bytes into a frame-sized buffer.
void BM_MemcpySameBytes(benchmark::State& state) {
    const Stream s = MakeStream(static_cast<LidarProfile>(state.range(0)));
    std::vector<uint8_t> frame(s.bytes / 10);
    const size_t per_frame = s.packets.size() / 10;
    size_t frames = 0;
    for (auto _ : state) {
        for (size_t i = 0; i < s.packets.size(); ++i) {
            const auto& p = s.packets[i];
            std::memcpy(frame.data() + (i % per_frame) * p.size(), p.data(), p.size());
        }
        frames += 10;
        benchmark::DoNotOptimize(frame.data());
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(int64_t(frames));
    state.SetBytesProcessed(int64_t(state.iterations() * s.bytes));
    state.counters["per_frame"] = benchmark::Counter(
        double(frames), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
    state.SetLabel(std::string(ToString(static_cast<LidarProfile>(state.range(0)))));
}
BENCHMARK(BM_MemcpySameBytes)
    ->Arg(int(LidarProfile::kLegacy))
    ->Arg(int(LidarProfile::kRng19Rfl8Sig16Nir16))
    ->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace bimslam::ouster

BENCHMARK_MAIN();
