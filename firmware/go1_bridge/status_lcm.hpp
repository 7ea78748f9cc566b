// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The bridge's status on LCM (bimslam::go1_bridge_status_t, channel BIMSLAM_GO1_BRIDGE): its
// state, link, counters by cause and the HighState CRC forms seen. Published every
// kStatusLcmPeriodNs and once at exit; it doubles as the bridge's heartbeat (README.md, "Status
// on LCM").
#pragma once

#include <bimslam/go1_bridge_status_t.hpp>
#include <cstdint>
#include <lcm/lcm-cpp.hpp>
#include <string>

#include "firmware/go1_bridge/bridge.hpp"
#include "firmware/go1_bridge/sinks.hpp"

namespace bimslam::go1_bridge {

inline constexpr int64_t kStatusLcmPeriodNs = 500'000'000;  // 2 Hz
inline constexpr char kStatusLcmChannel[] = "BIMSLAM_GO1_BRIDGE";

// What the message holds besides the bridge's own counters.
struct StatusContext {
    bool link_ok = false;
    int64_t uptime_ns = 0;
    int64_t host_now_ns = 0;  // CLOCK_REALTIME
    uint64_t udp_errors = 0;  // send and receive errors of the UDP client
    SinkStats sink;
};

// The message for the bridge's current state (publish_time_ns and sequence are the publisher's).
go1_bridge_status_t MakeStatusMessage(const Bridge& bridge, const StatusContext& context);

class StatusPublisher {
public:
    // Throws common::Error (kUnavailable) naming the URL when LCM cannot be opened.
    StatusPublisher(const std::string& url, const std::string& channel);
    // Publishes; false (counted) when LCM refused. Never throws.
    bool Publish(go1_bridge_status_t message) noexcept;
    uint64_t failures() const { return failures_; }
    const std::string& description() const { return description_; }

private:
    lcm::LCM lcm_;
    std::string channel_;
    std::string description_;
    int64_t sequence_ = 0;
    uint64_t failures_ = 0;
};

}  // namespace bimslam::go1_bridge
