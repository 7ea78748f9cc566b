// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "drivers/net/pcap_reader.hpp"

#include <gtest/gtest.h>
#include <zlib.h>

#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "algorithms/common/status.hpp"
#include "drivers/net/pcap_writer.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::net {
namespace {
namespace BIMSLAM_UNITY_ID {

struct Rec {
    int64_t ts = 0;
    uint32_t link = 0;
    uint32_t interface_id = 0;
    uint32_t original = 0;
    std::string data;
    uint64_t index = 0;
    uint64_t offset = 0;
};

std::vector<Rec> ReadAll(PcapReader& reader) {
    std::vector<Rec> out;
    PcapRecord r;
    while (reader.Next(r)) {
        out.push_back({r.timestamp_ns, r.link_type, r.interface_id, r.original_length,
                       std::string(reinterpret_cast<const char*>(r.data.data()), r.data.size()),
                       r.index, r.file_offset});
    }
    return out;
}

std::vector<Rec> ReadAll(const std::string& bytes) {
    PcapReader reader = PcapReader::FromMemory("mem.pcap", bytes);
    return ReadAll(reader);
}

// Little helpers to write numbers in either byte order.
struct Out {
    bool big_endian = false;
    std::string s;
    void U8(uint8_t v) { s.push_back(static_cast<char>(v)); }
    void U16(uint16_t v) {
        if (big_endian) {
            U8(static_cast<uint8_t>(v >> 8));
            U8(static_cast<uint8_t>(v));
        } else {
            U8(static_cast<uint8_t>(v));
            U8(static_cast<uint8_t>(v >> 8));
        }
    }
    void U32(uint32_t v) {
        if (big_endian) {
            U16(static_cast<uint16_t>(v >> 16));
            U16(static_cast<uint16_t>(v));
        } else {
            U16(static_cast<uint16_t>(v));
            U16(static_cast<uint16_t>(v >> 16));
        }
    }
    void U64(uint64_t v) {
        if (big_endian) {
            U32(static_cast<uint32_t>(v >> 32));
            U32(static_cast<uint32_t>(v));
        } else {
            U32(static_cast<uint32_t>(v));
            U32(static_cast<uint32_t>(v >> 32));
        }
    }
    void Bytes(const std::string& b) { s += b; }
    void Pad() {
        while (s.size() % 4 != 0) U8(0);
    }
};

// pcapng blocks (draft-ietf-opsawg-pcapng), written by hand.
std::string Block(bool be, uint32_t type, const std::string& body) {
    Out b{be, {}};
    b.Bytes(body);
    b.Pad();
    Out o{be, {}};
    o.U32(type);
    o.U32(static_cast<uint32_t>(b.s.size() + 12));
    o.Bytes(b.s);
    o.U32(static_cast<uint32_t>(b.s.size() + 12));
    return o.s;
}
std::string SectionHeader(bool be) {
    Out o{be, {}};
    o.U32(0x1A2B3C4D);
    o.U16(1);
    o.U16(0);
    o.U64(~uint64_t{0});  // section length unknown
    return Block(be, 0x0A0D0D0A, o.s);
}
std::string Interface(bool be, uint16_t link, uint32_t snaplen, int tsresol = -1,
                      int64_t tsoffset = 0) {
    Out o{be, {}};
    o.U16(link);
    o.U16(0);
    o.U32(snaplen);
    if (tsresol >= 0) {
        o.U16(9);
        o.U16(1);
        o.U8(static_cast<uint8_t>(tsresol));
        o.Pad();
    }
    if (tsoffset != 0) {
        o.U16(14);
        o.U16(8);
        o.U64(static_cast<uint64_t>(tsoffset));
    }
    o.U16(2);  // if_name, ignored
    o.U16(3);
    o.Bytes("lo0");
    o.Pad();
    o.U16(0);
    o.U16(0);
    return Block(be, 1, o.s);
}
std::string Enhanced(bool be, uint32_t interface_id, uint64_t ts, const std::string& data,
                     uint32_t original = 0) {
    Out o{be, {}};
    o.U32(interface_id);
    o.U32(static_cast<uint32_t>(ts >> 32));
    o.U32(static_cast<uint32_t>(ts));
    o.U32(static_cast<uint32_t>(data.size()));
    o.U32(original ? original : static_cast<uint32_t>(data.size()));
    o.Bytes(data);
    o.Pad();
    o.U16(1);  // opt_comment, ignored
    o.U16(2);
    o.Bytes("hi");
    o.Pad();
    o.U16(0);
    o.U16(0);
    return Block(be, 6, o.s);
}
std::string Simple(bool be, const std::string& data) {
    Out o{be, {}};
    o.U32(static_cast<uint32_t>(data.size()));
    o.Bytes(data);
    return Block(be, 3, o.s);
}

// A classic pcap with `count` records of the given sizes.
std::string ClassicPcap(bool nanosecond, const std::vector<std::string>& payloads,
                        int64_t t0 = 1'700'000'000'123'456'789) {
    PcapWriterConfig options;
    options.nanosecond = nanosecond;
    options.link_type = kLinkTypeCanSocketcan;
    PcapWriter writer(options);
    for (size_t i = 0; i < payloads.size(); ++i) {
        writer.WriteRecord(t0 + static_cast<int64_t>(i) * 1'000'333, test::AsBytes(payloads[i]));
    }
    return writer.bytes();
}

TEST(PcapReader, ClassicNanosecondsAndMicroseconds) {
    std::mt19937 rng(1);
    const std::vector<std::string> payloads = {
        test::RandomBytes(16, rng), test::RandomBytes(0, rng), test::RandomBytes(6500, rng)};
    for (const bool ns : {true, false}) {
        const std::string file = ClassicPcap(ns, payloads);
        PcapReader reader = PcapReader::FromMemory("mem.pcap", file);
        EXPECT_EQ(reader.format(), PcapFormat::kPcap);
        EXPECT_EQ(reader.nanosecond(), ns);
        EXPECT_EQ(reader.link_type(), kLinkTypeCanSocketcan);
        EXPECT_EQ(reader.snaplen(), PcapReader::kMaxCaptureBytes);
        const auto records = ReadAll(reader);
        ASSERT_EQ(records.size(), 3u);
        uint64_t offset = 24;
        for (size_t i = 0; i < 3; ++i) {
            const int64_t t = 1'700'000'000'123'456'789 + static_cast<int64_t>(i) * 1'000'333;
            EXPECT_EQ(records[i].ts, ns ? t : t / 1000 * 1000);
            EXPECT_EQ(records[i].data, payloads[i]);
            EXPECT_EQ(records[i].original, payloads[i].size());
            EXPECT_EQ(records[i].index, i);
            EXPECT_EQ(records[i].offset, offset);
            EXPECT_EQ(records[i].link, kLinkTypeCanSocketcan);
            offset += 16 + payloads[i].size();
        }
        EXPECT_FALSE(reader.truncated());
        EXPECT_EQ(reader.records(), 3u);
        PcapRecord r;
        EXPECT_FALSE(reader.Next(r));  // stays at the end
    }
}

TEST(PcapReader, BigEndianClassic) {
    for (const uint32_t magic : {0xA1B2C3D4u, 0xA1B23C4Du}) {
        Out o{true, {}};
        o.U32(magic);
        o.U16(2);
        o.U16(4);
        o.U32(0);
        o.U32(0);
        o.U32(65535);
        o.U32(kLinkTypeEthernet | 0x14000000u);  // FCS-length bits do not change the link type
        o.U32(1'600'000'000);
        o.U32(999'999);
        o.U32(3);
        o.U32(60);
        o.Bytes("abc");
        const auto records = ReadAll(o.s);
        ASSERT_EQ(records.size(), 1u);
        const int64_t frac = magic == 0xA1B2C3D4u ? 999'999'000 : 999'999;
        EXPECT_EQ(records[0].ts, 1'600'000'000'000'000'000 + frac);
        EXPECT_EQ(records[0].link, kLinkTypeEthernet);
        EXPECT_EQ(records[0].original, 60u);
        EXPECT_EQ(records[0].data, "abc");
    }
}

TEST(PcapReader, PcapNgBothByteOrdersInterfacesAndResolutions) {
    for (const bool be : {false, true}) {
        std::string f = SectionHeader(be);
        f += Interface(be, kLinkTypeEthernet, 65535);                   // microseconds (default)
        f += Interface(be, kLinkTypeLinuxSll2, 0, 9);                   // nanoseconds
        f += Interface(be, kLinkTypeCanSocketcan, 0, 0x80 | 20, 1000);  // 2^-20 s, +1000 s
        f += Block(be, 4, std::string(9, 'n'));                         // name resolution: skipped
        f += Block(be, 0x40000BAD, std::string(100, 'x'));              // custom: skipped
        f += Enhanced(be, 0, 1'700'000'000'123'456ull, "first");
        f += Enhanced(be, 1, 1'700'000'000'123'456'789ull, "second", 1000);
        f += Enhanced(be, 2, (uint64_t{5} << 20) + (uint64_t{1} << 19), "third");
        f += Simple(be, "simple!");
        // A new section: interfaces start again, in the other byte order.
        f += SectionHeader(!be);
        f += Interface(!be, kLinkTypeRaw, 0, 3);  // milliseconds
        f += Enhanced(!be, 0, 42, "fourth");
        PcapReader reader = PcapReader::FromMemory("mem.pcapng", f);
        EXPECT_EQ(reader.format(), PcapFormat::kPcapNg);
        EXPECT_EQ(reader.link_type(), kLinkTypeEthernet);
        const auto records = ReadAll(reader);
        ASSERT_EQ(records.size(), 5u);
        EXPECT_EQ(records[0].ts, 1'700'000'000'123'456'000);
        EXPECT_EQ(records[0].link, kLinkTypeEthernet);
        EXPECT_EQ(records[0].data, "first");
        EXPECT_EQ(records[1].ts, 1'700'000'000'123'456'789);
        EXPECT_EQ(records[1].link, kLinkTypeLinuxSll2);
        EXPECT_EQ(records[1].interface_id, 1u);
        EXPECT_EQ(records[1].original, 1000u);
        EXPECT_EQ(records[2].ts, 1005'500'000'000);
        EXPECT_EQ(records[2].link, kLinkTypeCanSocketcan);
        EXPECT_EQ(records[3].data, "simple!");
        EXPECT_EQ(records[3].link, kLinkTypeEthernet);
        EXPECT_EQ(records[3].ts, 0);
        EXPECT_EQ(records[4].ts, 42'000'000);
        EXPECT_EQ(records[4].link, kLinkTypeRaw);
        EXPECT_EQ(records[4].data, "fourth");
        EXPECT_EQ(records[4].index, 4u);
        EXPECT_EQ(reader.skipped_blocks(), 2u);
        EXPECT_FALSE(reader.truncated());
        // The offset of a packet is its block's.
        EXPECT_EQ(f.substr(records[0].offset, 4), Block(be, 6, "").substr(0, 4));
    }
}

std::string Gzip(const std::string& bytes, const std::filesystem::path& path) {
    gzFile gz = gzopen(path.c_str(), "wb");
    EXPECT_NE(gz, nullptr);
    EXPECT_EQ(gzwrite(gz, bytes.data(), static_cast<unsigned>(bytes.size())),
              static_cast<int>(bytes.size()));
    EXPECT_EQ(gzclose(gz), Z_OK);
    std::ifstream f(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), {});
}

TEST(PcapReader, FilesPlainAndGzipLargerThanTheBuffer) {
    std::mt19937 rng(2);
    std::vector<std::string> payloads;
    for (int i = 0; i < 1500; ++i) {
        payloads.push_back(test::RandomBytes(rng() % 9000, rng));
        for (char& c : payloads.back()) c &= 0x03;  // compressible
    }
    const std::string file = ClassicPcap(true, payloads);
    test::TempDir dir;
    test::WriteBytes(dir / "a.pcap", file);
    const std::string gz = Gzip(file, dir / "a.pcap.gz");
    EXPECT_LT(gz.size(), file.size());
    for (const char* name : {"a.pcap", "a.pcap.gz"}) {
        PcapReader reader(dir / name);
        EXPECT_EQ(reader.name(), (dir / name).string());
        const auto records = ReadAll(reader);
        ASSERT_EQ(records.size(), payloads.size()) << name;
        uint64_t offset = 24;
        for (size_t i = 0; i < payloads.size(); ++i) {
            ASSERT_EQ(records[i].data, payloads[i]) << name << " " << i;
            ASSERT_EQ(records[i].offset, offset);
            offset += 16 + payloads[i].size();
        }
        EXPECT_FALSE(reader.truncated()) << name;
    }
    // A gzip stream cut short reads like a killed capture.
    test::WriteBytes(dir / "cut.pcap.gz", gz.substr(0, gz.size() / 2));
    PcapReader cut(dir / "cut.pcap.gz");
    const auto records = ReadAll(cut);
    EXPECT_GT(records.size(), 100u);
    EXPECT_LT(records.size(), payloads.size());
    EXPECT_TRUE(cut.truncated());
    for (size_t i = 0; i < records.size(); ++i) ASSERT_EQ(records[i].data, payloads[i]);
}

TEST(PcapReader, TruncatedFilesEndCleanly) {
    std::mt19937 rng(3);
    const std::vector<std::string> payloads = {
        test::RandomBytes(40, rng), test::RandomBytes(13, rng), test::RandomBytes(70, rng)};
    const std::string classic = ClassicPcap(false, payloads);
    std::string ng = SectionHeader(false) + Interface(false, kLinkTypeEthernet, 0);
    const size_t ng_header = ng.size();
    std::vector<size_t> ng_ends;
    for (const auto& p : payloads) {
        ng += Enhanced(false, 0, 7, p);
        ng_ends.push_back(ng.size());
    }
    const std::vector<size_t> classic_ends = {24 + 56, 24 + 56 + 29, classic.size()};
    struct Case {
        const std::string& file;
        size_t header;
        std::vector<size_t> ends;
    };
    for (const Case& c : {Case{classic, 24, classic_ends}, Case{ng, ng_header, ng_ends}}) {
        for (size_t cut = c.header; cut <= c.file.size(); ++cut) {
            const std::string bytes = c.file.substr(0, cut);
            PcapReader reader = PcapReader::FromMemory("cut.pcap", bytes);
            const auto records = ReadAll(reader);
            size_t complete = 0;
            size_t last_end = c.header;
            while (complete < c.ends.size() && c.ends[complete] <= cut)
                last_end = c.ends[complete++];
            ASSERT_EQ(records.size(), complete) << cut;
            for (size_t i = 0; i < complete; ++i) EXPECT_EQ(records[i].data, payloads[i]);
            EXPECT_EQ(reader.truncated(), cut != last_end) << cut;
            EXPECT_EQ(reader.truncated_bytes(), cut - last_end) << cut;
        }
    }
}

TEST(PcapReader, HeaderOnlyFileHasNoRecords) {
    const std::string file = ClassicPcap(false, {});
    ASSERT_EQ(file.size(), 24u);
    PcapReader reader = PcapReader::FromMemory("empty.pcap", file);
    PcapRecord r;
    EXPECT_FALSE(reader.Next(r));
    EXPECT_FALSE(reader.truncated());
    EXPECT_EQ(reader.records(), 0u);
    const std::string ng = SectionHeader(true);
    PcapReader ng_reader = PcapReader::FromMemory("empty.pcapng", ng);
    EXPECT_FALSE(ng_reader.Next(r));
    EXPECT_FALSE(ng_reader.truncated());
}

// Expects a FileError naming `name`, with "at byte <offset>" in its message.
template <typename F>
void ExpectCorrupt(F&& f, const std::string& name, uint64_t offset, const std::string& what) {
    try {
        f();
        ADD_FAILURE() << "no error; expected " << what;
    } catch (const common::FileError& e) {
        EXPECT_EQ(e.path(), name) << e.what();
        EXPECT_EQ(e.line(), 0u);
        EXPECT_NE(e.detail().find("at byte " + std::to_string(offset) + ":"), std::string::npos)
            << e.what();
        EXPECT_NE(e.detail().find(what), std::string::npos) << e.what();
    }
}

TEST(PcapReader, CorruptHeadersNameFileAndOffset) {
    std::mt19937 rng(4);
    const std::vector<std::string> payloads = {
        test::RandomBytes(40, rng), test::RandomBytes(13, rng), test::RandomBytes(70, rng)};
    const std::string good = ClassicPcap(true, payloads);
    auto open = [](const std::string& bytes) {
        return [bytes] {
            PcapReader reader = PcapReader::FromMemory("bad.pcap", bytes);
            ReadAll(reader);
        };
    };
    std::string bad = good;
    bad[0] = 'X';
    ExpectCorrupt(open(bad), "bad.pcap", 0, "bad magic");
    bad = good;
    bad[18] = 0x10;  // snaplen 0x100000 + ...
    ExpectCorrupt(open(bad), "bad.pcap", 16, "snaplen");
    bad = good;
    bad[4] = 1;
    ExpectCorrupt(open(bad), "bad.pcap", 4, "version");
    ExpectCorrupt(open(good.substr(0, 10)), "bad.pcap", 0, "24-byte pcap file header");
    EXPECT_FILE_ERROR(PcapReader::FromMemory("bad.pcap", std::string_view("ab")), "bad.pcap", 0);

    // The second record's caplen is absurd: the first record comes out, then the error.
    bad = good;
    const size_t second = 24 + 16 + 40;
    bad[second + 8 + 3] = 0x7F;
    {
        PcapReader reader = PcapReader::FromMemory("bad.pcap", bad);
        PcapRecord r;
        ASSERT_TRUE(reader.Next(r));
        EXPECT_EQ(r.data.size(), 40u);
        ExpectCorrupt([&] { reader.Next(r); }, "bad.pcap", second, "captured length");
    }

    // pcapng: bad length, mismatched trailer, unknown interface, block too large, bad BOM.
    const std::string shb = SectionHeader(false);
    const std::string idb = Interface(false, 1, 0);
    const std::string epb = Enhanced(false, 0, 1, "data");
    auto ng = [](const std::string& bytes) {
        return [bytes] {
            PcapReader reader = PcapReader::FromMemory("bad.pcapng", bytes);
            ReadAll(reader);
        };
    };
    std::string b = epb;
    b[4] = 13;  // not a multiple of 4
    ExpectCorrupt(ng(shb + idb + b), "bad.pcapng", shb.size() + idb.size(), "bad block length");
    b = epb;
    b[b.size() - 4] ^= 4;
    ExpectCorrupt(ng(shb + idb + b), "bad.pcapng", shb.size() + idb.size(), "at the end");
    ExpectCorrupt(ng(shb + epb), "bad.pcapng", shb.size(), "interface 0");
    b = epb;
    b[6] = 0x40;  // 4 MiB packet block
    ExpectCorrupt(ng(shb + idb + b), "bad.pcapng", shb.size() + idb.size(), "exceeds");
    b = epb;
    b[20] = 0x7F;  // caplen beyond the block
    ExpectCorrupt(ng(shb + idb + b), "bad.pcapng", shb.size() + idb.size(), "captured length");
    std::string s = shb;
    s[8] = 0;
    ExpectCorrupt(ng(s), "bad.pcapng", 8, "byte-order magic");
    ExpectCorrupt(ng(shb + idb + epb + s), "bad.pcapng", shb.size() + idb.size() + epb.size() + 8,
                  "byte-order");
    ExpectCorrupt(ng(shb.substr(0, 20)), "bad.pcapng", 0, "section header");
}

TEST(PcapReader, MissingFileIsNotFound) {
    test::TempDir dir;
    try {
        PcapReader reader(dir / "nope.pcap");
        ADD_FAILURE() << "opened a missing file";
    } catch (const common::FileError& e) {
        EXPECT_EQ(e.path(), (dir / "nope.pcap").string());
        EXPECT_EQ(e.code(), common::StatusCode::kNotFound);
    }
    test::WriteBytes(dir / "zero.pcap", "");
    EXPECT_FILE_ERROR(PcapReader(dir / "zero.pcap"), (dir / "zero.pcap").string(), 0);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::net
