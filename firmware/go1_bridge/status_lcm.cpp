// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "firmware/go1_bridge/status_lcm.hpp"

#include <exception>

#include "algorithms/common/status.hpp"
#include "algorithms/common/time.hpp"

namespace bimslam::go1_bridge {
namespace {

int64_t Count(uint64_t v) { return static_cast<int64_t>(v); }

}  // namespace

go1_bridge_status_t MakeStatusMessage(const Bridge& bridge, const StatusContext& context) {
    const BridgeStats& s = bridge.stats();
    go1_bridge_status_t m{};
    m.schema_version = go1_bridge_status_t::SCHEMA_VERSION;
    m.sample_time_ns = context.host_now_ns;
    m.uptime_ns = context.uptime_ns;
    m.state = static_cast<int8_t>(bridge.state());  // STATE_* = STS_BridgeState values
    m.udp_link_ok = context.link_ok;
    m.crc_check = bridge.config().check_crc;
    int8_t forms = 0;
    if (s.crc_plain > 0) forms |= go1_bridge_status_t::CRC_FORM_PLAIN;
    if (s.crc_scrambled > 0) forms |= go1_bridge_status_t::CRC_FORM_SCRAMBLED;
    m.crc_forms_seen = forms;
    m.polls = Count(s.polls);
    m.datagrams = Count(s.datagrams);
    m.highstates_crc_plain = Count(s.crc_plain);
    m.highstates_crc_scrambled = Count(s.crc_scrambled);
    m.rejected_size = Count(s.wrong_size);
    m.rejected_head = Count(s.bad_head);
    m.rejected_level_flag = Count(s.bad_level_flag);
    m.rejected_crc = Count(s.crc_failures);
    m.lost = Count(s.lost);
    m.link_losses = Count(s.link_losses);
    m.can_samples = Count(s.samples);
    m.can_frames = Count(s.frames);
    m.can_send_failures = Count(context.sink.failed);
    m.udp_errors = Count(context.udp_errors);
    return m;
}

StatusPublisher::StatusPublisher(const std::string& url, const std::string& channel)
    : lcm_(url), channel_(channel) {
    if (!lcm_.good()) {
        throw common::Error(common::StatusCode::kUnavailable,
                            "cannot open LCM at '" + url +
                                "' for the status (udpm:// needs a multicast route: "
                                "toolchain/setup-multicast.sh)");
    }
    description_ = "LCM " + url + " channel " + channel;
}

bool StatusPublisher::Publish(go1_bridge_status_t message) noexcept {
    message.publish_time_ns = common::HostNow().ns;
    message.sequence = sequence_++;
    try {
        if (lcm_.publish(channel_, &message) == 0) return true;
    } catch (const std::exception&) {
    }
    ++failures_;
    return false;
}

}  // namespace bimslam::go1_bridge
