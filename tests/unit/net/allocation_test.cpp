// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The per-packet paths of drivers/net must not allocate once set up (DESIGN.md, "Hot path"):
// PcapReader::Next, UdpExtractor::Feed (reassembly included), UdpSource::Receive, and
// PcapWriter::WriteRecord/WriteUdp to a file. Its binary links the counting operator new of
// tests/support/allocation_counter.hpp.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <random>
#include <string>

#include "drivers/net/ipv4.hpp"
#include "drivers/net/pcap_reader.hpp"
#include "drivers/net/pcap_writer.hpp"
#include "drivers/net/udp_source.hpp"
#include "tests/support/allocation_counter.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::net {
namespace {
namespace BIMSLAM_UNITY_ID {

TEST(HotPath, ReaderExtractorAndWriterDoNotAllocate) {
    std::mt19937 rng(1);
    std::string payload(6464, '\0');
    for (char& c : payload) c = static_cast<char>(rng());
    test::TempDir dir;
    PcapWriter writer(dir / "a.pcap");
    ExtractorConfig config;
    config.max_datagrams_in_flight = 2;
    UdpExtractor extractor(config);
    {
        const size_t before = test::Allocations();
        for (int i = 0; i < 300; ++i) {
            const uint32_t mtu = i % 3 == 0 ? 0 : i % 3 == 1 ? 1500 : 576;
            writer.WriteUdp(int64_t{i} * 600'000'000, 0x0A050501, 7502, 0x0A050502, 7502,
                            test::AsBytes(payload).first(rng() % payload.size()), mtu);
            writer.WriteRecord(int64_t{i} * 600'000'000, test::AsBytes(payload).first(100));
        }
        EXPECT_EQ(test::Allocations() - before, 0u) << "PcapWriter";
    }
    writer.Close();
    const std::string bytes = [&] {
        PcapWriter memory;
        for (int i = 0; i < 50; ++i) {
            memory.WriteUdp(int64_t{i} * 600'000'000, 1, 2, 3, 4, test::AsBytes(payload), 1500);
        }
        return memory.bytes();
    }();
    PcapReader from_file(dir / "a.pcap");
    PcapReader from_memory = PcapReader::FromMemory("m.pcap", bytes);
    PcapRecord record;
    UdpDatagram datagram;
    const size_t before = test::Allocations();
    size_t datagrams = 0;
    while (from_file.Next(record)) datagrams += extractor.Feed(record, datagram);
    size_t dropped = 0;
    while (from_memory.Next(record)) {
        // Every third fragment lost: reassembly, timeouts and evictions all run.
        if (++dropped % 3 != 0) datagrams += extractor.Feed(record, datagram);
    }
    extractor.Finish();
    EXPECT_EQ(test::Allocations() - before, 0u) << "PcapReader/UdpExtractor";
    EXPECT_EQ(datagrams, 300u);
    EXPECT_GT(extractor.stats().timed_out_datagrams + extractor.stats().evicted_datagrams_limit,
              0u);
}

TEST(HotPath, UdpSourceDoesNotAllocate) {
    UdpSourceConfig config;
    config.bind_address = "127.0.0.1";
    config.port = 0;
    config.receive_buffer_bytes = 0;
    UdpSource source(config);
    const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
    ASSERT_GE(fd, 0);
    sockaddr_in to{};
    to.sin_family = AF_INET;
    to.sin_port = htons(source.port());
    to.sin_addr.s_addr = htonl(0x7F000001);
    const std::string packet(6464, 'x');
    size_t received = 0;
    const size_t before = test::Allocations();
    for (int round = 0; round < 10; ++round) {
        for (int i = 0; i < 20; ++i) {
            ::sendto(fd, packet.data(), packet.size(), 0, reinterpret_cast<const sockaddr*>(&to),
                     sizeof(to));
        }
        for (int tries = 0; tries < 20 && received < 20u * (round + 1); ++tries) {
            received += source.Receive(common::Duration::FromMilliseconds(50)).datagrams.size();
        }
    }
    source.Receive(common::Duration{0});  // a timeout
    EXPECT_EQ(test::Allocations() - before, 0u);
    EXPECT_EQ(received, 200u);
    ::close(fd);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::net
