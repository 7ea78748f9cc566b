// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// A fake Unitree Go1 on loopback for the bimslam-go1-bridge tests (go1_bridge_test.cpp): it
// checks every HighCmd and answers with HighStates of known values, playing a script counted in
// HighCmds, not in time.
#pragma once

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <thread>

#include "drivers/go1/high_state.hpp"

namespace bimslam::go1::fake {

// The HighState the fake Go1 sends as its k-th answer. Every value is a function of k; vx
// (1 mm/s steps, exact in the DBC's 0.001 m/s) gives k back.
inline HighState MakeHighState(int k) {
    HighState s;
    s.head = {0xfe, 0xef};
    s.level_flag = kHighLevel;
    s.velocity = {0.001f * static_cast<float>(k), -0.0005f * static_cast<float>(k), 0.01f};
    s.yaw_speed = 0.5f * std::sin(0.01f * static_cast<float>(k));
    s.body_height = 0.28f + 0.0001f * static_cast<float>(k % 100);
    s.foot_raise_height = 0.08f;
    s.imu.gyroscope = {0.1f * std::sin(0.02f * static_cast<float>(k)),
                       0.1f * std::cos(0.02f * static_cast<float>(k)), -0.05f};
    s.imu.accelerometer = {0.1f, -0.2f, 9.81f};
    const float yaw = 0.001f * static_cast<float>(k);
    const float sign = k % 2 ? -1.f : 1.f;  // the bridge must flip to w >= 0
    s.imu.quaternion = {sign * std::cos(yaw / 2), 0.f, 0.f, sign * std::sin(yaw / 2)};
    s.imu.rpy = {0.f, 0.f, yaw};
    s.imu.temperature = 35;
    s.foot_force = {static_cast<int16_t>((k % 100) * 10), 500, 5, 42};
    s.position = {0.004f * static_cast<float>(k), -0.002f * static_cast<float>(k), 0.3f};
    s.mode = 1;
    s.gait_type = 2;
    s.bms.soc = 90;
    return s;
}

// Faults a FakeGo1 puts into its answers: every n-th answer (0: never) has one bit flipped in
// its velocity (a bad CRC), or a wrong head. Such answers do not use up a k.
struct InjectedFaults {
    int flip_bit_every = 0;
    int wrong_head_every = 0;
};

// What a FakeGo1 does, counted in HighCmds received, not in time: what the bridge sees then
// follows from what was sent, however fast or loaded the machine is. It answers `answer`
// HighCmds (faulty answers included); then withholds `withhold`, from the first HighCmd that
// finds it caught up; answers `then` more; then answers nothing and is done (Settled()).
struct Script {
    int answer = 0;
    int withhold = 0;
    int then = 0;
};

// A Go1 on 127.0.0.1 playing a Script: its intact answers are MakeHighState(k) for k = 0, 1, ...,
// their CRC in `form` (scrambled, as the robot's sport controller sends it:
// drivers/go1/README.md).
//
// Caught up: it reads every HighCmd queued, then sleeps in poll(); the first HighCmd after a
// wake found the socket empty, so the bridge sent it after every answer before it had been
// queued to the bridge (loopback delivers a datagram within sendto). The silence starts at such
// a HighCmd, so the bridge has already read the last answer before it when it sends the next
// one: from then on it hears nothing for `withhold` - 1 poll periods at least (its polls keep
// absolute deadlines and never burst). Done at the second such HighCmd after the last answer:
// the bridge read every answer before sending it, and its summary then counts all of them.
class FakeGo1 {
public:
    explicit FakeGo1(Script script, CrcForm form = CrcForm::kScrambled, InjectedFaults faults = {})
        : script_(script), form_(form), faults_(faults) {
        fd_ = ::socket(AF_INET, SOCK_DGRAM, 0);
        EXPECT_GE(fd_, 0);
        sockaddr_in a{};
        a.sin_family = AF_INET;
        a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        a.sin_port = 0;
        EXPECT_EQ(::bind(fd_, reinterpret_cast<sockaddr*>(&a), sizeof(a)), 0);
        socklen_t n = sizeof(a);
        ::getsockname(fd_, reinterpret_cast<sockaddr*>(&a), &n);
        port_ = ntohs(a.sin_port);
        thread_ = std::thread([this] { Serve(); });
    }
    ~FakeGo1() {
        stop_ = true;
        thread_.join();
        ::close(fd_);
    }
    std::string endpoint() const { return "127.0.0.1:" + std::to_string(port_); }
    // The script played to its end: every answer has reached the bridge.
    bool Settled() const { return settled_; }

    // Read after the bridge stopped (the serving thread writes them).
    std::atomic<int> commands{0};      // HighCmds received
    std::atomic<int> bad_commands{0};  // not a valid idle HighCmd (size, CRC, levelFlag, motion)
    int answered = 0;                  // intact answers: k of the next one
    int replies = 0;                   // answers sent, intact or not
    int answered_before_silence = 0;
    int withheld = 0;  // HighCmds left unanswered in the silence
    int flipped = 0;   // answers sent with a bad CRC
    int wrong_heads = 0;

private:
    enum class Phase { kAnswer, kCatchUp, kSilence, kThen, kTail };

    void Serve() {
        std::array<uint8_t, 2048> buffer{};
        while (!stop_) {
            pollfd p{fd_, POLLIN, 0};
            if (::poll(&p, 1, 20) <= 0) continue;  // 20 ms: only to see stop_
            for (bool caught_up = true;; caught_up = false) {
                sockaddr_in from{};
                socklen_t n = sizeof(from);
                const ssize_t got = ::recvfrom(fd_, buffer.data(), buffer.size(), MSG_DONTWAIT,
                                               reinterpret_cast<sockaddr*>(&from), &n);
                if (got < 0) break;
                Handle(std::span<const uint8_t>(buffer.data(), static_cast<size_t>(got)), caught_up,
                       from, n);
            }
        }
    }

    void Handle(std::span<const uint8_t> bytes, bool caught_up, const sockaddr_in& from,
                socklen_t from_size) {
        ++commands;
        HighCmd cmd;
        const bool idle = ParseHighCmd(bytes, cmd) == ParseResult::kOk &&
                          cmd.level_flag == kHighLevel && cmd.mode == 0 && cmd.velocity[0] == 0 &&
                          cmd.velocity[1] == 0 && cmd.yaw_speed == 0 && cmd.head == kHighCmdHead;
        if (!idle) ++bad_commands;
        if (phase_ == Phase::kAnswer && replies >= script_.answer) {
            phase_ = script_.withhold > 0 ? Phase::kCatchUp : Phase::kTail;
        }
        if (phase_ == Phase::kCatchUp && caught_up) {
            phase_ = Phase::kSilence;
            answered_before_silence = answered;
        }
        if (phase_ == Phase::kSilence && withheld == script_.withhold) phase_ = Phase::kThen;
        if (phase_ == Phase::kThen && replies >= answered_at_silence_end_ + script_.then) {
            phase_ = Phase::kTail;
        }
        if (phase_ == Phase::kSilence) {
            ++withheld;
            answered_at_silence_end_ = replies;
            return;
        }
        if (phase_ == Phase::kTail) {
            if (caught_up && ++caught_up_in_tail_ == 2) settled_ = true;
            return;
        }
        Reply(from, from_size);  // kAnswer, kThen, and kCatchUp's HighCmds queued before
    }

    void Reply(const sockaddr_in& to, socklen_t to_size) {
        std::array<uint8_t, kHighStateSize> reply{};
        const int reply_index = replies++;
        if (Every(faults_.flip_bit_every, reply_index)) {
            SerializeHighState(MakeHighState(answered), reply, form_);
            reply[layout::hs::kVelocity] ^= 0x01;
            ++flipped;
        } else if (Every(faults_.wrong_head_every, reply_index)) {
            HighState hs = MakeHighState(answered);
            hs.head = {0xef, 0xfe};
            SerializeHighState(hs, reply, form_);
            ++wrong_heads;
        } else {
            SerializeHighState(MakeHighState(answered++), reply, form_);
        }
        ::sendto(fd_, reply.data(), reply.size(), 0, reinterpret_cast<const sockaddr*>(&to),
                 to_size);
    }

    static bool Every(int n, int index) { return n > 0 && index % n == n - 1; }

    Script script_;
    CrcForm form_;
    InjectedFaults faults_;
    Phase phase_ = Phase::kAnswer;
    int answered_at_silence_end_ = 0;
    int caught_up_in_tail_ = 0;
    std::atomic<bool> settled_{false};
    int fd_ = -1;
    uint16_t port_ = 0;
    std::atomic<bool> stop_{false};
    std::thread thread_;
};

}  // namespace bimslam::go1::fake
