// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The Ouster driver on the real recordings of ../shared/data/ouster (label `data`): the SDK's
// md5 digests reproduced bit for bit, and faults injected into the real packets.
#include "host_tools/capture/ouster_capture.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <random>

#include "drivers/net/ipv4.hpp"
#include "drivers/net/pcap_reader.hpp"
#include "drivers/net/pcap_writer.hpp"
#include "drivers/ouster/frame_batcher.hpp"
#include "drivers/ouster/metadata.hpp"
#include "tests/support/md5.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::ouster {
namespace {
namespace BIMSLAM_UNITY_ID {
namespace fs = std::filesystem;
using Packets = std::vector<std::vector<uint8_t>>;

const char* kCaptures[] = {"OS-1-32-G_v2.1.1_1024x10", "OS-0-32-U1_v2.2.0_1024x10",
                           "OS-2-128-U1_v2.3.0_1024x10", "OS-0-128-U1_v2.3.0_1024x10"};

struct Recording {
    SensorInfo info;
    nlohmann::json digest;
    Packets lidar;  // payloads on the lidar port, in file order
    Packets imu;
};

Recording Load(const fs::path& dir, const std::string& name) {
    Recording r;
    r.info = LoadMetadata(dir / (name + ".json"));
    std::ifstream(dir / (name + "_digest.json")) >> r.digest;
    net::PcapReader reader(dir / (name + ".pcap"));
    net::UdpExtractor extractor;
    net::PcapRecord record;
    net::UdpDatagram d;
    while (reader.Next(record)) {
        if (!extractor.Feed(record, d)) continue;
        auto& dst = d.dst_port == 7502 ? r.lidar : r.imu;
        dst.emplace_back(d.payload.begin(), d.payload.end());
    }
    return r;
}

template <typename T>
void Add(test::Md5& md5, T value) {
    md5.Update(&value, sizeof(value));
}

// Every key of "packet_hash": per packet, fields as pixels_per_column x columns_per_packet arrays
// in C order of the SDK dtype, and the per-column header arrays.
void ExpectPacketDigests(const Recording& r) {
    const PacketFormat f(r.info);
    std::map<std::string, test::Md5> md5;
    const int h = f.pixels_per_column(), cpp = f.columns_per_packet();
    for (const auto& packet : r.lidar) {
        const uint8_t* p = packet.data();
        for (int c = 0; c < cpp; ++c) {
            const uint8_t* col = f.Column(p, c);
            Add(md5["TIMESTAMP"], f.ColumnTimestamp(col));
            Add(md5["MEASUREMENT_ID"], f.MeasurementId(col));
            Add(md5["STATUS"], f.ColumnStatus(col));
            Add(md5["FRAME_ID"], f.ColumnFrameId(col));
            Add(md5["ENCODER_COUNT"], f.EncoderCount(col));
        }
        for (int u = 0; u < h; ++u) {
            for (int c = 0; c < cpp; ++c) {
                const uint8_t* px = f.Pixels(f.Column(p, c)) + u * f.pixel_size();
                for (const FieldSpec& s : f.fields()) {
                    const uint32_t v =
                        ((Load32(px + 4 * s.word) >> s.shift) & s.mask) * s.multiplier;
                    test::Md5& m = md5[std::string(ToString(s.field))];
                    switch (TypeOf(s.field)) {
                        case FieldType::kU32:
                            Add(m, v);
                            break;
                        case FieldType::kU16:
                            Add(m, uint16_t(v));
                            break;
                        case FieldType::kU8:
                            Add(m, uint8_t(v));
                            break;
                    }
                }
                for (size_t k = 0; k < f.pixel_size() / 4; ++k) {
                    Add(md5["RAW32_WORD" + std::to_string(k + 1)], Load32(px + 4 * k));
                }
            }
        }
    }
    const auto& expected = r.digest.at("packet_hash");
    for (const auto& [key, value] : expected.items()) {
        ASSERT_TRUE(md5.count(key)) << key << " not decoded";
        EXPECT_EQ(md5[key].HexDigest(), value.get<std::string>()) << key;
    }
}

// Every key of "scans"[0]: staggered H x W field images, headers as the SDK's LidarScan holds
// them (TIMESTAMP, STATUS and ENCODER_COUNT as uint64, MEASUREMENT_ID as uint16).
void ExpectFrameDigests(const LidarFrame& frame, const nlohmann::json& scan) {
    EXPECT_EQ(std::to_string(frame.frame_id), scan.at("FRAME_ID").get<std::string>());
    const size_t w = frame.w, n = size_t(frame.h) * frame.w;
    auto u64 = [&](auto get) {
        std::vector<uint64_t> v(w);
        for (size_t i = 0; i < w; ++i) v[i] = get(i);
        return test::Md5Hex(v.data(), v.size() * 8);
    };
    for (const auto& [key, value] : scan.items()) {
        std::string got;
        if (key == "FRAME_ID") continue;
        if (key == "TIMESTAMP")
            got = u64([&](size_t i) { return frame.timestamp[i]; });
        else if (key == "STATUS")
            got = u64([&](size_t i) { return frame.status[i]; });
        else if (key == "ENCODER_COUNT")
            got = u64([&](size_t i) { return frame.encoder.empty() ? 0 : frame.encoder[i]; });
        else if (key == "MEASUREMENT_ID")
            got = test::Md5Hex(frame.measurement_id.data(), w * 2);
        else {
            bool found = false;
            for (int k = 0; k < kNumFields; ++k) {
                const auto field = static_cast<Field>(k);
                if (ToString(field) != key || !frame.FieldData(field)) continue;
                const size_t bytes = TypeOf(field) == FieldType::kU32   ? 4
                                     : TypeOf(field) == FieldType::kU16 ? 2
                                                                        : 1;
                got = test::Md5Hex(frame.FieldData(field), n * bytes);
                found = true;
            }
            ASSERT_TRUE(found) << key;
        }
        EXPECT_EQ(got, value.get<std::string>()) << key;
    }
}

std::vector<LidarFrame> Batch(const SensorInfo& info, const Packets& packets, FrameBatcher** out) {
    static std::unique_ptr<FrameBatcher> keep;
    keep = std::make_unique<FrameBatcher>(info);
    std::vector<LidarFrame> frames;
    for (const auto& p : packets) {
        keep->AddPacket(p.data(), p.size());
        for (const LidarFrame* f : keep->ready()) frames.push_back(*f);
    }
    keep->Flush();
    for (const LidarFrame* f : keep->ready()) frames.push_back(*f);
    *out = keep.get();
    return frames;
}

class RealCapture : public ::testing::TestWithParam<const char*> {
protected:
    void SetUp() override {
        const auto data = test::SharedDataDir();
        if (!data || !fs::exists(*data / "ouster" / (std::string(GetParam()) + ".pcap"))) {
            GTEST_SKIP() << "../shared/data/ouster/" << GetParam()
                         << ".pcap is absent: these tests need the shared real-data folder "
                            "beside the project (see ../shared/data/README.md)";
        }
        dir_ = *data / "ouster";
        rec_ = Load(dir_, GetParam());
    }
    fs::path dir_;
    Recording rec_;
};

TEST_P(RealCapture, PacketDigestsOfTheSdkAreReproduced) {
    ASSERT_EQ(rec_.lidar.size(), 64u);
    ExpectPacketDigests(rec_);
}

TEST_P(RealCapture, FrameDigestsOfTheSdkAreReproduced) {
    capture::OusterCapture cap(dir_ / (std::string(GetParam()) + ".pcap"), rec_.info);
    const LidarFrame* frame = cap.NextFrame();
    ASSERT_NE(frame, nullptr);
    EXPECT_TRUE(frame->complete);
    ExpectFrameDigests(*frame, rec_.digest.at("scans")[0]);
    EXPECT_EQ(cap.NextFrame(), nullptr);
    EXPECT_EQ(cap.lidar_stats().TotalRejected(), 0u);
    EXPECT_EQ(cap.stats().imu_packets, rec_.imu.size());
    EXPECT_EQ(cap.stats().imu_samples, rec_.imu.size());
}

TEST_P(RealCapture, TenPercentDroppedGivesTheRightCounts) {
    std::mt19937 rng(1);
    Packets kept;
    int dropped = 0;
    for (const auto& p : rec_.lidar) {
        if (rng() % 10 == 0) {
            ++dropped;
        } else {
            kept.push_back(p);
        }
    }
    ASSERT_GT(dropped, 0);
    FrameBatcher* b;
    const auto frames = Batch(rec_.info, kept, &b);
    ASSERT_EQ(frames.size(), 1u);
    EXPECT_FALSE(frames[0].complete);
    EXPECT_EQ(b->stats().frames_incomplete, 1u);
    EXPECT_EQ(b->stats().columns_lost, uint64_t(16 * dropped));
    EXPECT_EQ(b->stats().accepted, kept.size());
    EXPECT_EQ(frames[0].columns_received, 1024 - 16 * dropped);
}

TEST_P(RealCapture, SwappedNeighboursAndDuplicatesChangeNothing) {
    Packets p;
    for (size_t i = 0; i + 1 < rec_.lidar.size(); i += 2) {
        p.push_back(rec_.lidar[i + 1]);
        p.push_back(rec_.lidar[i]);
        if (i % 8 == 0) p.push_back(rec_.lidar[i + 1]);  // 8 duplicates, all inside the frame
    }
    FrameBatcher* b;
    const auto frames = Batch(rec_.info, p, &b);
    ASSERT_EQ(frames.size(), 1u);
    EXPECT_TRUE(frames[0].complete);
    ExpectFrameDigests(frames[0], rec_.digest.at("scans")[0]);
    EXPECT_EQ(b->stats().Rejected(Reject::kDuplicate), 8u);
}

TEST_P(RealCapture, RandomBitFlipsNeverCrashAndEveryPacketIsAccountedFor) {
    std::mt19937 rng(7);
    for (int trial = 0; trial < 40; ++trial) {
        Packets p = rec_.lidar;
        const int flips = 1 + int(rng() % 64);
        for (int k = 0; k < flips; ++k) {
            auto& packet = p[rng() % p.size()];
            packet[rng() % packet.size()] ^= uint8_t(1u << (rng() % 8));
        }
        FrameBatcher* b;
        const auto frames = Batch(rec_.info, p, &b);
        const LidarStats& s = b->stats();
        EXPECT_EQ(s.accepted + s.TotalRejected(), s.packets);
        EXPECT_EQ(s.packets, p.size());
        EXPECT_EQ(frames.size(), s.frames_complete + s.frames_incomplete);
        for (const auto& f : frames) EXPECT_LE(f.columns_received, 1024);
    }
}

TEST_P(RealCapture, FrameIdWrapAt65535) {
    const PacketFormat f(rec_.info);
    Packets p;
    for (uint16_t id : {uint16_t{65535}, uint16_t{0}}) {
        for (auto packet : rec_.lidar) {
            if (f.legacy()) {
                for (int c = 0; c < f.columns_per_packet(); ++c) {
                    uint8_t* col = packet.data() + (f.Column(packet.data(), c) - packet.data());
                    std::memcpy(col + 10, &id, 2);
                }
            } else {
                std::memcpy(packet.data() + 2, &id, 2);
            }
            p.push_back(packet);
        }
    }
    FrameBatcher* b;
    const auto frames = Batch(rec_.info, p, &b);
    ASSERT_EQ(frames.size(), 2u);
    EXPECT_EQ(frames[0].frame_id, 65535u);
    EXPECT_EQ(frames[1].frame_id, 0u);
    EXPECT_TRUE(frames[0].complete && frames[1].complete);
    EXPECT_EQ(b->stats().TotalRejected(), 0u);
}

// Writes the recording as our own pcap (optionally fragmented), `cut` bytes short.
fs::path WritePcap(const test::TempDir& tmp, const Recording& r, uint32_t mtu, size_t cut) {
    net::PcapWriter w;
    const uint32_t sensor = *net::ParseIpv4("10.5.5.87"), host = *net::ParseIpv4("10.5.5.1");
    int64_t t = 1'700'000'000'000'000'000;
    for (size_t i = 0; i < r.lidar.size(); ++i) {
        w.WriteUdp(t += 97'656, sensor, 7502, host, 7502, r.lidar[i], mtu);
        if (i % 6 == 0 && i / 6 < r.imu.size()) {
            w.WriteUdp(t, sensor, 7503, host, 7503, r.imu[i / 6], mtu);
        }
    }
    const fs::path path = tmp / "capture.pcap";
    const std::string& bytes = w.bytes();
    test::WriteBytes(path, bytes.substr(0, bytes.size() - cut));
    return path;
}

TEST_P(RealCapture, OurWriterFragmentingAtMtu1500ReadsBackBitIdentical) {
    test::TempDir tmp;
    const fs::path path = WritePcap(tmp, rec_, 1500, 0);
    const Recording back = [&] {
        Recording r = rec_;
        r.lidar.clear();
        r.imu.clear();
        net::PcapReader reader(path);
        net::UdpExtractor extractor;
        net::PcapRecord record;
        net::UdpDatagram d;
        while (reader.Next(record)) {
            if (!extractor.Feed(record, d)) continue;
            (d.dst_port == 7502 ? r.lidar : r.imu).emplace_back(d.payload.begin(), d.payload.end());
        }
        EXPECT_EQ(extractor.stats().reassembled, 64u);
        return r;
    }();
    EXPECT_EQ(back.lidar, rec_.lidar);
    EXPECT_EQ(back.imu, rec_.imu);
    capture::OusterCapture cap(path, rec_.info);
    const LidarFrame* frame = cap.NextFrame();
    ASSERT_NE(frame, nullptr);
    ExpectFrameDigests(*frame, rec_.digest.at("scans")[0]);
}

TEST_P(RealCapture, FileCutMidPacketEndsCleanlyWithTheRightCounts) {
    test::TempDir tmp;
    const fs::path path = WritePcap(tmp, rec_, 0, 1000);  // the last lidar packet loses 1000 B
    capture::OusterCapture cap(path, rec_.info);
    const LidarFrame* frame = cap.NextFrame();
    ASSERT_NE(frame, nullptr);
    EXPECT_FALSE(frame->complete);
    EXPECT_EQ(frame->columns_received, 1024 - 16);
    EXPECT_EQ(cap.NextFrame(), nullptr);
    EXPECT_TRUE(cap.stats().truncated);
    EXPECT_EQ(cap.stats().lidar_packets, 63u);
    EXPECT_EQ(cap.lidar_stats().columns_lost, 16u);
}

INSTANTIATE_TEST_SUITE_P(Ouster, RealCapture, ::testing::ValuesIn(kCaptures),
                         [](const auto& param) {
                             return ::bimslam::test::Identifier(param.param);
                         });

TEST(RealCaptureFaults, VelodyneIsRejectedAndTheEmptyCaptureHasNoFrames) {
    BIMSLAM_REQUIRE_SHARED_DATA(dir, "ouster");
    const SensorInfo info = LoadMetadata(dir / "OS-1-32-G_v2.1.1_1024x10.json");
    try {
        capture::OusterCapture cap(dir / "VLI-16-one-packet.pcap", info);
        while (cap.NextFrame()) {
        }
        ADD_FAILURE() << "a Velodyne capture was accepted";
    } catch (const common::FileError& e) {
        EXPECT_NE(std::string(e.what()).find("no Ouster lidar packets"), std::string::npos)
            << e.what();
        EXPECT_NE(std::string(e.what()).find("VLI-16-one-packet.pcap"), std::string::npos);
    }
    const SensorInfo empty_info = LoadMetadata(dir / "empty_pcap.json");
    capture::OusterCapture empty(dir / "empty_pcap.pcap", empty_info);
    EXPECT_EQ(empty.NextFrame(), nullptr);
    EXPECT_EQ(empty.stats().datagrams, 0u);
    EXPECT_EQ(empty.lidar_stats().frames_complete + empty.lidar_stats().frames_incomplete, 0u);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::ouster
