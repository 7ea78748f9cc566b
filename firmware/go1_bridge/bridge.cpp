// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "firmware/go1_bridge/bridge.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <string>

#include "algorithms/common/status.hpp"

namespace bimslam::go1_bridge {
namespace {

using can::Go1Sample;

constexpr int kMaxFootForceRaw = 4094;  // FOOT_Force_* range; 4095 is SNA
constexpr uint32_t kMaxRxLost = 254;    // STS_UdpRxLost range; 255 is SNA

bool Finite(float a) { return std::isfinite(a); }
template <size_t N>
bool Finite(const std::array<float, N>& a) {
    return std::all_of(a.begin(), a.end(), [](float v) { return std::isfinite(v); });
}

[[noreturn]] void Invalid(const std::string& field, const std::string& value,
                          const std::string& why) {
    throw common::Error(common::StatusCode::kInvalidArgument,
                        "BridgeConfig." + field + ": " + value + " (" + why + ")");
}

}  // namespace

const char* ToString(BridgeState state) {
    switch (state) {
        case BridgeState::kInit:
            return "INIT";
        case BridgeState::kRunning:
            return "RUNNING";
        case BridgeState::kDegraded:
            return "DEGRADED";
        case BridgeState::kFault:
            return "FAULT";
    }
    return "?";
}

void BridgeConfig::Validate() const {
    // Polling must keep up with the 10 ms CAN sample period, and not flood the Go1.
    if (poll_period_ns < 500'000 || poll_period_ns > 10'000'000) {
        Invalid("poll_period_ns", std::to_string(poll_period_ns),
                "must be 0.5 ms .. 10 ms: 100 .. 2000 Hz");
    }
    if (link_timeout_ns != 0 && link_timeout_ns < poll_period_ns) {
        Invalid("link_timeout_ns", std::to_string(link_timeout_ns),
                "must be 0 (3 poll periods) or at least one poll period, " +
                    std::to_string(poll_period_ns) + " ns");
    }
    if (contact_off_raw < 0 || contact_on_raw > kMaxFootForceRaw ||
        contact_off_raw >= contact_on_raw) {
        Invalid("contact_on_raw/contact_off_raw",
                std::to_string(contact_on_raw) + "/" + std::to_string(contact_off_raw),
                "need 0 <= off < on <= 4094");
    }
    if (!(odom_jump_m > 0) || !std::isfinite(odom_jump_m)) {
        Invalid("odom_jump_m", std::to_string(odom_jump_m), "must be positive");
    }
    if (!(odom_max_speed_mps >= 0) || !std::isfinite(odom_max_speed_mps)) {
        Invalid("odom_max_speed_mps", std::to_string(odom_max_speed_mps),
                "must be zero or positive");
    }
    if (odom_reset_gap_ns <= 0) {
        Invalid("odom_reset_gap_ns", std::to_string(odom_reset_gap_ns), "must be positive");
    }
    if (!(quat_norm_tolerance > 0 && quat_norm_tolerance < 1)) {
        Invalid("quat_norm_tolerance", std::to_string(quat_norm_tolerance), "must be in (0, 1)");
    }
}

Bridge::Bridge(const BridgeConfig& config) : config_(config), encoder_(can::Go1EncoderConfig{}) {
    config_.Validate();
}

bool Bridge::link_ok(int64_t now_ns) const {
    return ever_received_ && now_ns - last_rx_ns_ <= config_.EffectiveLinkTimeoutNs();
}

void Bridge::OnPoll(int64_t /*now_ns*/) {
    ++stats_.polls;
    if (polled_ && !answered_) {
        ++stats_.lost;
        ++window_lost_;
    }
    polled_ = true;
    answered_ = false;
}

ParseResult Bridge::Reject(uint64_t& counter, ParseResult why) {
    ++counter;
    last_datagram_ok_ = false;
    ++window_faults_;
    return why;
}

const char* Bridge::crc_forms_seen() const {
    if (stats_.crc_plain > 0 && stats_.crc_scrambled > 0) return "plain+scrambled";
    if (stats_.crc_scrambled > 0) return "scrambled";
    if (stats_.crc_plain > 0) return "plain";
    return "none yet";
}

ParseResult Bridge::OnDatagram(std::span<const uint8_t> bytes, int64_t receive_ns) {
    ++stats_.datagrams;
    CrcForm form = CrcForm::kPlain;
    const ParseResult r = ParseHighState(bytes, highstate_, &form);
    switch (r) {
        case ParseResult::kOk:
            ++(form == CrcForm::kScrambled ? stats_.crc_scrambled : stats_.crc_plain);
            last_datagram_ok_ = true;
            break;
        // Not a high-level HighState: never decoded, whatever check_crc says.
        case ParseResult::kWrongSize:
            return Reject(stats_.wrong_size, r);
        case ParseResult::kBadHead:
            return Reject(stats_.bad_head, r);
        case ParseResult::kBadLevelFlag:
            return Reject(stats_.bad_level_flag, r);
        case ParseResult::kBadCrc:
            Reject(stats_.crc_failures, r);
            if (config_.check_crc) return r;
            break;
    }
    MapHighState(highstate_, receive_ns);
    ++stats_.highstates;
    has_newest_ = true;
    ever_received_ = true;
    last_rx_ns_ = receive_ns;
    answered_ = true;
    return r;
}

void Bridge::MapHighState(const HighState& hs, int64_t receive_ns) {
    Go1Sample& s = newest_;
    s = Go1Sample{};
    s.bridge_time_ns = receive_ns;
    s.host_time_ns = receive_ns;
    uint16_t valid = can::kAllGroups;
    const auto require = [&valid](bool ok, uint16_t group) {
        if (!ok) valid = static_cast<uint16_t>(valid & ~group);
    };

    s.vx = hs.velocity[0];
    s.vy = hs.velocity[1];
    s.yaw_rate = hs.yaw_speed;
    require(Finite(hs.velocity[0]) && Finite(hs.velocity[1]) && Finite(hs.yaw_speed),
            can::kGroupBodyVel);
    s.vz = hs.velocity[2];
    s.body_height = hs.body_height;
    s.foot_raise_height = hs.foot_raise_height;
    require(Finite(hs.velocity[2]) && Finite(hs.body_height) && Finite(hs.foot_raise_height),
            can::kGroupBodyState);

    for (size_t i = 0; i < 3; ++i) {
        s.gyro[i] = hs.imu.gyroscope[i];
        s.accel[i] = hs.imu.accelerometer[i];
    }
    require(Finite(hs.imu.gyroscope), can::kGroupGyro);
    require(Finite(hs.imu.accelerometer), can::kGroupAccel);
    s.gyro_saturated = false;  // HighState has no saturation flags
    s.accel_saturated = false;

    // Quaternion (w, x, y, z): normalised, w >= 0.
    {
        const auto& q = hs.imu.quaternion;
        double norm = 0;
        for (float c : q) norm += static_cast<double>(c) * c;
        norm = std::sqrt(norm);
        const bool usable =
            std::isfinite(norm) && std::abs(norm - 1.0) <= config_.quat_norm_tolerance;
        require(usable, can::kGroupQuat);
        if (usable) {
            const double sign = q[0] < 0 ? -1.0 : 1.0;
            for (size_t i = 0; i < 4; ++i) s.quat_wxyz[i] = sign * q[i] / norm;
        }
    }

    // Feet: clipped raw force, contact by hysteresis.
    for (size_t i = 0; i < 4; ++i) {
        const int f = hs.foot_force[i];
        if (f >= config_.contact_on_raw) {
            contact_[i] = true;
        } else if (f <= config_.contact_off_raw) {
            contact_[i] = false;
        }
        s.foot_contact[i] = contact_[i];
        s.foot_force_raw[i] = static_cast<uint16_t>(std::clamp(f, 0, kMaxFootForceRaw));
    }

    // Unitree's odometry; a jump or a long silence (reboot) raises the reset flag.
    s.odom_x = hs.position[0];
    s.odom_y = hs.position[1];
    s.odom_z = hs.position[2];
    s.odom_yaw = hs.imu.rpy[2];
    const bool position_ok = Finite(hs.position);
    require(Finite(hs.position[0]) && Finite(hs.position[1]), can::kGroupOdomXy);
    require(Finite(hs.position[2]) && Finite(hs.imu.rpy[2]), can::kGroupOdomZYaw);
    if (ever_received_ && receive_ns - last_rx_ns_ > config_.odom_reset_gap_ns) {
        reset_pending_ = true;
    }
    if (position_ok) {
        if (have_position_) {
            double d2 = 0;
            for (size_t i = 0; i < 3; ++i) {
                const double d = static_cast<double>(hs.position[i]) - last_position_[i];
                d2 += d * d;
            }
            const double dt = static_cast<double>(receive_ns - last_position_ns_) * 1e-9;
            const double allowed =
                config_.odom_jump_m + config_.odom_max_speed_mps * std::max(0.0, dt);
            if (d2 > allowed * allowed) reset_pending_ = true;
        }
        have_position_ = true;
        last_position_ = hs.position;
        last_position_ns_ = receive_ns;
    }

    s.mode = hs.mode;
    s.gait = hs.gait_type;
    s.battery_soc = hs.bms.soc;
    s.imu_temperature_c = hs.imu.temperature;
    s.valid = valid;
}

void Bridge::UpdateState(bool link) {
    if (!ever_received_) {
        state_ = BridgeState::kInit;
    } else if (!link) {
        state_ = BridgeState::kFault;
    } else if (window_lost_ > 0 || window_faults_ > 0 || !last_datagram_ok_) {
        state_ = BridgeState::kDegraded;
    } else {
        state_ = BridgeState::kRunning;
    }
}

size_t Bridge::OnTick(int64_t now_ns, int64_t frame_timestamp_ns, Frames out) {
    const bool link = link_ok(now_ns);
    if (link_was_ok_ && !link) {
        ++stats_.link_losses;
        contact_ = {};  // a new contact phase starts with the next HighState
    }
    link_was_ok_ = link;

    if (!encoder_.sample_tick_next()) {
        // The repeat tick: the 5 ms messages of the current sample once more. When the link
        // dropped since that sample, the copy (values received before the loss, Valid set) is
        // not sent; the encoder still steps its schedule.
        const size_t n = encoder_.Tick(nullptr, frame_timestamp_ns, out);
        if (!link && sample_has_data_) {
            stats_.withheld_frames += n;
            return 0;
        }
        stats_.frames += n;
        return n;
    }

    const uint16_t groups = encoder_.NextSampleGroups();
    if (link && has_newest_) {
        sample_ = newest_;
        has_newest_ = false;
        sample_has_data_ = true;
        sample_.sample_age_us =
            static_cast<uint32_t>(std::max<int64_t>(0, now_ns - last_rx_ns_) / 1000);
        const auto unusable = static_cast<uint16_t>(can::kAllGroups & ~sample_.valid);
        if (unusable != 0) {
            ++window_faults_;
            stats_.unusable_groups += static_cast<uint64_t>(std::popcount(unusable));
        }
    } else if (link) {
        // Nothing new since the last sample, but the link is up: wait for the next HighState
        // rather than repeat a sample (the encoder tries again at the next tick).
        ++stats_.skipped_ticks;
        return encoder_.Tick(nullptr, frame_timestamp_ns, out);
    } else {
        // The link is down (or never came up): a sample with nothing valid. STATUS keeps the
        // last HighState's mode, gait, battery and temperature (see bridge.hpp).
        const Go1Sample& last = newest_;
        sample_ = Go1Sample{};
        sample_.bridge_time_ns = now_ns;
        sample_.host_time_ns = now_ns;
        sample_.mode = last.mode;
        sample_.gait = last.gait;
        sample_.battery_soc = last.battery_soc;
        sample_.imu_temperature_c = last.imu_temperature_c;
        sample_.valid = 0;
        has_newest_ = false;
        sample_has_data_ = false;
        ++stats_.placeholder_samples;
    }

    UpdateState(link);
    sample_.valid |= can::kGroupStatus;  // the bridge's own status is always current
    sample_.udp_link_ok = link;
    sample_.highstate_crc_ok = last_datagram_ok_;
    sample_.bridge_state = static_cast<uint8_t>(state_);
    sample_.udp_rx_lost = static_cast<uint8_t>(std::min(window_lost_, kMaxRxLost));
    sample_.odom_reset = false;
    if ((groups & can::kGroupOdomXy) && (sample_.valid & can::kGroupOdomXy) && reset_pending_) {
        sample_.odom_reset = true;
        reset_pending_ = false;
        ++stats_.odom_resets;
    }

    const size_t n = encoder_.Tick(&sample_, frame_timestamp_ns, out);
    sample_.counter = encoder_.counter();
    if (groups & can::kGroupStatus) {
        window_lost_ = 0;
        window_faults_ = 0;
    }
    ++stats_.samples;
    stats_.frames += n;
    return n;
}

}  // namespace bimslam::go1_bridge
