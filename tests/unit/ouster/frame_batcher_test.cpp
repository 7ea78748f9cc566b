// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "drivers/ouster/frame_batcher.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "tests/support/ouster_fixtures.hpp"

namespace bimslam::ouster {
namespace {
namespace BIMSLAM_UNITY_ID {
using Packets = std::vector<std::vector<uint8_t>>;

// Feeds packets; returns copies of every frame emitted (Flush at the end).
std::vector<LidarFrame> Feed(FrameBatcher& b, const Packets& packets, bool flush = true) {
    std::vector<LidarFrame> out;
    for (const auto& p : packets) {
        b.AddPacket(p.data(), p.size());
        for (const LidarFrame* f : b.ready()) out.push_back(*f);
    }
    if (flush) {
        b.Flush();
        for (const LidarFrame* f : b.ready()) out.push_back(*f);
    }
    return out;
}

void ExpectSameFields(const LidarFrame& a, const LidarFrame& b, int first_col = 0,
                      int last_col = -1) {
    if (last_col < 0) last_col = a.w - 1;
    for (int f = 0; f < kNumFields; ++f) {
        const Field field = static_cast<Field>(f);
        const void* pa = a.FieldData(field);
        const void* pb = b.FieldData(field);
        ASSERT_EQ(pa == nullptr, pb == nullptr) << ToString(field);
        if (!pa) continue;
        const size_t bytes = TypeOf(field) == FieldType::kU32   ? 4
                             : TypeOf(field) == FieldType::kU16 ? 2
                                                                : 1;
        for (int u = 0; u < a.h; ++u) {
            const size_t off = a.Index(u, first_col) * bytes;
            const size_t len = size_t(last_col - first_col + 1) * bytes;
            ASSERT_EQ(0, std::memcmp(static_cast<const uint8_t*>(pa) + off,
                                     static_cast<const uint8_t*>(pb) + off, len))
                << ToString(field) << " row " << u;
        }
    }
}

class EveryProfile : public ::testing::TestWithParam<LidarProfile> {};

TEST_P(EveryProfile, EncodedFrameDecodesIdenticallyAndEmitsAtItsLastPacket) {
    const SensorInfo info = fixtures::MakeSensor(GetParam());
    const PacketEncoder enc(info, /*fill_crc=*/true);
    const LidarFrame truth = fixtures::MakeFrame(enc.format(), 77, 1);
    const Packets packets = fixtures::Encode(enc, truth);
    FrameBatcher b(info);
    for (size_t i = 0; i + 1 < packets.size(); ++i) {
        EXPECT_EQ(b.AddPacket(packets[i].data(), packets[i].size()).frames, 0);
    }
    const PacketResult last = b.AddPacket(packets.back().data(), packets.back().size());
    ASSERT_EQ(last.frames, 1);  // no need to wait for the next frame
    const LidarFrame& f = *b.ready()[0];
    EXPECT_TRUE(f.complete);
    EXPECT_EQ(f.frame_id, 77u);
    EXPECT_EQ(f.packets, 64);
    EXPECT_EQ(f.timestamp, truth.timestamp);
    EXPECT_EQ(f.status, truth.status);
    EXPECT_EQ(f.start_ns, truth.timestamp[0]);
    ExpectSameFields(f, truth);
    EXPECT_EQ(b.stats().frames_complete, 1u);
    EXPECT_EQ(b.stats().TotalRejected(), 0u);
    EXPECT_EQ(b.stats().crc_checked, GetParam() == LidarProfile::kLegacy ? 0u : 64u);
    if (GetParam() == LidarProfile::kLegacy) {
        EXPECT_EQ(f.encoder[512], 512u * 90112 / 1024);
        EXPECT_EQ(f.column_frame_id[3], 77);
    }
}

INSTANTIATE_TEST_SUITE_P(Profiles, EveryProfile, ::testing::ValuesIn(fixtures::kAllProfiles));

TEST(FrameBatcher, FusaHeaderWith32BitFrameIds) {
    const SensorInfo info =
        fixtures::MakeSensor(LidarProfile::kFusaRng15Rfl8Nir8Dual, 32, 1024, HeaderType::kFusa);
    const PacketEncoder enc(info);
    Packets packets = fixtures::Encode(enc, fixtures::MakeFrame(enc.format(), 0xFFFFFFFFu, 1));
    const Packets next = fixtures::Encode(enc, fixtures::MakeFrame(enc.format(), 0, 2));
    packets.insert(packets.end(), next.begin(), next.end());
    FrameBatcher b(info);
    const auto frames = Feed(b, packets);
    ASSERT_EQ(frames.size(), 2u);
    EXPECT_EQ(frames[0].frame_id, 0xFFFFFFFFu);
    EXPECT_EQ(frames[1].frame_id, 0u);  // 0 follows 2^32 - 1
    EXPECT_EQ(b.stats().frames_complete, 2u);
}

struct Capture {
    SensorInfo info;
    std::vector<LidarFrame> truth;
    Packets packets;
};

// n consecutive frames starting at frame id `first`.
Capture MakeCapture(LidarProfile profile, int n, uint32_t first) {
    Capture c;
    c.info = fixtures::MakeSensor(profile);
    const PacketEncoder enc(c.info);
    for (int i = 0; i < n; ++i) {
        c.truth.push_back(fixtures::MakeFrame(enc.format(), (first + i) & 0xFFFF, 10 + i));
        const Packets p = fixtures::Encode(enc, c.truth.back());
        c.packets.insert(c.packets.end(), p.begin(), p.end());
    }
    return c;
}

TEST(FrameBatcher, DroppedPacketsGiveIncompleteFramesWithZeroedInvalidColumns) {
    Capture c = MakeCapture(LidarProfile::kRng19Rfl8Sig16Nir16, 3, 100);
    std::mt19937 rng(4);
    Packets kept;
    std::vector<int> dropped_per_frame(3, 0);
    for (size_t i = 0; i < c.packets.size(); ++i) {
        // Drop 10 % of packets, never the first of a frame (it would not change the counts).
        if (i % 64 != 0 && rng() % 10 == 0) {
            ++dropped_per_frame[i / 64];
            continue;
        }
        kept.push_back(c.packets[i]);
    }
    FrameBatcher b(c.info);
    const auto frames = Feed(b, kept);
    ASSERT_EQ(frames.size(), 3u);
    int lost = 0;
    for (int k = 0; k < 3; ++k) {
        const LidarFrame& f = frames[k];
        EXPECT_EQ(f.complete, dropped_per_frame[k] == 0);
        EXPECT_EQ(f.columns_received, 1024 - 16 * dropped_per_frame[k]);
        lost += 16 * dropped_per_frame[k];
        for (int v = 0; v < 1024; ++v) {
            const bool arrived = f.ColumnValid(v);
            for (int u = 0; u < f.h; ++u) {
                const size_t i = f.Index(u, v);
                ASSERT_EQ(f.range[i], arrived ? c.truth[k].range[i] : 0u);
            }
            if (!arrived) {
                ASSERT_EQ(f.timestamp[v], 0u);
            }
        }
    }
    EXPECT_EQ(b.stats().columns_lost, uint64_t(lost));
    EXPECT_EQ(b.stats().frames_incomplete + b.stats().frames_complete, 3u);
}

TEST(FrameBatcher, ReorderingWithinAFrameAndDuplicatesAreHarmless) {
    Capture c = MakeCapture(LidarProfile::kLegacy, 2, 7);
    Packets shuffled;
    for (size_t i = 0; i < c.packets.size(); i += 2) {  // swap neighbours
        shuffled.push_back(c.packets[i + 1]);
        shuffled.push_back(c.packets[i]);
        if (i % 10 == 0) shuffled.push_back(c.packets[i]);  // and duplicate some
    }
    FrameBatcher b(c.info);
    const auto frames = Feed(b, shuffled);
    ASSERT_EQ(frames.size(), 2u);
    for (int k = 0; k < 2; ++k) {
        EXPECT_TRUE(frames[k].complete);
        ExpectSameFields(frames[k], c.truth[k]);
    }
    // Duplicates of the first frame's packets that arrive after it was emitted are late.
    EXPECT_EQ(b.stats().Rejected(Reject::kDuplicate) + b.stats().Rejected(Reject::kLate), 13u);
    EXPECT_EQ(b.stats().accepted, 128u);
}

TEST(FrameBatcher, LatePacketsOfAnOlderFrameAreDroppedAndCounted) {
    Capture c = MakeCapture(LidarProfile::kRng15Rfl8Nir8, 2, 50);
    Packets p(c.packets.begin(), c.packets.begin() + 60);  // frame 50 without 4 packets
    p.insert(p.end(), c.packets.begin() + 64, c.packets.begin() + 70);  // frame 51 starts
    p.insert(p.end(), c.packets.begin() + 60, c.packets.begin() + 64);  // frame 50's stragglers
    p.insert(p.end(), c.packets.begin() + 70, c.packets.end());
    FrameBatcher b(c.info);
    const auto frames = Feed(b, p);
    ASSERT_EQ(frames.size(), 2u);
    EXPECT_FALSE(frames[0].complete);
    EXPECT_TRUE(frames[1].complete);
    EXPECT_EQ(b.stats().Rejected(Reject::kLate), 4u);
    EXPECT_EQ(b.stats().columns_lost, 64u);
}

TEST(FrameBatcher, FrameIdWrapsAt65535) {
    Capture c = MakeCapture(LidarProfile::kRng19Rfl8Sig16Nir16Dual, 4, 65534);
    FrameBatcher b(c.info);
    const auto frames = Feed(b, c.packets);
    ASSERT_EQ(frames.size(), 4u);
    const uint32_t ids[] = {65534, 65535, 0, 1};
    for (int k = 0; k < 4; ++k) {
        EXPECT_EQ(frames[k].frame_id, ids[k]);
        EXPECT_TRUE(frames[k].complete);
    }
    EXPECT_EQ(b.stats().TotalRejected(), 0u);
}

TEST(FrameBatcher, ColumnWindowsIncludingOnesThatWrap) {
    for (const auto& [first, last] : {std::pair{256, 511}, std::pair{896, 127}}) {
        SensorInfo info = fixtures::MakeSensor(LidarProfile::kRng19Rfl8Sig16Nir16);
        info.format.column_window_first = first;
        info.format.column_window_last = last;
        const PacketEncoder enc(info);
        LidarFrame truth = fixtures::MakeFrame(enc.format(), 9, 3);
        for (int v = 0; v < 1024; ++v) {
            if (!info.format.InWindow(v)) truth.status[v] = 0;  // the sensor marks them invalid
        }
        // The sensor sends only the packets of the window, starting at its first column.
        Packets packets;
        const Packets all = fixtures::Encode(enc, truth);
        for (int k = 0; k < 64; ++k) {
            const int pk = (first / 16 + k) % 64;
            if (info.format.InWindow(pk * 16)) packets.push_back(all[pk]);
        }
        FrameBatcher b(info);
        std::vector<LidarFrame> frames;
        for (size_t i = 0; i < packets.size(); ++i) {
            const auto r = b.AddPacket(packets[i].data(), packets[i].size());
            EXPECT_EQ(r.frames, i + 1 == packets.size() ? 1 : 0) << first;
            for (const LidarFrame* f : b.ready()) frames.push_back(*f);
        }
        ASSERT_EQ(frames.size(), 1u);
        EXPECT_TRUE(frames[0].complete);
        EXPECT_EQ(frames[0].columns_expected, 256);
        uint64_t earliest = ~0ull;
        for (int v = 0; v < 1024; ++v) {
            if (info.format.InWindow(v)) earliest = std::min(earliest, truth.timestamp[v]);
        }
        EXPECT_EQ(frames[0].start_ns, earliest);
        for (int v = 0; v < 1024; ++v) {
            EXPECT_EQ(frames[0].ColumnValid(v), info.format.InWindow(v));
            EXPECT_EQ(frames[0].range[frames[0].Index(5, v)],
                      info.format.InWindow(v) ? truth.range[truth.Index(5, v)] : 0u);
        }
    }
}

TEST(FrameBatcher, ValidatesEveryPacketAndCountsEachCause) {
    SensorInfo info = fixtures::MakeSensor(LidarProfile::kRng19Rfl8Sig16Nir16);
    const PacketEncoder enc(info, /*fill_crc=*/true);
    const Packets good = fixtures::Encode(enc, fixtures::MakeFrame(enc.format(), 3, 1));
    FrameBatcher b(info);
    auto expect = [&](std::vector<uint8_t> p, Reject cause) {
        const auto r = b.AddPacket(p.data(), p.size());
        ASSERT_TRUE(r.rejected.has_value()) << ToString(cause);
        EXPECT_EQ(*r.rejected, cause);
    };
    expect(std::vector<uint8_t>(good[0].begin(), good[0].end() - 1), Reject::kSize);
    expect(std::vector<uint8_t>(100, 0), Reject::kSize);
    auto p = good[0];
    p[0] = 2;  // an IMU packet type
    expect(p, Reject::kPacketType);
    p = good[0];
    p[8] ^= 1;  // prod_sn
    expect(p, Reject::kProdSn);
    p = good[0];
    p[5] ^= 1;  // init_id
    expect(p, Reject::kInitId);
    p = good[0];
    p[500] ^= 0x10;  // a pixel bit: only the CRC tells
    expect(p, Reject::kCrc);
    SensorInfo no_crc = info;
    FrameBatcher unchecked(no_crc, {.check_crc = false});
    EXPECT_FALSE(unchecked.AddPacket(p.data(), p.size()).rejected.has_value());
    p = good[1];
    p[32 + 8] = 0xFF;  // measurement id 0xFFxx of column 0
    p[32 + 9] = 0xFF;
    std::fill(p.end() - 8, p.end(), uint8_t{0});  // no CRC, so the id is what is wrong
    expect(p, Reject::kMeasurementId);
    const LidarStats& s = b.stats();
    EXPECT_EQ(s.Rejected(Reject::kSize), 2u);
    for (Reject r : {Reject::kPacketType, Reject::kProdSn, Reject::kInitId, Reject::kCrc,
                     Reject::kMeasurementId}) {
        EXPECT_EQ(s.Rejected(r), 1u) << ToString(r);
    }
    EXPECT_EQ(s.packets, 7u);
    EXPECT_EQ(s.accepted, 0u);
}

TEST(FrameBatcher, InitIdChangeClosesTheFrameAndResets) {
    SensorInfo info = fixtures::MakeSensor(LidarProfile::kRng19Rfl8Sig16Nir16);
    SensorInfo restarted = info;
    restarted.init_id = 999;
    const PacketEncoder enc_a(info), enc_b(restarted);
    Packets packets = fixtures::Encode(enc_a, fixtures::MakeFrame(enc_a.format(), 400, 1));
    packets.resize(30);  // the sensor restarts mid-frame ...
    const Packets after = fixtures::Encode(enc_b, fixtures::MakeFrame(enc_b.format(), 2, 2));
    packets.insert(packets.end(), after.begin(), after.end());  // ... with a lower frame id
    SensorInfo unknown_init = info;
    unknown_init.init_id = 0;  // metadata without init_id: restarts are followed
    FrameBatcher b(unknown_init);
    const auto frames = Feed(b, packets);
    ASSERT_EQ(frames.size(), 2u);
    EXPECT_FALSE(frames[0].complete);
    EXPECT_TRUE(frames[1].complete);
    EXPECT_EQ(frames[1].init_id, 999u);
    EXPECT_EQ(b.stats().sensor_restarts, 1u);
    EXPECT_EQ(b.stats().Rejected(Reject::kLate), 0u);
    // With the metadata's init_id the restarted sensor's packets are rejected instead.
    FrameBatcher strict(info);
    Feed(strict, packets);
    EXPECT_EQ(strict.stats().Rejected(Reject::kInitId), 64u);
}

TEST(FrameBatcher, PointCloudHasRingTimeAndOnlyReturns) {
    const SensorInfo info = fixtures::MakeSensor(LidarProfile::kLegacy);
    const PacketEncoder enc(info);
    LidarFrame truth = fixtures::MakeFrame(enc.format(), 1, 5);
    size_t returns = 0;
    for (auto& r : truth.range) {
        r = (r % 3 == 0) ? 0 : r % 50000;
        returns += r != 0;
    }
    FrameBatcher b(info);
    Feed(b, fixtures::Encode(enc, truth), false);
    ASSERT_EQ(b.ready().size(), 1u);
    common::PointCloud cloud;
    ToPointCloud(*b.ready()[0], &cloud);
    EXPECT_EQ(cloud.size(), returns);
    ASSERT_TRUE(cloud.ChannelsConsistent());
    EXPECT_EQ(cloud.stamp.ns, int64_t(truth.timestamp[0]));
    EXPECT_EQ(cloud.time_offset_ns.back(), truth.timestamp[1023] - truth.timestamp[0]);
    EXPECT_LT(*std::max_element(cloud.ring.begin(), cloud.ring.end()), 32);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::ouster

namespace bimslam::ouster {
namespace {
namespace BIMSLAM_UNITY_ID {

TEST(FrameBatcher, Fw2FootersAreNoCrc) {
    // FW 2.3 puts a constant marker in the footer (see PacketFormat::HasCrcFooter).
    SensorInfo info = fixtures::MakeSensor(LidarProfile::kRng19Rfl8Sig16Nir16);
    info.build_rev = "v2.3.0";
    info.fw_major = 2;
    const PacketEncoder enc(info);
    auto packets = fixtures::Encode(enc, fixtures::MakeFrame(enc.format(), 5, 1));
    const uint8_t marker[] = {0xde, 0xc0, 0, 0, 0xef, 0xbe, 0xad, 0xde};
    for (auto& p : packets) std::copy(marker, marker + 8, p.end() - 8);
    FrameBatcher b(info);
    for (const auto& p : packets) b.AddPacket(p.data(), p.size());
    EXPECT_EQ(b.stats().frames_complete, 1u);
    EXPECT_EQ(b.stats().crc_checked, 0u);
    EXPECT_EQ(b.stats().TotalRejected(), 0u);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::ouster

namespace bimslam::ouster {
namespace {
namespace BIMSLAM_UNITY_ID {

TEST(FrameBatcher, ResetForgetsEverything) {
    const SensorInfo info = fixtures::MakeSensor(LidarProfile::kRng15Rfl8Nir8);
    const PacketEncoder enc(info);
    auto packets = fixtures::Encode(enc, fixtures::MakeFrame(enc.format(), 9, 1));
    FrameBatcher b(info);
    for (size_t i = 0; i < 40; ++i) b.AddPacket(packets[i].data(), packets[i].size());
    b.Reset();
    EXPECT_EQ(b.stats().packets, 0u);
    EXPECT_EQ(b.Flush(), 0);  // nothing held
    // Frame 9 again is not "late" after a reset.
    for (const auto& p : packets) b.AddPacket(p.data(), p.size());
    EXPECT_EQ(b.stats().frames_complete, 1u);
    EXPECT_EQ(b.stats().TotalRejected(), 0u);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::ouster
