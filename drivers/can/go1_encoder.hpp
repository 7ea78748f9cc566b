// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Go1Samples to the CAN frames of go1_odometry.dbc: the sending side of the contract that
// Go1Decoder checks, used by the Go1 bridge (firmware/go1_bridge) and the capture simulator.
//
// The encoder owns the schedule (drivers/can/README.md, "Counters and cycles"), derived from the
// DBC's cycle times by Go1Layout: the bridge calls Tick every 5 ms. A tick that starts a sample
// (every second one) takes the newest HighState sample, gives it the next alive counter (0..14,
// once per sample forwarded) and sends every message due for it, slowest cycle first: GO1_STATUS
// with every 10th sample, the 20 ms messages with every 2nd, GO1_SYNC and the 10 ms messages and
// the 5 ms IMU messages with every sample. The tick between repeats the 5 ms messages byte for
// byte (same sample, same counter), which the decoder takes as the planned copy.
//
// Each frame: counter in byte 1, Valid bit from sample.valid (a group without its bit is sent
// with Valid 0 and every value as SNA), NaN values as SNA, out-of-range values clamped to the DBC
// range (counted), the quaternion normalised and sign-flipped to w >= 0 (only x, y, z are sent),
// BridgeTime as bridge_time_ns in microseconds modulo 2^32, and the CRC-8 in byte 0 last.
// Tick and EncodeSample allocate nothing and never throw.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "algorithms/common/can_frame.hpp"
#include "drivers/can/dbc.hpp"
#include "drivers/can/go1_messages.hpp"
#include "drivers/can/go1_sample.hpp"

namespace bimslam::can {

struct Go1EncoderConfig {
    uint8_t first_counter = 0;  // alive counter of the first sample, 0..14
    // Frame i of a tick is stamped timestamp_ns + i * frame_spacing_ns (an 8-byte classic frame
    // occupies a 500 kbit/s bus for about 0.23 ms); 0 stamps them all alike.
    int64_t frame_spacing_ns = 0;

    // Throws common::Error naming the field and its value.
    void Validate() const;
};

struct Go1EncoderStats {
    uint64_t samples = 0;  // samples encoded (alive counter steps)
    uint64_t frames = 0;   // frames produced
    uint64_t clamped = 0;  // values outside their DBC range, sent as the nearest bound
    uint64_t sna = 0;      // values sent as SNA: not finite, or their group not valid

    template <typename F>
    void ForEach(F&& f) const {
        f("samples", samples);
        f("frames", frames);
        f("clamped", clamped);
        f("sna", sna);
    }
};

class Go1Encoder {
public:
    static constexpr size_t kMaxFramesPerTick = kGo1Messages;
    using Frames = std::span<common::CanFrame, kMaxFramesPerTick>;

    // Derives the message table and schedule from `dbc` (set-up: may allocate and throw
    // common::Error).
    explicit Go1Encoder(const Go1EncoderConfig& config = {}, const Dbc& dbc = Go1Dbc());

    // One tick of the bridge's 5 ms timer; returns the frames written to `out`, in send order.
    // When the tick starts a sample (sample_tick_next()), `newest` is that sample (its counter,
    // host_time_ns and fresh fields are not used); nullptr sends nothing and the next tick
    // tries again. Otherwise the tick repeats the current sample's 5 ms messages and `newest`
    // is not used.
    size_t Tick(const Go1Sample* newest, int64_t timestamp_ns, Frames out);
    // Starts a sample now, whatever the tick phase (the next Tick is its repeat tick).
    size_t EncodeSample(const Go1Sample& sample, int64_t timestamp_ns, Frames out);
    // One frame of message `index` (Go1Group bit index, 0..9) for `sample` with alive counter
    // `counter`, exactly as EncodeSample sends it (tests and tools).
    common::CanFrame EncodeMessage(size_t index, const Go1Sample& sample, uint8_t counter,
                                   int64_t timestamp_ns);

    bool sample_tick_next() const { return phase_ == 0; }
    // The alive counter of the last sample encoded (the configured first counter before any).
    uint8_t counter() const { return counter_; }
    // Go1Group bits of the messages the next sample will carry.
    uint16_t NextSampleGroups() const;
    // Forgets the schedule and the counter, as after construction.
    void Reset();

    const Go1EncoderStats& stats() const { return stats_; }
    const Go1Layout& layout() const { return layout_; }

private:
    Go1Layout layout_;
    Go1EncoderConfig config_;
    uint32_t phase_ = 0;         // tick within the sample period; 0: the next tick starts a sample
    uint64_t sample_index_ = 0;  // samples encoded so far
    uint8_t counter_ = 0;
    std::array<common::CanFrame, kGo1Messages> last_{};  // the current sample's frames
    Go1EncoderStats stats_;
};

}  // namespace bimslam::can
