// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "drivers/net/can_pcap.hpp"

#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "algorithms/common/status.hpp"
#include "drivers/net/pcap_writer.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::net {
namespace {
namespace BIMSLAM_UNITY_ID {

using common::CanFrame;

void ExpectSame(const CanFrame& a, const CanFrame& b) {
    EXPECT_EQ(a.timestamp_ns, b.timestamp_ns);
    EXPECT_EQ(a.id, b.id);
    EXPECT_EQ(a.extended, b.extended);
    EXPECT_EQ(a.remote, b.remote);
    EXPECT_EQ(a.error, b.error);
    EXPECT_EQ(a.fd, b.fd);
    EXPECT_EQ(a.len, b.len);
    EXPECT_EQ(a.fd_flags, b.fd_flags);
    EXPECT_EQ(a.len8_dlc, b.len8_dlc);
    EXPECT_EQ(a.data, b.data);
}

CanFrame Frame(int64_t ts, uint32_t id, std::vector<uint8_t> data, bool extended = false) {
    CanFrame f;
    f.timestamp_ns = ts;
    f.id = id;
    f.extended = extended;
    f.len = static_cast<uint8_t>(data.size());
    std::copy(data.begin(), data.end(), f.data.begin());
    return f;
}

// Every kind of frame.
std::vector<CanFrame> AllKinds() {
    std::vector<CanFrame> frames;
    frames.push_back(Frame(1'000'000'001, 0x100, {0, 0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77}));
    frames.push_back(Frame(1'000'000'002, 0x7FF, {}));
    frames.push_back(Frame(1'000'000'003, 0x000, {1}));
    frames.push_back(Frame(1'000'000'004, 0x1FFFFFFF, {0xDE, 0xAD}, true));
    frames.push_back(Frame(1'000'000'005, 0x12345681, {9}, true));
    CanFrame remote = Frame(1'000'000'006, 0x123, {});
    remote.remote = true;
    remote.len = 8;
    remote.len8_dlc = 0xC;
    frames.push_back(remote);
    remote = Frame(1'000'000'007, 0x1ABCDE, {}, true);
    remote.remote = true;
    remote.len = 3;
    frames.push_back(remote);
    CanFrame fd = Frame(1'000'000'008, 0x321, {1, 2, 3});
    fd.fd = true;
    fd.fd_flags = 0x1;  // BRS, no FDF: told by the 72-byte record
    frames.push_back(fd);
    fd = Frame(1'000'000'009, 0x1234567, std::vector<uint8_t>(64, 0xA5), true);
    fd.fd = true;
    fd.fd_flags = 0x5;  // BRS | FDF
    frames.push_back(fd);
    fd = Frame(1'000'000'010, 0x42, std::vector<uint8_t>(12, 0x5A));
    fd.fd = true;
    frames.push_back(fd);
    fd = Frame(1'000'000'011, 0x43, {});
    fd.fd = true;
    frames.push_back(fd);
    CanFrame error = Frame(1'000'000'012, 0x84, {0, 4, 0, 0, 0, 0, 0, 0});
    error.error = true;
    frames.push_back(error);
    CanFrame raw_dlc = Frame(1'000'000'013, 0x111, {1, 2, 3, 4, 5, 6, 7, 8});
    raw_dlc.len8_dlc = 15;
    frames.push_back(raw_dlc);
    // Many standard frames: the votes.
    for (int i = 0; i < 20; ++i) {
        frames.push_back(Frame(1'000'000'100 + i, static_cast<uint32_t>(0x100 + 0x31 * i),
                               {static_cast<uint8_t>(i)}));
    }
    return frames;
}

std::string WritePcap(const std::vector<CanFrame>& frames) {
    PcapWriterConfig config;
    config.link_type = kLinkTypeCanSocketcan;
    PcapWriter writer(config);
    for (const CanFrame& f : frames) WriteCanFrame(writer, f);
    return writer.bytes();
}

// The same capture with every record's ID word reversed (as host-order writers store it).
std::string SwapIds(const std::string& pcap) {
    std::string out = pcap;
    size_t pos = 24;
    while (pos + 16 <= out.size()) {
        uint32_t caplen;
        std::memcpy(&caplen, out.data() + pos + 8, 4);
        if (caplen >= 4) std::reverse(out.begin() + pos + 16, out.begin() + pos + 20);
        pos += 16 + caplen;
    }
    return out;
}

struct Decoded {
    std::vector<CanFrame> frames;
    CanPcapStats stats;
    CanIdOrder order = CanIdOrder::kAuto;
};

Decoded ReadPcap(const std::string& bytes, const CanPcapConfig& config = {}) {
    CanPcapReader reader = CanPcapReader::FromMemory("mem.pcap", test::AsBytes(bytes), config);
    Decoded out;
    CanFrame f;
    while (reader.Next(f)) out.frames.push_back(f);
    out.stats = reader.stats();
    out.order = reader.decoder().socketcan_order();
    return out;
}

TEST(CanPcap, PlausibleIds) {
    EXPECT_TRUE(IsPlausibleCanId(0x00000123));
    EXPECT_TRUE(IsPlausibleCanId(0x000007FF));
    EXPECT_FALSE(IsPlausibleCanId(0x00000800));
    EXPECT_TRUE(IsPlausibleCanId(0x40000123));  // remote, standard
    EXPECT_FALSE(IsPlausibleCanId(0x40000800));
    EXPECT_TRUE(IsPlausibleCanId(0x9FFFFFFF));  // extended
    EXPECT_TRUE(IsPlausibleCanId(0xC0000001));  // extended remote
    EXPECT_TRUE(IsPlausibleCanId(0x20000204));  // error: CRTL | CNT
    EXPECT_FALSE(IsPlausibleCanId(0x20000800));
    EXPECT_FALSE(IsPlausibleCanId(0xA0000004));  // error + EFF
    EXPECT_FALSE(IsPlausibleCanId(0x60000004));  // error + RTR
    // The gmlan capture's 0x12A stored little-endian, read big-endian: ERR with a huge class.
    EXPECT_FALSE(IsPlausibleCanId(0x2A010000));
}

TEST(CanPcap, WriteReadRoundTrip) {
    const std::vector<CanFrame> frames = AllKinds();
    const std::string pcap = WritePcap(frames);
    const Decoded read = ReadPcap(pcap);
    ASSERT_EQ(read.frames.size(), frames.size());
    for (size_t i = 0; i < frames.size(); ++i) {
        SCOPED_TRACE(i);
        ExpectSame(read.frames[i], frames[i]);
    }
    EXPECT_EQ(read.order, CanIdOrder::kBigEndian);
    EXPECT_EQ(read.stats.frames, frames.size());
    EXPECT_EQ(read.stats.big_endian_ids, frames.size());
    EXPECT_EQ(read.stats.order_disagreements, 0u);
    EXPECT_EQ(read.stats.implausible_id, 0u);
    // Kernel layout: 16-byte records for classic frames, 72 for CAN FD, the ID big-endian.
    PcapReader reader = PcapReader::FromMemory("mem.pcap", pcap);
    PcapRecord r;
    ASSERT_TRUE(reader.Next(r));
    EXPECT_EQ(reader.link_type(), kLinkTypeCanSocketcan);
    ASSERT_EQ(r.data.size(), kCanMtu);
    EXPECT_EQ(r.data[0], 0x00);
    EXPECT_EQ(r.data[2], 0x01);
    EXPECT_EQ(r.data[3], 0x00);
    EXPECT_EQ(r.data[4], 8);
}

TEST(CanPcap, HostOrderIdsAreDetected) {
    const std::vector<CanFrame> frames = AllKinds();
    const Decoded read = ReadPcap(SwapIds(WritePcap(frames)));
    ASSERT_EQ(read.frames.size(), frames.size());
    for (size_t i = 0; i < frames.size(); ++i) {
        SCOPED_TRACE(i);
        ExpectSame(read.frames[i], frames[i]);
    }
    EXPECT_EQ(read.order, CanIdOrder::kLittleEndian);
    EXPECT_EQ(read.stats.little_endian_ids, frames.size());
    EXPECT_EQ(read.stats.order_disagreements, 0u);
    // The extended id 0x12345681 is plausible both ways: decoded right only thanks to the votes
    // of the frames after it (the reader reads ahead).
    EXPECT_GE(read.stats.ambiguous_ids, 1u);
}

TEST(CanPcap, ScapyLayoutLittleEndianWithShortRecords) {
    // As in ../shared/data/can/gmlan_trace.pcap.gz: 8 + len bytes a record, the ID little-endian.
    PcapWriterConfig config;
    config.link_type = kLinkTypeCanSocketcan;
    config.nanosecond = false;
    PcapWriter writer(config);
    const std::vector<uint8_t> r1 = {0x2A, 0x01, 0,    0,    8, 0, 0,    0,
                                     0x12, 0x20, 0x10, 0xFF, 0, 0, 0x10, 0x80};
    const std::vector<uint8_t> r2 = {0xE1, 0x01, 0, 0, 7, 0, 0, 0, 0, 0, 4, 0, 0, 0, 0};
    writer.WriteRecord(297'000'000, r1);
    writer.WriteRecord(2'713'000'000, r2);
    const Decoded read = ReadPcap(writer.bytes());
    ASSERT_EQ(read.frames.size(), 2u);
    EXPECT_EQ(read.frames[0].id, 0x12Au);
    EXPECT_EQ(read.frames[0].len, 8);
    EXPECT_EQ(read.frames[0].data[7], 0x80);
    EXPECT_EQ(read.frames[0].timestamp_ns, 297'000'000);
    EXPECT_EQ(read.frames[1].id, 0x1E1u);
    EXPECT_EQ(read.frames[1].len, 7);
    EXPECT_FALSE(read.frames[1].fd);
    EXPECT_EQ(read.order, CanIdOrder::kLittleEndian);
}

TEST(CanPcap, DisagreeingAndImplausibleRecords) {
    std::vector<CanFrame> frames = AllKinds();
    std::string pcap = WritePcap(frames);
    // One record in the other order (a merged capture), one plausible in neither.
    PcapWriterConfig config;
    config.link_type = kLinkTypeCanSocketcan;
    PcapWriter extra(config);
    extra.WriteRecord(5, std::vector<uint8_t>{0x23, 0x01, 0, 0, 1, 0, 0, 0, 0xAB});
    extra.WriteRecord(6, std::vector<uint8_t>{0x21, 0, 0, 0x21, 1, 0, 0, 0, 0xAB});
    pcap += extra.bytes().substr(24);
    const Decoded read = ReadPcap(pcap);
    ASSERT_EQ(read.frames.size(), frames.size() + 1);
    EXPECT_EQ(read.frames.back().id, 0x123u);
    EXPECT_EQ(read.frames.back().data[0], 0xAB);
    EXPECT_EQ(read.stats.order_disagreements, 1u);
    EXPECT_EQ(read.stats.implausible_id, 1u);
    EXPECT_EQ(read.order, CanIdOrder::kBigEndian);

    // A fixed order: the other order's records are implausible, nothing is flipped.
    CanPcapConfig fixed;
    fixed.id_order = CanIdOrder::kBigEndian;
    const Decoded strict = ReadPcap(pcap, fixed);
    EXPECT_EQ(strict.frames.size(), frames.size());
    EXPECT_EQ(strict.stats.implausible_id, 2u);
    fixed.id_order = CanIdOrder::kLittleEndian;
    const Decoded wrong = ReadPcap(pcap, fixed);
    EXPECT_GT(wrong.stats.implausible_id, 20u);
}

TEST(CanPcap, BareDecoderVotesAsItGoes) {
    const std::string pcap = SwapIds(WritePcap(AllKinds()));
    PcapReader reader = PcapReader::FromMemory("mem.pcap", pcap);
    CanRecordDecoder decoder;
    PcapRecord r;
    CanFrame f;
    size_t frames = 0;
    while (reader.Next(r)) frames += decoder.Decode(r, f) == CanDecodeResult::kFrame;
    EXPECT_EQ(frames, AllKinds().size());
    EXPECT_EQ(decoder.socketcan_order(), CanIdOrder::kLittleEndian);
    EXPECT_EQ(decoder.cooked_order(), CanIdOrder::kLittleEndian);  // no votes: host order
}

TEST(CanPcap, BadRecordsAreCounted) {
    PcapWriterConfig config;
    config.link_type = kLinkTypeCanSocketcan;
    config.snaplen = 12;
    PcapWriter writer(config);
    writer.WriteRecord(1, std::vector<uint8_t>{0, 0, 1, 0x23, 8, 0, 0, 0, 1, 2, 3, 4, 5, 6, 7, 8});
    writer.WriteRecord(2, std::vector<uint8_t>{0, 0, 1});  // shorter than the header
    const Decoded cut = ReadPcap(writer.bytes());
    EXPECT_EQ(cut.frames.size(), 0u);
    EXPECT_EQ(cut.stats.truncated, 2u);

    PcapWriterConfig full;
    full.link_type = kLinkTypeCanSocketcan;
    PcapWriter bad(full);
    bad.WriteRecord(1, std::vector<uint8_t>(8 + 65, 0));                        // > 64 bytes
    bad.WriteRecord(2, std::vector<uint8_t>{0, 0, 1, 0x23, 9, 0x04, 0, 0});     // FD length 9
    bad.WriteRecord(3, std::vector<uint8_t>{0x40, 0, 1, 0x23, 9, 0, 0, 0});     // remote, 9
    bad.WriteRecord(4, std::vector<uint8_t>{0x40, 0, 1, 0x23, 1, 0x04, 0, 0});  // remote FD
    bad.WriteRecord(5, std::vector<uint8_t>{0, 0, 1, 0x23, 0x80, 0, 0, 0, 0, 0, 0, 0});  // XL
    std::vector<uint8_t> big(8 + 65, 0);
    big[4] = 65;
    bad.WriteRecord(6, big);
    const Decoded read = ReadPcap(bad.bytes());
    EXPECT_EQ(read.frames.size(), 1u);  // the first: 0 bytes of data, the rest padding
    EXPECT_EQ(read.stats.malformed, 4u);
    EXPECT_EQ(read.stats.can_xl, 1u);
}

// Linux cooked captures (tcpdump -i any): SLL and SLL2 headers, the ID in host order.
std::vector<uint8_t> Sll(uint16_t protocol, const std::vector<uint8_t>& payload, bool v2) {
    std::vector<uint8_t> out;
    if (v2) {
        out = {static_cast<uint8_t>(protocol >> 8),
               static_cast<uint8_t>(protocol),
               0,
               0,
               0,
               0,
               0,
               3,  // interface index
               0x01,
               0x18,  // ARPHRD_CAN (280)
               0,
               0,
               0,
               0,
               0,
               0,
               0,
               0,
               0,
               0};
    } else {
        out = {0,
               0,
               0x01,
               0x18,
               0,
               0,
               0,
               0,
               0,
               0,
               0,
               0,
               0,
               0,
               static_cast<uint8_t>(protocol >> 8),
               static_cast<uint8_t>(protocol)};
    }
    out.insert(out.end(), payload.begin(), payload.end());
    return out;
}

TEST(CanPcap, LinuxCookedCaptures) {
    for (bool v2 : {false, true}) {
        SCOPED_TRACE(v2 ? "SLL2" : "SLL");
        PcapWriterConfig config;
        config.link_type = v2 ? kLinkTypeLinuxSll2 : kLinkTypeLinuxSll;
        PcapWriter writer(config);
        // struct can_frame, host (little-endian) order: 0x123, then 0x80000456 (extended).
        writer.WriteRecord(
            1,
            Sll(kSllProtocolCan, {0x23, 0x01, 0, 0, 2, 0, 0, 0, 0xAA, 0xBB, 0, 0, 0, 0, 0, 0}, v2));
        writer.WriteRecord(
            2, Sll(kSllProtocolCan, {0x56, 0x04, 0, 0x80, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0}, v2));
        std::vector<uint8_t> fd(72, 0);
        fd[0] = 0x11;
        fd[4] = 2;
        fd[5] = 0x01;
        fd[8] = 0xCC;
        writer.WriteRecord(3, Sll(kSllProtocolCanFd, fd, v2));
        writer.WriteRecord(4, Sll(0x0800, {0x45, 0, 0, 20}, v2));  // IPv4: not CAN
        writer.WriteRecord(5, Sll(kSllProtocolCanXl, std::vector<uint8_t>(20, 0), v2));
        writer.WriteRecord(6, std::vector<uint8_t>{0, 0, 1});  // shorter than the cooked header
        const Decoded read = ReadPcap(writer.bytes());
        ASSERT_EQ(read.frames.size(), 3u);
        EXPECT_EQ(read.frames[0].id, 0x123u);
        EXPECT_EQ(read.frames[0].len, 2);
        EXPECT_EQ(read.frames[0].data[1], 0xBB);
        EXPECT_TRUE(read.frames[1].extended);
        EXPECT_EQ(read.frames[1].id, 0x456u);
        EXPECT_TRUE(read.frames[2].fd);
        EXPECT_EQ(read.frames[2].id, 0x11u);
        EXPECT_EQ(read.frames[2].fd_flags, 1);
        EXPECT_EQ(read.frames[2].len, 2);
        EXPECT_EQ(read.frames[2].data[0], 0xCC);
        EXPECT_EQ(read.stats.not_can, 1u);
        EXPECT_EQ(read.stats.can_xl, 1u);
        EXPECT_EQ(read.stats.truncated, 1u);
        EXPECT_EQ(read.stats.little_endian_ids, 3u);
    }
}

TEST(CanPcap, OtherLinkTypesAreSkipped) {
    PcapWriter writer;  // Ethernet
    writer.WriteUdp(1, 0x7F000001, 1000, 0x7F000001, 2000, std::vector<uint8_t>(10, 1));
    const Decoded read = ReadPcap(writer.bytes());
    EXPECT_TRUE(read.frames.empty());
    EXPECT_EQ(read.stats.not_can, 1u);
    EXPECT_EQ(read.stats.records, 1u);
}

TEST(CanPcap, EncoderRefusesWhatCannotBeRead) {
    uint8_t out[kCanFdMtu];
    CanFrame f = Frame(0, 0x800, {});
    EXPECT_EQ(EncodeCanSocketcan(f, out), 0u);
    f.id = 0x7FF;
    EXPECT_EQ(EncodeCanSocketcan(f, out), kCanMtu);
    EXPECT_EQ(EncodeCanSocketcan(f, std::span<uint8_t>(out, 15)), 0u);
    f.error = true;
    f.id = 0x800;  // a valid SocketCAN error class word, but not one rule 1 would read back
    EXPECT_EQ(EncodeCanSocketcan(f, out), 0u);
    PcapWriterConfig config;
    config.link_type = kLinkTypeCanSocketcan;
    PcapWriter writer(config, "mem.pcap");
    try {
        WriteCanFrame(writer, f);
        ADD_FAILURE() << "no error";
    } catch (const common::Error& e) {
        EXPECT_EQ(e.code(), common::StatusCode::kInvalidArgument);
        EXPECT_NE(std::string(e.what()).find("mem.pcap"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("0x800"), std::string::npos) << e.what();
    }
    f = Frame(0, 0x1, std::vector<uint8_t>(9, 0));  // classic with 9 bytes
    EXPECT_THROW(WriteCanFrame(writer, f), common::Error);
}

TEST(CanPcap, GzipFileThroughThePath) {
    test::TempDir dir;
    const std::vector<CanFrame> frames = AllKinds();
    const std::string pcap = SwapIds(WritePcap(frames));
    const auto path = dir / "can.pcap.gz";
    gzFile gz = gzopen(path.c_str(), "wb");
    ASSERT_NE(gz, nullptr);
    gzwrite(gz, pcap.data(), static_cast<unsigned>(pcap.size()));
    gzclose(gz);
    CanPcapReader reader(path);
    CanFrame f;
    size_t i = 0;
    while (reader.Next(f)) {
        ASSERT_LT(i, frames.size());
        ExpectSame(f, frames[i++]);
    }
    EXPECT_EQ(i, frames.size());
    EXPECT_EQ(reader.decoder().socketcan_order(), CanIdOrder::kLittleEndian);
    EXPECT_FILE_ERROR(CanPcapReader(dir / "missing.pcap"), (dir / "missing.pcap").string(), 0);
}

TEST(CanPcap, ConfigValidation) {
    CanPcapConfig config;
    config.detect_records = 0;
    EXPECT_THROW(config.Validate(), common::Error);
    EXPECT_THROW(CanRecordDecoder{config}, common::Error);
}

TEST(CanPcap, MutatedCapturesDecodeOrFailCleanly) {
    const std::string be = WritePcap(AllKinds());
    std::vector<test::FuzzSeed> seeds = {{be, 128}, {SwapIds(be), 128}};
    size_t frames = 0;
    const auto counts = test::FuzzReader(
        "fuzz.pcap", seeds, 3000, 5, test::kMutationBytes, [&](const std::string& bytes) {
            CanPcapReader reader = CanPcapReader::FromMemory("fuzz.pcap", test::AsBytes(bytes));
            CanFrame f;
            while (reader.Next(f)) {
                ++frames;
                // Every decoded frame encodes, and decodes back to itself.
                ASSERT_EQ(common::CanFrameProblem(f), nullptr);
                uint8_t out[kCanFdMtu];
                const size_t n = EncodeCanSocketcan(f, out);
                ASSERT_GT(n, 0u);
                PcapRecord r;
                r.link_type = kLinkTypeCanSocketcan;
                r.timestamp_ns = f.timestamp_ns;
                r.data = std::span<const uint8_t>(out, n);
                r.original_length = static_cast<uint32_t>(n);
                CanPcapConfig fixed;
                fixed.id_order = CanIdOrder::kBigEndian;
                CanRecordDecoder decoder(fixed);
                CanFrame again;
                ASSERT_EQ(decoder.Decode(r, again), CanDecodeResult::kFrame);
                ExpectSame(again, f);
            }
        });
    EXPECT_GT(counts.accepted, 100u);
    EXPECT_GT(frames, 10000u);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::net
