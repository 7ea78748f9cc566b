// `bimslam simulate` end to end on the sample building: a 5-minute OS1-32 1024x10 walk (Go1, then
// handheld), planned, ray cast per column (rolling shutter), encoded and written as the capture's
// files. Counters: the capture's duration over the wall time (the real-time multiple; the goal is
// >= 20 on a 2-core machine) and lidar.pcap's megabytes per captured minute.
#include <benchmark/benchmark.h>

#include "algorithms/io/sha256.hpp"
#include "host_tools/bim/ifc_model.hpp"
#include "host_tools/bim/sample_building.hpp"
#include "host_tools/simulate/simulate.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::simulate {
namespace {

void BM_SimulateCapture(benchmark::State& state) {
    test::TempDir tmp;
    const std::filesystem::path ifc = tmp / "building.ifc";
    bim::WriteSampleBuilding(ifc);
    const bim::BimModel model = bim::LoadIfc(ifc);
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

}  // namespace
}  // namespace bimslam::simulate

BENCHMARK_MAIN();
