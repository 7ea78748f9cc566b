// Reading a capture and extracting its UDP datagrams: 640 OS1-32 LEGACY lidar packets (6464 B,
// one second of a 1024x10 sensor), unfragmented (an MTU-9000 link or loopback) and fragmented at
// MTU 1500 (five IPv4 fragments each, what a real sensor on a standard link sends). From memory
// (parsing alone) and from a file in $TMPDIR (through zlib's transparent read). Bytes/s counts
// the capture file's bytes; items/s counts datagrams.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <random>
#include <string>

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

}  // namespace
}  // namespace bimslam::net

BENCHMARK_MAIN();
