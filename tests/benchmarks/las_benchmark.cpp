// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// LAS 1.4 writing (issue 34's target: 10^7 points written in at most 1 s): a cloud of 10^7
// points with map_bim.las's fields (class, user data, point source, GPS time; extra bytes
// distance, element, object, keyframes: 44-byte records, 440 MB), encoded in memory
// (SerializeLas) and written to a file (WriteLas: encoding, write past the page cache, fsync and
// rename), and read back (ReadLas). The points are a building's surfaces' worth of voxels (random in 60 x 40 x 10 m).
#include <benchmark/benchmark.h>

#include <random>

#include "algorithms/io/las.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::io {
namespace {

constexpr size_t kPoints = 10'000'000;

const LasData& Cloud() {
    static const LasData d = [] {
        LasData c;
        std::mt19937 rng(1);
        std::uniform_real_distribution<float> u(0, 1);
        LasExtraField distance{"distance", LasType::kFloat32, "signed distance, m", 1e9, {}};
        LasExtraField element{"element", LasType::kInt32, "element index", -1, {}};
        LasExtraField object{"object", LasType::kInt32, "new object id", -1, {}};
        LasExtraField keyframes{"keyframes", LasType::kUint16, "keyframes", {}, {}};
        for (auto* f : {&distance, &element, &object, &keyframes}) f->values.resize(kPoints);
        c.xyz.resize(kPoints);
        c.classification.resize(kPoints);
        c.user_data.resize(kPoints);
        c.point_source_id.assign(kPoints, 1);
        c.gps_time.resize(kPoints);
        for (size_t i = 0; i < kPoints; ++i) {
            c.xyz[i] = Eigen::Vector3d(60 * u(rng), 40 * u(rng), 10 * u(rng));
            c.user_data[i] = uint8_t(i % 6);
            c.classification[i] = i % 6 == 0 ? 6 : uint8_t(64 + i % 3);
            c.gps_time[i] = 4.8e8 + double(i) * 1e-4;
            distance.values[i] = u(rng) - 0.5f;
            element.values[i] = double(i % 5000);
            object.values[i] = i % 10 == 0 ? double(i % 40) : -1;
            keyframes.values[i] = double(1 + i % 30);
        }
        c.extra = {distance, element, object, keyframes};
        return c;
    }();
    return d;
}

void Label(benchmark::State& state, size_t bytes) {
    state.SetItemsProcessed(state.iterations() * int64_t(kPoints));
    state.SetBytesProcessed(state.iterations() * int64_t(bytes));
}

void BM_SerializeLas(benchmark::State& state) {
    size_t bytes = 0;
    for (auto _ : state) {
        const std::string s = SerializeLas(Cloud());
        bytes = s.size();
        benchmark::DoNotOptimize(s.data());
    }
    Label(state, bytes);
}
BENCHMARK(BM_SerializeLas)->Iterations(3)->Unit(benchmark::kMillisecond);

void BM_WriteLas(benchmark::State& state) {
    Cloud();  // made before the clock starts
    test::TempDir dir;
    for (auto _ : state) WriteLas(dir / "map.las", Cloud());
    Label(state, std::filesystem::file_size(dir / "map.las"));
}
BENCHMARK(BM_WriteLas)->Iterations(3)->Unit(benchmark::kMillisecond);

void BM_ReadLas(benchmark::State& state) {
    test::TempDir dir;
    WriteLas(dir / "map.las", Cloud());
    for (auto _ : state) {
        const LasData d = ReadLas(dir / "map.las");
        benchmark::DoNotOptimize(d.xyz.data());
    }
    Label(state, std::filesystem::file_size(dir / "map.las"));
}
BENCHMARK(BM_ReadLas)->Iterations(3)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace bimslam::io

BENCHMARK_MAIN();
