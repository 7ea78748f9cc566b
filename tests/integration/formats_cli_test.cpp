// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The recording formats of the field as a user gives them to the commands (issue 17, item 3):
// folders of per-scan point clouds (PCD with per-point time, KITTI .bin without) with a times
// file; ROS 1 bags as ouster-ros records them, written here by Debian's python3-rosbag
// (tests/support/ouster_bag.py) from a simulated capture's packets, must be accepted by every
// command that takes a recording and give what the same packets give as a pcap; a bag without
// its metadata topic and a truncated bag exit 2 naming the file.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>

#include "algorithms/io/file_util.hpp"
#include "algorithms/io/trajectory.hpp"
#include "drivers/net/packet_recording.hpp"
#include "drivers/ouster/metadata.hpp"
#include "tests/integration/rig_test_support.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam {
namespace {
namespace BIMSLAM_UNITY_ID {
namespace fs = std::filesystem;

using test::rig::kCli;
using test::rig::kRig;
const std::string kBagTool = test::OusterBagTool();

class Formats : public test::rig::RigFixture {
protected:
    void SetUp() override {
        if (const std::string missing = test::OusterBagToolMissing(); !missing.empty()) {
            GTEST_SKIP() << missing;
        }
    }

    // A 4 s handheld capture of the sample building, and the same packets as walk.pcap +
    // walk.json (the Ouster tools' layout: no capture.json mount, as a bag has none).
    static fs::path Capture() {
        const fs::path dir = RigFixture::Capture("handheld", 4);
        const fs::path ouster_style = Tmp() / "ouster_style";
        if (!fs::exists(ouster_style / "walk.json")) {
            fs::create_directories(ouster_style);
            fs::copy_file(dir / "lidar.pcap", ouster_style / "walk.pcap");
            fs::copy_file(dir / "metadata.json", ouster_style / "walk.json");
        }
        return dir;
    }

    // The capture's lidar and IMU packets as a bag (python3-rosbag), with `flags` for the tool.
    static fs::path Bag(const std::string& name, const std::string& flags) {
        const fs::path cap = Capture();
        const fs::path bag = Tmp() / (name + ".bag");
        if (fs::exists(bag)) return bag;
        const ouster::SensorInfo info = ouster::LoadMetadata(cap / "metadata.json");
        std::ofstream stream(Tmp() / "packets.bin", std::ios::binary);
        net::PacketRecording recording(cap / "lidar.pcap");
        net::UdpDatagram d;
        while (recording.Next(d)) {
            const bool lidar = d.dst_port == info.udp_port_lidar.value_or(7502);
            if (!lidar && d.dst_port != info.udp_port_imu.value_or(7503)) continue;
            const uint8_t kind = lidar ? 0 : 1;
            const uint32_t n = uint32_t(d.payload.size());
            stream.write(reinterpret_cast<const char*>(&d.timestamp_ns), 8);
            stream.write(reinterpret_cast<const char*>(&kind), 1);
            stream.write(reinterpret_cast<const char*>(&n), 4);
            stream.write(reinterpret_cast<const char*>(d.payload.data()), n);
        }
        stream.close();
        const auto r =
            test::RunCommand(kBagTool + " write " + (Tmp() / "packets.bin").string() + " " +
                             (cap / "metadata.json").string() + " " + bag.string() + " " + flags);
        EXPECT_EQ(r.exit_code, 0) << r.err;
        return bag;
    }
};

nlohmann::json Json(const test::CommandResult& r) {
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return r.exit_code == 0 ? nlohmann::json::parse(r.out) : nlohmann::json();
}

TEST_F(Formats, BagFromOusterRosGivesWhatItsPacketsGiveAsAPcapInEveryCommand) {
    const fs::path bag = Bag("walk", "--ns /ouster");  // ouster-ros >= 0.10's namespace
    const fs::path pcap = Tmp() / "ouster_style" / "walk.pcap";

    // bimslam ouster info: the same packets, frames and IMU samples; the topics named.
    const nlohmann::json from_bag =
        Json(test::RunCommand(kCli + " ouster info --json " + bag.string()));
    const nlohmann::json from_pcap =
        Json(test::RunCommand(kCli + " ouster info --json " + pcap.string()));
    ASSERT_FALSE(from_bag.is_null());
    EXPECT_EQ(from_bag["format"], "rosbag");
    EXPECT_EQ(from_bag["bag_topics"]["lidar"], "/ouster/lidar_packets");
    EXPECT_EQ(from_bag["bag_topics"]["metadata"], "/ouster/metadata");
    for (const char* key : {"lidar_packets", "imu_packets", "frames_complete", "frames_incomplete",
                            "columns_lost", "imu_samples", "first_frame_id", "last_frame_id"}) {
        EXPECT_EQ(from_bag[key], from_pcap[key]) << key;
    }
    EXPECT_GT(from_bag["frames_complete"].get<int>(), 30);

    // bimslam ouster export: the same frame, byte for byte.
    for (const auto& [name, in] : {std::pair{"bag", bag}, std::pair{"pcap", pcap}}) {
        const auto r = test::RunCommand(kCli + " ouster export " + in.string() + " --frame 3 -o " +
                                        (Tmp() / ("export_" + std::string(name))).string());
        ASSERT_EQ(r.exit_code, 0) << r.err;
    }
    for (const char* file : {"RANGE.npy", "TIMESTAMP.npy", "xyz.npy", "cloud.pcd"}) {
        EXPECT_EQ(io::ReadFileToString(Tmp() / "export_bag" / file),
                  io::ReadFileToString(Tmp() / "export_pcap" / file))
            << file;
    }

    // bimslam odometry: the same trajectory (an unbounded budget, so the machine's load cannot
    // change it).
    for (const auto& [name, in] : {std::pair{"bag", bag}, std::pair{"pcap", pcap}}) {
        const auto r = test::RunCommand(kCli + " odometry " + in.string() + " -o " +
                                        (Tmp() / ("odometry_" + std::string(name))).string() +
                                        " --budget-ms 1000 --overwrite");
        ASSERT_EQ(r.exit_code, 0) << r.err;
    }
    const std::string trajectory = io::ReadFileToString(Tmp() / "odometry_pcap" / "trajectory.tum");
    EXPECT_GT(trajectory.size(), 1000u);
    EXPECT_EQ(io::ReadFileToString(Tmp() / "odometry_bag" / "trajectory.tum"), trajectory);

    // bimslam-rig replay: the on-board firmware reads the bag too, to the same trajectory.
    const fs::path config = test::rig::WriteConfig(Tmp() / "rig.yaml", "");
    const nlohmann::json j =
        test::rig::RigJson(kRig + " replay " + bag.string() + " --speed max --json --config " +
                           config.string() + " --session-root " + (Tmp() / "rig").string());
    ASSERT_FALSE(j.is_null());
    EXPECT_EQ(io::ReadFileToString(fs::path(j["session"].get<std::string>()) / "trajectory.tum"),
              trajectory);
}

TEST_F(Formats, BagWithoutItsMetadataTopicExits2NamingTheFileAndWhatItHolds) {
    const fs::path bag = Bag("no_metadata", "--no-metadata");
    for (const std::string& command :
         {kCli + " odometry " + bag.string() + " -o " + (Tmp() / "s_nometa").string(),
          kCli + " ouster info " + bag.string(),
          kRig + " replay " + bag.string() + " --speed max --no-record --config " +
              test::rig::WriteConfig(Tmp() / "rig.yaml", "").string()}) {
        const auto r = test::RunCommand(command);
        EXPECT_EQ(r.exit_code, 2) << command << "\n" << r.err;
        EXPECT_NE(r.err.find(bag.string()), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("no metadata topic"), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("/os_node/lidar_packets"), std::string::npos) << r.err;
    }
    // The sensor's JSON given by hand reads it.
    const auto r = test::RunCommand(kCli + " ouster info " + bag.string() + " --meta " +
                                    (Capture() / "metadata.json").string());
    EXPECT_EQ(r.exit_code, 0) << r.err;
}

TEST_F(Formats, TruncatedBagExits2NamingTheFile) {
    const std::string whole = io::ReadFileToString(Bag("walk", "--ns /ouster"));
    const fs::path cut = Tmp() / "cut.bag";
    test::WriteBytes(cut, whole.substr(0, whole.size() / 2));
    for (const std::string& command :
         {kCli + " odometry " + cut.string() + " -o " + (Tmp() / "s_cut").string(),
          kCli + " ouster info " + cut.string(),
          kRig + " replay " + cut.string() + " --speed max --no-record --config " +
              test::rig::WriteConfig(Tmp() / "rig.yaml", "").string()}) {
        const auto r = test::RunCommand(command);
        EXPECT_EQ(r.exit_code, 2) << command << "\n" << r.err;
        EXPECT_NE(r.err.find(cut.string()), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("not a readable ROS 1 bag"), std::string::npos) << r.err;
    }
}

// `bimslam ouster export --all`: the capture's frames as per-scan files (PCD or PLY with
// per-point time t, KITTI .bin without), times.txt, imu.csv and the ground truth, as public data
// sets ship them and as a peer odometry takes them.
fs::path ExportClouds(const fs::path& capture, const fs::path& dir, const std::string& format) {
    const auto r = test::RunCommand(kCli + " ouster export " + capture.string() + " --all -o " +
                                    dir.string() + " --format " + format);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return dir;
}

size_t Lines(const fs::path& file) {
    const std::string text = io::ReadFileToString(file);
    return size_t(std::count(text.begin(), text.end(), '\n'));
}

double OdometryApe(const fs::path& input, const fs::path& session, const fs::path& truth,
                   std::string* notes) {
    const auto r = test::RunCommand(kCli + " odometry " + input.string() + " -o " +
                                    session.string() + " --budget-ms 1000 --overwrite --json");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    if (r.exit_code != 0) return 1e9;
    *notes = nlohmann::json::parse(r.out).at("notes").dump();
    const auto e =
        test::RunCommand(kCli + " evaluate --json --est " + (session / "trajectory.tum").string() +
                         " --ref " + truth.string());
    EXPECT_EQ(e.exit_code, 0) << e.err;
    return nlohmann::json::parse(e.out).at("ape_trans_rmse_m").get<double>();
}

// The peer-benchmark folder holds what it says: a cloud a frame, a time a cloud, the IMU, and the
// ground truth both ways (TUM as the capture has it, KITTI poses from the first scan).
TEST_F(Formats, ExportAllWritesWhatAPeerOdometryNeeds) {
    const fs::path cap = Capture();
    const fs::path dir = ExportClouds(cap, Tmp() / "peer", "ply");
    const auto info = Json(test::RunCommand(kCli + " ouster info --json " + cap.string()));
    const size_t scans = Lines(dir / "times.txt");
    EXPECT_GE(scans, 39u);  // 4 s at 10 Hz
    EXPECT_TRUE(fs::exists(dir / "000000.ply"));
    EXPECT_TRUE(fs::exists(
        dir / (std::string(scans < 100 ? "0000" : "000") + std::to_string(scans - 1) + ".ply")));
    EXPECT_FALSE(fs::exists(
        dir / (std::string(scans < 100 ? "0000" : "000") + std::to_string(scans) + ".ply")));
    EXPECT_EQ(Lines(dir / "poses.txt"), scans);
    EXPECT_EQ(io::ReadFileToString(dir / "ground_truth.tum"),
              io::ReadFileToString(cap / "ground_truth.tum"));
    // The KITTI poses start at the identity and end where the ground truth does, relative to
    // its first pose.
    const auto kitti = io::ReadKitti(dir / "poses.txt");
    const auto truth = io::ReadTum(cap / "ground_truth.tum");
    EXPECT_LT((kitti.front().matrix() - Eigen::Matrix4d::Identity()).norm(), 1e-12);
    const Eigen::Isometry3d last = truth.front().Pose().inverse() * truth[scans - 1].Pose();
    EXPECT_LT((kitti.back().matrix() - last.matrix()).norm(), 1e-9);
    // imu.csv: the recording's IMU samples, header plus one line each (100 Hz).
    ASSERT_TRUE(info.is_object());
    EXPECT_GT(Lines(dir / "imu.csv"), 4 * 90u);
    EXPECT_EQ(io::ReadFileToString(dir / "imu.csv").rfind("t_s,gyro_x,", 0), 0u);
    // Bad format: exit 2 from the command line, nothing written.
    const auto bad = test::RunCommand(kCli + " ouster export " + cap.string() + " --all -o " +
                                      (Tmp() / "peer_bad").string() + " --format las");
    EXPECT_EQ(bad.exit_code, 2) << bad.err;
    EXPECT_FALSE(fs::exists(Tmp() / "peer_bad"));
}

TEST_F(Formats, FolderOfPointCloudsWithATimesFileIsARecording) {
    const fs::path cap = Capture();
    const fs::path truth = cap / "ground_truth.tum";
    const fs::path ouster_style = Tmp() / "ouster_style" / "walk.pcap";
    // The same frames from the pcap (no capture.json mount, as the folder has none).
    const auto pcap_ape = [&](const std::string& flags, const std::string& name) {
        const auto run =
            test::RunCommand(kCli + " odometry " + ouster_style.string() + " -o " +
                             (Tmp() / name).string() + flags + " --budget-ms 1000 --overwrite");
        EXPECT_EQ(run.exit_code, 0) << run.err;
        const auto e = test::RunCommand(kCli + " evaluate --json --est " +
                                        (Tmp() / name / "trajectory.tum").string() + " --ref " +
                                        truth.string());
        return nlohmann::json::parse(e.out).at("ape_trans_rmse_m").get<double>();
    };
    const double pcap_imu = pcap_ape("", "pcap_imu");
    const double pcap_noimu = pcap_ape(" --no-imu", "pcap_noimu");
    std::string notes;
    // PCD with per-point time and the IMU file: deskewed, with the IMU, as the recording.
    const fs::path pcd_dir = ExportClouds(cap, Tmp() / "pcd_scans", "pcd");
    const double pcd = OdometryApe(pcd_dir, Tmp() / "pcd_session", truth, &notes);
    EXPECT_EQ(notes.find("deskew is off"), std::string::npos) << notes;
    EXPECT_EQ(notes.find("no imu.csv"), std::string::npos) << notes;
    // PLY likewise.
    const double ply = OdometryApe(ExportClouds(cap, Tmp() / "ply_scans", "ply"),
                                   Tmp() / "ply_session", truth, &notes);
    // Without its IMU file the folder is the recording without its IMU, and says so.
    fs::remove(pcd_dir / "imu.csv");
    const double pcd_noimu = OdometryApe(pcd_dir, Tmp() / "pcd_noimu_session", truth, &notes);
    EXPECT_NE(notes.find("no imu.csv"), std::string::npos) << notes;
    // KITTI .bin, no per-point time: runs, says deskew is off.
    const double bin = OdometryApe(ExportClouds(cap, Tmp() / "kitti" / "velodyne", "bin"),
                                   Tmp() / "bin_session", truth, &notes);
    EXPECT_NE(notes.find("deskew is off"), std::string::npos) << notes;
    std::cout << "APE RMSE on the 4 s handheld capture: pcap " << pcap_imu * 100
              << " cm, PCD folder with imu.csv " << pcd * 100 << " cm, PLY " << ply * 100
              << " cm; without the IMU: pcap " << pcap_noimu * 100 << " cm, PCD " << pcd_noimu * 100
              << " cm; KITTI .bin without time " << bin * 100 << " cm\n";
    // Per-point time and the IMU used: the folder gives what the recording gives (t is float32
    // seconds in a PCD and PLY, the IMU 9 digits, so not bit for bit).
    EXPECT_NEAR(pcd, pcap_imu, 0.005);
    EXPECT_NEAR(ply, pcap_imu, 0.005);
    EXPECT_NEAR(pcd_noimu, pcap_noimu, 0.01);
    EXPECT_LT(pcd, 0.03);
    EXPECT_LT(bin, 0.10);

    // times.txt moved to the KITTI place (the parent of velodyne/) still reads; gone: exit 2.
    fs::rename(Tmp() / "kitti" / "velodyne" / "times.txt", Tmp() / "kitti" / "times.txt");
    EXPECT_LT(OdometryApe(Tmp() / "kitti" / "velodyne", Tmp() / "bin_session2", truth, &notes),
              0.10);
    fs::remove(Tmp() / "kitti" / "times.txt");
    const auto missing =
        test::RunCommand(kCli + " odometry " + (Tmp() / "kitti" / "velodyne").string() + " -o " +
                         (Tmp() / "bin_session3").string());
    EXPECT_EQ(missing.exit_code, 2) << missing.err;
    EXPECT_NE(missing.err.find((Tmp() / "kitti" / "velodyne" / "times.txt").string()),
              std::string::npos)
        << missing.err;
    EXPECT_NE(missing.err.find("needs a times file"), std::string::npos) << missing.err;
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam
