// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Faults of firmware/app/README.md ("Faults") put into a running bimslam-rig, seen where an
// operator sees them: the rig_health_t messages on LCM (FAULT_* bits) and systemd's STATUS line.
// The rig keeps running and exits 0. Each fault is caused by what the rig is given, not by the
// machine's speed:
// - deadline misses: every scan waits can.wait_ms (100 ms) for CAN frames that never come
//   (can.source lcm, nobody sending), longer than odometry.deadline_ms (20 ms);
// - queue overflow: the scans of a recording sent at full speed into a scan queue of one slot,
//   drained one scan per 100 ms;
// - a wall-clock jump: the rig's CLOCK_REALTIME moved an hour ahead while it runs (libfaketime,
//   CLOCK_MONOTONIC left alone), as an NTP step would;
// - a stalled thread: one thread of the rig frozen from outside (ptrace), the watchdog's case.
#include <sys/ptrace.h>

#include <atomic>
#include <bimslam/rig_health_t.hpp>
#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <lcm/lcm-cpp.hpp>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "tests/integration/rig_test_support.hpp"

namespace bimslam {
namespace {
namespace BIMSLAM_UNITY_ID {
namespace fs = std::filesystem;
using test::rig::kCli;
using test::rig::kRig;

// Every rig_health_t of a rig, received in a thread of its own and kept.
class HealthSubscriber {
public:
    explicit HealthSubscriber(const std::string& url) : lcm_(url) {
        lcm_.lcm.subscribe("BIMSLAM_RIG_HEALTH", &HealthSubscriber::Handle, this);
        lcm_.Start();
    }
    // Waits until every bit of `bits` was latched (a guard `limit` against a hung test).
    bool WaitForLatched(int64_t bits, std::chrono::seconds limit = std::chrono::seconds(60)) {
        std::unique_lock<std::mutex> lock(m_);
        return cv_.wait_for(lock, limit, [&] { return (latched_ & bits) == bits; });
    }
    // Waits for a message for which `done` holds; the first such (nullopt: none before `limit`).
    std::optional<bimslam::rig_health_t> WaitFor(
        const std::function<bool(const bimslam::rig_health_t&)>& done,
        std::chrono::seconds limit = std::chrono::seconds(60)) {
        std::unique_lock<std::mutex> lock(m_);
        std::optional<bimslam::rig_health_t> found;
        cv_.wait_for(lock, limit, [&] {
            for (const bimslam::rig_health_t& h : all_) {
                if (done(h)) found = h;
                if (found) return true;
            }
            return false;
        });
        return found;
    }
    int messages() const { return messages_; }

private:
    void Handle(const lcm::ReceiveBuffer* b, const std::string&) {
        bimslam::rig_health_t h;
        if (h.decode(b->data, 0, int(b->data_size)) != int(b->data_size)) return;
        std::lock_guard<std::mutex> lock(m_);
        latched_ |= h.faults_latched;
        all_.push_back(h);
        ++messages_;
        cv_.notify_all();
    }

    std::mutex m_;
    std::condition_variable cv_;
    int64_t latched_ = 0;
    std::vector<bimslam::rig_health_t> all_;
    std::atomic<int> messages_{0};
    test::rig::LcmThread lcm_;  // last: its thread ends first
};

class RigFaults : public test::rig::RigFixture {};

TEST_F(RigFaults, DeadlineMissesAndAFullQueueShowOnLcmAndTheRigRunsOn) {
    const fs::path cap = Capture("handheld", 4);
    const int port = test::rig::FreeUdpPortPair();
    const fs::path config = test::rig::WriteConfig(
        Tmp() / "overload.yaml",
        "sensor:\n  metadata: " + (cap / "metadata.json").string() +
            "\n  bind_address: 127.0.0.1\n  lidar_port: " + std::to_string(port) +
            "\n  imu_port: " + std::to_string(port + 1) +
            "\ncan:\n  source: lcm\n  lcm_channel: BIMSLAM_NOBODY_" + std::to_string(::getpid()) +
            "\n  wait_ms: 100\nodometry:\n  budget_ms: 10\n  deadline_ms: 20\nqueues:\n  "
            "scans: 1\n");
    HealthSubscriber health(test::rig::PrivateLcmUrl());
    test::rig::NotifySocket notify(Tmp() / "overload.sock");
    const pid_t rig = test::rig::Spawn(
        notify.Env() + kRig + " live --json --no-record --config " + config.string(),
        Tmp() / "overload.out", Tmp() / "overload.err");
    EXPECT_TRUE(notify.WaitForReady()) << notify.messages();
    const auto sent = test::RunCommand(
        kCli + " ouster replay " + cap.string() + " --speed max --to 127.0.0.1 --lidar-port " +
        std::to_string(port) + " --imu-port " + std::to_string(port + 1));
    EXPECT_EQ(sent.exit_code, 0) << sent.err;
    const int64_t both =
        bimslam::rig_health_t::FAULT_DEADLINE_MISS | bimslam::rig_health_t::FAULT_QUEUE_OVERFLOW;
    EXPECT_TRUE(health.WaitForLatched(both)) << health.messages() << " health messages\n"
                                             << notify.messages();
    EXPECT_TRUE(notify.WaitFor([](const std::string& m) {
        return m.find("STATUS=") != m.npos && m.find("DEADLINE_MISS") != m.npos;
    })) << notify.messages();
    ::kill(rig, SIGINT);
    ASSERT_EQ(test::rig::Wait(rig), 0)
        << test::RunCommand("cat " + (Tmp() / "overload.err").string()).out;
    std::ifstream in(Tmp() / "overload.out");
    const nlohmann::json j = nlohmann::json::parse(in);
    EXPECT_GT(j["deadline_misses"].get<int>(), 0) << j.dump(1);
    EXPECT_GT(j["scans_dropped"].get<int>(), 0) << j.dump(1);
    EXPECT_GT(j["scans"].get<int>(), 0) << "the odometry stopped";
}

TEST_F(RigFaults, AWallClockJumpShowsOnLcm) {
    const fs::path preload = "/usr/lib/x86_64-linux-gnu/faketime/libfaketimeMT.so.1";
    if (!fs::exists(preload)) {
        GTEST_SKIP() << preload << " is missing (Debian's libfaketime: toolchain/install-deps.sh "
                     << "--test)";
    }
    const fs::path cap = Capture("handheld", 4);
    const fs::path config = test::rig::WriteConfig(Tmp() / "clock.yaml", "");
    const fs::path offset = Tmp() / "faketime";
    std::ofstream(offset) << "+0\n";
    HealthSubscriber health(test::rig::PrivateLcmUrl());
    test::rig::NotifySocket notify(Tmp() / "clock.sock");
    // The offset is read again at every call (FAKETIME_NO_CACHE); CLOCK_MONOTONIC is not faked.
    const std::string faketime = "LD_PRELOAD=" + preload.string() +
                                 " FAKETIME_TIMESTAMP_FILE=" + offset.string() +
                                 " FAKETIME_NO_CACHE=1 FAKETIME_DONT_FAKE_MONOTONIC=1";
    const pid_t rig =
        test::rig::Spawn(notify.Env(faketime) + kRig + " replay " + cap.string() +
                             " --speed 1 --json --no-record --config " + config.string(),
                         Tmp() / "clock.out", Tmp() / "clock.err");
    // A health period with the clock as it was, then the step.
    EXPECT_TRUE(notify.WaitForScans(1)) << notify.messages();
    EXPECT_EQ(notify.messages().find("CLOCK_JUMP"), std::string::npos) << notify.messages();
    std::ofstream(offset) << "+3600\n";
    EXPECT_TRUE(health.WaitForLatched(bimslam::rig_health_t::FAULT_CLOCK_JUMP))
        << health.messages() << " health messages\n"
        << notify.messages();
    EXPECT_TRUE(notify.WaitFor([](const std::string& m) {
        return m.find("STATUS=") != m.npos && m.find("CLOCK_JUMP") != m.npos;
    })) << notify.messages();
    EXPECT_EQ(test::rig::Wait(rig), 0)
        << test::RunCommand("cat " + (Tmp() / "clock.err").string()).out;
    EXPECT_NE(test::RunCommand("cat " + (Tmp() / "clock.err").string()).out.find("wall clock"),
              std::string::npos);
}

// One thread of a running process, stopped from outside by ptrace as a debugger stops it
// (PTRACE_SEIZE + PTRACE_INTERRUPT stop that thread only) until Resume or destruction.
class FrozenThread {
public:
    FrozenThread(pid_t pid, const std::string& comm) : tid_(FindThread(pid, comm)) {
        if (tid_ <= 0) {
            error_ = "no thread named '" + comm + "' in /proc/" + std::to_string(pid) + "/task";
        } else if (::ptrace(PTRACE_SEIZE, tid_, nullptr, nullptr) != 0 ||
                   ::ptrace(PTRACE_INTERRUPT, tid_, nullptr, nullptr) != 0) {
            error_ = std::string("ptrace: ") + std::strerror(errno);
            denied_ = errno == EPERM;
        } else {
            int status = 0;
            if (::waitpid(tid_, &status, __WALL) != tid_ || !WIFSTOPPED(status)) {
                error_ = "the thread did not stop";
            } else {
                frozen_ = true;
            }
        }
    }
    ~FrozenThread() { Resume(); }
    FrozenThread(const FrozenThread&) = delete;
    FrozenThread& operator=(const FrozenThread&) = delete;

    void Resume() {
        if (frozen_) ::ptrace(PTRACE_DETACH, tid_, nullptr, nullptr);
        frozen_ = false;
    }
    bool frozen() const { return frozen_; }
    bool denied() const { return denied_; }  // ptrace not allowed here (Yama, seccomp)
    const std::string& error() const { return error_; }

private:
    // The thread of `pid` whose name (pthread_setname_np) is `comm`; 0 when none.
    static pid_t FindThread(pid_t pid, const std::string& comm) {
        const fs::path task = "/proc/" + std::to_string(pid) + "/task";
        for (const auto& e : fs::directory_iterator(task)) {
            std::string name;
            std::getline(std::ifstream(e.path() / "comm"), name);
            if (name == comm) return pid_t(std::stoi(e.path().filename().string()));
        }
        return 0;
    }

    pid_t tid_;
    bool frozen_ = false, denied_ = false;
    std::string error_;
};

// The watchdog's rule (firmware/app/README.md, "Under systemd") in a running rig: one thread
// stops beating, the WATCHDOG=1 pings stop, FAULT_THREAD_STALLED names the thread on LCM and in
// STATUS; the thread runs again, the pings come back.
//
// How the thread is stalled: the session writer ("writer", which on the rig blocks on the disk's
// fsync) is stopped by ptrace, as a debugger stops one thread; nothing in the rig is there for
// the test. The alternatives were worse: SIGSTOP to one tid stops the whole process (group stop),
// so the health thread would stop too; a FIFO as the --lcm-log file does stall a real thread,
// but it is the LCM thread, which then cannot publish the fault; the session folder's name is
// the start time, so no blocking file can be put in its place beforehand. The rig runs live with
// no sensor, so every other thread idles, and the writer is stopped in its wait (holding no
// lock). Nothing here waits a fixed time: each step waits for the message that shows it.
TEST_F(RigFaults, AStalledThreadStopsTheWatchdogAndShowsOnLcm) {
    const fs::path cap = Capture("handheld", 1);
    const int port = test::rig::FreeUdpPortPair();
    const fs::path config = test::rig::WriteConfig(
        Tmp() / "stall.yaml",
        "sensor:\n  metadata: " + (cap / "metadata.json").string() +
            "\n  bind_address: 127.0.0.1\n  lidar_port: " + std::to_string(port) +
            "\n  imu_port: " + std::to_string(port + 1) + "\n");
    HealthSubscriber health(test::rig::PrivateLcmUrl());
    test::rig::NotifySocket notify(Tmp() / "stall.sock");
    const pid_t rig = test::rig::Spawn(
        notify.Env("WATCHDOG_USEC=1000000") + kRig + " live --handheld --json --session-root " +
            (Tmp() / "stall_sessions").string() + " --config " + config.string(),
        Tmp() / "stall.out", Tmp() / "stall.err");
    // A failed assertion below must not leave the rig running.
    bool waited = false;
    std::shared_ptr<void> kill_rig(nullptr, [rig, &waited](void*) {
        if (!waited && ::kill(rig, SIGKILL) == 0) test::rig::Wait(rig);
    });
    const auto ping = [](const std::string& m) { return m.find("WATCHDOG=1") != m.npos; };
    const auto stalled = [](const std::string& m) {
        return m.find("STATUS=") != m.npos && m.find("THREAD_STALLED") != m.npos;
    };
    ASSERT_TRUE(notify.WaitForReady()) << notify.messages();
    ASSERT_TRUE(notify.WaitFor(ping)) << "no watchdog ping while every thread runs\n"
                                      << notify.messages();

    FrozenThread writer(rig, "writer");
    if (writer.denied()) {
        GTEST_SKIP() << "this machine does not allow ptrace (" << writer.error() << ")";
    }
    ASSERT_TRUE(writer.frozen()) << writer.error();
    // The health period that finds the stale heartbeat says so in STATUS; from that moment on
    // no ping may come while the writer stays stopped: two more STATUS lines without one.
    ASSERT_TRUE(notify.WaitFor(stalled)) << notify.messages();
    int status_lines = 0, pings = 0;
    ASSERT_TRUE(notify.WaitFor([&](const std::string& m) {
        pings += ping(m) ? 1 : 0;
        return m.find("STATUS=") != m.npos && ++status_lines == 2;
    })) << notify.messages();
    EXPECT_EQ(pings, 0) << "WATCHDOG=1 sent while the writer was stopped\n" << notify.messages();
    // On LCM: the bit active, and the writer's own stall count.
    const int64_t bit = bimslam::rig_health_t::FAULT_THREAD_STALLED;
    const auto seen =
        health.WaitFor([bit](const bimslam::rig_health_t& h) { return (h.faults & bit) != 0; });
    ASSERT_TRUE(seen) << health.messages() << " health messages\n" << notify.messages();
    for (int i = 0; i < seen->num_threads; ++i) {
        EXPECT_EQ(seen->thread_stalls[size_t(i)], seen->thread_name[size_t(i)] == "writer" ? 1 : 0)
            << seen->thread_name[size_t(i)];
    }

    writer.Resume();
    EXPECT_TRUE(notify.WaitFor(ping)) << "the pings did not come back\n" << notify.messages();
    ::kill(rig, SIGINT);
    const int exit_code = test::rig::Wait(rig);
    waited = true;
    const std::string err = test::RunCommand("cat " + (Tmp() / "stall.err").string()).out;
    ASSERT_EQ(exit_code, 0) << err;
    EXPECT_NE(err.find("thread 'writer' has not beaten for"), std::string::npos) << err;
    std::ifstream in(Tmp() / "stall.out");
    const nlohmann::json j = nlohmann::json::parse(in);
    EXPECT_EQ(j["threads_stalled"], nlohmann::json({{"writer", 1}})) << j.dump(1);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam
