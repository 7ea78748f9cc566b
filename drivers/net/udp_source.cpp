// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "drivers/net/udp_source.hpp"

#include <arpa/inet.h>
#include <poll.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <ctime>

#include "drivers/net/byte_order.hpp"

namespace bimslam::net {
namespace {
using detail::RealtimeNs;

using common::Error;
using common::StatusCode;

}  // namespace

void UdpSourceConfig::Validate() const {
    if (!ParseIpv4(bind_address)) {
        throw Error(StatusCode::kInvalidArgument,
                    "bind_address: '" + bind_address + "' is not a dotted IPv4 address");
    }
    if (!sensor_address.empty() && !ParseIpv4(sensor_address)) {
        throw Error(StatusCode::kInvalidArgument,
                    "sensor_address: '" + sensor_address + "' is not a dotted IPv4 address");
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
    if (max_datagram_bytes < 1 || max_datagram_bytes > 65536) {
        throw Error(StatusCode::kInvalidArgument,
                    "max_datagram_bytes: " + std::to_string(max_datagram_bytes) +
                        ", must be in [1, 65536]");
    }
}

UdpSource::UdpSource(const UdpSourceConfig& config) : config_(config) {
    config_.Validate();
    const std::string where = config_.bind_address + ":" + std::to_string(config_.port);
    auto fail = [&](const std::string& what) {
        const int err = errno;
        if (fd_ >= 0) ::close(fd_);
        fd_ = -1;
        throw Error(StatusCode::kUnavailable,
                    "UDP " + where + ": " + what + ": " + std::strerror(err));
    };
    fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    if (fd_ < 0) fail("socket");
    const int one = 1;
    if (config_.reuse_address && ::setsockopt(fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one))) {
        fail("SO_REUSEADDR");
    }
    if (config_.receive_buffer_bytes > 0) {
        const int want = config_.receive_buffer_bytes;
        if (::setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &want, sizeof(want)) != 0) {
            fail("SO_RCVBUF");
        }
    }
    socklen_t length = sizeof(receive_buffer_bytes_);
    if (::getsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &receive_buffer_bytes_, &length) != 0) {
        fail("getsockopt SO_RCVBUF");
    }
    // Linux stores min(request, net.core.rmem_max) * 2 and reports that (socket(7)).
    if (config_.receive_buffer_bytes > 0 &&
        static_cast<int64_t>(receive_buffer_bytes_) < 2 * int64_t{config_.receive_buffer_bytes}) {
        receive_buffer_warning_ =
            "UDP " + where + ": asked for a " + std::to_string(config_.receive_buffer_bytes) +
            "-byte receive buffer, the kernel gave " + std::to_string(receive_buffer_bytes_ / 2) +
            " usable bytes (getsockopt reports " + std::to_string(receive_buffer_bytes_) +
            ", Linux doubles the value); packets may be dropped in bursts. Raise the limit with "
            "'sysctl -w net.core.rmem_max=" +
            std::to_string(config_.receive_buffer_bytes) + "'";
    }
    kernel_timestamps_ = ::setsockopt(fd_, SOL_SOCKET, SO_TIMESTAMPNS, &one, sizeof(one)) == 0;
    if (::setsockopt(fd_, IPPROTO_IP, IP_PKTINFO, &one, sizeof(one)) != 0) fail("IP_PKTINFO");

    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(config_.port);
    address.sin_addr.s_addr = htonl(*ParseIpv4(config_.bind_address));
    if (::bind(fd_, reinterpret_cast<const sockaddr*>(&address), sizeof(address)) != 0) {
        fail("bind");
    }
    socklen_t address_length = sizeof(address);
    if (::getsockname(fd_, reinterpret_cast<sockaddr*>(&address), &address_length) != 0) {
        fail("getsockname");
    }
    bound_port_ = ntohs(address.sin_port);
    if (!config_.sensor_address.empty()) {
        filter_ = true;
        sensor_ip_ = *ParseIpv4(config_.sensor_address);
    }

    const size_t n = config_.batch_size;
    control_bytes_ = CMSG_SPACE(sizeof(timespec)) + CMSG_SPACE(sizeof(in_pktinfo));
    data_.resize(n * config_.max_datagram_bytes);
    control_.resize(n * control_bytes_);
    iov_.resize(n);
    messages_.resize(n);
    sources_.resize(n);
    datagrams_.resize(n);
}

UdpSource::~UdpSource() {
    if (fd_ >= 0) ::close(fd_);
}

UdpBatch UdpSource::Receive(common::Duration timeout) {
    UdpBatch batch;
    pollfd p{fd_, POLLIN, 0};
    const int64_t timeout_ns = std::max<int64_t>(timeout.ns, 0);
    const timespec wait{static_cast<time_t>(timeout_ns / 1'000'000'000),
                        static_cast<long>(timeout_ns % 1'000'000'000)};
    // No wait: recvmmsg with MSG_DONTWAIT says the same as a zero-timeout ppoll (EAGAIN), one
    // system call less per turn (the rig's ingest polls both sockets itself, per datagram).
    const int ready = timeout_ns > 0 ? ::ppoll(&p, 1, &wait, nullptr) : 1;
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
    // The headers are rewritten each call: recvmmsg overwrites the lengths.
    const size_t n = config_.batch_size;
    for (size_t i = 0; i < n; ++i) {
        iov_[i].iov_base = data_.data() + i * config_.max_datagram_bytes;
        iov_[i].iov_len = config_.max_datagram_bytes;
        msghdr& h = messages_[i].msg_hdr;
        h.msg_name = &sources_[i];
        h.msg_namelen = sizeof(sockaddr_in);
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
    batch.full = static_cast<size_t>(got) == n;
    int64_t software_ns = -1;
    size_t accepted = 0;
    for (size_t i = 0; i < static_cast<size_t>(got); ++i) {
        msghdr& h = messages_[i].msg_hdr;
        const uint32_t src = ntohl(sources_[i].sin_addr.s_addr);
        if (filter_ && src != sensor_ip_) {
            ++stats_.filtered;
            continue;
        }
        if (h.msg_flags & MSG_TRUNC) {
            ++stats_.truncated;
            continue;
        }
        UdpDatagram& d = datagrams_[accepted];
        d.timestamp_ns = -1;
        d.dst_ip = 0;
        for (cmsghdr* c = CMSG_FIRSTHDR(&h); c != nullptr; c = CMSG_NXTHDR(&h, c)) {
            if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SCM_TIMESTAMPNS) {
                timespec ts;
                std::memcpy(&ts, CMSG_DATA(c), sizeof(ts));
                d.timestamp_ns = static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
            } else if (c->cmsg_level == IPPROTO_IP && c->cmsg_type == IP_PKTINFO) {
                in_pktinfo info;
                std::memcpy(&info, CMSG_DATA(c), sizeof(info));
                d.dst_ip = ntohl(info.ipi_addr.s_addr);
            }
        }
        if (d.timestamp_ns < 0) {
            if (software_ns < 0) software_ns = RealtimeNs();
            d.timestamp_ns = software_ns;
            ++stats_.software_timestamps;
        }
        d.src_ip = src;
        d.src_port = ntohs(sources_[i].sin_port);
        d.dst_port = bound_port_;
        d.payload = std::span<const uint8_t>(static_cast<const uint8_t*>(iov_[i].iov_base),
                                             messages_[i].msg_len);
        d.record_index = stats_.received;
        d.fragments = 1;
        ++stats_.received;
        ++accepted;
    }
    batch.datagrams = std::span<const UdpDatagram>(datagrams_.data(), accepted);
    return batch;
}

}  // namespace bimslam::net
