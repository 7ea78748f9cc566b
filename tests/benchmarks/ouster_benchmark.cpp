// Decode + batch + XYZ of OS1-32 1024x10 frames from packets held in memory, on one core
// (issue target: <= 0.2 ms per frame, i.e. > 500x real time at 10 Hz), against a plain memcpy of
// the same bytes. Synthetic frames from PacketEncoder, so the figures need no shared data.
#include <benchmark/benchmark.h>

#include <cstring>
#include <random>

#include "drivers/ouster/frame_batcher.hpp"
#include "drivers/ouster/packet_encoder.hpp"
#include "tests/unit/ouster/ouster_fixtures.hpp"

namespace bimslam::ouster {
namespace {

struct Stream {
    SensorInfo info;
    std::vector<std::vector<uint8_t>> packets;  // 10 frames
    size_t bytes = 0;
};

Stream MakeStream(LidarProfile profile) {
    Stream s;
    s.info = test::MakeSensor(profile);
    s.info.build_rev = "v2.3.0";  // no CRC footers, as the FW 2.x sensors send
    s.info.fw_major = 2;
    const PacketEncoder enc(s.info);
    std::mt19937 rng(1);
    for (uint32_t id = 0; id < 10; ++id) {
        LidarFrame f = test::MakeFrame(enc.format(), id, id);
        // Indoor ranges (0.5 - 30 m) with 10 % no-returns, as a real scan has.
        for (auto& r : f.range) r = (rng() % 10 == 0) ? 0 : 500 + rng() % 29500;
        if (!f.range.empty() && enc.format().fields()[0].multiplier == 8) {
            for (auto& r : f.range) r &= ~7u;
        }
        for (const auto& p : test::Encode(enc, f)) {
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
        for (const auto& p : s.packets) frames += b.AddPacket(p.data(), p.size()).frames;
    }
    state.SetItemsProcessed(int64_t(frames));
    state.SetBytesProcessed(int64_t(state.iterations() * s.bytes));
    state.counters["ms_per_frame"] = benchmark::Counter(
        1e3 * double(frames), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
    state.SetLabel(std::string(ToString(profile)) + (xyz ? " +xyz" : " no xyz"));
}
BENCHMARK(BM_DecodeBatchXyz)
    ->ArgsProduct({{int(LidarProfile::kLegacy), int(LidarProfile::kRng19Rfl8Sig16Nir16),
                    int(LidarProfile::kRng15Rfl8Nir8), int(LidarProfile::kRng19Rfl8Sig16Nir16Dual)},
                   {1}})
    ->Args({int(LidarProfile::kLegacy), 0})
    ->Unit(benchmark::kMicrosecond);

// The floor: copying the same packet bytes into a frame-sized buffer.
void BM_MemcpySameBytes(benchmark::State& state) {
    const Stream s = MakeStream(static_cast<LidarProfile>(state.range(0)));
    std::vector<uint8_t> frame(s.bytes / 10);
    size_t frames = 0;
    for (auto _ : state) {
        size_t at = 0;
        for (const auto& p : s.packets) {
            if (at + p.size() > frame.size()) {
                at = 0;
                ++frames;
            }
            std::memcpy(frame.data() + at, p.data(), p.size());
            at += p.size();
        }
        ++frames;
        benchmark::DoNotOptimize(frame.data());
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(int64_t(frames));
    state.SetBytesProcessed(int64_t(state.iterations() * s.bytes));
    state.counters["ms_per_frame"] = benchmark::Counter(
        1e3 * double(frames), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
    state.SetLabel(std::string(ToString(static_cast<LidarProfile>(state.range(0)))));
}
BENCHMARK(BM_MemcpySameBytes)
    ->Arg(int(LidarProfile::kLegacy))
    ->Arg(int(LidarProfile::kRng19Rfl8Sig16Nir16))
    ->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace bimslam::ouster

BENCHMARK_MAIN();
