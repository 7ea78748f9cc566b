// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "drivers/can/go1_decoder.hpp"

#include <cmath>
#include <limits>
#include <string>

#include "algorithms/common/status.hpp"
#include "drivers/can/crc8.hpp"

namespace bimslam::can {
namespace {

using go1::kCounterModulo;
using go1::kNaN;

// a - b modulo 15, both in 0..14.
inline uint8_t Diff(uint8_t a, uint8_t b) {
    return static_cast<uint8_t>((a + kCounterModulo - b) % kCounterModulo);
}

// The 8 data bytes as one little-endian word (compiles to a load on little-endian hosts).
inline uint64_t LoadWord(const uint8_t* d) {
    uint64_t w = 0;
    for (int i = 7; i >= 0; --i) w = (w << 8) | d[i];
    return w;
}

}  // namespace

void Go1DecoderConfig::Validate() const {
    if (max_hold_ns < 0) {
        throw common::Error(
            common::StatusCode::kInvalidArgument,
            "Go1DecoderConfig.max_hold_ns: " + std::to_string(max_hold_ns) + " is negative");
    }
    if (resync_frames < 1 || resync_frames > 14) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            "Go1DecoderConfig.resync_frames: " + std::to_string(resync_frames) +
                                " (must be 1..14)");
    }
}

std::string_view ToString(Go1Verdict v) {
    switch (v) {
        case Go1Verdict::kAccepted:
            return "accepted";
        case Go1Verdict::kForeignId:
            return "foreign_id";
        case Go1Verdict::kErrorFrame:
            return "error_frame";
        case Go1Verdict::kBadFrame:
            return "bad_frame";
        case Go1Verdict::kBadDlc:
            return "bad_dlc";
        case Go1Verdict::kCrc:
            return "crc";
        case Go1Verdict::kCounterInvalid:
            return "counter_invalid";
        case Go1Verdict::kCounterRepeat:
            return "counter_repeat";
        case Go1Verdict::kCounterResync:
            return "counter_resync";
        case Go1Verdict::kResyncing:
            return "resyncing";
        case Go1Verdict::kDuplicate:
            return "duplicate";
        case Go1Verdict::kLate:
            return "late";
    }
    return "unknown";
}

uint64_t Go1DecoderStats::Count(Go1Verdict v) const {
    switch (v) {
        case Go1Verdict::kAccepted:
            return accepted;
        case Go1Verdict::kForeignId:
            return foreign_id;
        case Go1Verdict::kErrorFrame:
            return error_frame;
        case Go1Verdict::kBadFrame:
            return bad_frame;
        case Go1Verdict::kBadDlc:
            return bad_dlc;
        case Go1Verdict::kCrc:
            return crc;
        case Go1Verdict::kCounterInvalid:
            return counter_invalid;
        case Go1Verdict::kCounterRepeat:
            return counter_repeat;
        case Go1Verdict::kCounterResync:
            return counter_resync;
        case Go1Verdict::kResyncing:
            return resyncing;
        case Go1Verdict::kDuplicate:
            return duplicate;
        case Go1Verdict::kLate:
            return late;
    }
    return 0;
}

uint64_t Go1DecoderStats::Faults() const {
    return error_frame + bad_frame + bad_dlc + crc + counter_invalid + counter_repeat +
           counter_resync + resyncing + late;
}

Go1Decoder::Go1Decoder(const Go1DecoderConfig& config, const Dbc& dbc)
    : layout_(dbc), config_(config) {
    config_.Validate();
    Reset();
}

void Go1Decoder::Reset() {
    msg_ = {};
    started_ = false;
    all_timed_out_ = false;
    current_ = Go1Sample{};
    pending_ = false;
    pending_counter_ = 0;
    pending_start_ns_ = pending_last_ns_ = 0;
    fresh_ = due_ = 0;
    has_emitted_ = false;
    emitted_counter_ = 0;
    emitted_start_ns_ = 0;
    has_sync_ = false;
    last_bridge_us_ = 0;
    bridge_us_ = 0;
    sync_counter_ = 0;
    ready_count_ = 0;
    stats_ = Go1DecoderStats{};
}

uint16_t Go1Decoder::timed_out() const {
    uint16_t bits = 0;
    for (size_t m = 0; m < kGo1Messages; ++m) {
        if (msg_[m].timed_out) bits |= layout_[m].group;
    }
    return bits;
}

Go1FeedResult Go1Decoder::Result(Go1Verdict v) {
    switch (v) {
        case Go1Verdict::kAccepted:
            ++stats_.accepted;
            break;
        case Go1Verdict::kForeignId:
            ++stats_.foreign_id;
            break;
        case Go1Verdict::kErrorFrame:
            ++stats_.error_frame;
            break;
        case Go1Verdict::kBadFrame:
            ++stats_.bad_frame;
            break;
        case Go1Verdict::kBadDlc:
            ++stats_.bad_dlc;
            break;
        case Go1Verdict::kCrc:
            ++stats_.crc;
            break;
        case Go1Verdict::kCounterInvalid:
            ++stats_.counter_invalid;
            break;
        case Go1Verdict::kCounterRepeat:
            ++stats_.counter_repeat;
            break;
        case Go1Verdict::kCounterResync:
            ++stats_.counter_resync;
            break;
        case Go1Verdict::kResyncing:
            ++stats_.resyncing;
            break;
        case Go1Verdict::kDuplicate:
            ++stats_.duplicate;
            break;
        case Go1Verdict::kLate:
            ++stats_.late;
            break;
    }
    return {v, static_cast<int>(ready_count_)};
}

Go1FeedResult Go1Decoder::Feed(const common::CanFrame& frame) {
    ready_count_ = 0;
    ++stats_.frames;
    if (frame.error) return Result(Go1Verdict::kErrorFrame);
    const int index = frame.extended ? -1 : layout_.IndexOf(frame.id);
    if (index < 0) return Result(Go1Verdict::kForeignId);
    if (frame.remote || frame.fd) return Result(Go1Verdict::kBadFrame);
    if (frame.len != 8) return Result(Go1Verdict::kBadDlc);

    const int64_t t = frame.timestamp_ns;
    if (!started_) {
        // Every message's clock starts with the first Go1 frame: one that never comes times out.
        started_ = true;
        for (auto& s : msg_) s.last_seen_ns = t;
    }
    Advance(t);  // as if Tick(t) had been called just before
    if (all_timed_out_) {
        // The first Go1 frame after total silence (a bridge restart, a cable): start afresh as
        // at the first frame, so that the every-sample messages are expected again.
        for (auto& s : msg_) s = MessageState{.last_seen_ns = t};
        all_timed_out_ = false;
        has_emitted_ = false;
    }

    const uint8_t* d = frame.data.data();
    if (config_.check_crc && Go1FrameCrc(frame.id, d) != d[0]) return Result(Go1Verdict::kCrc);
    const uint8_t counter = d[1] & 0x0F;  // byte 1 bits 0..3 (Go1Layout checked the DBC says so)
    if (counter >= kCounterModulo) return Result(Go1Verdict::kCounterInvalid);
    const auto m = static_cast<size_t>(index);
    Go1Verdict verdict = CheckCounter(m, counter, t);
    if (verdict == Go1Verdict::kAccepted) Assemble(m, counter, LoadWord(d), t, &verdict);
    return Result(verdict);
}

int Go1Decoder::Tick(int64_t now_ns) {
    ready_count_ = 0;
    if (started_) Advance(now_ns);
    return static_cast<int>(ready_count_);
}

int Go1Decoder::Flush() {
    ready_count_ = 0;
    if (pending_) Emit();
    return static_cast<int>(ready_count_);
}

void Go1Decoder::Advance(int64_t now_ns) {
    CheckTimeouts(now_ns);
    if (pending_ && (Complete() || now_ns - pending_start_ns_ >= config_.max_hold_ns)) Emit();
}

void Go1Decoder::CheckTimeouts(int64_t now_ns) {
    bool all = true;
    for (size_t m = 0; m < kGo1Messages; ++m) {
        MessageState& s = msg_[m];
        if (!s.timed_out && now_ns - s.last_seen_ns > layout_[m].timeout_ns) {
            s.timed_out = true;
            s.has_ref = s.synced = false;
            s.has_data = false;
            // due_ stays: the sample being assembled still waits for it (until max_hold_ns or
            // the next sample); a 5 ms message after one lost sample times out at about the
            // moment its next frame arrives, and that frame belongs in this sample.
            ++stats_.timeout;
        }
        all = all && s.timed_out;
    }
    all_timed_out_ = all;
}

Go1Verdict Go1Decoder::CheckCounter(size_t m, uint8_t counter, int64_t t) {
    MessageState& s = msg_[m];
    const Go1MessageLayout& layout = layout_[m];
    if (!s.has_ref) {
        // First frame, or the first after a timeout: nothing to check it against.
        s.has_ref = s.synced = true;
        s.timed_out = false;
        s.ref = counter;
        s.copies_seen = 1;
        s.resync_good = 0;
        s.last_seen_ns = t;
        return Go1Verdict::kAccepted;
    }
    const uint8_t d = Diff(counter, s.ref);
    if (d == 0) {
        // The same sample again: the 5 ms messages' planned copies are benign; any other repeat
        // (a stuck bridge, a duplicated frame) does not even count as a sign of life.
        if (s.copies_seen < layout.copies) {
            ++s.copies_seen;
            s.last_seen_ns = t;
            return Go1Verdict::kDuplicate;
        }
        return Go1Verdict::kCounterRepeat;
    }
    s.last_seen_ns = t;
    s.ref = counter;
    s.copies_seen = 1;
    const uint8_t step = static_cast<uint8_t>(layout.step % kCounterModulo);
    if (!s.synced) {
        if (d == step) {
            if (++s.resync_good >= config_.resync_frames) {
                s.synced = true;
                return Go1Verdict::kAccepted;
            }
            return Go1Verdict::kResyncing;
        }
        s.resync_good = 0;
        return Go1Verdict::kCounterResync;
    }
    if (d == step) return Go1Verdict::kAccepted;
    if (d == (2 * layout.step) % kCounterModulo) {
        ++stats_.counter_lost;  // one transmission (one sample, or one of every k) lost
        return Go1Verdict::kAccepted;
    }
    s.synced = false;
    s.resync_good = 0;
    return Go1Verdict::kCounterResync;
}

void Go1Decoder::Assemble(size_t m, uint8_t counter, uint64_t word, int64_t t,
                          Go1Verdict* verdict) {
    // Counters compare modulo 15: up to 7 ahead is newer, behind is older. Beyond half the
    // counter cycle (70 ms) the comparison means nothing and a new counter starts a new sample.
    const int64_t window_ns = 7 * layout_.sample_period_ns();
    if (pending_) {
        const uint8_t d = Diff(counter, pending_counter_);
        if (d != 0) {
            if (d > 7 && t - pending_start_ns_ <= window_ns) {
                *verdict = Go1Verdict::kLate;  // older than the sample being assembled
                return;
            }
            Emit();  // a newer sample began: the pending one will not get more frames
            StartSample(counter, t);
        }
    } else {
        if (has_emitted_ && t - emitted_start_ns_ <= window_ns) {
            const uint8_t d = Diff(counter, emitted_counter_);
            if (d == 0 || d > 7) {
                *verdict = Go1Verdict::kLate;  // its sample is out already: never emit twice
                return;
            }
        }
        StartSample(counter, t);
    }
    Apply(m, counter, word);
    fresh_ |= layout_[m].group;
    pending_last_ns_ = t;
    if (Complete()) Emit();
}

void Go1Decoder::StartSample(uint8_t counter, int64_t t) {
    pending_ = true;
    pending_counter_ = counter;
    pending_start_ns_ = pending_last_ns_ = t;
    fresh_ = 0;
    // Due: the messages whose frame with this counter is expected and would be accepted. Not
    // yet seen (or restarted after total silence): the every-sample ones. In sequence: the next
    // transmission by their step (or the one after, one lost). Resynchronising: the frame that
    // completes the resynchronisation. Never a timed-out message.
    due_ = 0;
    for (size_t m = 0; m < kGo1Messages; ++m) {
        const MessageState& s = msg_[m];
        const Go1MessageLayout& layout = layout_[m];
        if (s.timed_out) continue;
        const uint8_t d = Diff(counter, s.ref);
        const uint8_t step = static_cast<uint8_t>(layout.step % kCounterModulo);
        bool due;
        if (!s.has_ref) {
            due = layout.step == 1;
        } else if (s.synced) {
            // One lost: 2k, when that is unambiguous modulo 15 (not for GO1_STATUS, whose 20
            // would read as 5, half its period).
            due = d == step || (2 * layout.step < kCounterModulo && d == 2 * layout.step);
        } else {
            due = d == step && s.resync_good + 1u >= config_.resync_frames;
        }
        if (due) due_ |= layout.group;
    }
}

void Go1Decoder::Apply(size_t m, uint8_t counter, uint64_t word) {
    const Go1MessageLayout& layout = layout_[m];
    MessageState& s = msg_[m];
    bool sna = false;
    auto raw = [&](size_t slot) -> uint64_t {
        const SignalCodec& c = layout.sig[slot];
        const uint64_t r = c.ExtractWord(word);
        if (c.IsSna(r)) {
            sna = true;
            ++stats_.sna;
        } else if (!c.InRange(r)) {
            ++stats_.out_of_range;
        }
        return r;
    };
    auto value = [&](size_t slot) -> double {
        const uint64_t r = raw(slot);
        return layout.sig[slot].IsSna(r) ? kNaN : layout.sig[slot].ToPhysical(r);
    };
    auto flag = [&](size_t slot) { return layout.sig[slot].ExtractWord(word) != 0; };
    s.valid_bit = layout.has_valid ? flag(go1::kValid) : true;
    if (!s.valid_bit) ++stats_.not_valid;

    Go1Sample& o = current_;
    switch (layout.group) {
        case kGroupSync: {
            o.udp_link_ok = flag(go1::kSyncLinkOk);
            o.highstate_crc_ok = flag(go1::kSyncCrcOk);
            const auto us = static_cast<uint32_t>(raw(go1::kSyncBridgeTime));
            // 32-bit microseconds wrap every 71.6 min: unwrap by the signed 32-bit difference.
            bridge_us_ = has_sync_ ? bridge_us_ + static_cast<int32_t>(us - last_bridge_us_) : us;
            last_bridge_us_ = us;
            has_sync_ = true;
            sync_counter_ = counter;
            const double age = value(go1::kSyncSampleAge);
            o.sample_age_us = std::isnan(age) ? 0 : static_cast<uint32_t>(age);
            break;
        }
        case kGroupBodyVel:
            o.vx = value(go1::kBvelVx);
            o.vy = value(go1::kBvelVy);
            o.yaw_rate = value(go1::kBvelYawRate);
            break;
        case kGroupBodyState:
            o.vz = value(go1::kBstVz);
            o.body_height = value(go1::kBstBodyHeight);
            o.foot_raise_height = value(go1::kBstFootRaise);
            break;
        case kGroupGyro:
            o.gyro_saturated = flag(go1::kImuSaturated);
            for (size_t i = 0; i < 3; ++i) o.gyro[i] = value(go1::kImuX + i);
            break;
        case kGroupAccel:
            o.accel_saturated = flag(go1::kImuSaturated);
            for (size_t i = 0; i < 3; ++i) o.accel[i] = value(go1::kImuX + i);
            break;
        case kGroupQuat: {
            const double x = value(go1::kQuatX), y = value(go1::kQuatX + 1),
                         z = value(go1::kQuatX + 2);
            // The bridge sends the unit quaternion with w >= 0 (DBC comment of QUAT_X).
            const double w = std::sqrt(std::max(0.0, 1.0 - x * x - y * y - z * z));
            o.quat_wxyz = sna ? std::array<double, 4>{kNaN, kNaN, kNaN, kNaN}
                              : std::array<double, 4>{w, x, y, z};
            break;
        }
        case kGroupFoot:
            for (size_t i = 0; i < 4; ++i) {
                o.foot_contact[i] = flag(go1::kFootContact + i);
                o.foot_force_raw[i] = static_cast<uint16_t>(raw(go1::kFootForce + i));
            }
            break;
        case kGroupOdomXy:
            o.odom_reset = flag(go1::kOxyReset);
            o.odom_x = value(go1::kOxyX);
            o.odom_y = value(go1::kOxyY);
            break;
        case kGroupOdomZYaw:
            o.odom_z = value(go1::kOzyZ);
            o.odom_yaw = value(go1::kOzyYaw);
            break;
        case kGroupStatus:
            o.udp_link_ok = flag(go1::kStsLinkOk);
            o.highstate_crc_ok = flag(go1::kStsCrcOk);
            o.mode = static_cast<uint8_t>(raw(go1::kStsMode));
            o.gait = static_cast<uint8_t>(raw(go1::kStsGait));
            o.battery_soc = static_cast<uint8_t>(raw(go1::kStsBattery));
            o.imu_temperature_c =
                static_cast<int8_t>(layout.sig[go1::kStsImuTemp].SignedRaw(raw(go1::kStsImuTemp)));
            o.udp_rx_lost = static_cast<uint8_t>(raw(go1::kStsRxLost));
            o.bridge_state = static_cast<uint8_t>(raw(go1::kStsBridgeState));
            break;
        default:
            break;
    }
    s.sna = sna;
    s.has_data = true;
}

void Go1Decoder::Emit() {
    if (ready_count_ >= ready_.size()) ready_count_ = ready_.size() - 1;  // cannot happen
    Go1Sample& out = ready_[ready_count_++];
    out = current_;
    out.counter = pending_counter_;
    out.fresh = fresh_;
    out.host_time_ns = pending_last_ns_;
    out.valid = 0;
    for (size_t m = 0; m < kGo1Messages; ++m) {
        const MessageState& s = msg_[m];
        if (s.has_data && !s.timed_out && s.synced && s.valid_bit && !s.sna) {
            out.valid |= layout_[m].group;
        }
    }
    if (has_sync_) {
        int64_t us = bridge_us_;
        // Without this sample's SYNC: the last SYNC's time plus the samples since.
        if (!(fresh_ & kGroupSync)) {
            us += Diff(pending_counter_, sync_counter_) * (layout_.sample_period_ns() / 1000);
        }
        out.bridge_time_ns = us * 1000;
    } else {
        out.bridge_time_ns = 0;
    }
    ++stats_.samples;
    if (!Complete()) ++stats_.samples_incomplete;
    has_emitted_ = true;
    emitted_counter_ = pending_counter_;
    emitted_start_ns_ = pending_start_ns_;
    pending_ = false;
}

}  // namespace bimslam::can
