// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The bridge core: HighState -> Go1Sample mapping (checked through the real Go1Encoder and
// Go1Decoder), contact hysteresis, alive counter, link loss (UdpLinkOk, lost count, bridge state,
// no stale values marked valid), rejected datagrams by reason, both CRC forms, the LCM status
// message, odometry reset.
#include "firmware/go1_bridge/bridge.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <optional>
#include <vector>

#include "algorithms/common/status.hpp"
#include "drivers/can/go1_decoder.hpp"
#include "firmware/go1_bridge/status_lcm.hpp"

namespace bimslam::go1_bridge {
namespace {
namespace BIMSLAM_UNITY_ID {

using can::Go1Sample;
using common::CanFrame;

constexpr int64_t kMs = 1'000'000;
constexpr int64_t kT0 = 1'000 * kMs;     // a multiple of every period
constexpr int64_t kRxDelayNs = 150'000;  // poll to HighState receive

// The Go1 identifiers the tests look at, and the Valid bit (byte 1, bit 4) where the message has
// one (specs/go1-can.md).
constexpr uint32_t kSync = 0x0F0, kBodyVel = 0x100, kGyro = 0x110, kQuat = 0x112, kFoot = 0x120,
                   kOdomXy = 0x130, kStatus = 0x140;
bool HasValidBit(uint32_t id) { return id != kSync && id != kFoot && id != kStatus; }
bool ValidBit(const CanFrame& f) { return (f.data[1] & 0x10) != 0; }
uint8_t Counter(const CanFrame& f) { return f.data[1] & 0x0f; }

// A plausible HighState whose values follow k (the poll index).
HighState MakeHighState(int k) {
    HighState s;
    s.head = {0xfe, 0xef};
    s.level_flag = kHighLevel;
    const float t = 0.002f * static_cast<float>(k);
    s.velocity = {0.5f + 0.001f * static_cast<float>(k % 100), -0.25f, 0.0625f};
    s.yaw_speed = 0.3f - 0.002f * static_cast<float>(k % 50);
    s.body_height = 0.28f;
    s.foot_raise_height = 0.08f;
    s.imu.gyroscope = {0.01f * static_cast<float>(k % 30), -0.2f, 0.15f};
    s.imu.accelerometer = {0.3f, -0.1f, 9.81f};
    const float half = 0.5f * 0.1f * static_cast<float>(k % 20);  // yaw rotation
    s.imu.quaternion = {std::cos(half), 0.f, 0.f, std::sin(half)};
    s.imu.rpy = {0.01f, -0.02f, 2.f * half};
    s.imu.temperature = 41;
    s.foot_force = {100, 5, 100, 5};
    s.position = {0.01f * static_cast<float>(k), 0.005f * static_cast<float>(k), 0.001f};
    (void)t;
    s.mode = 2;
    s.gait_type = 1;
    s.bms.soc = 77;
    return s;
}

std::array<uint8_t, kHighStateSize> Bytes(const HighState& s) {
    std::array<uint8_t, kHighStateSize> b{};
    SerializeHighState(s, b);
    return b;
}

// Drives a Bridge on a simulated clock: a poll every poll period (answered by `peer`), a tick
// every 5 ms; the frames go through a Go1Decoder.
class Harness {
public:
    explicit Harness(const BridgeConfig& config = {}) : bridge(config) {}

    // Returns the HighState the Go1 answers poll k with, or nothing (silence).
    std::function<std::optional<HighState>(int)> peer = [](int k) {
        return std::optional<HighState>(MakeHighState(k));
    };

    void Run(int64_t duration_ns) {
        const int64_t end = now + duration_ns;
        while (now < end) {
            now += kMs / 2;
            if (now % bridge.config().poll_period_ns == 0) {
                bridge.OnPoll(now);
                const int k = polls++;
                if (auto hs = peer(k)) {
                    const int64_t rx = now + kRxDelayNs;
                    sent_by_rx_us[rx / 1000] = *hs;
                    bridge.OnDatagram(Bytes(*hs), rx);
                }
            }
            if (now % bridge.tick_ns() == 0) {
                std::array<CanFrame, Bridge::kMaxFramesPerTick> out{};
                const size_t n = bridge.OnTick(now, now, out);
                tick_frames.push_back(n);
                for (size_t i = 0; i < n; ++i) {
                    frames.push_back(out[i]);
                    Collect(decoder.Feed(out[i]).samples);
                }
                Collect(decoder.Tick(now + kMs));
            }
        }
    }

    void Collect(int count) {
        const auto ready = decoder.ready();
        for (int i = 0; i < count; ++i) decoded.push_back(ready[ready.size() - count + i]);
    }

    Bridge bridge;
    can::Go1Decoder decoder;
    int64_t now = kT0;
    int polls = 0;
    std::map<int64_t, HighState> sent_by_rx_us;
    std::vector<CanFrame> frames;
    std::vector<size_t> tick_frames;
    std::vector<Go1Sample> decoded;
};

TEST(BridgeConfig, RejectsBadValuesNamingTheField) {
    const auto message = [](const BridgeConfig& c) -> std::string {
        try {
            c.Validate();
        } catch (const common::Error& e) {
            return e.what();
        }
        return "";
    };
    EXPECT_EQ(message(BridgeConfig{}), "");
    BridgeConfig c;
    c.poll_period_ns = 50 * kMs;
    EXPECT_NE(message(c).find("poll_period_ns: 50000000"), std::string::npos) << message(c);
    c = BridgeConfig{};
    c.link_timeout_ns = kMs;
    EXPECT_NE(message(c).find("link_timeout_ns"), std::string::npos);
    c = BridgeConfig{};
    c.contact_on_raw = 10;
    c.contact_off_raw = 20;
    EXPECT_NE(message(c).find("contact_on_raw/contact_off_raw: 10/20"), std::string::npos);
    c = BridgeConfig{};
    c.odom_jump_m = -1;
    EXPECT_NE(message(c).find("odom_jump_m"), std::string::npos);
    EXPECT_EQ(BridgeConfig{}.EffectiveLinkTimeoutNs(), 6 * kMs);
}

TEST(Bridge, MapsHighStateToTheCanSignalsWithinScaling) {
    Harness h;
    h.Run(500 * kMs);
    EXPECT_EQ(h.bridge.state(), BridgeState::kRunning);
    ASSERT_GT(h.decoded.size(), 40u);
    EXPECT_EQ(h.decoder.stats().Faults(), 0u);
    EXPECT_EQ(h.decoder.stats().samples_incomplete, 0u);
    int checked_odom = 0;
    for (const Go1Sample& d : h.decoded) {
        ASSERT_TRUE(d.fresh & can::kGroupSync);
        // SYNC BridgeTime is the HighState's receive time in µs: find the HighState.
        const auto it = h.sent_by_rx_us.find(d.bridge_time_ns / 1000);
        ASSERT_NE(it, h.sent_by_rx_us.end()) << d.bridge_time_ns;
        const HighState& hs = it->second;
        EXPECT_TRUE(d.udp_link_ok);
        EXPECT_TRUE(d.highstate_crc_ok);
        EXPECT_EQ(d.valid, can::kAllGroups);
        EXPECT_LE(d.sample_age_us, 2000u);  // received within the last poll period
        EXPECT_NEAR(d.vx, hs.velocity[0], 0.000501);
        EXPECT_NEAR(d.vy, hs.velocity[1], 0.000501);
        EXPECT_NEAR(d.yaw_rate, hs.yaw_speed, 0.000501);
        for (size_t i = 0; i < 3; ++i) {
            EXPECT_NEAR(d.gyro[i], hs.imu.gyroscope[i], 0.000501);
            EXPECT_NEAR(d.accel[i], hs.imu.accelerometer[i], 0.002501);
        }
        for (size_t i = 0; i < 4; ++i) {
            EXPECT_NEAR(d.quat_wxyz[i], hs.imu.quaternion[i], 1e-4) << i;
            EXPECT_EQ(d.foot_force_raw[i], static_cast<uint16_t>(hs.foot_force[i]));
            EXPECT_EQ(d.foot_contact[i], hs.foot_force[i] >= 40);
        }
        if (d.fresh & can::kGroupOdomXy) {
            ++checked_odom;
            EXPECT_NEAR(d.odom_x, hs.position[0], 0.000501);
            EXPECT_NEAR(d.odom_y, hs.position[1], 0.000501);
            EXPECT_NEAR(d.vz, hs.velocity[2], 0.000501);
            EXPECT_NEAR(d.body_height, hs.body_height, 0.000501);
            EXPECT_NEAR(d.foot_raise_height, hs.foot_raise_height, 0.000501);
            EXPECT_NEAR(d.odom_z, hs.position[2], 0.000501);
            EXPECT_NEAR(d.odom_yaw, hs.imu.rpy[2], 0.0000501);
        }
        if (d.fresh & can::kGroupStatus) {
            EXPECT_EQ(d.mode, 2);
            EXPECT_EQ(d.gait, 1);
            EXPECT_EQ(d.battery_soc, 77);
            EXPECT_EQ(d.imu_temperature_c, 41);
        }
    }
    EXPECT_GT(checked_odom, 20);
    // 10 ms per CAN sample, 2 ms per poll: 5 HighStates per sample, one forwarded.
    EXPECT_EQ(h.bridge.stats().samples, 50u);
    EXPECT_EQ(h.bridge.stats().highstates, 250u);
    EXPECT_EQ(h.bridge.stats().lost, 0u);
    EXPECT_EQ(h.bridge.stats().placeholder_samples, 0u);
}

TEST(Bridge, QuaternionIsNormalisedAndFlippedToNonNegativeW) {
    Harness h;
    h.peer = [](int k) {
        HighState s = MakeHighState(k);
        s.imu.quaternion = {-0.9f * 1.05f, 0.3f * 1.05f, -0.2f * 1.05f, 0.1f * 1.05f};
        return std::optional<HighState>(s);
    };
    h.Run(100 * kMs);
    const Go1Sample& last = h.bridge.last_sample();
    const double n = std::sqrt(0.81 + 0.09 + 0.04 + 0.01);
    EXPECT_NEAR(last.quat_wxyz[0], 0.9 / n, 1e-6);
    EXPECT_NEAR(last.quat_wxyz[1], -0.3 / n, 1e-6);
    EXPECT_NEAR(last.quat_wxyz[2], 0.2 / n, 1e-6);
    EXPECT_NEAR(last.quat_wxyz[3], -0.1 / n, 1e-6);
    ASSERT_FALSE(h.decoded.empty());
    EXPECT_NEAR(h.decoded.back().quat_wxyz[0], 0.9 / n, 1e-4);
    EXPECT_NEAR(h.decoded.back().quat_wxyz[1], -0.3 / n, 1e-4);

    // A quaternion far from unit norm, or NaN values: the group goes out not valid, as SNA.
    Harness bad;
    bad.peer = [](int k) {
        HighState s = MakeHighState(k);
        s.imu.quaternion = {0.5f, 0.f, 0.f, 0.f};
        s.velocity[1] = std::nanf("");
        return std::optional<HighState>(s);
    };
    bad.Run(100 * kMs);
    EXPECT_EQ(bad.bridge.last_sample().valid & can::kGroupQuat, 0);
    EXPECT_EQ(bad.bridge.last_sample().valid & can::kGroupBodyVel, 0);
    EXPECT_NE(bad.bridge.last_sample().valid & can::kGroupGyro, 0);
    EXPECT_EQ(bad.bridge.state(), BridgeState::kDegraded);
    for (const CanFrame& f : bad.frames) {
        if (f.id == kQuat || f.id == kBodyVel) {
            EXPECT_FALSE(ValidBit(f));
        }
        if (f.id == kGyro) {
            EXPECT_TRUE(ValidBit(f));
        }
    }
}

TEST(Bridge, FootContactFollowsTheHysteresis) {
    BridgeConfig config;
    config.contact_on_raw = 40;
    config.contact_off_raw = 20;
    Bridge b(config);
    const int forces[] = {0, 30, 39, 40, 30, 21, 20, 30, 39, 45, 500, -5, 50};
    const bool expected[] = {false, false, false, true, true,  true, false,
                             false, false, true,  true, false, true};
    int64_t t = kT0;
    for (size_t i = 0; i < std::size(forces); ++i) {
        HighState s = MakeHighState(0);
        s.foot_force = {static_cast<int16_t>(forces[i]), 0, 100, 0};
        t += 2 * kMs;
        b.OnDatagram(Bytes(s), t);
        // A sample tick (the encoder alternates sample and repeat ticks).
        std::array<CanFrame, Bridge::kMaxFramesPerTick> out{};
        if (!b.encoder().sample_tick_next()) b.OnTick(t, t, out);
        ASSERT_GT(b.OnTick(t, t, out), 0u);
        EXPECT_EQ(b.last_sample().foot_contact[0], expected[i]) << "force " << forces[i];
        EXPECT_TRUE(b.last_sample().foot_contact[2]);
        EXPECT_FALSE(b.last_sample().foot_contact[1]);
        EXPECT_EQ(b.last_sample().foot_force_raw[0], std::clamp(forces[i], 0, 4094));
    }
}

TEST(Bridge, CounterStepsOncePerForwardedSampleThroughLinkLoss) {
    Harness h;
    h.peer = [](int k) {
        return k >= 100 && k < 200 ? std::nullopt : std::optional<HighState>(MakeHighState(k));
    };
    h.Run(1000 * kMs);
    // Every sample tick sends a sample (link up with new data, or link down): 100 samples.
    EXPECT_EQ(h.bridge.stats().samples, 100u);
    // Ticks alternate: a sample tick (a new counter for all its frames), then a repeat tick of
    // the 5 ms messages with the same counter. Counters step by 1 modulo 15, never 15.
    ASSERT_EQ(h.tick_frames.size(), 200u);
    std::vector<uint8_t> tick_counter;
    size_t next = 0;
    int withheld = 0;
    for (size_t tick = 0; tick < h.tick_frames.size(); ++tick) {
        if (h.tick_frames[tick] == 0) {
            // Only the repeat tick right after the link dropped is withheld.
            EXPECT_EQ(tick % 2, 1u) << tick;
            ++withheld;
            tick_counter.push_back(tick_counter.back());
            continue;
        }
        const uint8_t c = Counter(h.frames[next]);
        for (size_t i = 0; i < h.tick_frames[tick]; ++i) {
            EXPECT_EQ(Counter(h.frames[next + i]), c) << "tick " << tick;
        }
        next += h.tick_frames[tick];
        EXPECT_NE(c, 15);
        if (tick % 2 == 1) {
            EXPECT_EQ(c, tick_counter.back()) << "repeat tick " << tick;
        } else if (tick > 0) {
            EXPECT_EQ(c, (tick_counter.back() + 1) % 15) << "sample tick " << tick;
        }
        tick_counter.push_back(c);
    }
    EXPECT_EQ(next, h.frames.size());
    EXPECT_EQ(withheld, 1);
    EXPECT_EQ(h.bridge.stats().withheld_frames, 2u);  // GYRO and ACCEL
    EXPECT_EQ(h.decoder.stats().Faults(), 0u);
    EXPECT_EQ(h.decoder.stats().counter_lost, 0u);
}

TEST(Bridge, LinkLossClearsUdpLinkOkCountsLostAndMarksNothingValid) {
    Harness h;
    // Answers polls 0..99 (200 ms), silent for 100 polls (200 ms), then answers again.
    h.peer = [](int k) {
        return k >= 100 && k < 200 ? std::nullopt : std::optional<HighState>(MakeHighState(k));
    };
    h.Run(200 * kMs);
    EXPECT_TRUE(h.bridge.link_ok(h.now));
    EXPECT_EQ(h.bridge.state(), BridgeState::kRunning);
    const size_t before = h.frames.size();
    const size_t decoded_before = h.decoded.size();

    h.Run(200 * kMs);  // the silence
    EXPECT_FALSE(h.bridge.link_ok(h.now));
    EXPECT_EQ(h.bridge.state(), BridgeState::kFault);
    EXPECT_EQ(h.bridge.stats().link_losses, 1u);
    // Polls 100..199 went unanswered; poll k finds out about poll k - 1, so 101..199 so far.
    EXPECT_EQ(h.bridge.stats().lost, 99u);
    // The link drops after 3 poll periods: at most the first sample of the silence is still
    // sent with data (received < 6 ms before).
    EXPECT_GE(h.bridge.stats().placeholder_samples, 19u);

    // Frames kept coming at their cycles; none after the timeout marks a value valid.
    int sync = 0, status = 0, lost_in_status = 0, max_lost = 0;
    for (size_t i = before; i < h.frames.size(); ++i) {
        const CanFrame& f = h.frames[i];
        // Poll k is sent at kT0 + 2 (k + 1) ms; the last answered is poll 99.
        const int64_t since_last_rx = f.timestamp_ns - (kT0 + 200 * kMs + kRxDelayNs);
        if (since_last_rx > 6 * kMs && HasValidBit(f.id)) {
            EXPECT_FALSE(ValidBit(f)) << std::hex << f.id << " at " << std::dec << f.timestamp_ns;
        }
        if (f.id == kSync) ++sync;
        if (f.id == kStatus) {
            ++status;
            lost_in_status += f.data[6];  // STS_UdpRxLost
            max_lost = std::max<int>(max_lost, f.data[6]);
        }
    }
    EXPECT_EQ(sync, 20);
    EXPECT_EQ(status, 2);
    EXPECT_GE(lost_in_status, 50);  // a STATUS every 100 ms: 50 polls a window
    EXPECT_GE(max_lost, 49);
    // The decoder sees the link down and no group valid but the bridge's status.
    ASSERT_GT(h.decoded.size(), decoded_before + 15);
    const Go1Sample& d = h.decoded.back();
    EXPECT_FALSE(d.udp_link_ok);
    EXPECT_EQ(d.valid & ~can::kGroupStatus, 0) << std::hex << d.valid;
    EXPECT_EQ(d.bridge_state, static_cast<uint8_t>(BridgeState::kFault));
    // Every group the samples of the silence carry is not valid (the decoder keeps a group
    // that a sample does not carry valid until its own timeout: that is the receiver's rule).
    for (const Go1Sample& s : h.decoded) {
        if (s.host_time_ns > kT0 + 200 * kMs + 6 * kMs && s.host_time_ns <= kT0 + 400 * kMs) {
            EXPECT_FALSE(s.udp_link_ok);
            EXPECT_EQ(s.valid & s.fresh & ~can::kGroupStatus, 0) << std::hex << s.fresh;
        }
    }

    // Recovery: the link comes back; the first STATUS window reports the losses (DEGRADED),
    // then RUNNING; the long gap raises the odometry reset once.
    const uint64_t resets = h.bridge.stats().odom_resets;
    h.Run(50 * kMs);
    EXPECT_TRUE(h.bridge.link_ok(h.now));
    EXPECT_TRUE(h.decoded.back().udp_link_ok);
    EXPECT_EQ(h.decoded.back().valid, can::kAllGroups);
    h.Run(200 * kMs);
    EXPECT_EQ(h.bridge.state(), BridgeState::kRunning);
    EXPECT_EQ(h.decoded.back().bridge_state, static_cast<uint8_t>(BridgeState::kRunning));
    EXPECT_EQ(h.decoded.back().udp_rx_lost, 0);
    EXPECT_EQ(h.bridge.stats().odom_resets, resets);  // a 200 ms gap is no reboot (1 s)
    EXPECT_EQ(h.decoder.stats().Faults(), 0u);
}

TEST(Bridge, BeforeTheFirstHighStateFramesSayInitAndNothingValid) {
    Harness h;
    h.peer = [](int) { return std::optional<HighState>(); };
    h.Run(300 * kMs);
    EXPECT_EQ(h.bridge.state(), BridgeState::kInit);
    EXPECT_EQ(h.bridge.stats().samples, 30u);
    ASSERT_FALSE(h.frames.empty());
    for (const CanFrame& f : h.frames) {
        if (HasValidBit(f.id)) {
            EXPECT_FALSE(ValidBit(f)) << std::hex << f.id;
        }
        if (f.id == kSync || f.id == kStatus) {
            EXPECT_EQ(f.data[1] & 0x30, 0);  // UdpLinkOk, HighStateCrcOk
        }
        if (f.id == kStatus) {
            EXPECT_EQ(f.data[7], 0);  // BridgeState INIT
        }
    }
}

TEST(Bridge, RejectsBadCrcAndWrongSizeAndReportsThem) {
    Bridge b;
    auto bytes = Bytes(MakeHighState(1));
    EXPECT_EQ(b.OnDatagram(bytes, kT0), ParseResult::kOk);
    EXPECT_TRUE(b.link_ok(kT0));
    bytes[layout::hs::kPosition] ^= 1;
    EXPECT_EQ(b.OnDatagram(bytes, kT0 + 2 * kMs), ParseResult::kBadCrc);
    EXPECT_EQ(b.OnDatagram(std::span<const uint8_t>(bytes).first(1000), kT0 + 3 * kMs),
              ParseResult::kWrongSize);
    EXPECT_EQ(b.stats().crc_failures, 1u);
    EXPECT_EQ(b.stats().wrong_size, 1u);
    EXPECT_EQ(b.stats().highstates, 1u);
    // Rejected datagrams do not keep the link up.
    EXPECT_FALSE(b.link_ok(kT0 + 7 * kMs));
    std::array<CanFrame, Bridge::kMaxFramesPerTick> out{};
    ASSERT_GT(b.OnTick(kT0 + 4 * kMs, 0, out), 0u);
    EXPECT_FALSE(b.last_sample().highstate_crc_ok);
    EXPECT_EQ(b.state(), BridgeState::kDegraded);

    // With check_crc off the damaged HighState is forwarded, flagged.
    BridgeConfig config;
    config.check_crc = false;
    Bridge lax(config);
    EXPECT_EQ(lax.OnDatagram(bytes, kT0), ParseResult::kBadCrc);
    EXPECT_EQ(lax.stats().highstates, 1u);
    ASSERT_GT(lax.OnTick(kT0 + kMs, 0, out), 0u);
    EXPECT_TRUE(lax.last_sample().udp_link_ok);
    EXPECT_FALSE(lax.last_sample().highstate_crc_ok);
}

// A robot that sends the scrambled CRC (the SDK's encryptCRC) is accepted as one that sends the
// plain one; each form is counted, so a bench run tells which the robot sends.
TEST(Bridge, AcceptsBothCrcFormsAndCountsWhichMatched) {
    Bridge b;
    EXPECT_STREQ(b.crc_forms_seen(), "none yet");
    std::array<uint8_t, kHighStateSize> bytes{};
    SerializeHighState(MakeHighState(1), bytes, CrcForm::kScrambled);
    EXPECT_EQ(b.OnDatagram(bytes, kT0), ParseResult::kOk);
    EXPECT_EQ(b.OnDatagram(bytes, kT0 + 2 * kMs), ParseResult::kOk);
    EXPECT_EQ(b.stats().crc_scrambled, 2u);
    EXPECT_EQ(b.stats().crc_plain, 0u);
    EXPECT_STREQ(b.crc_forms_seen(), "scrambled");
    std::array<CanFrame, Bridge::kMaxFramesPerTick> out{};
    ASSERT_GT(b.OnTick(kT0 + 3 * kMs, 0, out), 0u);
    EXPECT_TRUE(b.last_sample().highstate_crc_ok);
    EXPECT_TRUE(b.last_sample().udp_link_ok);

    SerializeHighState(MakeHighState(2), bytes, CrcForm::kPlain);
    EXPECT_EQ(b.OnDatagram(bytes, kT0 + 4 * kMs), ParseResult::kOk);
    EXPECT_EQ(b.stats().crc_plain, 1u);
    EXPECT_STREQ(b.crc_forms_seen(), "plain+scrambled");
    EXPECT_EQ(b.stats().highstates, 3u);

    // Either form with a bit flipped is rejected, counted as a CRC failure.
    for (const CrcForm form : {CrcForm::kPlain, CrcForm::kScrambled}) {
        SerializeHighState(MakeHighState(3), bytes, form);
        bytes[layout::hs::kVelocity + 1] ^= 0x04;
        EXPECT_EQ(b.OnDatagram(bytes, kT0 + 5 * kMs), ParseResult::kBadCrc) << ToString(form);
    }
    EXPECT_EQ(b.stats().crc_failures, 2u);
    EXPECT_EQ(b.stats().highstates, 3u);
}

// A datagram with a wrong head or levelFlag is counted by reason and never forwarded, even with
// the CRC check off.
TEST(Bridge, WrongHeadOrLevelFlagIsCountedByReasonAndNeverForwarded) {
    BridgeConfig config;
    config.check_crc = false;
    Bridge b(config);
    HighState hs = MakeHighState(1);
    hs.head = {0x00, 0x00};
    EXPECT_EQ(b.OnDatagram(Bytes(hs), kT0), ParseResult::kBadHead);
    hs = MakeHighState(1);
    hs.level_flag = kLowLevel;
    EXPECT_EQ(b.OnDatagram(Bytes(hs), kT0 + kMs), ParseResult::kBadLevelFlag);
    EXPECT_EQ(b.stats().bad_head, 1u);
    EXPECT_EQ(b.stats().bad_level_flag, 1u);
    EXPECT_EQ(b.stats().crc_failures, 0u);
    EXPECT_EQ(b.stats().highstates, 0u);
    EXPECT_FALSE(b.link_ok(kT0 + kMs));
    std::array<CanFrame, Bridge::kMaxFramesPerTick> out{};
    b.OnTick(kT0 + 2 * kMs, 0, out);
    EXPECT_EQ(b.state(), BridgeState::kInit);  // nothing valid ever arrived
    EXPECT_FALSE(b.last_sample().highstate_crc_ok);
}

// The LCM status carries the counters by cause and the CRC forms seen.
TEST(BridgeStatus, MessageCarriesStateCountersAndCrcForms) {
    Bridge b;
    std::array<uint8_t, kHighStateSize> bytes{};
    SerializeHighState(MakeHighState(1), bytes, CrcForm::kScrambled);
    b.OnPoll(kT0);
    b.OnDatagram(bytes, kT0 + kRxDelayNs);
    HighState bad = MakeHighState(2);
    bad.level_flag = 0;
    b.OnDatagram(Bytes(bad), kT0 + kMs);
    b.OnDatagram(std::span<const uint8_t>(bytes).first(100), kT0 + kMs);
    std::array<CanFrame, Bridge::kMaxFramesPerTick> out{};
    b.OnTick(kT0 + 5 * kMs, 0, out);
    StatusContext context;
    context.link_ok = true;
    context.uptime_ns = 7 * kMs;
    context.host_now_ns = 1'700'000'000'000'000'000;
    context.udp_errors = 3;
    context.sink.failed = 2;
    const go1_bridge_status_t m = MakeStatusMessage(b, context);
    EXPECT_EQ(m.schema_version, go1_bridge_status_t::SCHEMA_VERSION);
    EXPECT_EQ(m.state, go1_bridge_status_t::STATE_DEGRADED);
    EXPECT_EQ(m.crc_forms_seen, go1_bridge_status_t::CRC_FORM_SCRAMBLED);
    EXPECT_EQ(m.highstates_crc_scrambled, 1);
    EXPECT_EQ(m.highstates_crc_plain, 0);
    EXPECT_EQ(m.rejected_level_flag, 1);
    EXPECT_EQ(m.rejected_size, 1);
    EXPECT_EQ(m.rejected_head, 0);
    EXPECT_EQ(m.rejected_crc, 0);
    EXPECT_EQ(m.datagrams, 3);
    EXPECT_EQ(m.polls, 1);
    EXPECT_TRUE(m.udp_link_ok);
    EXPECT_TRUE(m.crc_check);
    EXPECT_EQ(m.uptime_ns, 7 * kMs);
    EXPECT_EQ(m.sample_time_ns, context.host_now_ns);
    EXPECT_EQ(m.udp_errors, 3);
    EXPECT_EQ(m.can_send_failures, 2);
    EXPECT_EQ(m.can_frames, static_cast<int64_t>(b.stats().frames));
}

TEST(Bridge, OdometryResetOnFirstSampleJumpAndLongGapCarriedByOdomXy) {
    Harness h;
    int jump_at = 60, gap_from = 120, gap_to = 700;  // polls: jump, then 1.16 s silence
    h.peer = [&](int k) {
        if (k >= gap_from && k < gap_to) return std::optional<HighState>();
        HighState s = MakeHighState(k);
        if (k >= jump_at) s.position[0] += 3.f;
        if (k >= gap_to) s.position = {0.f, 0.f, 0.f};  // rebooted
        return std::optional<HighState>(s);
    };
    h.Run(1600 * kMs);
    EXPECT_EQ(h.bridge.stats().odom_resets, 3u);
    std::vector<int64_t> reset_times;
    for (const CanFrame& f : h.frames) {
        if (f.id == kOdomXy && (f.data[1] & 0x20)) {
            EXPECT_TRUE(ValidBit(f));
            reset_times.push_back(f.timestamp_ns);
        }
    }
    ASSERT_EQ(reset_times.size(), 3u);
    EXPECT_LE(reset_times[0], kT0 + 25 * kMs);                       // the first ODOM_XY
    EXPECT_NEAR(reset_times[1], kT0 + 2 * jump_at * kMs, 25 * kMs);  // the jump
    EXPECT_NEAR(reset_times[2], kT0 + 2 * gap_to * kMs, 25 * kMs);   // after the gap
}

TEST(Bridge, WaitsForNewDataRatherThanRepeatingASample) {
    // Polling at 100 Hz with a 50 ms link timeout: some sample ticks find nothing new.
    BridgeConfig config;
    config.poll_period_ns = 10 * kMs;
    config.link_timeout_ns = 50 * kMs;
    Harness h(config);
    h.peer = [](int k) {
        return k % 4 == 3 ? std::nullopt : std::optional<HighState>(MakeHighState(k));
    };
    h.Run(400 * kMs);
    EXPECT_GT(h.bridge.stats().skipped_ticks, 0u);
    // Only the first sample tick (5 ms, before the first poll) sends a placeholder.
    EXPECT_EQ(h.bridge.stats().placeholder_samples, 1u);
    // Each forwarded sample is a different HighState.
    std::map<int64_t, int> seen;
    for (const Go1Sample& d : h.decoded) {
        EXPECT_EQ(++seen[d.bridge_time_ns], 1);
    }
    EXPECT_EQ(h.bridge.stats().samples, h.bridge.stats().highstates + 1);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::go1_bridge
