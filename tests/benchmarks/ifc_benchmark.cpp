// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// LoadIfc (read, check, IFC++ parse, carve geometry with openings subtracted, triangulation) of
// the three real models of ../shared/data/ifc, one core; skipped when the folder is absent.
// Counters: triangles and elements with geometry of the loaded model.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <string>

#include "host_tools/bim/ifc_model.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::bim {
namespace {

const char* const kModels[] = {"AC20-FZK-Haus.ifc", "Duplex_A_20110907.ifc",
                               "Office_A_20110811.ifc"};

void BM_LoadIfc(benchmark::State& state) {
    const std::string name = kModels[state.range(0)];
    state.SetLabel(name);
    const auto data = bimslam::test::SharedDataDir();
    if (!data || !std::filesystem::exists(*data / "ifc" / name)) {
        state.SkipWithError(("../shared/data/ifc/" + name + " is absent").c_str());
        return;
    }
    const std::filesystem::path path = *data / "ifc" / name;
    size_t triangles = 0, elements = 0, failed = 0;
    for (auto _ : state) {
        const BimModel m = LoadIfc(path);
        triangles = m.mesh.triangles.size();
        elements = m.elements.size();
        failed = m.failed.size();
        benchmark::DoNotOptimize(m.mesh.vertices.data());
    }
    state.counters["triangles"] = double(triangles);
    state.counters["elements"] = double(elements);
    state.counters["failed"] = double(failed);
    state.SetBytesProcessed(int64_t(state.iterations()) *
                            int64_t(std::filesystem::file_size(path)));
}
BENCHMARK(BM_LoadIfc)->DenseRange(0, 2)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace bimslam::bim

BENCHMARK_MAIN();
