// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The SocketCAN recordings of ../shared/data/can (see its README.md): the same frames of a real
// car's bus as a pcap of link type 227 whose CAN IDs are stored little-endian (against the
// standard) and as a candump log; both gzip-compressed.
#include <gtest/gtest.h>
#include <zlib.h>

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "algorithms/common/can_frame.hpp"
#include "drivers/can/candump.hpp"
#include "drivers/net/can_pcap.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam {
namespace {
namespace BIMSLAM_UNITY_ID {

using common::CanFrame;

constexpr size_t kFrames = 1087;  // records in the pcap, lines in the log

std::vector<CanFrame> ReadCandump(const std::filesystem::path& path,
                                  std::vector<std::string>* interfaces = nullptr) {
    can::CandumpReader reader(path);  // strict: every line must parse
    std::vector<CanFrame> frames;
    can::CandumpRecord r;
    while (reader.Next(r)) {
        frames.push_back(r.frame);
        if (interfaces != nullptr) interfaces->emplace_back(r.interface_name);
    }
    EXPECT_FALSE(reader.truncated());
    EXPECT_EQ(reader.stats().skipped_lines(), 0u);
    EXPECT_EQ(reader.stats().lines, kFrames);
    return frames;
}

std::string Gunzip(const std::filesystem::path& path) {
    gzFile gz = gzopen(path.c_str(), "rb");
    EXPECT_NE(gz, nullptr) << path;
    std::string out;
    char buffer[65536];
    int n = 0;
    while (gz != nullptr && (n = gzread(gz, buffer, sizeof(buffer))) > 0) out.append(buffer, n);
    if (gz != nullptr) gzclose(gz);
    return out;
}

TEST(CanData, CandumpLogParsesAndWritesBackIdentically) {
    BIMSLAM_REQUIRE_SHARED_DATA(path, "can/gmlan_trace.candump.gz");
    std::vector<std::string> interfaces;
    const std::vector<CanFrame> frames = ReadCandump(path, &interfaces);
    ASSERT_EQ(frames.size(), kFrames);
    for (const std::string& name : interfaces) EXPECT_EQ(name, "vcan2");
    // The log has unpadded seconds (candump pads them to 10 digits): written so, it is identical.
    can::CandumpWriterConfig config;
    config.seconds_width = 1;
    can::CandumpWriter writer(config);
    for (size_t i = 0; i < frames.size(); ++i) writer.Write(frames[i], interfaces[i]);
    EXPECT_EQ(writer.text(), Gunzip(path));
}

TEST(CanData, PcapParsesWithLittleEndianIdsDetected) {
    BIMSLAM_REQUIRE_SHARED_DATA(path, "can/gmlan_trace.pcap.gz");
    net::CanPcapReader reader(path);
    std::vector<CanFrame> frames;
    CanFrame f;
    while (reader.Next(f)) frames.push_back(f);
    EXPECT_EQ(frames.size(), kFrames);
    EXPECT_EQ(reader.pcap().records(), kFrames);
    EXPECT_EQ(reader.pcap().link_type(), net::kLinkTypeCanSocketcan);
    EXPECT_EQ(reader.decoder().socketcan_order(), net::CanIdOrder::kLittleEndian);
    const net::CanPcapStats& s = reader.stats();
    EXPECT_EQ(s.frames, kFrames);
    EXPECT_EQ(s.little_endian_ids, kFrames);
    EXPECT_EQ(s.order_disagreements, 0u);
    EXPECT_EQ(s.implausible_id, 0u);
    EXPECT_EQ(s.not_can + s.truncated + s.malformed + s.can_xl, 0u);
    for (const CanFrame& frame : frames) {
        EXPECT_FALSE(frame.extended);
        EXPECT_LE(frame.id, 0x7FFu);
    }
}

TEST(CanData, PcapAndCandumpHoldTheSameFrames) {
    BIMSLAM_REQUIRE_SHARED_DATA(log_path, "can/gmlan_trace.candump.gz");
    BIMSLAM_REQUIRE_SHARED_DATA(pcap_path, "can/gmlan_trace.pcap.gz");
    const std::vector<CanFrame> logged = ReadCandump(log_path);
    net::CanPcapReader reader(pcap_path);
    std::vector<CanFrame> captured;
    CanFrame f;
    while (reader.Next(f)) captured.push_back(f);
    ASSERT_EQ(logged.size(), kFrames);
    ASSERT_EQ(captured.size(), kFrames);

    std::map<uint32_t, size_t> logged_ids;
    std::map<uint32_t, size_t> captured_ids;
    for (const CanFrame& x : logged) ++logged_ids[x.id];
    for (const CanFrame& x : captured) ++captured_ids[x.id];
    EXPECT_EQ(logged_ids, captured_ids);
    EXPECT_GT(logged_ids.size(), 10u);

    size_t mismatches = 0;
    for (size_t i = 0; i < kFrames; ++i) {
        const CanFrame& a = logged[i];
        const CanFrame& b = captured[i];
        const bool same = a.id == b.id && a.len == b.len && a.data == b.data &&
                          a.timestamp_ns == b.timestamp_ns && a.extended == b.extended &&
                          a.remote == b.remote && a.error == b.error && a.fd == b.fd;
        if (!same && ++mismatches <= 5) {
            ADD_FAILURE() << "frame " << i << ": log id 0x" << std::hex << a.id << " len "
                          << std::dec << int{a.len} << " t " << a.timestamp_ns << ", pcap id 0x"
                          << std::hex << b.id << " len " << std::dec << int{b.len} << " t "
                          << b.timestamp_ns;
        }
    }
    EXPECT_EQ(mismatches, 0u);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam
