// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "drivers/net/can_socket.hpp"

#include <linux/can.h>
#include <linux/can/error.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <ctime>

#include "drivers/net/byte_order.hpp"

namespace bimslam::net {
namespace {
using detail::RealtimeNs;

using common::CanFrame;
using common::Error;
using common::StatusCode;

constexpr size_t kMaxFilters = 512;  // CAN_RAW_FILTER_MAX

static_assert(sizeof(can_frame) == 16 && sizeof(canfd_frame) == 72);

}  // namespace

std::string_view CanErrorClassName(size_t bit) {
    static constexpr std::string_view kNames[kCanErrorClasses] = {
        "tx-timeout", "lost-arbitration", "controller", "protocol",  "transceiver",
        "no-ack",     "bus-off",          "bus-error",  "restarted", "error-counter"};
    return bit < kCanErrorClasses ? kNames[bit] : "unknown";
}

void CanSocketConfig::Validate() const {
    if (interface_name.empty() || interface_name.size() >= IFNAMSIZ) {
        throw Error(StatusCode::kInvalidArgument, "interface_name: '" + interface_name +
                                                      "', must have 1 to " +
                                                      std::to_string(IFNAMSIZ - 1) + " characters");
    }
    if (filters.size() > kMaxFilters) {
        throw Error(StatusCode::kInvalidArgument,
                    "filters: " + std::to_string(filters.size()) + " entries, at most " +
                        std::to_string(kMaxFilters) + " (CAN_RAW_FILTER_MAX)");
    }
    for (size_t i = 0; i < filters.size(); ++i) {
        const CanIdFilter& f = filters[i];
        const uint32_t limit = f.extended ? common::kCanEffMask : common::kCanSffMask;
        if (f.id > limit || f.mask > limit) {
            throw Error(StatusCode::kInvalidArgument,
                        "filters[" + std::to_string(i) + "]: id " + std::to_string(f.id) +
                            " or mask " + std::to_string(f.mask) + " beyond the " +
                            (f.extended ? "29" : "11") + "-bit range");
        }
    }
    if (receive_buffer_bytes < 0) {
        throw Error(
            StatusCode::kInvalidArgument,
            "receive_buffer_bytes: " + std::to_string(receive_buffer_bytes) + ", must be >= 0");
    }
    if (batch_size < 1 || batch_size > 1024) {
        throw Error(StatusCode::kInvalidArgument,
                    "batch_size: " + std::to_string(batch_size) + ", must be in [1, 1024]");
    }
}

CanSocket::CanSocket(const CanSocketConfig& config) : config_(config) {
    config_.Validate();
    const std::string where = "CAN interface '" + config_.interface_name + "'";
    auto fail = [&](const std::string& what) {
        const int err = errno;
        if (fd_ >= 0) ::close(fd_);
        fd_ = -1;
        std::string message = where + ": " + what + " failed: " + std::strerror(err);
        if (err == EAFNOSUPPORT) message += " (this kernel has no SocketCAN)";
        throw Error(StatusCode::kUnavailable, message);
    };
    fd_ = ::socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, CAN_RAW);
    if (fd_ < 0) fail("socket(PF_CAN, SOCK_RAW, CAN_RAW)");
    if (config_.interface_name != "any") {
        interface_index_ = static_cast<int>(::if_nametoindex(config_.interface_name.c_str()));
        if (interface_index_ == 0) fail("if_nametoindex");
    }

    if (!config_.filters.empty()) {
        std::vector<can_filter> filters;
        for (const CanIdFilter& f : config_.filters) {
            can_filter k{};
            k.can_id = f.id | (f.extended ? CAN_EFF_FLAG : 0U);
            k.can_mask = f.mask | CAN_EFF_FLAG | CAN_RTR_FLAG;
            filters.push_back(k);
        }
        if (::setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_FILTER, filters.data(),
                         static_cast<socklen_t>(filters.size() * sizeof(can_filter))) != 0) {
            fail("setsockopt CAN_RAW_FILTER");
        }
    }
    const can_err_mask_t error_mask = config_.error_frames ? CAN_ERR_MASK : 0U;
    if (::setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &error_mask, sizeof(error_mask)) != 0) {
        fail("setsockopt CAN_RAW_ERR_FILTER");
    }
    const int one = 1;
    if (config_.fd_frames &&
        ::setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_FD_FRAMES, &one, sizeof(one)) != 0) {
        fail("setsockopt CAN_RAW_FD_FRAMES (does the interface support CAN FD?)");
    }
    if (config_.receive_own_messages &&
        ::setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_RECV_OWN_MSGS, &one, sizeof(one)) != 0) {
        fail("setsockopt CAN_RAW_RECV_OWN_MSGS");
    }
    if (config_.receive_buffer_bytes > 0) {
        const int want = config_.receive_buffer_bytes;
        if (::setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &want, sizeof(want)) != 0) {
            fail("setsockopt SO_RCVBUF");
        }
    }
    kernel_timestamps_ = ::setsockopt(fd_, SOL_SOCKET, SO_TIMESTAMPNS, &one, sizeof(one)) == 0;
    if (::setsockopt(fd_, SOL_SOCKET, SO_RXQ_OVFL, &one, sizeof(one)) != 0) {
        fail("setsockopt SO_RXQ_OVFL");
    }

    sockaddr_can address{};
    address.can_family = AF_CAN;
    address.can_ifindex = interface_index_;
    if (::bind(fd_, reinterpret_cast<const sockaddr*>(&address), sizeof(address)) != 0) {
        fail("bind");
    }

    const size_t n = config_.batch_size;
    // The timestamp as struct timespec or, with 64-bit time on 32-bit systems,
    // struct __kernel_timespec (16 bytes), then the drop counter.
    control_bytes_ = CMSG_SPACE(16) + CMSG_SPACE(sizeof(uint32_t));
    data_.resize(n * CANFD_MTU);
    control_.resize(n * control_bytes_);
    iov_.resize(n);
    messages_.resize(n);
    frames_.resize(n);
}

CanSocket::~CanSocket() {
    if (fd_ >= 0) ::close(fd_);
}

CanBatch CanSocket::Receive(common::Duration timeout) {
    CanBatch batch;
    pollfd p{fd_, POLLIN, 0};
    const int64_t timeout_ns = std::max<int64_t>(timeout.ns, 0);
    const timespec wait{static_cast<time_t>(timeout_ns / 1'000'000'000),
                        static_cast<long>(timeout_ns % 1'000'000'000)};
    const int ready = ::ppoll(&p, 1, &wait, nullptr);
    if (ready < 0) {
        if (errno == EINTR) {  // a signal: the caller's loop checks its stop flag
            batch.code = StatusCode::kDeadlineExceeded;
            return batch;
        }
        ++stats_.errors;
        batch.code = StatusCode::kIoError;
        batch.error_number = errno;
        return batch;
    }
    if (ready == 0) {
        ++stats_.timeouts;
        batch.code = StatusCode::kDeadlineExceeded;
        return batch;
    }
    const size_t n = config_.batch_size;
    for (size_t i = 0; i < n; ++i) {
        iov_[i].iov_base = data_.data() + i * CANFD_MTU;
        iov_[i].iov_len = CANFD_MTU;
        msghdr& h = messages_[i].msg_hdr;
        h.msg_name = nullptr;
        h.msg_namelen = 0;
        h.msg_iov = &iov_[i];
        h.msg_iovlen = 1;
        h.msg_control = control_.data() + i * control_bytes_;
        h.msg_controllen = control_bytes_;
        h.msg_flags = 0;
        messages_[i].msg_len = 0;
    }
    const int got =
        ::recvmmsg(fd_, messages_.data(), static_cast<unsigned>(n), MSG_DONTWAIT, nullptr);
    if (got < 0) {
        if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) {
            ++stats_.timeouts;
            batch.code = StatusCode::kDeadlineExceeded;
            return batch;
        }
        ++stats_.errors;
        batch.code = StatusCode::kIoError;
        batch.error_number = errno;
        return batch;
    }
    ++stats_.batches;
    int64_t software_ns = -1;
    size_t accepted = 0;
    for (size_t i = 0; i < static_cast<size_t>(got); ++i) {
        msghdr& h = messages_[i].msg_hdr;
        int64_t timestamp_ns = -1;
        for (cmsghdr* c = CMSG_FIRSTHDR(&h); c != nullptr; c = CMSG_NXTHDR(&h, c)) {
            if (c->cmsg_level != SOL_SOCKET) continue;
            if (c->cmsg_type == SCM_TIMESTAMPNS) {
                timespec ts;
                std::memcpy(&ts, CMSG_DATA(c), sizeof(ts));
                timestamp_ns = static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
            } else if (c->cmsg_type == SO_RXQ_OVFL) {
                uint32_t count;
                std::memcpy(&count, CMSG_DATA(c), sizeof(count));
                const uint32_t delta = count - last_drop_count_;  // wraps at 2^32 as the kernel's
                last_drop_count_ = count;
                batch.dropped += delta;
                stats_.dropped += delta;
            }
        }
        const size_t size = messages_[i].msg_len;
        if ((h.msg_flags & MSG_TRUNC) != 0 || (size != CAN_MTU && size != CANFD_MTU)) {
            ++stats_.malformed;
            continue;
        }
        canfd_frame raw;
        std::memcpy(&raw, iov_[i].iov_base, size);
        CanFrame& f = frames_[accepted];
        f = CanFrame{};
        if (timestamp_ns < 0) {
            if (software_ns < 0) software_ns = RealtimeNs();
            timestamp_ns = software_ns;
            ++stats_.software_timestamps;
        }
        f.timestamp_ns = timestamp_ns;
        f.fd = size == CANFD_MTU;
        f.error = (raw.can_id & CAN_ERR_FLAG) != 0;
        f.remote = !f.fd && !f.error && (raw.can_id & CAN_RTR_FLAG) != 0;
        f.extended = !f.error && (raw.can_id & CAN_EFF_FLAG) != 0;
        f.id = raw.can_id & (f.extended || f.error ? CAN_EFF_MASK : CAN_SFF_MASK);
        if (f.fd) {
            f.len = std::min<uint8_t>(raw.len, CANFD_MAX_DLEN);
            if (!common::IsCanFdLength(f.len)) f.len = CANFD_MAX_DLEN;  // never from the kernel
            f.fd_flags = raw.flags & common::kCanFdFlagsMask;
        } else {
            can_frame classic;
            std::memcpy(&classic, &raw, sizeof(classic));
            f.len = std::min<uint8_t>(classic.len, CAN_MAX_DLEN);
            if (f.len == CAN_MAX_DLEN && classic.len8_dlc > CAN_MAX_DLEN &&
                classic.len8_dlc <= CAN_MAX_RAW_DLC) {
                f.len8_dlc = classic.len8_dlc;
            }
        }
        if (!f.remote) std::memcpy(f.data.data(), raw.data, f.len);
        if (f.error) {
            ++stats_.error_frames;
            for (size_t bit = 0; bit < kCanErrorClasses; ++bit) {
                if (f.id & (1U << bit)) ++stats_.error_classes[bit];
            }
            if (f.id >> kCanErrorClasses) ++stats_.unknown_error_classes;
        }
        ++stats_.received;
        ++accepted;
    }
    batch.frames = std::span<const CanFrame>(frames_.data(), accepted);
    return batch;
}

CanSendResult CanSocket::Send(const CanFrame& frame) {
    CanSendResult result;
    if (common::CanFrameProblem(frame) != nullptr || frame.error ||
        (frame.fd && !config_.fd_frames) || interface_index_ == 0) {
        ++stats_.send_errors;
        result.code = StatusCode::kInvalidArgument;
        return result;
    }
    canfd_frame raw{};
    raw.can_id = frame.id;
    if (frame.extended) raw.can_id |= CAN_EFF_FLAG;
    if (frame.remote) raw.can_id |= CAN_RTR_FLAG;
    raw.len = frame.len;
    size_t size = CAN_MTU;
    if (frame.fd) {
        raw.flags = frame.fd_flags;
        size = CANFD_MTU;
    } else {
        raw.__res1 = frame.len8_dlc;  // struct can_frame's len8_dlc
    }
    if (!frame.remote) std::memcpy(raw.data, frame.data.data(), frame.len);
    const ssize_t n = ::send(fd_, &raw, size, MSG_DONTWAIT);
    if (n == static_cast<ssize_t>(size)) {
        ++stats_.sent;
        return result;
    }
    if (n < 0 && (errno == ENOBUFS || errno == EAGAIN || errno == EWOULDBLOCK)) {
        ++stats_.send_busy;
        result.code = StatusCode::kUnavailable;
        result.error_number = errno;
        return result;
    }
    ++stats_.send_errors;
    result.code = StatusCode::kIoError;
    result.error_number = n < 0 ? errno : EIO;
    return result;
}

}  // namespace bimslam::net
