// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// libFuzzer target: PcapReader (from memory) + UdpExtractor over arbitrary bytes. They must end
// cleanly or throw common::FileError; anything else (a crash, a sanitizer report, another
// exception) is a finding. Built with clang by the fuzzing preset, not by the default build:
//   clang++ -std=c++20 -fsanitize=fuzzer,address,undefined -I. -isystem /usr/include/eigen3 \
//       tests/fuzz/pcap_fuzz.cpp drivers/net/*.cpp algorithms/common/*.cpp -lz -o pcap_fuzz
//   ./pcap_fuzz -max_len=70000 corpus/
// A seed corpus: any small .pcap/.pcapng (PcapWriter::WriteUdp with an mtu makes fragments).
#include <cstddef>
#include <cstdint>
#include <span>

#include "algorithms/common/status.hpp"
#include "drivers/net/ipv4.hpp"
#include "drivers/net/pcap_reader.hpp"

namespace {

bimslam::net::UdpExtractor& Extractor() {
    // Shared across inputs, as a long capture would share it: its state must survive anything.
    static bimslam::net::ExtractorConfig config = [] {
        bimslam::net::ExtractorConfig c;
        c.max_datagrams_in_flight = 4;
        c.max_bytes_in_flight = 65535;
        c.check_udp_checksum = true;
        return c;
    }();
    static bimslam::net::UdpExtractor extractor(config);
    return extractor;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace bimslam;
    net::UdpExtractor& extractor = Extractor();
    try {
        net::PcapReader reader =
            net::PcapReader::FromMemory("fuzz.pcap", std::span<const uint8_t>(data, size));
        net::PcapRecord record;
        net::UdpDatagram datagram;
        size_t bytes = 0;
        while (reader.Next(record)) {
            if (record.data.data() < data ||
                record.data.data() + record.data.size() > data + size) {
                __builtin_trap();  // a record outside the input
            }
            if (extractor.Feed(record, datagram)) {
                for (uint8_t b : datagram.payload) bytes += b;  // touch every byte
                if (datagram.payload.size() > 65507) __builtin_trap();
            }
        }
        if (reader.truncated_bytes() > 0 && !reader.truncated()) __builtin_trap();
        (void)bytes;
    } catch (const common::FileError&) {
    }
    extractor.Finish();
    if (extractor.datagrams_in_flight() != 0 || extractor.bytes_in_flight() != 0) __builtin_trap();
    return 0;
}
