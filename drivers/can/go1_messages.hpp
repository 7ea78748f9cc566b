// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The ten messages of go1_odometry.dbc as Go1Encoder and Go1Decoder share them: each message's
// signal codecs in a fixed slot order, its Go1Group bit, and the schedule both sides derive from
// the DBC's cycle times (drivers/can/README.md, "Counters and cycles"):
// - the sample period is GO1_SYNC's cycle (10 ms): one HighState sample, one alive counter step;
// - a message whose cycle is a multiple k of it is sent with every k-th sample (step k: the
//   20 ms messages with every second sample, GO1_STATUS with every tenth);
// - a message whose cycle divides it is sent `copies` times per sample, every copy carrying the
//   same sample and counter (the 5 ms IMU messages: twice, the second a benign repeat);
// - the tick is the shortest cycle (5 ms), the bridge's timer period.
// Everything is taken from the DBC by name; the constructor refuses a DBC that does not fit the
// spec's frame rules (DLC 8, CRC in byte 0, counter in byte 1 bits 0..3, cycles that nest).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "drivers/can/dbc.hpp"
#include "drivers/can/signal_codec.hpp"

namespace bimslam::can {

// Message index i is Go1Group bit (1 << i) (go1_sample.hpp).
inline constexpr size_t kGo1Messages = 10;

// Signal slots per message (the order of go1_messages.cpp's table).
namespace go1 {
inline constexpr size_t kCrc = 0, kCounter = 1;  // every message
inline constexpr size_t kValid = 2;  // BODY_VEL, BODY_STATE, IMU_*, ODOM_*: the Valid bit
inline constexpr size_t kSyncLinkOk = 2, kSyncCrcOk = 3, kSyncBridgeTime = 4, kSyncSampleAge = 5;
inline constexpr size_t kBvelVx = 3, kBvelVy = 4, kBvelYawRate = 5;
inline constexpr size_t kBstVz = 3, kBstBodyHeight = 4, kBstFootRaise = 5;
inline constexpr size_t kImuSaturated = 3, kImuX = 4;      // GYRO, ACCEL: X, Y, Z follow
inline constexpr size_t kQuatX = 3;                        // X, Y, Z
inline constexpr size_t kFootContact = 2, kFootForce = 6;  // FR, FL, RR, RL each
inline constexpr size_t kOxyReset = 3, kOxyX = 4, kOxyY = 5;
inline constexpr size_t kOzyZ = 3, kOzyYaw = 4;
inline constexpr size_t kStsLinkOk = 2, kStsCrcOk = 3, kStsMode = 4, kStsGait = 5, kStsBattery = 6,
                        kStsImuTemp = 7, kStsRxLost = 8, kStsBridgeState = 9;
inline constexpr size_t kMaxSlots = 10;
// The alive counter runs 0 ... 14 (specs/go1-can.md); 15 is never sent.
inline constexpr uint8_t kCounterModulo = 15;
// What a signal holding its SNA (signal not available) raw value decodes to.
inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Slots from here on carry values (flags have no SNA, so checking them all is harmless).
inline constexpr size_t kFirstValueSlot = 2;
}  // namespace go1

struct Go1MessageLayout {
    const char* name = "";  // the DBC's BO_ name
    uint32_t id = 0;
    uint16_t group = 0;      // Go1Group bit
    int64_t cycle_ns = 0;    // GenMsgCycleTime
    int64_t timeout_ns = 0;  // GenMsgTimeout, or 3 x the cycle when the DBC gives none
    uint32_t step = 1;       // samples from one transmission to the next (cycle / sample period)
    uint32_t copies = 1;     // transmissions per sample (sample period / cycle)
    bool has_valid = false;  // slot go1::kValid is a Valid bit
    size_t slots = 0;
    std::array<SignalCodec, go1::kMaxSlots> sig{};
};

class Go1Layout {
public:
    // Throws common::Error naming the message or signal the DBC lacks or lays out differently.
    explicit Go1Layout(const Dbc& dbc);

    const Go1MessageLayout& operator[](size_t i) const { return messages_[i]; }
    // Message index of a standard (11-bit) identifier, or -1.
    int IndexOf(uint32_t id) const { return id < index_.size() ? index_[id] : -1; }
    int64_t sample_period_ns() const { return sample_period_ns_; }
    int64_t tick_ns() const { return tick_ns_; }
    uint32_t ticks_per_sample() const { return ticks_per_sample_; }
    // Message indices, slowest cycle first (ties by id): the order a sample is sent in, so that
    // a receiver that is not yet synchronised sees the occasional messages of a sample before
    // the every-sample ones that complete it.
    const std::array<uint8_t, kGo1Messages>& send_order() const { return send_order_; }

private:
    std::array<Go1MessageLayout, kGo1Messages> messages_{};
    std::array<int8_t, 2048> index_{};
    std::array<uint8_t, kGo1Messages> send_order_{};
    int64_t sample_period_ns_ = 0;
    int64_t tick_ns_ = 0;
    uint32_t ticks_per_sample_ = 1;
};

}  // namespace bimslam::can
