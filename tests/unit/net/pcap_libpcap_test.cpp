// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// What moving pcap file I/O onto libpcap (issue 34) brought or had to guard against: the
// modified pcap format libpcap reads, timestamps past 2038 (libpcap's fields are signed), the
// link types libpcap numbers differently from the file, broken gzip data, and link types libpcap
// cannot write.
#include <gtest/gtest.h>
#include <zlib.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <random>
#include <string>

#include "algorithms/common/status.hpp"
#include "drivers/net/pcap_reader.hpp"
#include "drivers/net/pcap_writer.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::net {
namespace {
namespace BIMSLAM_UNITY_ID {

void Put32(std::string& s, uint32_t v) { s.append(reinterpret_cast<const char*>(&v), 4); }

TEST(PcapLibpcap, ModifiedFormatWith24ByteRecordHeadersIsRead) {
    // Kuznetsov's patched libpcap (magic A1B2CD34): record headers carry ifindex, protocol and
    // packet type after the four usual fields (libpcap's sf-pcap.c). The old reader refused it.
    std::string f;
    for (uint32_t v : {0xA1B2CD34u, 0x00040002u, 0u, 0u, 65535u, uint32_t{kLinkTypeEthernet}}) {
        Put32(f, v);
    }
    const std::string payloads[] = {"first packet", "2nd"};
    for (int i = 0; i < 2; ++i) {
        for (uint32_t v : {1'600'000'000u + i, 250'000u, uint32_t(payloads[i].size()),
                           uint32_t(payloads[i].size()) + 10, 3u, 0x0800u}) {
            Put32(f, v);
        }
        f += payloads[i];
    }
    test::TempDir dir;
    test::WriteBytes(dir / "modified.pcap", f);
    PcapReader from_memory = PcapReader::FromMemory("modified.pcap", f);
    PcapReader from_file(dir / "modified.pcap");
    for (PcapReader* reader : {&from_memory, &from_file}) {
        PcapRecord r;
        uint64_t offset = 24;
        for (int i = 0; i < 2; ++i) {
            ASSERT_TRUE(reader->Next(r)) << reader->name();
            EXPECT_EQ(std::string(reinterpret_cast<const char*>(r.data.data()), r.data.size()),
                      payloads[i]);
            EXPECT_EQ(r.original_length, payloads[i].size() + 10);
            EXPECT_EQ(r.timestamp_ns, (1'600'000'000 + i) * 1'000'000'000ll + 250'000'000);
            EXPECT_EQ(r.file_offset, offset);
            offset += 24 + payloads[i].size();
        }
        EXPECT_FALSE(reader->Next(r));
        EXPECT_FALSE(reader->truncated());
    }
}

TEST(PcapLibpcap, TimestampsUpTo2106AndRawLinkTypeRoundTrip) {
    // ts_sec is unsigned in the file; libpcap's pcap_pkthdr holds it sign-extended from 2038 on.
    const int64_t late = 4'000'000'000ll * 1'000'000'000 + 987'654'321;
    for (const bool ns : {true, false}) {
        PcapWriterConfig config;
        config.link_type = kLinkTypeRaw;  // libpcap's DLT_RAW is 12: the file must say 101
        config.nanosecond = ns;
        PcapWriter writer(config);
        writer.WriteUdp(late, 0x0A000001, 1, 0x0A000002, 2, test::AsBytes(std::string(9, 'x')));
        writer.WriteRecord(0xFFFFFFFFll * 1'000'000'000 + 999'999'999,
                           test::AsBytes(std::string("y")));
        const std::string& bytes = writer.bytes();
        uint32_t link_type = 0;
        std::memcpy(&link_type, bytes.data() + 20, 4);
        EXPECT_EQ(link_type, kLinkTypeRaw);
        PcapReader reader = PcapReader::FromMemory("late.pcap", bytes);
        EXPECT_EQ(reader.link_type(), kLinkTypeRaw);
        PcapRecord r;
        ASSERT_TRUE(reader.Next(r));
        EXPECT_EQ(r.timestamp_ns, ns ? late : late / 1000 * 1000);
        EXPECT_EQ(r.link_type, kLinkTypeRaw);
        ASSERT_TRUE(reader.Next(r));
        EXPECT_EQ(r.timestamp_ns, 0xFFFFFFFFll * 1'000'000'000 + (ns ? 999'999'999 : 999'999'000));
    }
}

TEST(PcapLibpcap, BrokenGzipDataIsAFileErrorNamingTheFile) {
    std::mt19937 rng(5);
    PcapWriterConfig config;
    config.link_type = kLinkTypeCanSocketcan;
    PcapWriter writer(config);
    for (int i = 0; i < 8000; ++i) writer.WriteRecord(i, test::AsBytes(test::RandomBytes(64, rng)));
    test::TempDir dir;
    const auto path = dir / "broken.pcap.gz";
    gzFile gz = gzopen(path.c_str(), "wb");
    ASSERT_NE(gz, nullptr);
    ASSERT_EQ(gzwrite(gz, writer.bytes().data(), static_cast<unsigned>(writer.bytes().size())),
              static_cast<int>(writer.bytes().size()));
    ASSERT_EQ(gzclose(gz), Z_OK);
    std::ifstream in(path, std::ios::binary);
    std::string compressed((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    // The trailer's CRC-32 (RFC 1952): zlib reads every byte, then fails the check. (Damage
    // inside the deflate data may decode into garbage instead, which is a corrupt record.)
    compressed[compressed.size() - 8] ^= 0x5A;
    test::WriteBytes(path, compressed);
    // The records zlib handed out before it checked come out, then the error.
    uint64_t records = 0;
    try {
        PcapReader reader(path);
        PcapRecord r;
        while (reader.Next(r)) ++records;
        ADD_FAILURE() << "broken gzip data read to the end";
    } catch (const common::FileError& e) {
        EXPECT_EQ(e.path(), path.string());
        EXPECT_NE(e.detail().find("gzip data broken"), std::string::npos) << e.what();
    }
    EXPECT_GT(records, 3000u);
}

TEST(PcapLibpcap, LinkTypeLibpcapCannotWriteIsAFileError) {
    test::TempDir dir;
    PcapWriterConfig config;
    config.link_type = 60000;  // beyond libpcap 1.10's table (LINKTYPE_MATCHING_MAX 289)
    EXPECT_FILE_ERROR(PcapWriter(dir / "x.pcap", config), (dir / "x.pcap").string(), 0);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::net
