// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// bimslam-go1-bridge end to end: the real executable polls a fake Go1 on loopback (written here:
// it checks every HighCmd and answers it with a HighState of known, changing values and a valid
// CRC, and falls silent for a number of HighCmds), writes a candump log, and the drivers/can
// reader and Go1Decoder read it back: HighState values -> CAN frames -> decoder -> the same values
// within the DBC's scaling; alive counters consistent; UdpLinkOk false and lost samples counted
// during the silence. The fake Go1 sends the scrambled CRC, as the robot does. Also: the LCM sink,
// the status on LCM (CRC form, rejections by reason), SIGINT, --duration, and the exit codes.
// The fake's script is counted in HighCmds and the run ends when it has played (SIGINT): the
// counts asserted follow from what was sent, not from how fast the machine ran.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <bimslam/can_frame_t.hpp>
#include <bimslam/go1_bridge_status_t.hpp>
#include <cctype>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstring>
#include <fstream>
#include <iostream>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <thread>
#include <vector>

#include "algorithms/common/can_frame.hpp"
#include "drivers/can/candump.hpp"
#include "drivers/can/go1_decoder.hpp"
#include "drivers/go1/high_state.hpp"
#include "tests/integration/fake_go1.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::go1_bridge {
namespace {
namespace BIMSLAM_UNITY_ID {
using namespace ::bimslam::go1;        // the HighState codec (drivers/go1)
using namespace ::bimslam::go1::fake;  // the fake Go1 (fake_go1.hpp)

using can::Go1Sample;
using Clock = std::chrono::steady_clock;

const std::string kBridge = BIMSLAM_GO1_BRIDGE_PATH;

// Runs the bridge (`args` after its --go1 and --local-port) against `go1` until the fake has
// played its script, then stops it with SIGINT: no --duration, so how long the script takes is
// the machine's business, not the test's. Handles `lcm`'s messages meanwhile (when given), then
// drains what is still queued. A 60 s guard only ends a run whose script never ends.
test::CommandResult RunBridge(const FakeGo1& go1, const std::string& args,
                              lcm::LCM* lcm = nullptr) {
    test::TempDir tmp;
    const pid_t pid = test::Spawn(kBridge + " --go1 " + go1.endpoint() + " --local-port 0 " + args,
                                  tmp / "out", tmp / "err");
    const auto guard = Clock::now() + std::chrono::seconds(60);
    const auto handle = [&] {
        if (lcm != nullptr) {
            lcm->handleTimeout(20);
        } else {
            ::usleep(20'000);  // polling for the script's end, not a guess of how long it takes
        }
    };
    int status = 0;
    bool exited = false;  // before its end (a failure: the assertions on its output say why)
    while (!go1.Settled() && Clock::now() < guard && !exited) {
        handle();
        exited = ::waitpid(pid, &status, WNOHANG) == pid;
    }
    EXPECT_TRUE(go1.Settled()) << "the fake Go1's script did not end"
                               << (exited ? " (the bridge exited)" : " in 60 s") << ": "
                               << go1.commands.load() << " HighCmds received";
    if (!exited) {
        ::kill(pid, SIGINT);
        while (::waitpid(pid, &status, WNOHANG) == 0) handle();
    }
    while (lcm != nullptr && lcm->handleTimeout(100) > 0) {
    }
    test::CommandResult r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    const auto slurp = [](const std::filesystem::path& path) {
        std::ifstream f(path, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(f), {});
    };
    r.out = slurp(tmp / "out");
    r.err = slurp(tmp / "err");
    return r;
}

// The number printed right before `key` in the bridge's summary ("... 812 HighStates accepted
// ..."), or -1 when there is none.
int64_t SummaryNumber(const std::string& out, const std::string& key) {
    const size_t summary = out.find("summary:");
    const size_t at = summary == std::string::npos ? summary : out.find(key, summary);
    if (at == std::string::npos) return -1;
    size_t start = at;
    while (start > 0 && std::isdigit(static_cast<unsigned char>(out[start - 1]))) --start;
    return start == at ? -1 : std::stoll(out.substr(start, at - start));
}

struct Checked {
    int samples = 0;
    int with_data = 0;
    int link_down = 0;
    int lost_reported = 0;  // sum of STS_UdpRxLost
    int max_k = -1;
    int repeats = 0;  // samples with data whose k is not above the previous one's
};

// Decoded samples against the HighStates: every sample with data is some MakeHighState(k).
Checked CheckSamples(const std::vector<Go1Sample>& samples) {
    Checked c;
    int previous_counter = -1;
    for (const Go1Sample& d : samples) {
        ++c.samples;
        if (previous_counter >= 0) {
            EXPECT_EQ(d.counter, (previous_counter + 1) % 15) << "sample " << c.samples;
        }
        previous_counter = d.counter;
        if (d.fresh & can::kGroupStatus) c.lost_reported += d.udp_rx_lost;
        if (!d.udp_link_ok) {
            ++c.link_down;
            // Nothing this sample carries may be marked valid but the bridge's own status.
            EXPECT_EQ(d.valid & d.fresh & ~can::kGroupStatus, 0) << std::hex << d.fresh;
            continue;
        }
        if (!(d.fresh & d.valid & can::kGroupBodyVel)) continue;
        ++c.with_data;
        const int k = static_cast<int>(std::lround(d.vx / 0.001));
        // Each HighState is forwarded at most once, newest first: k only grows.
        if (k <= c.max_k) ++c.repeats;
        c.max_k = std::max(c.max_k, k);
        const HighState hs = MakeHighState(k);
        const double step = 0.000501;  // half a 0.001 step, and a little
        EXPECT_NEAR(d.vx, hs.velocity[0], step);
        EXPECT_NEAR(d.vy, hs.velocity[1], step);
        EXPECT_NEAR(d.yaw_rate, hs.yaw_speed, step);
        if (d.fresh & can::kGroupGyro) {
            for (size_t i = 0; i < 3; ++i) EXPECT_NEAR(d.gyro[i], hs.imu.gyroscope[i], step);
        }
        if (d.fresh & can::kGroupAccel) {
            for (size_t i = 0; i < 3; ++i) {
                EXPECT_NEAR(d.accel[i], hs.imu.accelerometer[i], 0.002501);
            }
        }
        if (d.fresh & can::kGroupQuat) {
            const double w = std::abs(hs.imu.quaternion[0]), z = std::abs(hs.imu.quaternion[3]);
            EXPECT_NEAR(d.quat_wxyz[0], w, 1e-4) << "k " << k;
            EXPECT_NEAR(d.quat_wxyz[3], z, 1e-4) << "k " << k;
        }
        if (d.fresh & can::kGroupFoot) {
            for (size_t i = 0; i < 4; ++i) {
                EXPECT_EQ(d.foot_force_raw[i], static_cast<uint16_t>(hs.foot_force[i]));
            }
            EXPECT_TRUE(d.foot_contact[1]);   // 500: always in contact
            EXPECT_FALSE(d.foot_contact[2]);  // 5: never
        }
        if (d.fresh & can::kGroupBodyState) {
            EXPECT_NEAR(d.vz, hs.velocity[2], step);
            EXPECT_NEAR(d.body_height, hs.body_height, step);
            EXPECT_NEAR(d.foot_raise_height, hs.foot_raise_height, step);
        }
        if (d.fresh & can::kGroupOdomXy) {
            EXPECT_NEAR(d.odom_x, hs.position[0], step) << "k " << k;
            EXPECT_NEAR(d.odom_y, hs.position[1], step) << "k " << k;
        }
        if (d.fresh & can::kGroupOdomZYaw) {
            EXPECT_NEAR(d.odom_z, hs.position[2], step);
            EXPECT_NEAR(d.odom_yaw, hs.imu.rpy[2], 0.0000501);
        }
        if (d.fresh & can::kGroupStatus) {
            EXPECT_EQ(d.mode, 1);
            EXPECT_EQ(d.gait, 2);
            EXPECT_EQ(d.battery_soc, 90);
            EXPECT_EQ(d.imu_temperature_c, 35);
        }
    }
    return c;
}

// The "late polls/ticks P/T" of the bridge's summary: T, the 5 ms ticks its loop skipped.
uint64_t LateTicks(const std::string& out) {
    const std::string key = "late polls/ticks ";
    const size_t at = out.find(key);
    EXPECT_NE(at, std::string::npos) << out;
    if (at == std::string::npos) return 0;
    const size_t slash = out.find('/', at + key.size());
    return std::stoull(out.substr(slash + 1));
}

TEST(Go1BridgeProgram, HelpAndBadUsage) {
    const auto help = test::RunCommand(kBridge + " --help");
    EXPECT_EQ(help.exit_code, 0);
    EXPECT_NE(help.out.find("--candump"), std::string::npos);
    EXPECT_NE(help.out.find("--poll-hz"), std::string::npos);
    // No sink, two sinks, a bad option value, an unknown option: 2.
    EXPECT_EQ(test::RunCommand(kBridge).exit_code, 2);
    EXPECT_EQ(test::RunCommand(kBridge + " --candump a.log --lcm udpm://").exit_code, 2);
    const auto hz = test::RunCommand(kBridge + " --candump /tmp/x.log --poll-hz 7");
    EXPECT_EQ(hz.exit_code, 2);
    EXPECT_NE(hz.err.find("--poll-hz: 7"), std::string::npos) << hz.err;
    const auto go1 = test::RunCommand(kBridge + " --candump /tmp/x.log --go1 localhost");
    EXPECT_EQ(go1.exit_code, 2);
    EXPECT_NE(go1.err.find("--go1: 'localhost'"), std::string::npos) << go1.err;
    EXPECT_EQ(test::RunCommand(kBridge + " --frobnicate").exit_code, 2);
}

TEST(Go1BridgeProgram, NoCanInTheKernelFailsNamingTheInterface) {
    const auto r = test::RunCommand(kBridge + " --can vcan_bimslam --duration 0.1");
    if (r.exit_code == 0) GTEST_SKIP() << "a CAN interface vcan_bimslam exists here";
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_NE(r.err.find("vcan_bimslam"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("failed: "), std::string::npos) << r.err;  // the errno's text
}

// Frames in a candump log, through the drivers/can reader (strict: every line must parse) and
// the decoder; the samples decoded.
struct DecodedLog {
    size_t frames = 0;
    bool truncated = false;
    std::vector<Go1Sample> samples;
    can::Go1DecoderStats stats;
};
DecodedLog DecodeLog(const std::string& path) {
    DecodedLog out;
    can::CandumpReader reader(path);
    can::Go1Decoder decoder;
    can::CandumpRecord record;
    const auto collect = [&](int n) {
        const auto ready = decoder.ready();
        for (int i = 0; i < n; ++i) out.samples.push_back(ready[ready.size() - n + i]);
    };
    while (reader.Next(record)) {
        ++out.frames;
        EXPECT_EQ(record.interface_name, "can0");
        collect(decoder.Feed(record.frame).samples);
    }
    collect(decoder.Flush());
    out.truncated = reader.truncated();
    out.stats = decoder.stats();
    return out;
}

// The whole chain against a Go1 that falls silent for 150 HighCmds. Every count asserted follows
// from what the fake Go1 sent (its script is counted in HighCmds) or from what the bridge says
// of its own loop (the ticks it skipped), not from how fast the machine ran: the figures
// themselves are printed.
TEST(Go1BridgeProgram, CandumpEndToEndAgainstAFakeGo1WithASilence) {
    test::TempDir tmp;
    const std::string log = (tmp / "go1.log").string();
    const Script script{300, 150, 300};  // 0.6 s, 0.3 s, 0.6 s at 500 Hz
    FakeGo1 go1(script);
    const auto r = RunBridge(go1, "--candump " + log + " --status-interval 0.5");
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    EXPECT_NE(r.out.find("summary: ran "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find(" (stopped by SIGINT)"), std::string::npos) << r.out;
    // The fake Go1 sends the scrambled CRC, as the robot does: accepted, and said.
    EXPECT_NE(r.out.find("HighState CRC form: scrambled\n"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find(" (0 with the plain CRC, "), std::string::npos) << r.out;
    EXPECT_EQ(go1.bad_commands, 0) << "the bridge sent something other than the idle HighCmd";
    EXPECT_EQ(go1.withheld, script.withhold);

    // What the bridge counted, against what the fake sent. Every answer was read (Settled).
    const int64_t polls = SummaryNumber(r.out, " HighCmds sent");
    const int64_t accepted = SummaryNumber(r.out, " HighStates accepted");
    const int64_t lost = SummaryNumber(r.out, " samples lost");
    const auto late_ticks = static_cast<int64_t>(LateTicks(r.out));
    const int64_t placeholders = SummaryNumber(r.out, " with the link down");
    EXPECT_EQ(SummaryNumber(r.out, " datagrams"), go1.replies) << r.out;
    EXPECT_EQ(accepted, go1.answered) << r.out;
    EXPECT_GE(polls, go1.commands.load()) << r.out;  // the last ones may not have been read
    // A poll period is lost unless a HighState came in it: at most `accepted` periods were not.
    EXPECT_GE(lost, polls - 1 - accepted) << r.out;
    EXPECT_GT(polls - 1 - accepted, script.withhold);
    EXPECT_NE(r.out.find("link losses "), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("link losses 0,"), std::string::npos) << r.out;
    // The silence as the bridge lived it: from the last answer before it (read before the
    // bridge sent its HighCmd s+1, s the first withheld) to the first after it (sent after
    // HighCmd s+W): more than W - 2 poll periods (2 ms; absolute deadlines, never a burst). The
    // link is down for all of it but its 6 ms timeout: more than 290 ms, so at least 57 of its
    // 5 ms ticks run inside it, less those the loop skipped (late ticks); every second tick is a
    // sample, sent as a placeholder.
    const int64_t down_ms = (script.withhold - 2) * 2 - 6;
    const int64_t min_placeholders = (down_ms / 5 - 1 - late_ticks) / 2;
    EXPECT_GE(placeholders, min_placeholders) << r.out;
    std::cout << go1.commands.load() << " HighCmds, " << accepted << " HighStates, " << lost
              << " lost, " << placeholders << " placeholder samples (at least " << min_placeholders
              << "), late ticks " << late_ticks << "\n";

    const DecodedLog decoded = DecodeLog(log);
    EXPECT_FALSE(decoded.truncated);
    EXPECT_EQ(static_cast<int64_t>(decoded.frames), SummaryNumber(r.out, " frames, ")) << r.out;
    EXPECT_EQ(decoded.stats.foreign_id, 0u);
    EXPECT_EQ(decoded.stats.crc, 0u);
    EXPECT_EQ(decoded.stats.counter_resync, 0u);
    EXPECT_EQ(decoded.stats.counter_repeat, 0u);
    // Frames go missing (counter_lost) or come after their sample was given up on (late) only
    // when the bridge's loop fell behind and skipped 5 ms ticks, which a loaded machine can
    // cause (it catches up rather than bursting, and reports it); each skipped tick can cost
    // every message due in it one transmission. Nothing else may go wrong.
    std::string stats;
    decoded.stats.ForEach([&](const char* name, uint64_t v) {
        stats += std::string(name) + " " + std::to_string(v) + ", ";
    });
    EXPECT_LE(decoded.stats.counter_lost + decoded.stats.late,
              static_cast<uint64_t>(late_ticks) * can::kGo1Messages)
        << stats << "\n"
        << r.out;
    EXPECT_EQ(decoded.stats.Faults() - decoded.stats.late, 0u) << stats << "\n" << r.out;

    const Checked c = CheckSamples(decoded.samples);
    EXPECT_LE(c.samples, SummaryNumber(r.out, " samples (")) << r.out;
    EXPECT_LE(c.link_down, placeholders);
    EXPECT_GE(c.link_down, 1);
    EXPECT_GE(c.with_data, 1);
    EXPECT_LE(c.with_data, accepted);
    EXPECT_EQ(c.repeats, 0) << "a HighState forwarded twice, or an older one after a newer";
    EXPECT_GT(c.lost_reported, 0);
    EXPECT_LE(c.lost_reported, lost);
    EXPECT_GE(c.max_k, go1.answered_before_silence) << "no data from after the silence";
    EXPECT_LT(c.max_k, go1.answered);
}

// --duration ends the run by itself, and the log is complete: every frame the summary counts.
TEST(Go1BridgeProgram, DurationEndsTheRunWithACompleteLog) {
    test::TempDir tmp;
    const std::string log = (tmp / "go1.log").string();
    FakeGo1 go1(Script{1'000'000});
    const auto r = test::RunCommand(kBridge + " --go1 " + go1.endpoint() +
                                    " --local-port 0 --candump " + log + " --duration 0.3");
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    EXPECT_NE(r.out.find("summary: ran "), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("stopped by"), std::string::npos) << r.out;
    const DecodedLog decoded = DecodeLog(log);
    EXPECT_FALSE(decoded.truncated);
    EXPECT_GT(decoded.frames, 0u);
    EXPECT_EQ(static_cast<int64_t>(decoded.frames), SummaryNumber(r.out, " frames, ")) << r.out;
}

// Collects can_frame_t messages as CanFrames (untyped subscription, decoded here).
struct FrameCollector {
    std::vector<common::CanFrame> frames;
    int bad = 0;  // undecodable, or schema_version / publish time wrong

    void Handle(const lcm::ReceiveBuffer* rbuf, const std::string& /*channel*/) {
        can_frame_t m;
        if (m.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)) < 0 ||
            m.schema_version != can_frame_t::SCHEMA_VERSION || m.publish_time_ns <= 0) {
            ++bad;
            return;
        }
        common::CanFrame f;
        f.timestamp_ns = m.sample_time_ns;
        f.id = static_cast<uint32_t>(m.id);
        f.extended = (m.flags & can_frame_t::FLAG_EFF) != 0;
        f.remote = (m.flags & can_frame_t::FLAG_RTR) != 0;
        f.error = (m.flags & can_frame_t::FLAG_ERR) != 0;
        f.fd = (m.flags & can_frame_t::FLAG_FD) != 0;
        f.len = static_cast<uint8_t>(m.len);
        for (size_t i = 0; i < f.data.size(); ++i) f.data[i] = m.data[i];
        frames.push_back(f);
    }
};

// The LCM sink: every frame as a bimslam::can_frame_t on a channel of its own. UDP multicast
// over loopback; a machine without a multicast route skips, saying so.
TEST(Go1BridgeProgram, LcmSinkPublishesEveryFrame) {
    const std::string url = "udpm://239.255.76.67:7667?ttl=0";
    lcm::LCM lcm(url);
    if (!lcm.good()) {
        GTEST_SKIP() << "LCM " << url << " is not usable here (no multicast route: run "
                     << "toolchain/setup-multicast.sh as root)";
    }
    const std::string channel = "BIMSLAM_GO1_BRIDGE_TEST_" + std::to_string(::getpid());
    FrameCollector collector;
    lcm.subscribe(channel, &FrameCollector::Handle, &collector);

    FakeGo1 go1(Script{300});  // 0.6 s at 500 Hz
    const test::CommandResult result =
        RunBridge(go1, "--lcm '" + url + "' --lcm-channel " + channel, &lcm);
    ASSERT_EQ(result.exit_code, 0) << result.out << result.err;
    EXPECT_EQ(collector.bad, 0);
    const std::vector<common::CanFrame>& frames = collector.frames;

    can::Go1Decoder decoder;
    std::vector<Go1Sample> samples;
    for (const common::CanFrame& f : frames) {
        const int n = decoder.Feed(f).samples;
        const auto ready = decoder.ready();
        for (int i = 0; i < n; ++i) samples.push_back(ready[ready.size() - n + i]);
    }
    // The bridge published every frame it made (its summary: "N frames, N to lcm ..., 0
    // failed"). About 960 a second (how many: the machine's, printed); UDP multicast on
    // loopback loses none on an idle machine, but under load the receiving socket's buffer
    // overflows while this process is not scheduled (825 of 960 arrived at load 9): a loss is
    // the transport's, so the share received is only checked to be most of them.
    const int64_t made = SummaryNumber(result.out, " frames, ");
    std::cout << made << " frames made, " << frames.size() << " received\n";
    EXPECT_GT(made, 0) << result.out;
    EXPECT_EQ(SummaryNumber(result.out, " to LCM " + url), made) << result.out;
    EXPECT_NE(result.out.find(channel + ", 0 failed"), std::string::npos) << result.out;
    EXPECT_GT(static_cast<int64_t>(frames.size()), made / 2) << result.out;
    EXPECT_LE(static_cast<int64_t>(frames.size()), made) << result.out;
    EXPECT_EQ(decoder.stats().crc, 0u);
    const Checked c = CheckSamples(samples);
    EXPECT_GE(c.with_data, 1);
    EXPECT_LE(c.with_data, go1.answered);
    EXPECT_EQ(c.repeats, 0);
}

struct StatusCollector {
    std::vector<go1_bridge_status_t> statuses;
    int undecodable = 0;

    void Handle(const lcm::ReceiveBuffer* rbuf, const std::string& /*channel*/) {
        go1_bridge_status_t m;
        if (m.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)) < 0) {
            ++undecodable;
        } else {
            statuses.push_back(m);
        }
    }
};

// The bridge's status on LCM (go1_bridge_status_t) from the real program: a Go1 that sends the
// plain CRC, with a bit flipped in every 40th answer and a wrong head in every 60th. The status
// says which CRC form the robot sends and counts each rejection by its reason; the candump log
// carries no frame made from a rejected answer. Its own channel, so that other bridges under
// test do not mix in.
TEST(Go1BridgeProgram, StatusOnLcmSaysTheCrcFormAndCountsRejectionsByReason) {
    const std::string url = "udpm://239.255.76.67:7667?ttl=0";
    lcm::LCM lcm(url);
    if (!lcm.good()) {
        GTEST_SKIP() << "LCM " << url << " is not usable here (no multicast route: run "
                     << "toolchain/setup-multicast.sh as root)";
    }
    const std::string channel = "BIMSLAM_GO1_BRIDGE_STATUS_TEST_" + std::to_string(::getpid());
    StatusCollector collector;
    lcm.subscribe(channel, &StatusCollector::Handle, &collector);

    test::TempDir tmp;
    FakeGo1 go1(Script{480}, CrcForm::kPlain, InjectedFaults{40, 60});  // 0.96 s at 500 Hz
    const test::CommandResult result =
        RunBridge(go1,
                  "--candump " + (tmp / "go1.log").string() + " --status-lcm '" + url +
                      "' --status-lcm-channel " + channel + " --status-interval 0",
                  &lcm);
    ASSERT_EQ(result.exit_code, 0) << result.out << result.err;
    // 480 answers: 12 with a flipped bit (every 40th), 4 more with a wrong head (every 60th,
    // not the 4 flipped already), 464 intact. The bridge read them all (the script settled).
    EXPECT_EQ(go1.flipped, 12);
    EXPECT_EQ(go1.wrong_heads, 4);
    EXPECT_EQ(SummaryNumber(result.out, " datagrams"), 480) << result.out;
    EXPECT_EQ(SummaryNumber(result.out, " with the plain CRC"), 464) << result.out;
    EXPECT_EQ(SummaryNumber(result.out, " rejected for CRC"), 12) << result.out;
    EXPECT_EQ(SummaryNumber(result.out, " for head"), 4) << result.out;
    EXPECT_EQ(SummaryNumber(result.out, " for size"), 0) << result.out;
    EXPECT_EQ(SummaryNumber(result.out, " for levelFlag"), 0) << result.out;

    EXPECT_EQ(collector.undecodable, 0);
    const std::vector<go1_bridge_status_t>& statuses = collector.statuses;
    // At least the final status, sent at exit; the periodic ones before it in order.
    ASSERT_GE(statuses.size(), 1u) << result.out;
    for (size_t i = 1; i < statuses.size(); ++i) {
        EXPECT_GT(statuses[i].sequence, statuses[i - 1].sequence);
        EXPECT_GE(statuses[i].uptime_ns, statuses[i - 1].uptime_ns);
    }
    // The last status received: the final one unless multicast lost it, so its counts are at
    // most the summary's (which are exact, above).
    const go1_bridge_status_t& last = statuses.back();
    EXPECT_EQ(last.schema_version, go1_bridge_status_t::SCHEMA_VERSION);
    EXPECT_EQ(last.crc_forms_seen, go1_bridge_status_t::CRC_FORM_PLAIN);
    EXPECT_EQ(last.highstates_crc_scrambled, 0);
    EXPECT_GT(last.highstates_crc_plain, 0);
    EXPECT_LE(last.highstates_crc_plain, 464);
    EXPECT_TRUE(last.crc_check);
    // Every rejection counted under its own reason.
    EXPECT_GT(last.rejected_crc, 0);
    EXPECT_LE(last.rejected_crc, go1.flipped);
    EXPECT_GT(last.rejected_head, 0);
    EXPECT_LE(last.rejected_head, go1.wrong_heads);
    EXPECT_EQ(last.rejected_level_flag, 0);
    EXPECT_EQ(last.rejected_size, 0);
    EXPECT_EQ(last.datagrams, last.highstates_crc_plain + last.rejected_crc + last.rejected_head);
    EXPECT_NE(result.out.find("HighState CRC form: plain\n"), std::string::npos) << result.out;

    // The log: only frames made from intact answers (their values are some MakeHighState(k)).
    const Checked c = CheckSamples(DecodeLog((tmp / "go1.log").string()).samples);
    EXPECT_GE(c.with_data, 1);
    EXPECT_EQ(c.repeats, 0);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::go1_bridge
