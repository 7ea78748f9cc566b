// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "drivers/net/ros_packet_bag.hpp"

#include <ros/serialization.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <optional>

#include "algorithms/common/status.hpp"

namespace bimslam::net {
namespace {
using common::FileError;
using common::StatusCode;

// MD5 of the message definitions (what ROS checks types by): "uint8[] buf" (ouster_ros/PacketMsg,
// ouster_sensor_msgs/PacketMsg) and "string data" (std_msgs/String).
constexpr const char* kPacketMsgMd5 = "4f7b5949e76f86d01e96b0e33ba9b5e3";
constexpr const char* kStringMd5 = "992ce8a1687cec8c8bd883ec73ca41d1";

bool EndsWith(const std::string& s, const std::string& suffix) {
    return s.size() >= suffix.size() &&
           s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// "/os_node0/lidar_packets" -> "/os_node0/".
std::string Namespace(const std::string& topic) { return topic.substr(0, topic.rfind('/') + 1); }

std::string Describe(const std::vector<std::pair<std::string, std::string>>& topics) {
    if (topics.empty()) return "no topics";
    std::string s;
    for (const auto& [topic, type] : topics)
        s += (s.empty() ? "" : ", ") + topic + " (" + type + ")";
    return s;
}

// The one topic of `candidates` in the lidar topic's namespace, else the only one, else none.
std::string Pick(const std::vector<std::string>& candidates, const std::string& ns) {
    for (const std::string& t : candidates) {
        if (Namespace(t) == ns) return t;
    }
    return candidates.size() == 1 ? candidates[0] : std::string();
}

// A serialized `uint8[] buf` or `string data`: a uint32 length, then the bytes (ROS
// serialization, read through the library's stream). Empty span when the lengths disagree.
std::span<const uint8_t> SerializedArray(uint8_t* data, uint32_t size) {
    ros::serialization::IStream in(data, size);
    uint32_t n = 0;
    if (size < 4) return {};
    in.next(n);
    if (uint64_t(n) + 4 != size) return {};
    return {in.getData(), n};
}

}  // namespace

bool LooksLikeRosBag(const std::filesystem::path& path) {
    static constexpr char kMagic[] = "#ROSBAG V2.0\n";
    char head[sizeof(kMagic) - 1] = {};
    std::ifstream in(path, std::ios::binary);
    return in.read(head, sizeof(head)) && std::memcmp(head, kMagic, sizeof(head)) == 0;
}

struct RosPacketBag::State {
    rosbag::Bag bag;
    std::optional<rosbag::View> view;
    rosbag::View::iterator it;
    bool started = false;
    std::vector<uint8_t> buffer = std::vector<uint8_t>(1 << 16);  // a UDP payload's maximum
};

RosPacketBag::RosPacketBag(const std::filesystem::path& path)
    : path_(path), state_(std::make_unique<State>()) {
    const std::string name = path.string();
    try {
        state_->bag.open(name, rosbag::bagmode::Read);
    } catch (const std::exception& e) {
        throw FileError(StatusCode::kParseError, name, 0,
                        std::string("not a readable ROS 1 bag (") + e.what() +
                            "); a bag whose recording was cut off has no index: `rosbag reindex` "
                            "rebuilds it from the chunks that are whole");
    }
    std::vector<std::string> lidar, imu, metadata;
    rosbag::View all(state_->bag);
    for (const rosbag::ConnectionInfo* c : all.getConnections()) {
        topics_.all.emplace_back(c->topic, c->datatype);
        const bool packet = c->md5sum == kPacketMsgMd5 || EndsWith(c->datatype, "/PacketMsg");
        if (packet && EndsWith(c->topic, "lidar_packets")) lidar.push_back(c->topic);
        if (packet && EndsWith(c->topic, "imu_packets")) imu.push_back(c->topic);
        if (c->md5sum == kStringMd5 && EndsWith(c->topic, "metadata")) {
            metadata.push_back(c->topic);
        }
    }
    std::sort(topics_.all.begin(), topics_.all.end());
    topics_.all.erase(std::unique(topics_.all.begin(), topics_.all.end()), topics_.all.end());
    for (auto* v : {&lidar, &imu, &metadata}) {
        std::sort(v->begin(), v->end());
        v->erase(std::unique(v->begin(), v->end()), v->end());
    }
    if (lidar.empty()) {
        throw FileError(StatusCode::kParseError, name, 0,
                        "no Ouster lidar packet topic (a PacketMsg topic ending in "
                        "lidar_packets, as ouster-ros records them); the bag holds " +
                            Describe(topics_.all));
    }
    if (lidar.size() > 1) {
        std::string list;
        for (const std::string& t : lidar) list += (list.empty() ? "" : ", ") + t;
        throw FileError(
            StatusCode::kParseError, name, 0,
            "several lidar packet topics (" + list + "): a bag of one sensor is expected");
    }
    topics_.lidar = lidar[0];
    topics_.imu = Pick(imu, Namespace(topics_.lidar));
    topics_.metadata = Pick(metadata, Namespace(topics_.lidar));
    topics_.lidar_messages = rosbag::View(state_->bag, rosbag::TopicQuery(topics_.lidar)).size();
    if (!topics_.imu.empty()) {
        topics_.imu_messages = rosbag::View(state_->bag, rosbag::TopicQuery(topics_.imu)).size();
    }
}

RosPacketBag::~RosPacketBag() = default;

std::string RosPacketBag::ReadMetadata() const {
    if (topics_.metadata.empty()) {
        throw FileError(StatusCode::kNotFound, path_.string(), 0,
                        "no metadata topic (a std_msgs/String topic ending in metadata, as "
                        "ouster-ros records the sensor's JSON); the bag holds " +
                            Describe(topics_.all) +
                            ". Give the sensor's metadata JSON with --meta "
                            "where the command has it");
    }
    try {
        rosbag::View view(state_->bag, rosbag::TopicQuery(topics_.metadata));
        for (const rosbag::MessageInstance& m : view) {
            std::vector<uint8_t> bytes(m.size());
            ros::serialization::OStream out(bytes.data(), uint32_t(bytes.size()));
            m.write(out);
            const std::span<const uint8_t> text = SerializedArray(bytes.data(), m.size());
            return std::string(text.begin(), text.end());
        }
    } catch (const std::exception& e) {
        throw FileError(StatusCode::kParseError, path_.string(), 0,
                        "reading " + topics_.metadata + ": " + e.what());
    }
    throw FileError(StatusCode::kNotFound, path_.string(), 0,
                    "the metadata topic " + topics_.metadata + " holds no message");
}

void RosPacketBag::SetPorts(uint16_t lidar_port, uint16_t imu_port) {
    lidar_port_ = lidar_port;
    imu_port_ = imu_port;
}

bool RosPacketBag::Next(UdpDatagram& out) {
    State& s = *state_;
    try {
        if (!s.started) {
            std::vector<std::string> wanted = {topics_.lidar};
            if (!topics_.imu.empty()) wanted.push_back(topics_.imu);
            s.view.emplace(s.bag, rosbag::TopicQuery(wanted));
            s.it = s.view->begin();
            s.started = true;
        } else if (s.it != s.view->end()) {
            ++s.it;
        }
        for (; s.it != s.view->end(); ++s.it) {
            const rosbag::MessageInstance& m = *s.it;
            const uint32_t size = m.size();
            if (size > s.buffer.size()) s.buffer.resize(size);
            ros::serialization::OStream stream(s.buffer.data(), size);
            m.write(stream);
            const std::span<const uint8_t> payload = SerializedArray(s.buffer.data(), size);
            const bool lidar = m.getTopic() == topics_.lidar;
            out = UdpDatagram{};
            out.timestamp_ns = int64_t(m.getTime().toNSec());
            out.dst_port = lidar ? lidar_port_ : imu_port_;
            out.payload = payload;
            out.record_index = packets_++;
            return true;
        }
    } catch (const std::exception& e) {
        throw FileError(StatusCode::kParseError, path_.string(), 0,
                        "reading packet " + std::to_string(packets_ + 1) + ": " + e.what());
    }
    return false;
}

}  // namespace bimslam::net
