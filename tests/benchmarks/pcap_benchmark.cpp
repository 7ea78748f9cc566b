// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Reading a capture and extracting its UDP datagrams: 640 OS1-32 LEGACY lidar packets (6464 B,
// one second of a 1024x10 sensor), unfragmented (an MTU-9000 link or loopback) and fragmented at
// MTU 1500 (five IPv4 fragments each, what a real sensor on a standard link sends). From memory
// (parsing alone) and from a file in $TMPDIR. Bytes/s counts the capture file's bytes; items/s
// counts datagrams.
//
// BM_ReadFile reads whole capture files with PcapReader alone (no UDP extraction) and reports
// packets/s: the files named in BIMSLAM_PCAP_FILES (':'-separated), else the pcaps of
// ../shared/data (run from the project root). Built at two commits and run back to back on the
// same files, it compares two readers (issue 34: libpcap against the reader of our own).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "drivers/net/ipv4.hpp"
#include "drivers/net/pcap_reader.hpp"
#include "drivers/net/pcap_writer.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::net {
namespace {

constexpr int kDatagrams = 640;
constexpr size_t kPayloadBytes = 6464;

const std::string& Capture(uint32_t mtu) {
    static const auto make = [](uint32_t m) {
        std::mt19937 rng(1);
        std::string payload(kPayloadBytes, '\0');
        PcapWriter writer;
        for (int i = 0; i < kDatagrams; ++i) {
            for (char& c : payload) c = static_cast<char>(rng());
            writer.WriteUdp(1'700'000'000'000'000'000 + i * 97'656, 0x0A050557, 7502, 0x0A050501,
                            7502,
                            {reinterpret_cast<const uint8_t*>(payload.data()), payload.size()}, m);
        }
        return writer.bytes();
    };
    static const std::string unfragmented = make(0);
    static const std::string fragmented = make(1500);
    return mtu == 0 ? unfragmented : fragmented;
}

size_t Extract(PcapReader& reader, UdpExtractor& extractor) {
    PcapRecord record;
    UdpDatagram datagram;
    size_t n = 0;
    while (reader.Next(record)) {
        if (extractor.Feed(record, datagram)) {
            benchmark::DoNotOptimize(datagram.payload.data());
            ++n;
        }
    }
    return n;
}

void Report(benchmark::State& state, size_t bytes) {
    state.SetBytesProcessed(state.iterations() * static_cast<int64_t>(bytes));
    state.SetItemsProcessed(state.iterations() * kDatagrams);
    state.SetLabel(state.range(0) == 0 ? "unfragmented" : "MTU 1500, 5 fragments");
}

void BM_ExtractFromMemory(benchmark::State& state) {
    const std::string& bytes = Capture(static_cast<uint32_t>(state.range(0)));
    UdpExtractor extractor;
    for (auto _ : state) {
        PcapReader reader = PcapReader::FromMemory("bench.pcap", bytes);
        if (Extract(reader, extractor) != kDatagrams) state.SkipWithError("datagrams lost");
    }
    Report(state, bytes.size());
}
BENCHMARK(BM_ExtractFromMemory)->Arg(0)->Arg(1500)->Unit(benchmark::kMicrosecond);

void BM_ExtractFromFile(benchmark::State& state) {
    const std::string& bytes = Capture(static_cast<uint32_t>(state.range(0)));
    test::TempDir dir;
    test::WriteBytes(dir / "bench.pcap", bytes);
    UdpExtractor extractor;
    for (auto _ : state) {
        PcapReader reader(dir / "bench.pcap");
        if (Extract(reader, extractor) != kDatagrams) state.SkipWithError("datagrams lost");
    }
    Report(state, bytes.size());
}
BENCHMARK(BM_ExtractFromFile)->Arg(0)->Arg(1500)->Unit(benchmark::kMicrosecond);

void BM_WriteUdpToFile(benchmark::State& state) {
    std::string payload(kPayloadBytes, 'x');
    test::TempDir dir;
    for (auto _ : state) {
        PcapWriter writer(dir / "out.pcap");
        for (int i = 0; i < kDatagrams; ++i) {
            writer.WriteUdp(i, 1, 7502, 2, 7502,
                            {reinterpret_cast<const uint8_t*>(payload.data()), payload.size()},
                            static_cast<uint32_t>(state.range(0)));
        }
        writer.Close();
    }
    Report(state, std::filesystem::file_size(dir / "out.pcap"));
}
BENCHMARK(BM_WriteUdpToFile)->Arg(0)->Arg(1500)->Unit(benchmark::kMicrosecond);

void BM_ReadFile(benchmark::State& state, const std::filesystem::path& path) {
    uint64_t packets = 0;
    for (auto _ : state) {
        PcapReader reader(path);
        PcapRecord record;
        while (reader.Next(record)) {
            benchmark::DoNotOptimize(record.data.data());
            ++packets;
        }
    }
    state.counters["packets/s"] =
        benchmark::Counter(static_cast<double>(packets), benchmark::Counter::kIsRate);
    state.SetBytesProcessed(state.iterations() *
                            static_cast<int64_t>(std::filesystem::file_size(path)));
}

std::vector<std::filesystem::path> FilesToRead() {
    std::vector<std::filesystem::path> files;
    if (const char* list = std::getenv("BIMSLAM_PCAP_FILES"); list != nullptr && *list != 0) {
        std::stringstream in(list);
        for (std::string item; std::getline(in, item, ':');) {
            if (!item.empty()) files.emplace_back(item);
        }
        return files;
    }
    if (const auto data = test::SharedDataDir()) {
        for (const char* sub : {"ouster", "can"}) {
            if (!std::filesystem::is_directory(*data / sub)) continue;
            for (const auto& entry : std::filesystem::directory_iterator(*data / sub)) {
                const std::string name = entry.path().filename().string();
                if (name.ends_with(".pcap") || name.ends_with(".pcap.gz")) {
                    files.push_back(entry.path());
                }
            }
        }
    }
    std::sort(files.begin(), files.end());
    return files;
}

}  // namespace
}  // namespace bimslam::net

int main(int argc, char** argv) {
    for (const auto& path : bimslam::net::FilesToRead()) {
        benchmark::RegisterBenchmark(("BM_ReadFile/" + path.filename().string()).c_str(),
                                     bimslam::net::BM_ReadFile, path)
            ->Unit(benchmark::kMicrosecond);
    }
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
