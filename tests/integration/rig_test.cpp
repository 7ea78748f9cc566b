// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// bimslam-rig as it runs on the rig and on the bench: replay of simulated captures (the same
// session as `bimslam odometry`), faults (packet loss, a corrupt stretch, the sensor silent and
// restarting, a CAN outage, a full disk), signals (SIGTERM finishes the session, SIGKILL leaves
// one `bimslam session info` recovers), the configuration (every shipped file loads; a wrong key,
// type or value exits 2 naming it), live on loopback fed by `bimslam ouster replay`, scheduling
// refused, SocketCAN absent, the odometry's verdict (trusted; untrusted with a 1 ms budget, in the
// summary and the session, also after SIGKILL). LCM and systemd: rig_lcm_test.cpp.
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>

#include "tests/integration/rig_test_support.hpp"

namespace bimslam {
namespace {
namespace BIMSLAM_UNITY_ID {
namespace fs = std::filesystem;
using test::rig::kCli;
using test::rig::kRig;
using test::rig::RigJson;
using test::rig::Spawn;
using test::rig::Wait;
using test::rig::WriteConfig;

std::string Slurp(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), {});
}

class Rig : public test::rig::RigFixture {
protected:
    // A Go1 walk seen by an OS1-128 at 2048x10 (262 144 points a scan): with a budget of 1 ms
    // every registration is cut short. An OS1-32's scans no longer were: once its voxel filters
    // got faster (25f2ee8), a scan now and then registered within 1 ms and split the stretch, by
    // the machine's load.
    static fs::path WideCapture() {
        return Capture("go1", 8, "sensor:\n  model: \"OS1-128\"\n  lidar_mode: \"2048x10\"\n");
    }
};

TEST_F(Rig, ReplayWritesTheSessionOfBimslamOdometry) {
    const fs::path cap = Capture("go1", 8);
    const fs::path offline = Tmp() / "offline";
    auto r = test::RunCommand(kCli + " odometry " + cap.string() + " -o " + offline.string() +
                              " --budget-ms 1000 --json");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto odo = nlohmann::json::parse(r.out);
    ASSERT_EQ(odo["over_budget"], 0) << "a scan over budget makes the comparison meaningless";
    const fs::path config = WriteConfig(Tmp() / "same.yaml", "");
    const nlohmann::json rig =
        RigJson(kRig + " replay " + cap.string() + " --speed max --json --config " +
                config.string() + " --session-root " + (Tmp() / "rig").string());
    ASSERT_FALSE(rig.is_null());
    EXPECT_EQ(rig["scans"], odo["scans"]);
    EXPECT_EQ(rig["scans_dropped"], 0);
    const fs::path session = rig["session"].get<std::string>();
    for (const char* f : {"trajectory.tum", "optimized_poses.txt", "odom_poses.txt", "times.txt",
                          "singlesession_posegraph.g2o", "odometry_verdict.json"}) {
        EXPECT_EQ(Slurp(session / f), Slurp(offline / f)) << f << " differs";
    }
    EXPECT_EQ(Slurp(session / "Scans" / "000003.pcd"), Slurp(offline / "Scans" / "000003.pcd"));
    EXPECT_TRUE(fs::exists(session / "session.json"));
    // The odometry's verdict, in the summary as in the session (compared above).
    EXPECT_EQ(odo["verdict"], "trusted");
    EXPECT_EQ(rig["verdict"], "trusted");
    EXPECT_EQ(rig["failed_stretches"].size(), 0u);
}

// A budget of 1 ms cuts every registration short (issue 32, item 3): past the few scans the gyro
// bridges, one failed stretch to the end. The summary says untrusted and names the stretch; the
// session's odometry_verdict.json (what `bimslam anchor` splits a session at) says the same.
TEST_F(Rig, AnOdometryThatFailsIsUntrustedInTheSummaryAndTheSession) {
    const fs::path cap = WideCapture();
    const fs::path config = WriteConfig(Tmp() / "tiny_budget.yaml", "odometry:\n  budget_ms: 1\n");
    const nlohmann::json rig =
        RigJson(kRig + " replay " + cap.string() + " --speed max --json --config " +
                config.string() + " --session-root " + (Tmp() / "tiny_budget").string());
    ASSERT_FALSE(rig.is_null());
    EXPECT_EQ(rig["verdict"], "untrusted");
    ASSERT_EQ(rig["failed_stretches"].size(), 1u) << rig.dump(1);
    const nlohmann::json& said = rig["failed_stretches"][0];
    EXPECT_EQ(said["last_scan"], rig["scans"].get<int>() - 1) << said.dump();
    const fs::path session = rig["session"].get<std::string>();
    EXPECT_TRUE(fs::exists(session / "session.json"));
    const auto v = nlohmann::json::parse(Slurp(session / "odometry_verdict.json"));
    EXPECT_EQ(v["verdict"], "untrusted");
    ASSERT_EQ(v["failed_stretches"].size(), 1u) << v.dump(1);
    const nlohmann::json& s = v["failed_stretches"][0];
    for (const char* k : {"first_scan", "last_scan", "failed", "reasons"})
        EXPECT_EQ(s[k], said[k]) << k;
    EXPECT_LT(s["first_stamp_ns"].get<int64_t>(), s["last_stamp_ns"].get<int64_t>());
}

// A rig killed after a stretch appeared leaves the verdict in the session: the file is written
// when a stretch appears, not only when the session closes.
TEST_F(Rig, SigkillAfterAFailedStretchLeavesTheUntrustedVerdict) {
    const fs::path cap = WideCapture();
    const fs::path root = Tmp() / "kill_untrusted";
    const fs::path config =
        WriteConfig(Tmp() / "kill_untrusted.yaml", "odometry:\n  budget_ms: 1\n");
    test::rig::NotifySocket notify(Tmp() / "kill_untrusted.sock");
    const pid_t pid =
        Spawn(notify.Env() + kRig + " replay " + cap.string() + " --speed 1 --config " +
                  config.string() + " --session-root " + root.string(),
              Tmp() / "kill_untrusted.out", Tmp() / "kill_untrusted.err");
    EXPECT_TRUE(notify.WaitForReady()) << notify.messages();
    ASSERT_TRUE(fs::is_directory(root));
    const fs::path session = fs::directory_iterator(root)->path();
    EXPECT_TRUE(
        test::rig::WaitUntil([&] { return fs::exists(session / "odometry_verdict.json"); }));
    ::kill(pid, SIGKILL);
    EXPECT_EQ(Wait(pid), 128 + SIGKILL);
    EXPECT_FALSE(fs::exists(session / "session.json"));
    const auto v = nlohmann::json::parse(Slurp(session / "odometry_verdict.json"));
    EXPECT_EQ(v["verdict"], "untrusted");
    EXPECT_EQ(v["failed_stretches"].size(), 1u) << v.dump(1);
}

TEST_F(Rig, KeepsRunningThroughFaultsAndCountsThem) {
    // 20 % of the datagrams lost (the simulator), then in the recording: a corrupt stretch
    // (bytes flipped in 40 lidar packets at 2 s), the sensor silent for 3 s from 4 s, a restart
    // (another init_id) from 8 s, and the Go1's CAN silent for 5 s from 1 s.
    const fs::path cap = Capture("go1", 11, "network:\n  fragment: false\n  packet_loss: 0.2\n");
    const fs::path faulty = Tmp() / "faulty";
    fs::create_directories(faulty);
    for (const char* f : {"metadata.json", "capture.json"}) fs::copy(cap / f, faulty / f);
    const test::rig::PcapEdit edit = test::rig::EditLidarPcap(
        cap / "lidar.pcap", faulty / "lidar.pcap", /*corrupt_from_s=*/2.0, /*corrupt_packets=*/40,
        /*silent_from_s=*/4.0, /*silent_s=*/3.0, /*restart_from_s=*/8.0);
    ASSERT_GT(edit.corrupted, 30u);
    ASSERT_GT(edit.removed, 1000u);
    ASSERT_GT(edit.restarted, 500u);
    const size_t can_removed =
        test::rig::DropCandump(cap / "go1_can.log", faulty / "go1_can.log", 1.0, 5.0);
    ASSERT_GT(can_removed, 1000u);
    const fs::path config = WriteConfig(Tmp() / "faults.yaml", "");
    const nlohmann::json j =
        RigJson(kRig + " replay " + faulty.string() + " --speed max --json --config " +
                config.string() + " --session-root " + (Tmp() / "faults").string());
    ASSERT_FALSE(j.is_null());
    EXPECT_GT(j["scans"], 60);  // 11 s at 10 Hz less the 3 s of silence
    EXPECT_GT(j["keyframes_written"], 2);
    EXPECT_GT(j["frames_incomplete"], 10) << "packet loss not counted";
    EXPECT_GT(j["crc_failures"], 20) << "the corrupt stretch was not counted";
    EXPECT_GE(j["silences"], 1) << "the 3 s silence was not counted";
    EXPECT_GE(j["sensor_restarts"], 1) << "the init_id change was not taken as a restart";
    EXPECT_GT(j["can_timeouts"], 0) << "the CAN outage was not counted";
    // The session stays intact: complete and readable.
    const auto info =
        test::RunCommand(kCli + " session info --json " + j["session"].get<std::string>());
    ASSERT_EQ(info.exit_code, 0) << info.err;
    const auto s = nlohmann::json::parse(info.out);
    EXPECT_TRUE(s["complete"].get<bool>()) << info.out;
    EXPECT_EQ(s["keyframes"], j["keyframes_written"]);
}

TEST_F(Rig, DiskAlmostFullStopsKeyframesNotOdometry) {
    const fs::path cap = Capture("handheld", 6);
    const fs::path config = WriteConfig(Tmp() / "disk.yaml", "session:\n  min_free_mb: 1e9\n");
    const nlohmann::json j =
        RigJson(kRig + " replay " + cap.string() + " --speed max --json --config " +
                config.string() + " --session-root " + (Tmp() / "disk").string());
    ASSERT_FALSE(j.is_null());
    EXPECT_GT(j["scans"], 50);
    EXPECT_GT(j["keyframes"], 2);
    EXPECT_EQ(j["keyframes_written"], 0);
    EXPECT_EQ(j["keyframes_skipped_disk"], j["keyframes"]);
    const auto info =
        test::RunCommand(kCli + " session info --json " + j["session"].get<std::string>());
    EXPECT_EQ(info.exit_code, 0) << info.err;  // complete, with every scan's pose and no keyframe
}

TEST_F(Rig, SigtermFinishesTheSession) {
    const fs::path cap = Capture("handheld", 8);
    const fs::path root = Tmp() / "term";
    const fs::path config = WriteConfig(Tmp() / "term.yaml", "");
    test::rig::NotifySocket notify(Tmp() / "term.sock");
    const pid_t pid =
        Spawn(notify.Env() + kRig + " replay " + cap.string() + " --speed 1 --json --config " +
                  config.string() + " --session-root " + root.string(),
              Tmp() / "term.out", Tmp() / "term.err");
    // Part way: once the health thread reports 10 scans done (of about 80 at 1x).
    EXPECT_TRUE(notify.WaitForScans(10)) << notify.messages();
    ::kill(pid, SIGTERM);
    EXPECT_EQ(Wait(pid), 0) << Slurp(Tmp() / "term.err");
    const auto j = nlohmann::json::parse(Slurp(Tmp() / "term.out"));
    EXPECT_EQ(j["stop_signal"], SIGTERM);
    EXPECT_LT(j["scans"], 75);  // stopped part way
    const fs::path session = j["session"].get<std::string>();
    EXPECT_TRUE(fs::exists(session / "session.json"));
    const auto info = test::RunCommand(kCli + " session info --json " + session.string());
    ASSERT_EQ(info.exit_code, 0) << info.err;
    EXPECT_TRUE(nlohmann::json::parse(info.out)["complete"].get<bool>());
}

TEST_F(Rig, SigkillLeavesARecoverableSession) {
    const fs::path cap = Capture("handheld", 8);
    const fs::path root = Tmp() / "kill";
    const fs::path config = WriteConfig(Tmp() / "kill.yaml", "");
    test::rig::NotifySocket notify(Tmp() / "kill.sock");
    const pid_t pid =
        Spawn(notify.Env() + kRig + " replay " + cap.string() + " --speed 1 --config " +
                  config.string() + " --session-root " + root.string(),
              Tmp() / "kill.out", Tmp() / "kill.err");
    EXPECT_TRUE(notify.WaitForReady()) << notify.messages();
    ASSERT_TRUE(fs::is_directory(root));
    const fs::path session = fs::directory_iterator(root)->path();
    // Killed once two keyframes are complete: in the pose graph, the last of the files that
    // hold them (SessionWriter::Flush appends to each in turn).
    EXPECT_TRUE(test::rig::WaitUntil([&] {
        std::ifstream graph(session / "singlesession_posegraph.g2o");
        int vertices = 0;
        for (std::string line; std::getline(graph, line);) vertices += line.rfind("VERTEX", 0) == 0;
        return vertices >= 2;
    }));
    ::kill(pid, SIGKILL);
    EXPECT_EQ(Wait(pid), 128 + SIGKILL);
    EXPECT_FALSE(fs::exists(session / "session.json"));
    const auto info = test::RunCommand(kCli + " session info --json " + session.string());
    ASSERT_EQ(info.exit_code, 0) << info.err;
    const auto s = nlohmann::json::parse(info.out);
    EXPECT_FALSE(s["complete"].get<bool>());
    EXPECT_GE(s["keyframes"].get<int>(), 2) << info.out;
}

TEST_F(Rig, RecordingAsPcapWithItsJsonLikeTheOusterTools) {
    const fs::path cap = Capture("handheld", 4);
    const fs::path dir = Tmp() / "ouster_style";
    fs::create_directories(dir);
    fs::copy_file(cap / "lidar.pcap", dir / "walk.pcap", fs::copy_options::overwrite_existing);
    fs::copy_file(cap / "metadata.json", dir / "walk.json", fs::copy_options::overwrite_existing);
    const auto r = test::RunCommand(kCli + " odometry " + (dir / "walk.pcap").string() + " -o " +
                                    (dir / "offline").string() + " --budget-ms 1000 --json");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const fs::path config = WriteConfig(Tmp() / "pcap.yaml", "");
    const nlohmann::json j =
        RigJson(kRig + " replay " + (dir / "walk.pcap").string() + " --speed max --json --config " +
                config.string() + " --session-root " + (dir / "rig").string());
    ASSERT_FALSE(j.is_null());
    EXPECT_EQ(Slurp(fs::path(j["session"].get<std::string>()) / "trajectory.tum"),
              Slurp(dir / "offline" / "trajectory.tum"));
}

TEST_F(Rig, ACaptureWithoutDatagramsSaysHowManyRecordsWereDroppedAndWhy) {
    const fs::path cap = Capture("handheld", 4, "network:\n  fragment: false\n");
    // Every IPv4 header's version nibble made 6: nothing is IPv4 any more.
    std::ifstream f(cap / "lidar.pcap", std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(f)), {});
    for (size_t at = 24; at + 16 <= bytes.size();) {
        uint32_t caplen;
        std::memcpy(&caplen, bytes.data() + at + 8, 4);
        if (caplen > 14) bytes[at + 16 + 14] = char(0x65);
        at += 16 + caplen;
    }
    const fs::path dir = Tmp() / "broken";
    fs::create_directories(dir);
    std::ofstream(dir / "x.pcap", std::ios::binary) << bytes;
    fs::copy_file(cap / "metadata.json", dir / "x.json", fs::copy_options::overwrite_existing);
    const auto r = test::RunCommand(kCli + " odometry " + (dir / "x.pcap").string() + " -o " +
                                    (dir / "s").string());
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("dropped: "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("malformed IPv4"), std::string::npos) << r.err;
}

TEST_F(Rig, ShippedConfigurationsLoad) {
    for (const char* name : {"go1.yaml", "handheld.yaml"}) {
        const fs::path file = fs::path(BIMSLAM_SOURCE_ROOT) / "firmware/app/config" / name;
        const auto r = test::RunCommand(kRig + " live --print-config --config " + file.string());
        EXPECT_EQ(r.exit_code, 0) << name << ": " << r.err;
        EXPECT_NE(r.out.find("budget_ms: 50"), std::string::npos) << r.out;
    }
}

TEST_F(Rig, BadConfigurationExits2NamingFileLineAndKey) {
    struct Case {
        std::string text, expected;
    };
    const Case cases[] = {
        {"sensor:\n  lidar_prot: 7502\n", "bad.yaml:2: sensor.lidar_prot: unknown key"},
        {"odometry:\n  use_imu: maybe\n", "bad.yaml:2: odometry.use_imu: expected true or false"},
        {"odometry:\n  budget_ms: fast\n", "bad.yaml:2: odometry.budget_ms: expected a number"},
        {"queues:\n  scans: 0\n", "bad.yaml:2: queues.scans: 0 is out of range [1, 64]"},
        {"can:\n  source: usb\n", "bad.yaml:2: can.source: 'usb' is not one of"},
        {"odometry: 3\n", "bad.yaml:1: odometry: expected a map"},
        {"sensor: [\n", "bad.yaml:"},
    };
    for (const Case& c : cases) {
        const fs::path file = Tmp() / "bad.yaml";
        std::ofstream(file) << c.text;
        const auto r = test::RunCommand(kRig + " live --print-config --config " + file.string());
        EXPECT_EQ(r.exit_code, 2) << c.text;
        EXPECT_NE(r.err.find(c.expected), std::string::npos) << c.text << "\n" << r.err;
    }
    const auto r = test::RunCommand(kRig + " replay " + (Tmp() / "nothing").string());
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("nothing"), std::string::npos) << r.err;
}

// With the building's map package, so that the localiser's session files are compared too (issue
// 35, item 6: replay equals live).
TEST_F(Rig, LiveOnLoopbackFedByTheReplayerWritesTheReplaySession) {
    const fs::path cap = Capture("handheld", 8);
    const int port = test::rig::FreeUdpPortPair();
    const fs::path package = Package();
    ASSERT_TRUE(fs::exists(package));
    const fs::path config =
        WriteConfig(Tmp() / "live.yaml",
                    "sensor:\n  metadata: " + (cap / "metadata.json").string() +
                        "\n  bind_address: 127.0.0.1\n  lidar_port: " + std::to_string(port) +
                        "\n  imu_port: " + std::to_string(port + 1) +
                        "\ncan:\n  source: none\nlocalization:\n  map: " + package.string() + "\n");
    // The replay first: how many scans the live run must reach before it is stopped.
    const nlohmann::json replay =
        RigJson(kRig + " replay " + cap.string() + " --handheld --speed max --json --config " +
                config.string() + " --session-root " + (Tmp() / "replayed").string());
    ASSERT_FALSE(replay.is_null());
    // The live run, fed at 2x. Live, the rig drops new items on a full queue by design: at 3x
    // (until stop 62) its first seconds, the localiser's first keyframes, overflowed a queue
    // (QUEUE_OVERFLOW at scan 20, 2 items) in a CI run and in 1 of 2 runs on an idle machine, a
    // scan never came and the comparison could not be made. A run that drops is said and done
    // once more; a second one that drops fails the test.
    nlohmann::json live;
    for (int attempt = 1; attempt <= 2; ++attempt) {
        const std::string name = "live" + std::to_string(attempt);
        test::rig::NotifySocket notify(Tmp() / (name + ".sock"));
        const pid_t rig = Spawn(notify.Env() + kRig + " live --json --config " + config.string() +
                                    " --session-root " + (Tmp() / name).string(),
                                Tmp() / (name + ".out"), Tmp() / (name + ".err"));
        EXPECT_TRUE(notify.WaitForReady()) << notify.messages();  // its sockets are bound
        // Faster than real time the datagrams come in bursts and the rig reads the lidar and IMU
        // sockets in batches that interleave: an IMU sample routed before lidar packets that came
        // before it gave the live scans one sample more than the replay's, and other trajectories
        // (6 of 13 runs at 3x before stop 61).
        const auto sent = test::RunCommand(
            kCli + " ouster replay " + cap.string() + " --to 127.0.0.1 --lidar-port " +
            std::to_string(port) + " --imu-port " + std::to_string(port + 1) + " --json --speed 2");
        EXPECT_EQ(sent.exit_code, 0) << sent.err;
        // Stopped once it has done the replay's scans (a scan lost never comes: then the guard
        // ends the wait).
        const bool all = notify.WaitForScans(replay["scans"].get<int>());
        ::kill(rig, SIGINT);
        ASSERT_EQ(Wait(rig), 0) << Slurp(Tmp() / (name + ".err"));
        live = nlohmann::json::parse(Slurp(Tmp() / (name + ".out")));
        const bool dropped = live["queue_drops"].get<int64_t>() > 0;
        if (all && !dropped) break;
        std::cout << "live run " << attempt << ": " << live["scans"] << " of " << replay["scans"]
                  << " scans, " << live["queue_drops"] << " items dropped on full queues\n"
                  << notify.messages() << "\n";
        if (attempt == 2) {
            ADD_FAILURE() << "two live runs dropped data or lost scans at 2x";
        }
    }
    EXPECT_EQ(live["queue_drops"], 0);
    EXPECT_EQ(live["scans"], replay["scans"]);
    EXPECT_EQ(live["scans_dropped"], 0);
    const fs::path a = live["session"].get<std::string>(), b = replay["session"].get<std::string>();
    EXPECT_EQ(Slurp(a / "trajectory.tum"), Slurp(b / "trajectory.tum"));
    EXPECT_EQ(Slurp(a / "optimized_poses.txt"), Slurp(b / "optimized_poses.txt"));
    EXPECT_EQ(Slurp(a / "localization_states.csv"), Slurp(b / "localization_states.csv"));
    EXPECT_EQ(Slurp(a / "trajectory_bim_live.tum"), Slurp(b / "trajectory_bim_live.tum"));
    EXPECT_FALSE(Slurp(a / "localization_states.csv").empty());
    EXPECT_EQ(live["localization"]["states"], replay["localization"]["states"]);
    std::cout << "live on loopback: localisation " << live["localization"].dump() << "\n";
    std::cout << "live on loopback: latency p50 " << live["latency_ms_p50"] << " ms, p99 "
              << live["latency_ms_p99"] << " ms, CPU " << live["cpu_percent"] << " %\n";
}

// Datagrams that reach the two sockets faster than the ingest reads them are read in batches, one
// socket after the other, so their kernel arrival times go back between the sockets (by the
// batch's span). The ingest keeps its arrival clock in order, and the sensor clock does not jump:
// no CLOCK_JUMP. The 2-hour soak of stop 61 raised it 17 times in 19 minutes of a loaded machine,
// "the sensor clock jumped (the odometry started again)", while the odometry never started again;
// a replay at 8x gives such bursts every time.
TEST_F(Rig, DatagramsInBurstsOnItsTwoSocketsAreNoClockJump) {
    const fs::path cap = Capture("handheld", 4);
    const int port = test::rig::FreeUdpPortPair();
    const fs::path config =
        WriteConfig(Tmp() / "burst.yaml",
                    "sensor:\n  metadata: " + (cap / "metadata.json").string() +
                        "\n  bind_address: 127.0.0.1\n  lidar_port: " + std::to_string(port) +
                        "\n  imu_port: " + std::to_string(port + 1) + "\ncan:\n  source: none\n");
    test::rig::NotifySocket notify(Tmp() / "burst.sock");
    const pid_t rig =
        Spawn(notify.Env() + kRig + " live --json --no-record --config " + config.string(),
              Tmp() / "burst.out", Tmp() / "burst.err");
    EXPECT_TRUE(notify.WaitForReady()) << notify.messages();
    const auto sent = test::RunCommand(
        kCli + " ouster replay " + cap.string() + " --to 127.0.0.1 --speed 8 --lidar-port " +
        std::to_string(port) + " --imu-port " + std::to_string(port + 1));
    EXPECT_EQ(sent.exit_code, 0) << sent.err;
    EXPECT_TRUE(notify.WaitForScans(30)) << notify.messages();
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // a health period after it
    ::kill(rig, SIGINT);
    ASSERT_EQ(Wait(rig), 0) << Slurp(Tmp() / "burst.err");
    const auto live = nlohmann::json::parse(Slurp(Tmp() / "burst.out"));
    EXPECT_GE(live["scans"].get<int>(), 30);
    EXPECT_EQ(live["clock_jumps"], 0);
    EXPECT_EQ(Slurp(Tmp() / "burst.err").find("CLOCK_JUMP"), std::string::npos)
        << Slurp(Tmp() / "burst.err");
}

// A replay stopped by its --duration mid-recording: the scan the ingest was handing over when the
// stop came is the run's end, not a scan dropped by a full queue ("a replay loses nothing at any
// speed"). Until stop 61 it was counted as one (scans_dropped 1, queue_drops 1). 0.1 s of running:
// with 0.3 s, a quiet machine (2.5-3 ms a scan) replayed all 80 scans before the stop (stop 66).
TEST_F(Rig, AReplayStoppedByItsDurationDropsNothing) {
    const fs::path cap = Capture("handheld", 8);
    const nlohmann::json j = RigJson(kRig + " replay " + cap.string() +
                                     " --handheld --speed max --no-record --duration 0.1 --json");
    ASSERT_FALSE(j.is_null());
    EXPECT_LT(j["scans"].get<int>(), 80) << "the recording ended before the duration";
    EXPECT_EQ(j["scans_dropped"], 0) << j.dump(1);
    EXPECT_EQ(j["queue_drops"], 0) << j.dump(1);
}

TEST_F(Rig, RefusedSchedulingIsAWarningNotAFailure) {
    if (::geteuid() != 0) {
        GTEST_SKIP() << "runs the rig as nobody through setpriv, which needs root";
    }
    if (test::RunCommand("command -v setpriv").exit_code != 0) {
        GTEST_SKIP() << "setpriv (util-linux) is absent";
    }
    const fs::path cap = Capture("handheld", 4);
    const fs::path root = Tmp() / "nobody";
    fs::create_directories(root);
    fs::permissions(Tmp().path(), fs::perms::all, fs::perm_options::add);
    fs::permissions(root, fs::perms::all, fs::perm_options::add);
    const fs::path config = WriteConfig(Tmp() / "fifo.yaml",
                                        "runtime:\n  lock_memory: true\nthreads:\n  ingest: "
                                        "{priority: 80, cpu: 0}\n  odometry: {priority: 60}\n");
    fs::permissions(config, fs::perms::all, fs::perm_options::add);
    const auto r = test::RunCommand("setpriv --reuid=65534 --regid=65534 --clear-groups " + kRig +
                                    " replay " + cap.string() + " --speed max --json --config " +
                                    config.string() + " --session-root " + root.string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    const std::string warnings = j["warnings"].dump();
    EXPECT_NE(warnings.find("thread ingest: SCHED_FIFO priority 80 refused"), std::string::npos)
        << warnings;
    EXPECT_NE(warnings.find("mlockall refused"), std::string::npos) << warnings;
    EXPECT_GT(j["scans"], 30);
}

TEST_F(Rig, LiveWithoutCanInTheKernelSaysWhatToDo) {
    if (test::rig::KernelHasCan()) GTEST_SKIP() << "this kernel has CAN: nothing to refuse";
    const fs::path cap = Capture("handheld", 4);
    const fs::path config =
        WriteConfig(Tmp() / "socketcan.yaml",
                    "sensor:\n  metadata: " + (cap / "metadata.json").string() +
                        "\n  lidar_port: " + std::to_string(test::rig::FreeUdpPortPair()) +
                        "\ncan:\n  source: socketcan\n  interface: can0\n");
    const auto r = test::RunCommand(kRig + " live --config " + config.string() +
                                    " --session-root " + (Tmp() / "nocan").string());
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_NE(r.err.find("can0"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("can.source"), std::string::npos) << r.err;
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam
