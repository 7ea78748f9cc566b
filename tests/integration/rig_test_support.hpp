// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// What the bimslam-rig integration tests share: simulated captures (made once per test process;
// ctest runs each test in its own), a test configuration (normal scheduling, a large budget so
// that results are deterministic, a private LCM port), processes run in the background, and
// edits of a recording (faults put into a pcap and a candump log).
#pragma once

#include <arpa/inet.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <cstring>
#include <deque>
#include <filesystem>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <string_view>
#include <thread>

#include "tests/support/test_support.hpp"

namespace bimslam::test::rig {
namespace fs = std::filesystem;

inline const std::string kCli = BIMSLAM_CLI_PATH;
inline const std::string kRig = BIMSLAM_RIG_PATH;

// An LCM URL no other test process uses (ctest -j runs several at once).
inline std::string PrivateLcmUrl() {
    return "udpm://239.255.76.67:" + std::to_string(20000 + ::getpid() % 20000) + "?ttl=0";
}

class RigFixture : public ::testing::Test {
protected:
    static void SetUpTestSuite() { tmp_ = std::make_unique<TempDir>(); }
    static void TearDownTestSuite() { tmp_.reset(); }
    static const TempDir& Tmp() { return *tmp_; }

    static fs::path Model() {
        const fs::path file = Tmp() / "building.ifc";
        if (!fs::exists(file)) {
            const auto r = RunCommand(kCli + " bim sample -o " + file.string());
            EXPECT_EQ(r.exit_code, 0) << r.err;
        }
        return file;
    }

    // The rig map package of Model() (`bimslam rig-map`), made once per test suite.
    static fs::path Package() {
        const fs::path file = Tmp() / "office.rigmap";
        if (!fs::exists(file)) {
            const auto r =
                RunCommand(kCli + " rig-map " + Model().string() + " -o " + file.string());
            EXPECT_EQ(r.exit_code, 0) << r.err;
        }
        return file;
    }

    // A capture of the default walk; `scenario` is extra scenario YAML.
    static fs::path Capture(const std::string& platform, int seconds,
                            const std::string& scenario = "") {
        const std::string name = "capture_" + platform + "_" + std::to_string(seconds) + "_" +
                                 std::to_string(std::hash<std::string>{}(scenario) % 1000);
        const fs::path dir = Tmp() / name;
        if (!fs::exists(dir / "ground_truth.tum")) {
            const fs::path yaml = Tmp() / (name + ".yaml");
            std::ofstream(yaml) << "platform: " << platform << "\n" << scenario;
            const auto r = RunCommand(
                kCli + " simulate --model " + Model().string() + " --scenario " + yaml.string() +
                " --duration " + std::to_string(seconds) + " -o " + dir.string() + " --overwrite");
            EXPECT_EQ(r.exit_code, 0) << r.err;
        }
        return dir;
    }

private:
    static inline std::unique_ptr<TempDir> tmp_;
};

// A test configuration: the normal scheduler, no mlockall, a budget far above any scan's time
// (results then do not depend on the machine's load), a private LCM port; then `extra`.
inline void Merge(YAML::Node base, const YAML::Node& extra) {
    for (const auto& kv : extra) {
        const std::string key = kv.first.as<std::string>();
        if (kv.second.IsMap() && base[key] && base[key].IsMap()) {
            Merge(base[key], kv.second);
        } else {
            base[key] = kv.second;
        }
    }
}
inline fs::path WriteConfig(const fs::path& path, const std::string& extra) {
    YAML::Node base = YAML::Load(
        "odometry:\n  budget_ms: 1000\n  deadline_ms: 2000\nlcm:\n  url: " + PrivateLcmUrl() +
        "\nruntime:\n  lock_memory: false\nthreads:\n  ingest: {priority: 0}\n  can: {priority: "
        "0}\n  odometry: {priority: 0}\n");
    if (!extra.empty()) Merge(base, YAML::Load(extra));
    std::ofstream(path) << base << "\n";
    return path;
}

// Runs a command that must succeed and print JSON.
inline nlohmann::json RigJson(const std::string& command) {
    const auto r = RunCommand(command);
    EXPECT_EQ(r.exit_code, 0) << command << "\n" << r.err;
    if (r.exit_code != 0) return nullptr;
    try {
        return nlohmann::json::parse(r.out);
    } catch (const nlohmann::json::exception& e) {
        ADD_FAILURE() << command << ": not JSON: " << r.out;
        return nullptr;
    }
}

// LCM on `url`, its messages handled in a thread of its own (Start, after subscribing) until
// destroyed. A subscriber declares it last, so that the thread ends before the rest goes.
class LcmThread {
public:
    explicit LcmThread(const std::string& url) : lcm(url) {
        EXPECT_TRUE(lcm.good()) << "LCM " << url << " (toolchain/setup-multicast.sh)";
    }
    ~LcmThread() {
        stop_ = true;
        if (thread_.joinable()) thread_.join();
    }
    void Start() {
        thread_ = std::thread([this] {
            while (!stop_) lcm.handleTimeout(50);
        });
    }
    lcm::LCM lcm;

private:
    std::thread thread_;
    std::atomic<bool> stop_{false};
};

// Processes in the background (tests/support): Spawn, and Wait for the exit code.
using ::bimslam::test::Spawn;
using ::bimslam::test::Wait;

// The systemd notify socket of a rig the test starts (`Env()` before its command): the test
// waits for what the rig says (READY=1 once its sockets are bound and its threads run, the
// health thread's STATUS lines with the scans done) instead of sleeping a fixed time.
// A thread reads the socket all the time, as systemd does: the rig's sd_notify blocks once the
// socket's queue is full (net.unix.max_dgram_qlen, 10 datagrams here), and a rig whose health
// thread blocks there stops its LCM health messages and cannot stop on SIGINT. So a test that
// waits on something else (LCM, a replay, the rig's exit) cannot stall the rig.
class NotifySocket {
public:
    explicit NotifySocket(const fs::path& path) : path_(path) {
        fd_ = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
        sockaddr_un a{};
        a.sun_family = AF_UNIX;
        std::strncpy(a.sun_path, path.c_str(), sizeof(a.sun_path) - 1);
        fs::remove(path);
        EXPECT_EQ(::bind(fd_, reinterpret_cast<sockaddr*>(&a), sizeof(a)), 0) << path;
        reader_ = std::thread([this] { Read(); });
    }
    ~NotifySocket() {
        stop_ = true;
        reader_.join();
        ::close(fd_);
    }
    NotifySocket(const NotifySocket&) = delete;
    NotifySocket& operator=(const NotifySocket&) = delete;

    // "env NOTIFY_SOCKET=... " to put before the rig's command.
    std::string Env(const std::string& more = "") const {
        return "env NOTIFY_SOCKET=" + path_.string() + " " + more + " ";
    }
    // Goes through the messages in order of arrival, from the first not yet gone through, until
    // one for which `done` holds; false when none came before `limit` (a guard against a hung
    // test, not a measurement: the test's assertions judge what happened).
    template <typename Done>
    bool WaitFor(Done done, std::chrono::seconds limit = std::chrono::seconds(60)) {
        const auto end = std::chrono::steady_clock::now() + limit;
        std::unique_lock<std::mutex> lock(m_);
        for (;;) {
            while (!queue_.empty()) {
                const std::string m = std::move(queue_.front());
                queue_.pop_front();
                messages_ += m + "\n";
                if (done(m)) return true;
            }
            if (!arrived_.wait_until(lock, end, [&] { return !queue_.empty(); })) return false;
        }
    }
    bool WaitForReady() {
        return WaitFor([](const std::string& m) { return m.find("READY=1") != m.npos; });
    }
    // Waits for a STATUS line of the health thread reporting at least `scans` scans done.
    bool WaitForScans(int scans) {
        return WaitFor([scans](const std::string& m) {
            const size_t at = m.find("STATUS=scans ");
            return at != m.npos && std::atoi(m.c_str() + at + 13) >= scans;
        });
    }
    // The messages gone through so far (WaitFor), one a line (for failure messages).
    const std::string& messages() const { return messages_; }

private:
    void Read() {
        while (!stop_) {
            pollfd p{fd_, POLLIN, 0};
            if (::poll(&p, 1, 100) <= 0) continue;  // 100 ms: only to see stop_
            char buf[4096];
            const ssize_t n = ::recv(fd_, buf, sizeof(buf), 0);
            if (n <= 0) continue;
            {
                std::lock_guard<std::mutex> lock(m_);
                queue_.emplace_back(buf, size_t(n));
            }
            arrived_.notify_all();
        }
    }

    fs::path path_;
    int fd_ = -1;
    std::mutex m_;
    std::condition_variable arrived_;
    std::deque<std::string> queue_;  // read, not yet gone through
    std::string messages_;           // gone through (the test's thread only)
    std::atomic<bool> stop_{false};
    std::thread reader_;
};

// Waits until `done()` holds (polled; a guard `limit` against a hung test); false when it never
// did.
template <typename Done>
bool WaitUntil(Done done, std::chrono::seconds limit = std::chrono::seconds(60)) {
    const auto end = std::chrono::steady_clock::now() + limit;
    while (!done()) {
        if (std::chrono::steady_clock::now() >= end) return false;
        ::usleep(20'000);  // polling for what the test waits for, not a guess of how long it takes
    }
    return true;
}

// Two consecutive free UDP ports on 127.0.0.1 (the first returned).
inline int FreeUdpPortPair() {
    for (int attempt = 0; attempt < 50; ++attempt) {
        const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
        sockaddr_in a{};
        a.sin_family = AF_INET;
        a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof(a));
        socklen_t n = sizeof(a);
        ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &n);
        const int port = ntohs(a.sin_port);
        const int fd2 = ::socket(AF_INET, SOCK_DGRAM, 0);
        a.sin_port = htons(uint16_t(port + 1));
        const bool ok =
            port < 65000 && ::bind(fd2, reinterpret_cast<sockaddr*>(&a), sizeof(a)) == 0;
        ::close(fd);
        ::close(fd2);
        if (ok) return port;
    }
    return 47502;
}

inline bool KernelHasCan() {
    const int fd = ::socket(29 /* PF_CAN */, SOCK_RAW, 1 /* CAN_RAW */);
    if (fd < 0) return false;
    ::close(fd);
    return true;
}

// Faults put into an unfragmented Ouster pcap (Ethernet, IPv4 without options, UDP; lidar on
// 7502, IMU on 7503): bytes flipped in `corrupt_packets` lidar packets from `corrupt_from_s` (a
// CRC-64 failure each), every record dropped for `silent_s` from `silent_from_s`, and from
// `restart_from_s` the lidar packets carry init_id + 1 with a zero CRC field (a sensor restart).
struct PcapEdit {
    size_t corrupted = 0, removed = 0, restarted = 0;
};
inline PcapEdit EditLidarPcap(const fs::path& in, const fs::path& out, double corrupt_from_s,
                              size_t corrupt_packets, double silent_from_s, double silent_s,
                              double restart_from_s) {
    std::ifstream f(in, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(f)), {});
    PcapEdit e;
    EXPECT_GE(bytes.size(), 24u);
    uint32_t magic;
    std::memcpy(&magic, bytes.data(), 4);
    EXPECT_TRUE(magic == 0xA1B2C3D4u || magic == 0xA1B23C4Du) << "a little-endian classic pcap";
    const double frac = magic == 0xA1B23C4Du ? 1e-9 : 1e-6;
    std::string result = bytes.substr(0, 24);
    double t0 = -1;
    for (size_t at = 24; at + 16 <= bytes.size();) {
        uint32_t sec, sub, caplen;
        std::memcpy(&sec, bytes.data() + at, 4);
        std::memcpy(&sub, bytes.data() + at + 4, 4);
        std::memcpy(&caplen, bytes.data() + at + 8, 4);
        std::string record = bytes.substr(at, 16 + caplen);
        at += 16 + caplen;
        const double t = sec + sub * frac;
        if (t0 < 0) t0 = t;
        const double rel = t - t0;
        if (rel >= silent_from_s && rel < silent_from_s + silent_s) {
            ++e.removed;
            continue;
        }
        const size_t payload = 16 + 14 + 20 + 8;
        if (record.size() < payload + 64) {
            result += record;
            continue;
        }
        const int port =
            (uint8_t(record[16 + 14 + 20 + 2]) << 8) | uint8_t(record[16 + 14 + 20 + 3]);
        if (port == 7502 && rel >= corrupt_from_s && e.corrupted < corrupt_packets) {
            record[payload + 1000] = char(record[payload + 1000] ^ 0x5A);
            ++e.corrupted;
        } else if (port == 7502 && rel >= restart_from_s) {
            record[payload + 4] = char(uint8_t(record[payload + 4]) + 1);  // init_id low byte
            std::memset(record.data() + record.size() - 8, 0, 8);          // no CRC
            ++e.restarted;
        }
        result += record;
    }
    std::ofstream(out, std::ios::binary) << result;
    return e;
}

// A candump -l log without the lines of [from_s, from_s + length_s) after its first line.
inline size_t DropCandump(const fs::path& in, const fs::path& out, double from_s, double length_s) {
    std::ifstream f(in);
    std::ofstream o(out);
    std::string line;
    double t0 = -1;
    size_t removed = 0;
    while (std::getline(f, line)) {
        const double t = std::stod(line.substr(1));
        if (t0 < 0) t0 = t;
        if (t - t0 >= from_s && t - t0 < from_s + length_s) {
            ++removed;
            continue;
        }
        o << line << "\n";
    }
    return removed;
}

}  // namespace bimslam::test::rig
