// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Scan Context figures: descriptor of an OS1-32 sized scan, pairwise distance, and candidate
// search among 10 000 keyframes (index build, and query including the full distances).
#include <benchmark/benchmark.h>

#include <cstdint>
#include <numbers>
#include <vector>

#include "algorithms/scancontext/candidate_index.hpp"
#include "algorithms/scancontext/descriptor.hpp"
#include "algorithms/scancontext/distance.hpp"
#include "tests/support/synthetic_scene.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::scancontext {
namespace {

void BM_DescriptorOutdoor(benchmark::State& state) {
    const common::PointCloud cloud = test::MakeRoomScan(32, 1024, 1);
    DescriptorBuilder builder(ScanContextConfig::Outdoor());
    Descriptor d;
    for (auto _ : state) {
        builder.Build(cloud, &d);
        benchmark::DoNotOptimize(d.data());
    }
    state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(cloud.size()));
    state.counters["points"] = static_cast<double>(cloud.size());
}
BENCHMARK(BM_DescriptorOutdoor)->Unit(benchmark::kMicrosecond);

// arg: the indoor cell rule (0 z_span, 1 z_stack, the default: it sorts the scan's points by cell
// and height).
void BM_DescriptorIndoor(benchmark::State& state) {
    const common::PointCloud cloud = test::MakeRoomScan(32, 1024, 1);
    ScanContextConfig config = ScanContextConfig::Indoor();
    config.indoor_rule = state.range(0) == 0 ? IndoorCellRule::kZSpan : IndoorCellRule::kZStack;
    DescriptorBuilder builder(config);
    Descriptor d;
    for (auto _ : state) {
        builder.Build(cloud, &d);
        benchmark::DoNotOptimize(d.data());
    }
    state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(cloud.size()));
    state.counters["points"] = static_cast<double>(cloud.size());
}
BENCHMARK(BM_DescriptorIndoor)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

// Two scans of the same room, the second turned by 40 degrees; arg = search ratio in percent.
void BM_Distance(benchmark::State& state) {
    const ScanContextConfig config = ScanContextConfig::Indoor();
    const common::PointCloud a = test::MakeRoomScan(32, 1024, 1);
    common::PointCloud b = test::MakeRoomScan(32, 1024, 2);
    const Eigen::Matrix3f R =
        Eigen::AngleAxisf(40.0f * std::numbers::pi_v<float> / 180.0f, Eigen::Vector3f::UnitZ())
            .toRotationMatrix();
    for (Eigen::Vector3f& p : b.xyz) p = R * p;
    const Descriptor da = MakeDescriptor(a, config), db = MakeDescriptor(b, config);
    const double ratio = static_cast<double>(state.range(0)) / 100.0;
    for (auto _ : state) {
        DistanceResult r = Distance(da, db, ratio);
        benchmark::DoNotOptimize(r);
    }
}
BENCHMARK(BM_Distance)->Arg(10)->Arg(100)->Unit(benchmark::kMicrosecond);

// 10 000 keyframe descriptors of distinct synthetic rooms, made once (a coarse scan keeps the
// set-up to a couple of seconds; the descriptors look like real indoor ones).
const std::vector<Descriptor>& Keyframes() {
    static const std::vector<Descriptor> keyframes = [] {
        test::LidarModel lidar;
        lidar.beams = 16;
        lidar.columns = 240;
        lidar.range_noise_sigma = 0.01;
        DescriptorBuilder builder(ScanContextConfig::Indoor());
        std::vector<Descriptor> out(10000);
        for (size_t i = 0; i < out.size(); ++i) {
            const test::Place place = test::MakeRandomRoom(static_cast<uint32_t>(i));
            const Eigen::Isometry3d T(Eigen::Translation3d(place.sensor));
            builder.Build(test::ScanScene(place.scene, T, lidar, static_cast<uint32_t>(i)),
                          &out[i]);
        }
        return out;
    }();
    return keyframes;
}

// Adding 10 000 keyframes (copies of the descriptors and their ring keys), then building the
// KD-tree over them; timed separately.
void BM_IndexAdd10k(benchmark::State& state) {
    const std::vector<Descriptor>& keyframes = Keyframes();
    for (auto _ : state) {
        CandidateIndex index(ScanContextConfig::Indoor());
        for (const Descriptor& d : keyframes) {
            if (!index.Add(d).ok()) state.SkipWithError("Add failed");
        }
        benchmark::DoNotOptimize(index.size());
        state.PauseTiming();  // leave the destruction out
        index = CandidateIndex(ScanContextConfig::Indoor());
        state.ResumeTiming();
    }
    state.counters["keyframes"] = static_cast<double>(keyframes.size());
}
BENCHMARK(BM_IndexAdd10k)->Unit(benchmark::kMillisecond);

void BM_IndexBuild10k(benchmark::State& state) {
    const std::vector<Descriptor>& keyframes = Keyframes();
    for (auto _ : state) {
        state.PauseTiming();
        CandidateIndex index(ScanContextConfig::Indoor());
        for (const Descriptor& d : keyframes) {
            if (!index.Add(d).ok()) state.SkipWithError("Add failed");
        }
        state.ResumeTiming();
        index.Build();
        benchmark::DoNotOptimize(index.Indexed());
        state.PauseTiming();
        index = CandidateIndex(ScanContextConfig::Indoor());
        state.ResumeTiming();
    }
    state.counters["keyframes"] = static_cast<double>(keyframes.size());
}
BENCHMARK(BM_IndexBuild10k)->Unit(benchmark::kMillisecond);

// Query among 10 000 keyframes: ring-key KD-tree plus the full distance of each candidate.
// arg = number of candidates.
void BM_Query10k(benchmark::State& state) {
    const std::vector<Descriptor>& keyframes = Keyframes();
    CandidateIndex index(ScanContextConfig::Indoor());
    for (const Descriptor& d : keyframes) {
        if (!index.Add(d).ok()) state.SkipWithError("Add failed");
    }
    index.Build();
    size_t q = 0;
    for (auto _ : state) {
        auto m =
            index.Query(keyframes[(q * 7919) % keyframes.size()], static_cast<int>(state.range(0)));
        benchmark::DoNotOptimize(m);
        ++q;
    }
}
BENCHMARK(BM_Query10k)->Arg(10)->Arg(50)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace bimslam::scancontext

BENCHMARK_MAIN();
