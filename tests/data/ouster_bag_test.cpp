// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The real ROS bag of ../shared/data/ouster (512x10_raw.bag, recorded by ouster-ros; label
// `data`): its frames and IMU samples, read through our bag reader, are bit for bit those of the
// same packets given as a pcap. The pcap is written from the bag by Debian's python3-rosbag
// (tests/support/ouster_bag.py topcap), so the packets reach the decoder by a path that shares
// nothing with ours but the decoder.
#include <gtest/gtest.h>

#include <cstring>

#include "algorithms/io/capture_files.hpp"
#include "drivers/net/ros_packet_bag.hpp"
#include "drivers/ouster/metadata.hpp"
#include "host_tools/capture/ouster_capture.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::capture {
namespace {
namespace BIMSLAM_UNITY_ID {
namespace fs = std::filesystem;

struct Decoded {
    std::vector<ouster::LidarFrame> frames;
    std::vector<int64_t> emitted_at;  // last_arrival_ns() when each frame came out
    std::vector<ouster::ImuSample> imu;
    OusterCaptureStats stats;
};

Decoded Decode(const fs::path& recording, const ouster::SensorInfo& info) {
    Decoded d;
    OusterCapture cap(recording, info);
    cap.OnImu([&](const ouster::ImuSample& s) { d.imu.push_back(s); });
    while (const ouster::LidarFrame* f = cap.NextFrame()) {
        d.frames.push_back(*f);
        d.emitted_at.push_back(cap.last_arrival_ns());
    }
    d.stats = cap.stats();
    return d;
}

void ExpectSameFrame(const ouster::LidarFrame& a, const ouster::LidarFrame& b) {
    EXPECT_EQ(a.frame_id, b.frame_id);
    EXPECT_EQ(a.complete, b.complete);
    EXPECT_EQ(a.columns_received, b.columns_received);
    EXPECT_EQ(a.packets, b.packets);
    EXPECT_EQ(a.start_ns, b.start_ns);
    EXPECT_EQ(a.first_arrival_ns, b.first_arrival_ns);
    EXPECT_EQ(a.last_arrival_ns, b.last_arrival_ns);
    EXPECT_EQ(a.timestamp, b.timestamp);
    EXPECT_EQ(a.measurement_id, b.measurement_id);
    EXPECT_EQ(a.status, b.status);
    int fields = 0;
    for (int k = 0; k < ouster::kNumFields; ++k) {
        const auto field = static_cast<ouster::Field>(k);
        const void* pa = a.FieldData(field);
        const void* pb = b.FieldData(field);
        ASSERT_EQ(pa == nullptr, pb == nullptr) << ToString(field);
        if (!pa) continue;
        ++fields;
        const size_t bytes = size_t(a.h) * a.w *
                             (ouster::TypeOf(field) == ouster::FieldType::kU32   ? 4
                              : ouster::TypeOf(field) == ouster::FieldType::kU16 ? 2
                                                                                 : 1);
        EXPECT_EQ(std::memcmp(pa, pb, bytes), 0) << ToString(field) << " differs";
    }
    EXPECT_GE(fields, 3);  // RNG15_RFL8_NIR8: range, reflectivity, near-IR
    ASSERT_EQ(a.xyz.size(), b.xyz.size());
    EXPECT_EQ(std::memcmp(a.xyz.data(), b.xyz.data(), a.xyz.size() * sizeof(a.xyz[0])), 0);
}

TEST(RealBag, FramesDecodeIdenticallyToTheSamePacketsAsAPcap) {
    BIMSLAM_REQUIRE_SHARED_DATA(dir, "ouster");
    const fs::path bag = dir / "512x10_raw.bag";
    if (!fs::exists(bag)) GTEST_SKIP() << bag << " is absent from the shared data folder";
    if (const std::string missing = test::OusterBagToolMissing(); !missing.empty()) {
        GTEST_SKIP() << missing;
    }
    test::TempDir tmp;
    const fs::path pcap = tmp / "bag.pcap";
    const auto py = test::RunCommand(test::OusterBagTool() + " topcap '" + bag.string() + "' '" +
                                     pcap.string() + "'");
    ASSERT_EQ(py.exit_code, 0) << py.err;

    // The bag as every command opens it: io::ResolveCapture, its metadata topic.
    const io::CaptureFiles files = io::ResolveCapture(bag);
    ASSERT_TRUE(files.bag);
    const ouster::SensorInfo info = LoadRecordingInfo(files);
    EXPECT_EQ(info.prod_line, "OS-0-128");
    EXPECT_EQ(info.format.columns_per_frame, 512);
    EXPECT_EQ(info.format.pixels_per_column, 128);
    const net::RosPacketBag topics(bag);
    EXPECT_EQ(topics.topics().lidar, "/os_node0/lidar_packets");
    EXPECT_EQ(topics.topics().imu, "/os_node0/imu_packets");
    EXPECT_EQ(topics.topics().metadata, "/os_node0/metadata");

    const Decoded from_bag = Decode(bag, info);
    const Decoded from_pcap = Decode(pcap, info);
    EXPECT_EQ(from_bag.stats.lidar_packets, 32u);
    EXPECT_EQ(from_bag.stats.imu_packets, 10u);
    EXPECT_EQ(from_bag.stats.other_datagrams, 0u);
    EXPECT_EQ(from_pcap.stats.lidar_packets, from_bag.stats.lidar_packets);
    EXPECT_EQ(from_pcap.stats.imu_packets, from_bag.stats.imu_packets);
    ASSERT_EQ(from_bag.frames.size(), 1u);  // 32 packets of 16 columns: one 512-column frame
    EXPECT_TRUE(from_bag.frames[0].complete);
    ASSERT_EQ(from_pcap.frames.size(), from_bag.frames.size());
    for (size_t i = 0; i < from_bag.frames.size(); ++i) {
        SCOPED_TRACE("frame " + std::to_string(i));
        ExpectSameFrame(from_bag.frames[i], from_pcap.frames[i]);
        EXPECT_EQ(from_bag.emitted_at[i], from_pcap.emitted_at[i]);
    }
    ASSERT_EQ(from_bag.imu.size(), 10u);
    ASSERT_EQ(from_pcap.imu.size(), from_bag.imu.size());
    for (size_t i = 0; i < from_bag.imu.size(); ++i) {
        EXPECT_EQ(from_bag.imu[i].time_ns, from_pcap.imu[i].time_ns);
        EXPECT_EQ(from_bag.imu[i].accel, from_pcap.imu[i].accel);
        EXPECT_EQ(from_bag.imu[i].gyro, from_pcap.imu[i].gyro);
    }
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::capture
