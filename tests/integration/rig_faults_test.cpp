// Faults of firmware/app/README.md ("Faults") put into a running bimslam-rig, seen where an
// operator sees them: the rig_health_t messages on LCM (FAULT_* bits) and systemd's STATUS line.
// The rig keeps running and exits 0. Each fault is caused by what the rig is given, not by the
// machine's speed:
// - deadline misses: every scan waits can.wait_ms (100 ms) for CAN frames that never come
//   (can.source lcm, nobody sending), longer than odometry.deadline_ms (20 ms);
// - queue overflow: the scans of a recording sent at full speed into a scan queue of one slot,
//   drained one scan per 100 ms;
// - a wall-clock jump: the rig's CLOCK_REALTIME moved an hour ahead while it runs (libfaketime,
//   CLOCK_MONOTONIC left alone), as an NTP step would.
#include <atomic>
#include <bimslam/rig_health_t.hpp>
#include <chrono>
#include <condition_variable>
#include <lcm/lcm-cpp.hpp>
#include <mutex>
#include <thread>

#include "tests/integration/rig_test_support.hpp"

namespace bimslam {
namespace {
namespace fs = std::filesystem;
using test::rig::kCli;
using test::rig::kRig;

// Every rig_health_t of a rig, in a thread of its own: the FAULT_* bits ever latched.
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
    int messages() const { return messages_; }

private:
    void Handle(const lcm::ReceiveBuffer* b, const std::string&) {
        bimslam::rig_health_t h;
        if (h.decode(b->data, 0, int(b->data_size)) != int(b->data_size)) return;
        std::lock_guard<std::mutex> lock(m_);
        latched_ |= h.faults_latched;
        ++messages_;
        cv_.notify_all();
    }

    std::mutex m_;
    std::condition_variable cv_;
    int64_t latched_ = 0;
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

}  // namespace
}  // namespace bimslam
