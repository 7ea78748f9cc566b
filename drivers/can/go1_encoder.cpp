// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "drivers/can/go1_encoder.hpp"

#include <cmath>
#include <limits>
#include <string>

#include "algorithms/common/status.hpp"
#include "drivers/can/crc8.hpp"

namespace bimslam::can {
namespace {

using go1::kCounterModulo;
using go1::kNaN;

// floor(ns / 1000), also for negative times.
int64_t FloorMicros(int64_t ns) { return ns >= 0 ? ns / 1000 : -((-(ns + 1)) / 1000) - 1; }

}  // namespace

void Go1EncoderConfig::Validate() const {
    if (first_counter >= kCounterModulo) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            "Go1EncoderConfig.first_counter: " + std::to_string(first_counter) +
                                " (must be 0..14)");
    }
    if (frame_spacing_ns < 0) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            "Go1EncoderConfig.frame_spacing_ns: " +
                                std::to_string(frame_spacing_ns) + " is negative");
    }
}

Go1Encoder::Go1Encoder(const Go1EncoderConfig& config, const Dbc& dbc)
    : layout_(dbc), config_(config) {
    config_.Validate();
    Reset();
}

void Go1Encoder::Reset() {
    phase_ = 0;
    sample_index_ = 0;
    counter_ = config_.first_counter;
    last_ = {};
    stats_ = Go1EncoderStats{};
}

uint16_t Go1Encoder::NextSampleGroups() const {
    uint16_t groups = 0;
    for (size_t m = 0; m < kGo1Messages; ++m) {
        if (sample_index_ % layout_[m].step == 0) groups |= layout_[m].group;
    }
    return groups;
}

size_t Go1Encoder::Tick(const Go1Sample* newest, int64_t timestamp_ns, Frames out) {
    if (phase_ == 0) {
        return newest ? EncodeSample(*newest, timestamp_ns, out) : 0;
    }
    // A repeat tick: the messages sent `copies` times per sample whose turn this phase is.
    const uint32_t ticks = layout_.ticks_per_sample();
    size_t n = 0;
    for (uint8_t m : layout_.send_order()) {
        const Go1MessageLayout& msg = layout_[m];
        if (msg.copies > 1 && phase_ % (ticks / msg.copies) == 0) {
            out[n] = last_[m];
            out[n].timestamp_ns = timestamp_ns + static_cast<int64_t>(n) * config_.frame_spacing_ns;
            ++n;
        }
    }
    phase_ = (phase_ + 1) % ticks;
    stats_.frames += n;
    return n;
}

size_t Go1Encoder::EncodeSample(const Go1Sample& sample, int64_t timestamp_ns, Frames out) {
    if (sample_index_ > 0) counter_ = static_cast<uint8_t>((counter_ + 1) % kCounterModulo);
    size_t n = 0;
    for (uint8_t m : layout_.send_order()) {
        if (sample_index_ % layout_[m].step != 0) continue;
        last_[m] = EncodeMessage(m, sample, counter_,
                                 timestamp_ns + static_cast<int64_t>(n) * config_.frame_spacing_ns);
        out[n++] = last_[m];
    }
    ++sample_index_;
    ++stats_.samples;
    stats_.frames += n;
    phase_ = 1 % layout_.ticks_per_sample();
    return n;
}

common::CanFrame Go1Encoder::EncodeMessage(size_t index, const Go1Sample& sample, uint8_t counter,
                                           int64_t timestamp_ns) {
    const Go1MessageLayout& layout = layout_[index];
    const bool valid = (sample.valid & layout.group) != 0;
    uint64_t w = 0;
    auto put_raw = [&](size_t slot, uint64_t raw) { w = layout.sig[slot].InsertWord(w, raw); };
    auto flag = [&](size_t slot, bool b) { put_raw(slot, b ? 1 : 0); };
    // A value of the group: SNA when the group is not valid or the value not finite.
    auto put = [&](size_t slot, double v) {
        uint64_t raw = 0;
        switch (layout.sig[slot].ToRaw(valid ? v : kNaN, &raw)) {
            case PackResult::kOk:
                break;
            case PackResult::kClamped:
                ++stats_.clamped;
                break;
            case PackResult::kSna:
            case PackResult::kNotFinite:
                ++stats_.sna;
                break;
        }
        put_raw(slot, raw);
    };
    put_raw(go1::kCounter, counter % kCounterModulo);
    if (layout.has_valid) flag(go1::kValid, valid);

    switch (layout.group) {
        case kGroupSync:
            // The time is always sent: it is what pairs the sample with the host clock.
            flag(go1::kSyncLinkOk, sample.udp_link_ok);
            flag(go1::kSyncCrcOk, sample.highstate_crc_ok);
            put_raw(go1::kSyncBridgeTime,
                    static_cast<uint32_t>(FloorMicros(sample.bridge_time_ns)));  // mod 2^32
            put(go1::kSyncSampleAge, static_cast<double>(sample.sample_age_us));
            break;
        case kGroupBodyVel:
            put(go1::kBvelVx, sample.vx);
            put(go1::kBvelVy, sample.vy);
            put(go1::kBvelYawRate, sample.yaw_rate);
            break;
        case kGroupBodyState:
            put(go1::kBstVz, sample.vz);
            put(go1::kBstBodyHeight, sample.body_height);
            put(go1::kBstFootRaise, sample.foot_raise_height);
            break;
        case kGroupGyro:
            flag(go1::kImuSaturated, sample.gyro_saturated);
            for (size_t i = 0; i < 3; ++i) put(go1::kImuX + i, sample.gyro[i]);
            break;
        case kGroupAccel:
            flag(go1::kImuSaturated, sample.accel_saturated);
            for (size_t i = 0; i < 3; ++i) put(go1::kImuX + i, sample.accel[i]);
            break;
        case kGroupQuat: {
            // Normalised, sign-flipped so that w >= 0 (the receiver reconstructs w from x, y, z).
            const auto& q = sample.quat_wxyz;
            const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
            const bool usable = std::isfinite(norm) && norm > 1e-9;
            const double s = !usable ? kNaN : (q[0] < 0 ? -1.0 : 1.0) / norm;
            for (size_t i = 0; i < 3; ++i) put(go1::kQuatX + i, q[i + 1] * s);
            break;
        }
        case kGroupFoot:
            for (size_t i = 0; i < 4; ++i) {
                flag(go1::kFootContact + i, valid && sample.foot_contact[i]);
                put(go1::kFootForce + i, static_cast<double>(sample.foot_force_raw[i]));
            }
            break;
        case kGroupOdomXy:
            flag(go1::kOxyReset, sample.odom_reset);
            put(go1::kOxyX, sample.odom_x);
            put(go1::kOxyY, sample.odom_y);
            break;
        case kGroupOdomZYaw:
            put(go1::kOzyZ, sample.odom_z);
            put(go1::kOzyYaw, sample.odom_yaw);
            break;
        case kGroupStatus:
            flag(go1::kStsLinkOk, sample.udp_link_ok);
            flag(go1::kStsCrcOk, sample.highstate_crc_ok);
            put(go1::kStsMode, sample.mode);
            put(go1::kStsGait, sample.gait);
            put(go1::kStsBattery, sample.battery_soc);
            put(go1::kStsImuTemp, sample.imu_temperature_c);
            put(go1::kStsRxLost, sample.udp_rx_lost);
            put(go1::kStsBridgeState, sample.bridge_state);
            break;
        default:
            break;
    }

    common::CanFrame f;
    f.timestamp_ns = timestamp_ns;
    f.id = layout.id;
    f.len = 8;
    for (size_t i = 0; i < 8; ++i) f.data[i] = static_cast<uint8_t>(w >> (8 * i));
    f.data[0] = Go1FrameCrc(f.id, f.data.data());  // last: it covers bytes 1..7
    return f;
}

}  // namespace bimslam::can
