// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// `bimslam simulate` end to end on the sample building: a 5-minute OS1-32 1024x10 walk (Go1, then
// handheld), planned, ray cast per column (rolling shutter), encoded and written as the capture's
// files. Counters: the capture's duration over the wall time (the real-time multiple; the goal is
// >= 20 on a 2-core machine) and lidar.pcap's megabytes per captured minute.
// BM_SimulateBuilding: the whole building (storey: all, issue 31): both storeys' coverage walks
// joined by the stair, up and back down; the goal is >= 10x real time. cpu_x is the capture's
// duration over the process's CPU time (user + system), which other jobs on the machine do not
// change: on an idle 2-core machine real_time_x lies between cpu_x and twice it.
#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include "algorithms/io/sha256.hpp"
#include "host_tools/bim/ifc_model.hpp"
#include "host_tools/bim/sample_building.hpp"
#include "host_tools/simulate/simulate.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::simulate {
namespace {

// The sample office written as IFC and read back through IFC++, as `bimslam simulate` reads it.
bim::BimModel SampleOffice(const test::TempDir& tmp) {
    const std::filesystem::path ifc = tmp / "building.ifc";
    bim::WriteSampleBuilding(ifc);
    return bim::LoadIfc(ifc);
}

void BM_SimulateCapture(benchmark::State& state) {
    test::TempDir tmp;
    const bim::BimModel model = SampleOffice(tmp);
    Scenario s = DefaultScenario(state.range(0) == 0 ? Platform::kGo1 : Platform::kHandheld);
    s.duration_s = double(state.range(1));
    CaptureReport r;
    double wall_s = 0;
    for (auto _ : state) {
        r = SimulateCapture(s, model, "", tmp / "capture");
        wall_s += r.wall_s;
    }
    const double n = double(state.iterations());
    state.counters["real_time_x"] = r.duration_s / (wall_s / n);
    state.counters["pcap_MB_per_min"] = double(r.pcap_bytes) / 1e6 / (r.duration_s / 60.0);
    state.counters["frames"] = double(r.frames);
    state.counters["can_frames"] = double(r.can_frames);
    state.SetLabel(s.platform == Platform::kGo1 ? "go1" : "handheld");
}
BENCHMARK(BM_SimulateCapture)
    ->Args({0, 300})
    ->Args({1, 300})
    ->ArgNames({"handheld", "seconds"})
    ->Unit(benchmark::kSecond)
    ->Iterations(1);

double ProcessCpuS() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
           1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

void BM_SimulateBuilding(benchmark::State& state) {
    test::TempDir tmp;
    const bim::BimModel model = SampleOffice(tmp);
    Scenario s = DefaultScenario(state.range(0) == 0 ? Platform::kGo1 : Platform::kHandheld);
    s.storey = kAllStoreys;
    CaptureReport r;
    double wall_s = 0, cpu_s = 0;
    for (auto _ : state) {
        const double cpu0 = ProcessCpuS();
        r = SimulateCapture(s, model, "", tmp / "capture");
        cpu_s += ProcessCpuS() - cpu0;
        wall_s += r.wall_s;
    }
    const double n = double(state.iterations());
    state.counters["real_time_x"] = r.duration_s / (wall_s / n);
    state.counters["cpu_x"] = r.duration_s / (cpu_s / n);
    state.counters["duration_s"] = r.duration_s;
    state.counters["walk_m"] = r.walk_length_m;
    state.counters["storeys"] = double(r.storeys.size());
    state.counters["flights"] = double(r.flights_walked);
    state.SetLabel(s.platform == Platform::kGo1 ? "go1" : "handheld");
}
BENCHMARK(BM_SimulateBuilding)
    ->Arg(0)
    ->Arg(1)
    ->ArgNames({"handheld"})
    ->Unit(benchmark::kSecond)
    ->Iterations(1);

}  // namespace
}  // namespace bimslam::simulate

BENCHMARK_MAIN();
