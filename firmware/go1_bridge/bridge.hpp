// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The Go1 bridge's core, without sockets: HighState datagrams and poll/tick events in, the CAN
// frames of go1_odometry.dbc out. The program (bimslam_go1_bridge_main.cpp) owns the UDP socket,
// the timers and the CAN sink and calls:
//   OnPoll(now)               each time it sends a HighCmd (every poll period, 2 ms at 500 Hz);
//   OnDatagram(bytes, t_rx)   for every datagram from the Go1, t_rx = CLOCK_MONOTONIC at receive;
//   OnTick(now, stamp, out)   every tick_ns() (5 ms), sending the frames it returns.
// All times are host CLOCK_MONOTONIC nanoseconds. None of these allocate or throw.
//
// Rules (README.md, "Rules"):
// - Samples. Every HighState that parses (size 1087, CRC good) becomes the newest sample,
//   stamped with its receive time (SYNC BridgeTime). The Go1Encoder's schedule starts a CAN
//   sample every second tick (10 ms): it takes the newest HighState if one arrived since the last
//   sample forwarded, gives it the next alive counter and sends the messages due. A HighState is
//   forwarded at most once; with nothing new but the link still up the sample tick is skipped
//   (the encoder tries again 5 ms later).
// - Link. UdpLinkOk = a valid HighState arrived within link_timeout_ns (default 3 poll periods).
//   While it is down every sample tick forwards a placeholder sample: every group's Valid bit
//   clear (values SNA), SYNC BridgeTime = the tick time with SampleAge SNA, UdpLinkOk 0. So
//   frames keep coming at their cycles and the counter keeps stepping, and nothing stale is
//   marked valid: the planned 5 ms repeat of the last sample with data is withheld when the
//   link dropped in between. GO1_STATUS has no Valid bit: its bridge fields (flags, lost count,
//   state) are current; its HighState fields (mode, gait, battery, IMU temperature) keep the last
//   values received (0 before the first) and must be read with STS_UdpLinkOk.
// - Frame checks as the SDK's receive path makes them (drivers/go1/README.md): size 1087, head
//   0xFE 0xEF, levelFlag HIGHLEVEL, then the CRC in either form, plain or scrambled (counted
//   apart, so a bench run tells which one the robot sends). A datagram failing size, head or
//   levelFlag is counted by reason and never decoded; a bad CRC is forwarded only when
//   check_crc is off.
// - HighStateCrcOk = the last datagram from the Go1 was an intact HighState (size, head,
//   levelFlag, CRC good); false before the first.
// - Lost samples. A poll period in which no valid HighState arrived (checked at the next poll)
//   is one missed sample. STS_UdpRxLost carries the missed samples since the previous STATUS
//   frame, saturating at 254.
// - Contact. Per leg, with hysteresis on the raw foot force: contact starts when the force
//   reaches contact_on_raw and ends when it falls to contact_off_raw or below; in between the
//   flag keeps its value. No contact before the first sample and after a link loss.
// - Odometry reset flag: raised on the first sample forwarded, on the first after the link was
//   down for longer than odom_reset_gap_ns (the robot may have rebooted: its position restarts
//   at 0), and when the position moved more than odom_jump_m + odom_max_speed_mps * dt between
//   two consecutive HighStates. It stays raised until a GO1_ODOM_XY frame has carried it.
// - Bridge state (STS_BridgeState): INIT until the first valid HighState; FAULT while the link
//   is down after that; DEGRADED while the link is up but the current STATUS window saw lost
//   samples, rejected datagrams (size, CRC) or a forwarded sample with unusable values; RUNNING
//   otherwise.
// - Values: the quaternion is normalised and flipped to w >= 0; a group whose values are not
//   all finite (or, for the quaternion, whose norm is off by more than quat_norm_tolerance) is
//   sent with Valid 0; foot forces are clipped to 0..4094; mode, gait type, battery SoC and IMU
//   temperature pass unchanged (the encoder clamps to the DBC ranges). HighState has no IMU
//   saturation flags: GYR/ACC_Saturated are always 0.
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "algorithms/common/can_frame.hpp"
#include "drivers/can/go1_encoder.hpp"
#include "drivers/can/go1_sample.hpp"
#include "drivers/go1/high_state.hpp"

namespace bimslam::go1_bridge {

// The HighState codec lives in drivers/go1 (the capture simulator writes HighStates too).
using namespace ::bimslam::go1;  // NOLINT(google-build-using-namespace)

// STS_BridgeState values (DBC VAL_ 320 STS_BridgeState).
enum class BridgeState : uint8_t { kInit = 0, kRunning = 1, kDegraded = 2, kFault = 3 };
const char* ToString(BridgeState state);

struct BridgeConfig {
    int64_t poll_period_ns = 2'000'000;  // 500 Hz, as the SDK examples
    // UdpLinkOk: a valid HighState within this time. 0: 3 poll periods.
    int64_t link_timeout_ns = 0;
    // Foot contact hysteresis on HighState.footForce (raw sensor units; tune on the robot).
    int contact_on_raw = 40;
    int contact_off_raw = 20;
    // Odometry reset detection.
    double odom_jump_m = 0.2;
    double odom_max_speed_mps = 5.0;
    int64_t odom_reset_gap_ns = 1'000'000'000;
    // Quaternions whose norm differs from 1 by more than this are sent as not valid.
    double quat_norm_tolerance = 0.1;
    // false: forward HighStates whose CRC fails too (HighStateCrcOk then says so); for bench
    // diagnosis of a Go1 whose CRC differs. Wrong sizes are always rejected.
    bool check_crc = true;

    int64_t EffectiveLinkTimeoutNs() const {
        return link_timeout_ns > 0 ? link_timeout_ns : 3 * poll_period_ns;
    }
    // Throws common::Error (kInvalidArgument) naming the field and its value.
    void Validate() const;
};

struct BridgeStats {
    uint64_t datagrams = 0;            // datagrams offered
    uint64_t highstates = 0;           // accepted HighStates (forwarded or superseded)
    uint64_t wrong_size = 0;           // rejected: not 1087 bytes
    uint64_t bad_head = 0;             // rejected: head not 0xFE 0xEF
    uint64_t bad_level_flag = 0;       // rejected: levelFlag not HIGHLEVEL
    uint64_t crc_failures = 0;         // CRC matches neither form (rejected when check_crc)
    uint64_t crc_plain = 0;            // accepted with the plain CRC-32
    uint64_t crc_scrambled = 0;        // accepted with the SDK's scrambled CRC (encryptCRC)
    uint64_t polls = 0;                // HighCmds sent
    uint64_t lost = 0;                 // poll periods without a valid HighState
    uint64_t samples = 0;              // CAN samples forwarded (alive counter steps)
    uint64_t placeholder_samples = 0;  // of these, sent with the link down (nothing valid)
    uint64_t skipped_ticks = 0;        // sample ticks skipped: link up, nothing new yet
    uint64_t frames = 0;               // CAN frames produced
    uint64_t withheld_frames = 0;      // repeat copies not sent because the link dropped
    uint64_t link_losses = 0;          // transitions of UdpLinkOk from 1 to 0
    uint64_t odom_resets = 0;          // reset flags raised
    uint64_t unusable_groups = 0;      // groups sent not valid because of non-finite values
};

class Bridge {
public:
    static constexpr size_t kMaxFramesPerTick = can::Go1Encoder::kMaxFramesPerTick;
    using Frames = can::Go1Encoder::Frames;

    // Set-up: validates the configuration and builds the encoder (may throw common::Error).
    explicit Bridge(const BridgeConfig& config = {});

    // A HighCmd was sent at `now_ns`.
    void OnPoll(int64_t now_ns);
    // A datagram from the Go1, received at `receive_ns`. Returns how it parsed.
    ParseResult OnDatagram(std::span<const uint8_t> bytes, int64_t receive_ns);
    // The bridge's 5 ms timer: writes the frames due into `out` (stamped `frame_timestamp_ns`,
    // the sink's clock) and returns how many.
    size_t OnTick(int64_t now_ns, int64_t frame_timestamp_ns, Frames out);

    int64_t tick_ns() const { return encoder_.layout().tick_ns(); }
    bool link_ok(int64_t now_ns) const;
    BridgeState state() const { return state_; }
    const BridgeStats& stats() const { return stats_; }
    const BridgeConfig& config() const { return config_; }
    // Which CRC forms the accepted HighStates carried: "none yet", "plain", "scrambled" or
    // "plain+scrambled".
    const char* crc_forms_seen() const;
    // The last sample handed to the encoder (placeholders included).
    const can::Go1Sample& last_sample() const { return sample_; }
    const can::Go1Encoder& encoder() const { return encoder_; }

private:
    // Counts a rejected datagram under `counter` and in the STATUS window; returns `why`.
    ParseResult Reject(uint64_t& counter, ParseResult why);
    void MapHighState(const HighState& hs, int64_t receive_ns);
    void UpdateState(bool link);

    BridgeConfig config_;
    can::Go1Encoder encoder_;

    // Receive side.
    HighState highstate_{};    // scratch for parsing
    can::Go1Sample newest_{};  // the newest valid HighState, mapped
    bool has_newest_ = false;  // newest_ not yet forwarded
    bool ever_received_ = false;
    int64_t last_rx_ns_ = 0;         // receive time of the newest valid HighState
    bool last_datagram_ok_ = false;  // HighStateCrcOk
    std::array<bool, 4> contact_{};
    bool have_position_ = false;
    std::array<float, 3> last_position_{};
    int64_t last_position_ns_ = 0;
    bool reset_pending_ = true;  // the first sample forwarded carries a reset
    bool answered_ = false;      // a valid HighState since the last poll
    bool polled_ = false;

    // Send side.
    bool link_was_ok_ = false;
    uint32_t window_lost_ = 0;    // lost samples since the last STATUS frame
    uint32_t window_faults_ = 0;  // rejected datagrams and unusable groups since then
    BridgeState state_ = BridgeState::kInit;
    can::Go1Sample sample_{};       // the sample handed to the encoder
    bool sample_has_data_ = false;  // sample_ carries a HighState (not a placeholder)
    BridgeStats stats_;
};

}  // namespace bimslam::go1_bridge
