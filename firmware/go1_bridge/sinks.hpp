// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Where the bridge's CAN frames go: a SocketCAN interface (the real bus), a candump log file, or
// LCM (bimslam::can_frame_t, for tests and tools on machines without CAN). Exactly one per run.
//
// Send never throws; it returns false and counts the failure (the bridge keeps running: a full
// CAN transmit queue or a lost LCM datagram must not stop the other frames). SocketCAN and
// candump sends do not allocate; an LCM publish allocates inside LCM (encode buffer), which is
// why LCM is the test sink, not the bus.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "algorithms/common/can_frame.hpp"

namespace bimslam::go1_bridge {

struct SinkStats {
    uint64_t sent = 0;
    uint64_t failed = 0;
    int last_error = 0;  // errno of the last failed send, when the sink knows it
};

class FrameSink {
public:
    virtual ~FrameSink() = default;
    // Hands one frame on; false when it was not sent (counted in stats()).
    virtual bool Send(const common::CanFrame& frame) noexcept = 0;
    // Flushes and closes (candump: the file is complete afterwards). May throw common::Error.
    virtual void Close() {}
    // "SocketCAN can0", "candump /path/log", "LCM udpm://... channel X".
    const std::string& description() const { return description_; }
    const SinkStats& stats() const { return stats_; }
    // Every frame must arrive (a recording): a failure makes the run fail.
    bool lossless() const { return lossless_; }

protected:
    std::string description_;
    SinkStats stats_;
    bool lossless_ = false;
};

// Each factory opens its sink and throws common::Error naming the interface, file or URL and the
// reason when it cannot (kUnavailable: no CAN in the kernel, no such interface, LCM not usable;
// a candump file that cannot be created: common::FileError).
std::unique_ptr<FrameSink> OpenSocketCanSink(const std::string& interface_name);
// Frames are written with `interface_name` (candump's second column) and their timestamps
// (CLOCK_REALTIME, as candump -l). The log is streamed: what was written survives a crash, and it
// always ends at a line end.
std::unique_ptr<FrameSink> OpenCandumpSink(const std::string& path,
                                           const std::string& interface_name = "can0");
std::unique_ptr<FrameSink> OpenLcmSink(const std::string& url, const std::string& channel);

}  // namespace bimslam::go1_bridge
