// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// PCD write and read of one Ouster OS1-32 scan (32 x 1024 points), binary and ASCII, to a
// temporary folder (atomic write with fsync, io/file_util.hpp) and in memory.
#include <benchmark/benchmark.h>

#include "algorithms/io/pcd.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::io {
namespace {

const common::PointCloud& Scan() {
    static const common::PointCloud cloud = test::MakeRoomScan(32, 1024, 1);
    return cloud;
}

PcdEncoding Encoding(const benchmark::State& state) {
    return state.range(0) == 0 ? PcdEncoding::kBinary : PcdEncoding::kAscii;
}

void SetLabels(benchmark::State& state, size_t bytes) {
    state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(Scan().size()));
    state.SetBytesProcessed(state.iterations() * static_cast<int64_t>(bytes));
    state.SetLabel(state.range(0) == 0 ? "binary" : "ascii");
}

void BM_SerializePcd(benchmark::State& state) {
    size_t bytes = 0;
    for (auto _ : state) {
        const std::string s = SerializePcd(Scan(), Encoding(state));
        bytes = s.size();
        benchmark::DoNotOptimize(s.data());
    }
    SetLabels(state, bytes);
}
BENCHMARK(BM_SerializePcd)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

void BM_ParsePcd(benchmark::State& state) {
    const std::string bytes = SerializePcd(Scan(), Encoding(state));
    for (auto _ : state) {
        const common::PointCloud c = ParsePcd("bench.pcd", bytes);
        benchmark::DoNotOptimize(c.xyz.data());
    }
    SetLabels(state, bytes.size());
}
BENCHMARK(BM_ParsePcd)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

void BM_WritePcd(benchmark::State& state) {
    test::TempDir dir;
    for (auto _ : state) WritePcd(dir / "scan.pcd", Scan(), Encoding(state));
    SetLabels(state, std::filesystem::file_size(dir / "scan.pcd"));
}
BENCHMARK(BM_WritePcd)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

void BM_ReadPcd(benchmark::State& state) {
    test::TempDir dir;
    WritePcd(dir / "scan.pcd", Scan(), Encoding(state));
    for (auto _ : state) {
        const common::PointCloud c = ReadPcd(dir / "scan.pcd");
        benchmark::DoNotOptimize(c.xyz.data());
    }
    SetLabels(state, std::filesystem::file_size(dir / "scan.pcd"));
}
BENCHMARK(BM_ReadPcd)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace bimslam::io

BENCHMARK_MAIN();
