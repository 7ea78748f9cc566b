// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// drivers/net on the real captures of ../shared/data (see its README.md): Ouster recordings
// (Ethernet, loopback addresses, not fragmented), a Velodyne packet, a header-only file, and a
// SocketCAN capture (link type 227, gzip) whose records must come out untouched.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "drivers/net/ipv4.hpp"
#include "drivers/net/pcap_reader.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::net {
namespace {
namespace BIMSLAM_UNITY_ID {

struct Expected {
    size_t lidar_datagrams = 0;  // on port 7502
    size_t lidar_bytes = 0;
    size_t imu_datagrams = 0;  // 48 B on port 7503
};

// Datagram counts per (destination port, payload size) of a whole capture.
struct Summary {
    std::map<std::pair<uint16_t, size_t>, size_t> datagrams;
    uint64_t records = 0;
    ExtractorStats stats;
    bool truncated = false;
};

Summary Summarize(const std::filesystem::path& path) {
    PcapReader reader(path);
    UdpExtractor extractor;
    Summary s;
    PcapRecord r;
    UdpDatagram d;
    while (reader.Next(r)) {
        EXPECT_EQ(r.link_type, kLinkTypeEthernet) << path;
        if (extractor.Feed(r, d)) ++s.datagrams[{d.dst_port, d.payload.size()}];
    }
    extractor.Finish();
    s.records = reader.records();
    s.stats = extractor.stats();
    s.truncated = reader.truncated();
    return s;
}

TEST(NetData, EveryOusterCapture) {
    BIMSLAM_REQUIRE_SHARED_DATA(dir, "ouster");
    const std::map<std::string, Expected> expected = {
        {"OS-1-32-G_v2.1.1_1024x10.pcap", {64, 6464, 0}},
        {"OS-0-32-U1_v2.2.0_1024x10.pcap", {64, 8448, 10}},
        {"OS-2-128-U1_v2.3.0_1024x10.pcap", {64, 24832, 10}},
        {"OS-0-128-U1_v2.3.0_1024x10.pcap", {64, 8448, 10}},
        {"OS-0-32-U1_v2.2.0_1024x10-single-packet.pcap", {1, 8448, 0}},
    };
    size_t seen = 0;
    std::vector<std::filesystem::path> files;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
        if (entry.path().extension() == ".pcap") files.push_back(entry.path());
    }
    std::sort(files.begin(), files.end());
    for (const auto& path : files) {
        const std::string name = path.filename().string();
        SCOPED_TRACE(name);
        const Summary s = Summarize(path);
        EXPECT_FALSE(s.truncated);
        EXPECT_EQ(s.stats.ip_bad_checksum, 0u);
        EXPECT_EQ(s.stats.ip_truncated, 0u);
        EXPECT_EQ(s.stats.udp_bad_length, 0u);
        EXPECT_EQ(s.stats.fragments, 0u);  // loopback captures: not fragmented
        if (name == "empty_pcap.pcap") {
            EXPECT_EQ(s.records, 0u);
            EXPECT_TRUE(s.datagrams.empty());
            ++seen;
            continue;
        }
        if (name == "VLI-16-one-packet.pcap") {
            ASSERT_EQ(s.datagrams.size(), 1u);
            EXPECT_EQ(s.datagrams.begin()->first.first, 2368);
            EXPECT_EQ(s.datagrams.begin()->second, 1u);
            ++seen;
            continue;
        }
        const auto it = expected.find(name);
        if (it == expected.end()) {
            ADD_FAILURE() << "a capture this test does not know: " << name;
            continue;
        }
        ++seen;
        const Expected& e = it->second;
        std::map<std::pair<uint16_t, size_t>, size_t> want = {
            {{7502, e.lidar_bytes}, e.lidar_datagrams}};
        if (e.imu_datagrams > 0) want[{7503, 48}] = e.imu_datagrams;
        EXPECT_EQ(s.datagrams, want);
        EXPECT_EQ(s.stats.datagrams, e.lidar_datagrams + e.imu_datagrams);
        EXPECT_EQ(s.records, s.stats.datagrams);  // nothing but the sensor's traffic

        // The ports, guessed from the payload sizes alone.
        const PortGuess guess = GuessPortsInCapture(path, e.lidar_bytes, 48);
        EXPECT_EQ(guess.lidar_port, 7502);
        EXPECT_EQ(guess.lidar_datagrams, e.lidar_datagrams);
        if (e.imu_datagrams > 0) {
            EXPECT_EQ(guess.imu_port, 7503);
            EXPECT_EQ(guess.imu_datagrams, e.imu_datagrams);
        } else {
            EXPECT_FALSE(guess.imu_port);
        }
    }
    EXPECT_EQ(seen, expected.size() + 2);
}

TEST(NetData, SocketCanCaptureRecordsComeOutUntouched) {
    BIMSLAM_REQUIRE_SHARED_DATA(path, "can/gmlan_trace.pcap.gz");
    PcapReader reader(path);
    EXPECT_EQ(reader.format(), PcapFormat::kPcap);
    EXPECT_EQ(reader.link_type(), kLinkTypeCanSocketcan);
    UdpExtractor extractor;
    PcapRecord r;
    UdpDatagram d;
    size_t records = 0;
    while (reader.Next(r)) {
        ASSERT_EQ(r.link_type, kLinkTypeCanSocketcan);
        // 8-byte header (ID, length, padding), then `length` data bytes (classic CAN: <= 8).
        ASSERT_GE(r.data.size(), 8u) << r.index;
        EXPECT_LE(r.data[4], 8) << r.index;
        EXPECT_EQ(r.data.size(), 8u + r.data[4]) << r.index;
        if (records == 0) {
            // candump: (0.297000) vcan2 12A#122010FF00001080; this file stores the ID
            // little-endian (../shared/data/README.md).
            EXPECT_EQ(r.timestamp_ns, 297'000'000);
            const std::vector<uint8_t> bytes(r.data.begin(), r.data.end());
            const std::vector<uint8_t> want = {0x2A, 0x01, 0x00, 0x00, 0x08, 0x00, 0x00, 0x00,
                                               0x12, 0x20, 0x10, 0xFF, 0x00, 0x00, 0x10, 0x80};
            EXPECT_EQ(bytes, want);
        }
        EXPECT_FALSE(extractor.Feed(r, d));
        ++records;
    }
    EXPECT_FALSE(reader.truncated());
    EXPECT_EQ(records, 1087u);  // one per line of gmlan_trace.candump.gz
    EXPECT_EQ(extractor.stats().unsupported_link_type, records);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::net
