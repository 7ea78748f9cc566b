// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "firmware/go1_bridge/sinks.hpp"

#include <bimslam/can_frame_t.hpp>
#include <lcm/lcm-cpp.hpp>

#include "algorithms/common/status.hpp"
#include "algorithms/common/time.hpp"
#include "drivers/can/candump.hpp"
#include "drivers/net/can_socket.hpp"

namespace bimslam::go1_bridge {
namespace {

class SocketCanSink final : public FrameSink {
public:
    explicit SocketCanSink(const net::CanSocketConfig& config) : socket_(config) {
        description_ = "SocketCAN " + config.interface_name;
    }
    bool Send(const common::CanFrame& frame) noexcept override {
        const net::CanSendResult r = socket_.Send(frame);
        if (r.code == common::StatusCode::kOk) {
            ++stats_.sent;
            return true;
        }
        ++stats_.failed;
        stats_.last_error = r.error_number;
        return false;
    }

private:
    net::CanSocket socket_;
};

class CandumpSink final : public FrameSink {
public:
    CandumpSink(const std::string& path, const std::string& interface_name)
        : writer_(path, Config()), interface_(interface_name) {
        description_ = "candump " + path;
        lossless_ = true;
    }
    bool Send(const common::CanFrame& frame) noexcept override {
        try {
            writer_.Write(frame, interface_);
        } catch (const std::exception&) {
            ++stats_.failed;
            return false;
        }
        ++stats_.sent;
        return true;
    }
    void Close() override { writer_.Close(); }

private:
    static can::CandumpWriterConfig Config() {
        can::CandumpWriterConfig c;
        c.atomic = false;  // streamed: a long live recording survives a crash
        return c;
    }
    can::CandumpWriter writer_;
    std::string interface_;
};

class LcmSink final : public FrameSink {
public:
    LcmSink(const std::string& url, const std::string& channel) : lcm_(url), channel_(channel) {
        if (!lcm_.good()) {
            throw common::Error(common::StatusCode::kUnavailable,
                                "cannot open LCM at '" + url +
                                    "' (udpm:// needs a multicast route: "
                                    "toolchain/setup-multicast.sh)");
        }
        description_ = "LCM " + url + " channel " + channel;
        msg_.schema_version = can_frame_t::SCHEMA_VERSION;
    }
    bool Send(const common::CanFrame& frame) noexcept override {
        msg_.sample_time_ns = frame.timestamp_ns;
        msg_.publish_time_ns = common::HostNow().ns;
        msg_.id = static_cast<int32_t>(frame.id);
        int32_t flags = 0;
        if (frame.extended) flags |= can_frame_t::FLAG_EFF;
        if (frame.remote) flags |= can_frame_t::FLAG_RTR;
        if (frame.error) flags |= can_frame_t::FLAG_ERR;
        if (frame.fd) flags |= can_frame_t::FLAG_FD;
        if (frame.fd_flags & 0x1) flags |= can_frame_t::FLAG_FD_BRS;
        if (frame.fd_flags & 0x2) flags |= can_frame_t::FLAG_FD_ESI;
        msg_.flags = flags;
        msg_.len = static_cast<int8_t>(frame.len);
        for (size_t i = 0; i < frame.data.size(); ++i) {
            msg_.data[i] = i < frame.len ? frame.data[i] : 0;
        }
        try {
            if (lcm_.publish(channel_, &msg_) == 0) {
                ++stats_.sent;
                return true;
            }
        } catch (const std::exception&) {
        }
        ++stats_.failed;
        return false;
    }

private:
    lcm::LCM lcm_;
    std::string channel_;
    can_frame_t msg_{};
};

}  // namespace

std::unique_ptr<FrameSink> OpenSocketCanSink(const std::string& interface_name) {
    net::CanSocketConfig config;
    config.interface_name = interface_name;
    config.error_frames = false;  // we only send
    return std::make_unique<SocketCanSink>(config);
}

std::unique_ptr<FrameSink> OpenCandumpSink(const std::string& path,
                                           const std::string& interface_name) {
    return std::make_unique<CandumpSink>(path, interface_name);
}

std::unique_ptr<FrameSink> OpenLcmSink(const std::string& url, const std::string& channel) {
    return std::make_unique<LcmSink>(url, channel);
}

}  // namespace bimslam::go1_bridge
