// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// RosPacketBag and PacketRecording on small bags written by Debian's python3-rosbag
// (tests/support/ouster_bag.py): topics found by suffix in any namespace, payloads and record
// times exact, ports given, the metadata text; bags that are not one sensor's, or not bags, are
// FileErrors naming the file.
#include "drivers/net/ros_packet_bag.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "algorithms/common/status.hpp"
#include "drivers/net/packet_recording.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::net {
namespace {
namespace BIMSLAM_UNITY_ID {
namespace fs = std::filesystem;

struct Packet {
    int64_t t_ns;
    uint8_t kind;  // 0 lidar, 1 imu
    std::vector<uint8_t> payload;
};

std::vector<Packet> MakePackets() {
    std::vector<Packet> p;
    for (int i = 0; i < 12; ++i) {
        std::vector<uint8_t> bytes(i % 4 == 3 ? 48 : 3000 + i);
        for (size_t k = 0; k < bytes.size(); ++k) bytes[k] = uint8_t(k * 7 + i);
        p.push_back({1'700'000'000'123'456'789 + i * 1'562'500LL, uint8_t(i % 4 == 3), bytes});
    }
    return p;
}

class RosBagTest : public ::testing::Test {
protected:
    void SetUp() override {
        if (const std::string missing = test::OusterBagToolMissing(); !missing.empty()) {
            GTEST_SKIP() << missing;
        }
    }
    fs::path Write(const std::string& name, const std::string& flags) {
        std::ofstream s(tmp_ / "packets.bin", std::ios::binary);
        for (const Packet& p : packets_) {
            const uint32_t n = uint32_t(p.payload.size());
            s.write(reinterpret_cast<const char*>(&p.t_ns), 8);
            s.write(reinterpret_cast<const char*>(&p.kind), 1);
            s.write(reinterpret_cast<const char*>(&n), 4);
            s.write(reinterpret_cast<const char*>(p.payload.data()), n);
        }
        s.close();
        test::WriteBytes(tmp_ / "meta.json", kMeta);
        const fs::path bag = tmp_ / (name + ".bag");
        const auto r = test::RunCommand(
            test::OusterBagTool() + " write " + (tmp_ / "packets.bin").string() + " " +
            (tmp_ / "meta.json").string() + " " + bag.string() + " " + flags);
        EXPECT_EQ(r.exit_code, 0) << r.err;
        return bag;
    }
    static constexpr const char* kMeta = "{\"sensor_info\": {\"prod_line\": \"OS-1-32\"}}";
    test::TempDir tmp_;
    std::vector<Packet> packets_ = MakePackets();
};

TEST_F(RosBagTest, PacketsComeOutExactlyInOrderOnTheirPorts) {
    const fs::path bag = Write("walk", "--ns /sensors/front");
    EXPECT_TRUE(LooksLikeRosBag(bag));
    RosPacketBag reader(bag);
    EXPECT_EQ(reader.topics().lidar, "/sensors/front/lidar_packets");
    EXPECT_EQ(reader.topics().imu, "/sensors/front/imu_packets");
    EXPECT_EQ(reader.topics().metadata, "/sensors/front/metadata");
    EXPECT_EQ(reader.topics().lidar_messages, 9u);
    EXPECT_EQ(reader.topics().imu_messages, 3u);
    EXPECT_EQ(reader.ReadMetadata(), kMeta);
    reader.SetPorts(7000, 7001);
    UdpDatagram d;
    size_t i = 0;
    for (; reader.Next(d); ++i) {
        ASSERT_LT(i, packets_.size());
        EXPECT_EQ(d.timestamp_ns, packets_[i].t_ns);
        EXPECT_EQ(d.dst_port, packets_[i].kind ? 7001 : 7000);
        EXPECT_EQ(std::vector<uint8_t>(d.payload.begin(), d.payload.end()), packets_[i].payload);
    }
    EXPECT_EQ(i, packets_.size());
    EXPECT_FALSE(reader.Next(d));

    // PacketRecording tells a bag from a pcap by its content.
    PacketRecordingOptions options;
    options.bag_lidar_port = 1;
    options.bag_imu_port = 2;
    PacketRecording recording(bag, options);
    EXPECT_TRUE(recording.is_bag());
    size_t n = 0;
    while (recording.Next(d)) EXPECT_EQ(d.dst_port, packets_[n++].kind ? 2 : 1);
    EXPECT_EQ(n, packets_.size());
    EXPECT_EQ(recording.records(), packets_.size());
}

TEST_F(RosBagTest, WithoutMetadataTheErrorNamesTheFileAndItsTopics) {
    const fs::path bag = Write("nometa", "--no-metadata --no-imu");
    RosPacketBag reader(bag);
    EXPECT_TRUE(reader.topics().metadata.empty());
    EXPECT_TRUE(reader.topics().imu.empty());
    try {
        (void)reader.ReadMetadata();
        ADD_FAILURE() << "no error";
    } catch (const common::FileError& e) {
        EXPECT_EQ(e.path(), bag.string());
        EXPECT_NE(std::string(e.what()).find("no metadata topic"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("/os_node/lidar_packets (ouster_ros/PacketMsg)"),
                  std::string::npos)
            << e.what();
    }
}

TEST_F(RosBagTest, TwoSensorsOrNoBagAreRefusedNamingTheFile) {
    const fs::path two = Write("two", "--also-ns /os_node1");
    EXPECT_FILE_ERROR(RosPacketBag{two}, two.string(), 0);
    try {
        RosPacketBag r(two);
    } catch (const common::FileError& e) {
        EXPECT_NE(std::string(e.what()).find("/os_node1/lidar_packets"), std::string::npos);
    }
    const std::string whole = [&] {
        std::ifstream f(two, std::ios::binary);
        return std::string((std::istreambuf_iterator<char>(f)), {});
    }();
    for (size_t cut : {size_t(20), whole.size() / 2, whole.size() - 10}) {
        const fs::path path = tmp_ / ("cut" + std::to_string(cut) + ".bag");
        test::WriteBytes(path, whole.substr(0, cut));
        EXPECT_FILE_ERROR(RosPacketBag{path}, path.string(), 0);
    }
    test::WriteBytes(tmp_ / "text.bag", "#ROSBAG V2.0\nnot really");
    EXPECT_FILE_ERROR(RosPacketBag{tmp_ / "text.bag"}, (tmp_ / "text.bag").string(), 0);
    EXPECT_FALSE(LooksLikeRosBag(tmp_ / "meta.json"));
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::net
