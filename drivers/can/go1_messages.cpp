// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "drivers/can/go1_messages.hpp"

#include <algorithm>
#include <numeric>
#include <string>
#include <utility>

#include "algorithms/common/status.hpp"
#include "drivers/can/go1_sample.hpp"

namespace bimslam::can {
namespace {

using common::Error;
using common::StatusCode;

struct MessageSpec {
    const char* name;
    bool has_valid;
    std::array<const char*, go1::kMaxSlots> signals;  // in slot order, nullptr-terminated
};

// Index i is Go1Group bit i (go1_sample.hpp); slots as in go1_messages.hpp.
constexpr MessageSpec kSpecs[kGo1Messages] = {
    {"GO1_SYNC",
     false,
     {"SYNC_CRC", "SYNC_Counter", "SYNC_UdpLinkOk", "SYNC_HighStateCrcOk", "SYNC_BridgeTime",
      "SYNC_SampleAge"}},
    {"GO1_BODY_VEL",
     true,
     {"BVEL_CRC", "BVEL_Counter", "BVEL_Valid", "BVEL_Vx", "BVEL_Vy", "BVEL_YawRate"}},
    {"GO1_BODY_STATE",
     true,
     {"BST_CRC", "BST_Counter", "BST_Valid", "BST_Vz", "BST_BodyHeight", "BST_FootRaiseHeight"}},
    {"GO1_IMU_GYRO",
     true,
     {"GYR_CRC", "GYR_Counter", "GYR_Valid", "GYR_Saturated", "GYR_X", "GYR_Y", "GYR_Z"}},
    {"GO1_IMU_ACCEL",
     true,
     {"ACC_CRC", "ACC_Counter", "ACC_Valid", "ACC_Saturated", "ACC_X", "ACC_Y", "ACC_Z"}},
    {"GO1_IMU_QUAT",
     true,
     {"QUAT_CRC", "QUAT_Counter", "QUAT_Valid", "QUAT_X", "QUAT_Y", "QUAT_Z"}},
    {"GO1_FOOT",
     false,
     {"FOOT_CRC", "FOOT_Counter", "FOOT_Contact_FR", "FOOT_Contact_FL", "FOOT_Contact_RR",
      "FOOT_Contact_RL", "FOOT_Force_FR", "FOOT_Force_FL", "FOOT_Force_RR", "FOOT_Force_RL"}},
    {"GO1_ODOM_XY",
     true,
     {"OXY_CRC", "OXY_Counter", "OXY_Valid", "OXY_ResetFlag", "OXY_PosX", "OXY_PosY"}},
    {"GO1_ODOM_Z_YAW", true, {"OZY_CRC", "OZY_Counter", "OZY_Valid", "OZY_PosZ", "OZY_Yaw"}},
    {"GO1_STATUS",
     false,
     {"STS_CRC", "STS_Counter", "STS_UdpLinkOk", "STS_HighStateCrcOk", "STS_Mode", "STS_GaitType",
      "STS_BatterySoc", "STS_ImuTemp", "STS_UdpRxLost", "STS_BridgeState"}},
};
static_assert(kGroupStatus == 1 << 9 && kAllGroups == (1 << kGo1Messages) - 1);

[[noreturn]] void Fail(const std::string& what) {
    throw Error(StatusCode::kInvalidArgument, "Go1 DBC: " + what);
}

void ExpectLayout(const SignalCodec& s, const std::string& name, uint32_t start, uint32_t length) {
    if (s.byte_order() != ByteOrder::kIntel || s.is_signed() || s.start_bit() != start ||
        s.length() != length || s.factor() != 1.0 || s.offset() != 0.0) {
        Fail("SG_ " + name + " must be " + std::to_string(start) + "|" + std::to_string(length) +
             "@1+ (1,0) (specs/go1-can.md, \"Rules every frame follows\")");
    }
}

}  // namespace

Go1Layout::Go1Layout(const Dbc& dbc) {
    index_.fill(-1);
    constexpr int64_t kMs = 1'000'000;
    for (size_t i = 0; i < kGo1Messages; ++i) {
        const MessageSpec& spec = kSpecs[i];
        const DbcMessage* m = dbc.FindMessage(std::string_view(spec.name));
        if (!m) Fail("no BO_ " + std::string(spec.name));
        if (m->extended || m->dlc != 8) {
            Fail("BO_ " + m->name + " must be a standard (11-bit) frame of DLC 8");
        }
        if (m->cycle_time_ms <= 0) Fail("BO_ " + m->name + " has no GenMsgCycleTime");
        const MessageCodec codec(*m);
        Go1MessageLayout& out = messages_[i];
        out.name = spec.name;
        out.id = m->id;
        out.group = static_cast<uint16_t>(1u << i);
        out.cycle_ns = m->cycle_time_ms * kMs;
        out.timeout_ns = (m->timeout_ms > 0 ? m->timeout_ms : 3 * m->cycle_time_ms) * kMs;
        out.has_valid = spec.has_valid;
        for (size_t k = 0; k < go1::kMaxSlots && spec.signals[k]; ++k) {
            out.sig[k] = codec[codec.Index(spec.signals[k])];
            out.slots = k + 1;
        }
        ExpectLayout(out.sig[go1::kCrc], spec.signals[go1::kCrc], 0, 8);
        ExpectLayout(out.sig[go1::kCounter], spec.signals[go1::kCounter], 8, 4);
        if (spec.has_valid && out.sig[go1::kValid].length() != 1) {
            Fail("SG_ " + std::string(spec.signals[go1::kValid]) + " must be 1 bit");
        }
        if (index_[m->id] >= 0) Fail("two Go1 messages share id " + std::to_string(m->id));
        index_[m->id] = static_cast<int8_t>(i);
    }

    // The schedule: the sample period is GO1_SYNC's cycle; every other cycle nests in it.
    sample_period_ns_ = messages_[0].cycle_ns;
    tick_ns_ = sample_period_ns_;
    for (const auto& m : messages_) tick_ns_ = std::min(tick_ns_, m.cycle_ns);
    for (auto& m : messages_) {
        const std::string what =
            "BO_ " + std::string(m.name) + " cycle " + std::to_string(m.cycle_ns / kMs) + " ms";
        if (m.cycle_ns < sample_period_ns_) {
            if (sample_period_ns_ % m.cycle_ns != 0 || m.cycle_ns % tick_ns_ != 0) {
                Fail(what + " does not divide the sample period (GO1_SYNC's cycle)");
            }
            m.copies = static_cast<uint32_t>(sample_period_ns_ / m.cycle_ns);
        } else {
            if (m.cycle_ns % sample_period_ns_ != 0) {
                Fail(what + " is not a multiple of the sample period (GO1_SYNC's cycle)");
            }
            m.step = static_cast<uint32_t>(m.cycle_ns / sample_period_ns_);
            // The alive counter counts modulo 15: a step of 15 would look like a repeat.
            if (m.step % 15 == 0) Fail(what + " is a multiple of 15 samples");
        }
    }
    ticks_per_sample_ = static_cast<uint32_t>(sample_period_ns_ / tick_ns_);

    // Insertion sort of ten indices (std::stable_sort would take a temporary heap buffer).
    auto before = [&](uint8_t a, uint8_t b) {
        if (messages_[a].cycle_ns != messages_[b].cycle_ns) {
            return messages_[a].cycle_ns > messages_[b].cycle_ns;
        }
        return messages_[a].id < messages_[b].id;
    };
    std::iota(send_order_.begin(), send_order_.end(), uint8_t{0});
    for (size_t i = 1; i < send_order_.size(); ++i) {
        for (size_t j = i; j > 0 && before(send_order_[j], send_order_[j - 1]); --j) {
            std::swap(send_order_[j], send_order_[j - 1]);
        }
    }
}

}  // namespace bimslam::can
