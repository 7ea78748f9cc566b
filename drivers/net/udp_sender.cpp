// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "drivers/net/udp_sender.hpp"

#include <arpa/inet.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "algorithms/common/status.hpp"
#include "drivers/net/ipv4.hpp"

namespace bimslam::net {
namespace {
constexpr size_t kMaxDatagram = 65536;
}

void UdpSenderConfig::Validate() const {
    if (!ParseIpv4(bind_address)) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            "bind_address: '" + bind_address + "' is not a dotted IPv4 address");
    }
    if (batch_size < 1 || batch_size > 1024) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            "batch_size: " + std::to_string(batch_size) + ", must be in [1, 1024]");
    }
}

UdpSender::UdpSender(const UdpSenderConfig& config) : config_(config) {
    config_.Validate();
    const std::string where = config_.bind_address + ":" + std::to_string(config_.bind_port);
    fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    const auto fail = [&](const char* what) {
        const int e = errno;
        if (fd_ >= 0) ::close(fd_);
        fd_ = -1;
        throw common::Error(common::StatusCode::kUnavailable,
                            "UDP sender " + where + ": " + what + ": " + std::strerror(e));
    };
    if (fd_ < 0) fail("socket");
    const int one = 1;
    ::setsockopt(fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one));
    if (config_.send_buffer_bytes > 0) {
        ::setsockopt(fd_, SOL_SOCKET, SO_SNDBUF, &config_.send_buffer_bytes,
                     sizeof(config_.send_buffer_bytes));
    }
    sockaddr_in local{};
    local.sin_family = AF_INET;
    local.sin_port = htons(config_.bind_port);
    local.sin_addr.s_addr = htonl(*ParseIpv4(config_.bind_address));
    if (::bind(fd_, reinterpret_cast<const sockaddr*>(&local), sizeof(local)) != 0) fail("bind");
    const size_t n = config_.batch_size;
    data_.resize(n * kMaxDatagram);
    addresses_.resize(n);
    iov_.resize(n);
    messages_.resize(n);
}

UdpSender::~UdpSender() {
    if (fd_ >= 0) ::close(fd_);
}

void UdpSender::Add(uint32_t dst_ip, uint16_t dst_port, std::span<const uint8_t> payload) {
    if (count_ == config_.batch_size) Flush();
    const size_t size = std::min(payload.size(), kMaxDatagram);
    uint8_t* slot = data_.data() + count_ * kMaxDatagram;
    std::memcpy(slot, payload.data(), size);
    sockaddr_in& a = addresses_[count_];
    a = sockaddr_in{};
    a.sin_family = AF_INET;
    a.sin_port = htons(dst_port);
    a.sin_addr.s_addr = htonl(dst_ip);
    iov_[count_] = {slot, size};
    mmsghdr& m = messages_[count_];
    m = mmsghdr{};
    m.msg_hdr.msg_name = &a;
    m.msg_hdr.msg_namelen = sizeof(a);
    m.msg_hdr.msg_iov = &iov_[count_];
    m.msg_hdr.msg_iovlen = 1;
    ++count_;
}

void UdpSender::Flush() {
    size_t done = 0;
    while (done < count_) {
        const int n = ::sendmmsg(fd_, messages_.data() + done, unsigned(count_ - done), 0);
        if (n <= 0) {
            stats_.last_error = errno;
            ++stats_.failed;  // this datagram; try the rest
            ++done;
            continue;
        }
        for (int i = 0; i < n; ++i) stats_.bytes += messages_[done + size_t(i)].msg_len;
        stats_.sent += unsigned(n);
        done += size_t(n);
    }
    count_ = 0;
}

}  // namespace bimslam::net
