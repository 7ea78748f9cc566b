// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// BIM -> reference session, end to end as `bimslam bim2session` runs it: IFC load, grids and
// walks, ray casting, descriptors, session files. Counters: seconds per keyframe and the ratio of
// the walk's real-time duration (at 0.5 m/s) to the whole run (load included). The paper drove its
// robot through Gazebo in real time: ratio 1.
#include <benchmark/benchmark.h>

#include <chrono>

#include "algorithms/io/sha256.hpp"
#include "host_tools/bim/ifc_model.hpp"
#include "host_tools/bim/reference_session.hpp"
#include "host_tools/bim/sample_building.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::bim {
namespace {

void Run(benchmark::State& state, const std::filesystem::path& model_file) {
    test::TempDir tmp;
    ReferenceSessionOptions options;
    options.overwrite = true;
    size_t keyframes = 0;
    double walk_s = 0, total_s = 0, load_s = 0, simulate_s = 0, plan_s = 0, write_s = 0;
    for (auto _ : state) {
        const auto t0 = std::chrono::steady_clock::now();
        const BimModel model = LoadIfc(model_file);
        const auto t1 = std::chrono::steady_clock::now();
        const ReferenceSessionReport r =
            WriteReferenceSession(model, io::Sha256File(model_file), tmp / "session", options);
        const auto t2 = std::chrono::steady_clock::now();
        load_s += std::chrono::duration<double>(t1 - t0).count();
        total_s += std::chrono::duration<double>(t2 - t0).count();
        keyframes += r.keyframes;
        walk_s += r.walk_s;
        plan_s += r.plan_s;
        simulate_s += r.simulate_s;
        write_s += r.write_s;
    }
    const double n = double(state.iterations());
    state.counters["keyframes"] = double(keyframes) / n;
    state.counters["walk_s"] = walk_s / n;
    state.counters["load_s"] = load_s / n;
    state.counters["plan_s"] = plan_s / n;
    state.counters["simulate_s"] = simulate_s / n;
    state.counters["write_s"] = write_s / n;
    state.counters["s_per_keyframe"] = total_s / double(std::max<size_t>(keyframes, 1));
    state.counters["realtime_ratio"] = walk_s / total_s;
}

void BM_Bim2Session_SampleBuilding(benchmark::State& state) {
    test::TempDir tmp;
    WriteSampleBuilding(tmp / "building.ifc");
    Run(state, tmp / "building.ifc");
}
BENCHMARK(BM_Bim2Session_SampleBuilding)->Unit(benchmark::kSecond)->Iterations(1);

void BM_Bim2Session_OfficeA(benchmark::State& state) {
    const auto data = test::SharedDataDir();
    const auto file = data ? *data / "ifc" / "Office_A_20110811.ifc" : std::filesystem::path();
    if (!data || !std::filesystem::exists(file)) {
        state.SkipWithError("../shared/data/ifc/Office_A_20110811.ifc is absent: skipped");
        return;
    }
    Run(state, file);
}
BENCHMARK(BM_Bim2Session_OfficeA)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace
}  // namespace bimslam::bim

BENCHMARK_MAIN();
