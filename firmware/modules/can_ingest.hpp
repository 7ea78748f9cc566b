// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The CAN ingest thread: Go1 CAN frames -> E2E checks and sample assembly (can::Go1Decoder) ->
// Go1 samples for the odometry thread and for LCM. The frames come from SocketCAN (the bus),
// from LCM (bimslam-go1-bridge --lcm: can_frame_t, for benches without CAN), or from a recording
// (a candump -l log or a CAN pcap, paced by the shared replay clock). Per frame nothing
// allocates, throws or logs; faults are counted in the decoder's statistics.
//
// Progress: after each turn the thread publishes the arrival time up to which it has handed on
// every sample (progress_ns(); kEndOfStream at the end of a recording). The odometry thread waits
// for it to pass a scan's arrival before processing the scan, so a scan gets the same Go1
// samples however the two threads are scheduled.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>

#include "firmware/modules/rig_types.hpp"
#include "firmware/runtime/seqlock.hpp"
#include "firmware/runtime/thread_table.hpp"

namespace bimslam::rig {

struct CanIngestConfig {
    std::string source = "socketcan";  // socketcan | lcm | log
    std::string interface_name = "can0";
    std::string log;
    std::string lcm_url;
    std::string lcm_channel = "BIMSLAM_GO1_CAN";
    bool publish_go1_state = true;
};

struct CanCounters {
    can::Go1DecoderStats decoder;
    uint16_t timed_out = 0;       // Go1Group bits timed out now
    uint64_t frames = 0;          // frames read from the source
    uint64_t bodies_dropped = 0;  // body queue full
    uint64_t source_errors = 0;   // receive errors, bad log lines
    uint64_t kernel_dropped = 0;  // SocketCAN: frames the kernel dropped
    int64_t last_frame_mono_ns = 0;
    bool finished = false;
    // What the Go1 bridge says of itself in its frames (SYNC/STATUS UdpLinkOk, STATUS
    // STS_BridgeState, STS_UdpRxLost): samples sent with its UDP link to the Go1 down, STATUS
    // frames saying anything but RUNNING, HighStates it lost, and its last state (-1 before the
    // first STATUS). Health raises FAULT_GO1_BRIDGE from them.
    uint64_t bridge_link_down = 0;
    uint64_t bridge_not_running = 0;
    uint64_t bridge_lost = 0;
    int bridge_state = -1;
};

class CanIngest {
public:
    // Opens the source; throws common::Error naming the interface, URL or file and the reason
    // (kUnavailable for a kernel without CAN: the message says what to use instead).
    CanIngest(const CanIngestConfig& config, runtime::SpscQueue<BodyItem>& bodies,
              runtime::SpscQueue<Go1Item>& go1_lcm, ReplayClock* replay);
    ~CanIngest();

    void Run(runtime::ThreadStats& stats, const std::atomic<bool>& stop);

    int64_t progress_ns() const { return progress_ns_.load(std::memory_order_acquire); }
    CanCounters counters() const { return counters_.Load(); }
    int64_t first_capture_ns() const;
    const std::string& description() const { return description_; }

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    std::atomic<int64_t> progress_ns_{0};
    runtime::Seqlock<CanCounters> counters_;
    std::string description_;
};

}  // namespace bimslam::rig
