// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Go1 CAN frames to Go1Samples (specs/go1-can.md; the rules in full: drivers/can/README.md):
// - every frame is checked end to end: identifier (foreign ones are ignored and counted), frame
//   type, DLC 8, CRC-8/SAE-J1850 (crc8.hpp), then the alive counter per message;
// - the counter check knows each message's schedule (go1_messages.hpp): step k = cycle / 10 ms
//   between transmissions is normal, 2k means one transmission lost (accepted, counted), 0 is a
//   repeat (dropped; except the 5 ms messages' second copy of each sample, a benign duplicate),
//   anything else is a jump: dropped, and the message is trusted again after two good frames;
// - a message silent for longer than its GenMsgTimeout (3 x its cycle) is timed out: its group
//   is invalid until a frame of it is accepted again; Tick(now) notices silence without frames;
// - accepted frames are assembled by counter into a Go1Sample (SI units, w of the quaternion
//   reconstructed, the bridge time unwrapped to int64 ns); a sample is emitted once, as soon as
//   every frame due for it arrived, else when a frame of a newer sample arrives or (Tick) when
//   it has waited max_hold_ns. Groups without a frame in this sample keep their last values
//   (fresh bit clear; valid while not timed out).
// Feed, Tick and Flush allocate nothing and never throw: every fault is counted in
// Go1DecoderStats. Timestamps (frame.timestamp_ns and Tick's now_ns) are host receive times in
// one monotonic clock.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "algorithms/common/can_frame.hpp"
#include "drivers/can/dbc.hpp"
#include "drivers/can/go1_messages.hpp"
#include "drivers/can/go1_sample.hpp"

namespace bimslam::can {

struct Go1DecoderConfig {
    bool check_crc = true;  // false: accept any byte 0 (bench logs of a bridge without CRC)
    // The longest an incomplete sample waits (after its first frame) for a missing due frame
    // before Tick emits it anyway. Default 7 ms: long enough for the second copy of a lost 5 ms
    // frame (sent 5 ms after the first), shorter than the 10 ms sample period.
    int64_t max_hold_ns = 7'000'000;
    // Good frames (expected counter step) after a counter jump before the message is trusted
    // again; specs/go1-can.md says two.
    uint32_t resync_frames = 2;

    // Throws common::Error naming the field and its value.
    void Validate() const;
};

// What became of one frame; each verdict but kAccepted has a counter of the same name.
enum class Go1Verdict : uint8_t {
    kAccepted,        // passed every check and went into a sample
    kForeignId,       // not one of the DBC's Go1 identifiers (extended frames included): ignored
    kErrorFrame,      // a CAN error frame
    kBadFrame,        // a Go1 identifier as a remote or CAN FD frame
    kBadDlc,          // a Go1 identifier with a length other than the DBC's 8
    kCrc,             // CRC-8 mismatch: dropped
    kCounterInvalid,  // counter 15, which is never sent: dropped
    kCounterRepeat,   // counter step 0 beyond the message's copies per sample: dropped
    kCounterResync,   // a counter jump: dropped, the message resynchronises
    kResyncing,       // a good frame while resynchronising: dropped
    kDuplicate,       // the expected second copy of a 5 ms message: dropped, not a fault
    kLate,            // passed the checks but its sample was already emitted: dropped
};
std::string_view ToString(Go1Verdict v);

struct Go1DecoderStats {
    uint64_t frames = 0;  // offered to Feed; the sum of the per-verdict counters below
    uint64_t accepted = 0;
    uint64_t foreign_id = 0;
    uint64_t error_frame = 0;
    uint64_t bad_frame = 0;
    uint64_t bad_dlc = 0;
    uint64_t crc = 0;
    uint64_t counter_invalid = 0;
    uint64_t counter_repeat = 0;
    uint64_t counter_resync = 0;
    uint64_t resyncing = 0;
    uint64_t duplicate = 0;
    uint64_t late = 0;
    // Events, not frame verdicts:
    uint64_t counter_lost = 0;        // accepted frames whose step shows one transmission lost
    uint64_t timeout = 0;             // a message went silent for longer than its timeout
    uint64_t sna = 0;                 // signals received as "not available"
    uint64_t not_valid = 0;           // accepted frames with their Valid bit clear
    uint64_t out_of_range = 0;        // signals outside their DBC [min|max] (kept)
    uint64_t samples = 0;             // samples emitted
    uint64_t samples_incomplete = 0;  // emitted with a due frame missing

    // Visits (name, value) for every counter in declaration order; the names are the JSON keys.
    template <typename F>
    void ForEach(F&& f) const {
        f("frames", frames);
        f("accepted", accepted);
        f("foreign_id", foreign_id);
        f("error_frame", error_frame);
        f("bad_frame", bad_frame);
        f("bad_dlc", bad_dlc);
        f("crc", crc);
        f("counter_invalid", counter_invalid);
        f("counter_repeat", counter_repeat);
        f("counter_resync", counter_resync);
        f("resyncing", resyncing);
        f("duplicate", duplicate);
        f("late", late);
        f("counter_lost", counter_lost);
        f("timeout", timeout);
        f("sna", sna);
        f("not_valid", not_valid);
        f("out_of_range", out_of_range);
        f("samples", samples);
        f("samples_incomplete", samples_incomplete);
    }
    // The counter of a verdict.
    uint64_t Count(Go1Verdict v) const;
    // Frames dropped for a fault (every verdict but accepted, foreign_id and duplicate).
    uint64_t Faults() const;
};

struct Go1FeedResult {
    Go1Verdict verdict = Go1Verdict::kAccepted;
    int samples = 0;  // samples emitted by this call (0..2), see ready()
};

class Go1Decoder {
public:
    // Derives the message table from `dbc` (set-up: may allocate and throw common::Error).
    explicit Go1Decoder(const Go1DecoderConfig& config = {}, const Dbc& dbc = Go1Dbc());

    Go1FeedResult Feed(const common::CanFrame& frame);
    // Notices timeouts and holds that ran out at `now_ns` without a frame; returns the samples
    // emitted (0 or 1), see ready().
    int Tick(int64_t now_ns);
    // End of stream: emits the sample being assembled, if any.
    int Flush();
    // Forgets every message, sample and counter, as after construction, without allocating.
    void Reset();

    // The samples emitted by the last Feed, Tick or Flush, oldest first; valid until the next call.
    std::span<const Go1Sample> ready() const { return {ready_.data(), ready_count_}; }
    const Go1DecoderStats& stats() const { return stats_; }
    // Go1Group bits of the messages timed out now.
    uint16_t timed_out() const;
    const Go1Layout& layout() const { return layout_; }
    const Go1DecoderConfig& config() const { return config_; }

private:
    struct MessageState {
        int64_t last_seen_ns = 0;  // last frame that showed the message alive (see README)
        uint8_t ref = 0;           // counter of the last frame in sequence
        bool has_ref = false;      // false at start and after a timeout: the next frame is taken
        bool synced = false;       // has_ref and not resynchronising
        uint8_t resync_good = 0;   // good steps since the jump
        uint8_t copies_seen = 0;   // frames seen with counter `ref`
        bool timed_out = false;
        bool has_data = false;   // a frame was accepted since start or the last timeout
        bool valid_bit = false;  // of the last accepted frame (true for messages without one)
        bool sna = false;        // the last accepted frame held an SNA signal
    };

    Go1Verdict CheckCounter(size_t m, uint8_t counter, int64_t t);
    void Advance(int64_t now_ns);  // timeouts, then emission of a complete or overdue sample
    void CheckTimeouts(int64_t now_ns);
    void Assemble(size_t m, uint8_t counter, uint64_t word, int64_t t, Go1Verdict* verdict);
    void StartSample(uint8_t counter, int64_t t);
    void Apply(size_t m, uint8_t counter, uint64_t word);
    bool Complete() const { return (fresh_ & due_) == due_; }
    void Emit();
    Go1FeedResult Result(Go1Verdict v);

    Go1Layout layout_;
    Go1DecoderConfig config_;
    std::array<MessageState, kGo1Messages> msg_{};
    bool started_ = false;        // a frame was fed: message clocks run from it
    bool all_timed_out_ = false;  // every message timed out: the next frame restarts them

    Go1Sample current_{};  // the latest values of every group, in place
    // The sample being assembled.
    bool pending_ = false;
    uint8_t pending_counter_ = 0;
    int64_t pending_start_ns_ = 0;  // receive time of its first frame
    int64_t pending_last_ns_ = 0;   // of its last accepted frame
    uint16_t fresh_ = 0;
    uint16_t due_ = 0;
    // The last sample emitted (frames with its counter are late).
    bool has_emitted_ = false;
    uint8_t emitted_counter_ = 0;
    int64_t emitted_start_ns_ = 0;
    // Bridge time: SYNC's 32-bit microseconds unwrapped.
    bool has_sync_ = false;
    uint32_t last_bridge_us_ = 0;
    int64_t bridge_us_ = 0;
    uint8_t sync_counter_ = 0;

    std::array<Go1Sample, 2> ready_{};
    size_t ready_count_ = 0;
    Go1DecoderStats stats_;
};

}  // namespace bimslam::can
