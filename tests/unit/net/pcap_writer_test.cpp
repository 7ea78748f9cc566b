// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "drivers/net/pcap_writer.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "algorithms/common/status.hpp"
#include "drivers/net/ipv4.hpp"
#include "drivers/net/pcap_reader.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::net {
namespace {
namespace BIMSLAM_UNITY_ID {

constexpr int64_t kT0 = 1'700'000'000'000'000'000;

std::vector<std::vector<uint8_t>> Records(const std::string& pcap) {
    PcapReader reader = PcapReader::FromMemory("w.pcap", pcap);
    std::vector<std::vector<uint8_t>> out;
    PcapRecord r;
    while (reader.Next(r)) out.emplace_back(r.data.begin(), r.data.end());
    return out;
}

uint16_t Be16(const std::vector<uint8_t>& f, size_t at) {
    return static_cast<uint16_t>((f[at] << 8) | f[at + 1]);
}

TEST(PcapWriter, FragmentsAsLinuxDoes) {
    std::mt19937 rng(20);
    std::string payload(6464, '\0');  // one OS1-32 LEGACY lidar packet
    for (char& c : payload) c = static_cast<char>(rng());
    PcapWriterConfig options;
    options.first_ip_id = 0xFFFF;  // wraps to 0 for the next datagram
    PcapWriter writer(options);
    writer.WriteUdp(kT0, 0x0A050557, 7502, 0x0A050501, 7502, test::AsBytes(payload), 1500);
    writer.WriteUdp(kT0, 0x0A050557, 7502, 0x0A050501, 7502, test::AsBytes(payload).first(1472),
                    1500);
    writer.WriteUdp(kT0, 0x0A050557, 7502, 0x0A050501, 7502, test::AsBytes(payload).first(1473),
                    1500);
    EXPECT_EQ(writer.next_ip_id(), 2);
    const auto frames = Records(writer.bytes());
    ASSERT_EQ(frames.size(), 5u + 1u + 2u);
    // 6472 bytes of IP payload: 4 x 1480 (1500 - 20, a multiple of 8) + 552.
    const uint16_t lengths[] = {1500, 1500, 1500, 1500, 572, 1500, 1500, 21};
    const uint16_t fields[] = {0x2000, 0x2000 | 185, 0x2000 | 370, 0x2000 | 555, 740,
                               0,      0x2000,       185};
    const uint16_t ids[] = {0xFFFF, 0xFFFF, 0xFFFF, 0xFFFF, 0xFFFF, 0, 1, 1};
    std::vector<uint8_t> udp;  // reassembled by hand
    for (size_t i = 0; i < frames.size(); ++i) {
        const auto& f = frames[i];
        ASSERT_EQ(f.size(), 14u + lengths[i]) << i;
        EXPECT_EQ(Be16(f, 12), kEtherTypeIpv4);
        EXPECT_EQ(f[14], 0x45);
        EXPECT_EQ(Be16(f, 16), lengths[i]) << i;
        EXPECT_EQ(Be16(f, 18), ids[i]) << i;
        EXPECT_EQ(Be16(f, 20), fields[i]) << i;  // never DF
        EXPECT_EQ(f[22], 64);
        EXPECT_EQ(f[23], kIpProtocolUdp);
        EXPECT_EQ(InternetChecksum(std::span<const uint8_t>(f).subspan(14, 20)), 0) << i;
        if (i < 5) udp.insert(udp.end(), f.begin() + 34, f.end());
    }
    ASSERT_EQ(udp.size(), 6472u);
    EXPECT_EQ(Be16(udp, 0), 7502);
    EXPECT_EQ(Be16(udp, 4), 6472);
    EXPECT_NE(Be16(udp, 6), 0);
    // The UDP checksum over pseudo-header + datagram checks to 0.
    const uint32_t pseudo = 0x0A05 + 0x0557 + 0x0A05 + 0x0501 + 17 + 6472;
    EXPECT_EQ(InternetChecksum(udp, pseudo), 0);
    EXPECT_EQ(std::string(udp.begin() + 8, udp.end()), payload);
}

TEST(PcapWriter, RawLinkTypeNoChecksumSnaplenAndMicroseconds) {
    PcapWriterConfig options;
    options.link_type = kLinkTypeIpv4;
    options.udp_checksum = false;
    options.nanosecond = false;
    options.snaplen = 60;
    PcapWriter writer(options);
    const std::string payload(100, 'p');
    writer.WriteUdp(kT0 + 1999, 0x7F000001, 1, 0x7F000001, 2, test::AsBytes(payload));
    PcapReader reader = PcapReader::FromMemory("w.pcap", writer.bytes());
    EXPECT_FALSE(reader.nanosecond());
    EXPECT_EQ(reader.snaplen(), 60u);
    PcapRecord r;
    ASSERT_TRUE(reader.Next(r));
    EXPECT_EQ(r.timestamp_ns, kT0 + 1000);
    EXPECT_EQ(r.original_length, 128u);
    ASSERT_EQ(r.data.size(), 60u);
    EXPECT_EQ(r.data[0], 0x45);
    EXPECT_EQ(r.data[26], 0);  // UDP checksum 0: none
    EXPECT_EQ(r.data[27], 0);
}

TEST(PcapWriter, CanRecordsRawAndFilesThroughTheBuffer) {
    test::TempDir dir;
    PcapWriterConfig options;
    options.link_type = kLinkTypeCanSocketcan;
    // SocketCAN frame: ID big-endian with flags, length, padding, data (LINKTYPE_CAN_SOCKETCAN).
    const std::string can("\x00\x00\x01\x2a\x08\x00\x00\x00\x01\x02\x03\x04\x05\x06\x07\x08", 16);
    std::mt19937 rng(21);
    {
        PcapWriter file(dir / "can.pcap", options);
        PcapWriter memory(options);
        for (int i = 0; i < 30000; ++i) {  // ~960 kB: several buffer flushes
            file.WriteRecord(kT0 + i * 1000, test::AsBytes(can));
            memory.WriteRecord(kT0 + i * 1000, test::AsBytes(can));
        }
        file.Close();
        file.Close();  // twice is fine
        EXPECT_FILE_ERROR(file.WriteRecord(kT0, test::AsBytes(can)), (dir / "can.pcap").string(),
                          0);
        std::ifstream f(dir / "can.pcap", std::ios::binary);
        EXPECT_EQ(std::string(std::istreambuf_iterator<char>(f), {}), memory.bytes());
        EXPECT_EQ(file.records(), 30000u);
    }
    PcapReader reader(dir / "can.pcap");
    EXPECT_EQ(reader.link_type(), kLinkTypeCanSocketcan);
    PcapRecord r;
    ASSERT_TRUE(reader.Next(r));
    EXPECT_EQ(std::string(reinterpret_cast<const char*>(r.data.data()), r.data.size()), can);
    // The destructor flushes too.
    {
        PcapWriter unclosed(dir / "unclosed.pcap", options);
        unclosed.WriteRecord(kT0, test::AsBytes(can));
    }
    EXPECT_EQ(std::filesystem::file_size(dir / "unclosed.pcap"), 24u + 16u + 16u);
}

TEST(PcapWriter, Errors) {
    test::TempDir dir;
    EXPECT_FILE_ERROR(PcapWriter(dir / "missing" / "x.pcap"), (dir / "missing" / "x.pcap").string(),
                      0);
    PcapWriter writer;
    const std::string big(65508, 'x');
    EXPECT_THROW(writer.WriteUdp(kT0, 1, 2, 3, 4, test::AsBytes(big)), common::Error);
    EXPECT_THROW(writer.WriteUdp(kT0, 1, 2, 3, 4, test::AsBytes(big).first(10), 27), common::Error);
    EXPECT_THROW(writer.WriteRecord(-1, test::AsBytes(big).first(10)), common::Error);
    EXPECT_THROW(writer.WriteRecord(int64_t{1} << 62, test::AsBytes(big).first(10)), common::Error);
    writer.WriteUdp(kT0, 1, 2, 3, 4, test::AsBytes(big).first(65507), 28);  // 8 bytes per fragment
    EXPECT_EQ(writer.records(), (65515u + 7) / 8);
    PcapWriterConfig sll;
    sll.link_type = kLinkTypeLinuxSll;
    PcapWriter cooked(sll);
    EXPECT_THROW(cooked.WriteUdp(kT0, 1, 2, 3, 4, test::AsBytes(big).first(10)), common::Error);
    PcapWriterConfig bad;
    bad.snaplen = 0;
    EXPECT_THROW(PcapWriter{bad}, common::Error);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::net
