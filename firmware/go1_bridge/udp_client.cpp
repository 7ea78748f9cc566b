// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "firmware/go1_bridge/udp_client.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "algorithms/common/status.hpp"

namespace bimslam::go1_bridge {
namespace {

using common::Error;
using common::StatusCode;

bool ParseIpv4(const std::string& text, in_addr& out) {
    return ::inet_pton(AF_INET, text.c_str(), &out) == 1;
}

std::string Endpoint(const std::string& address, uint16_t port) {
    return address + ":" + std::to_string(port);
}

}  // namespace

void UdpClientConfig::Validate() const {
    in_addr a{};
    if (!ParseIpv4(go1_address, a)) {
        throw Error(StatusCode::kInvalidArgument,
                    "go1_address: '" + go1_address + "' is not a dotted IPv4 address");
    }
    if (go1_port == 0) {
        throw Error(StatusCode::kInvalidArgument, "go1_port: 0 is not a port to send to");
    }
    if (!ParseIpv4(local_address, a)) {
        throw Error(StatusCode::kInvalidArgument,
                    "local_address: '" + local_address + "' is not a dotted IPv4 address");
    }
}

void ParseAddressAndPort(const std::string& text, const std::string& what, std::string& address,
                         uint16_t& port) {
    const size_t colon = text.rfind(':');
    const auto bad = [&](const std::string& why) {
        return Error(StatusCode::kInvalidArgument,
                     what + ": '" + text + "' is not IP:PORT (" + why + ")");
    };
    if (colon == std::string::npos || colon == 0 || colon + 1 == text.size()) {
        throw bad("expected e.g. 192.168.123.161:8082");
    }
    const std::string host = text.substr(0, colon);
    const std::string digits = text.substr(colon + 1);
    in_addr a{};
    if (!ParseIpv4(host, a)) throw bad("'" + host + "' is not a dotted IPv4 address");
    if (digits.size() > 5 || digits.find_first_not_of("0123456789") != std::string::npos) {
        throw bad("'" + digits + "' is not a port number");
    }
    const unsigned long value = std::stoul(digits);
    if (value == 0 || value > 65535) throw bad("port " + digits + " is outside 1..65535");
    address = host;
    port = static_cast<uint16_t>(value);
}

UdpClient::UdpClient(const UdpClientConfig& config) {
    config.Validate();
    fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    if (fd_ < 0) {
        throw Error(StatusCode::kUnavailable,
                    std::string("cannot create a UDP socket: ") + std::strerror(errno));
    }
    sockaddr_in local{};
    local.sin_family = AF_INET;
    local.sin_port = htons(config.local_port);
    ParseIpv4(config.local_address, local.sin_addr);
    if (::bind(fd_, reinterpret_cast<const sockaddr*>(&local), sizeof(local)) != 0) {
        const int e = errno;
        ::close(fd_);
        fd_ = -1;
        throw Error(StatusCode::kUnavailable,
                    "cannot bind UDP " + Endpoint(config.local_address, config.local_port) +
                        " (--local-port): " + std::strerror(e) +
                        (e == EADDRINUSE ? " (another SDK client or bridge uses the port?)" : ""));
    }
    sockaddr_in remote{};
    remote.sin_family = AF_INET;
    remote.sin_port = htons(config.go1_port);
    ParseIpv4(config.go1_address, remote.sin_addr);
    if (::connect(fd_, reinterpret_cast<const sockaddr*>(&remote), sizeof(remote)) != 0) {
        const int e = errno;
        ::close(fd_);
        fd_ = -1;
        throw Error(StatusCode::kUnavailable, "cannot connect UDP to the Go1 at " +
                                                  Endpoint(config.go1_address, config.go1_port) +
                                                  ": " + std::strerror(e));
    }
    sockaddr_in bound{};
    socklen_t length = sizeof(bound);
    if (::getsockname(fd_, reinterpret_cast<sockaddr*>(&bound), &length) == 0) {
        local_port_ = ntohs(bound.sin_port);
    }
}

UdpClient::~UdpClient() {
    if (fd_ >= 0) ::close(fd_);
}

int UdpClient::Send(std::span<const uint8_t> bytes) {
    const ssize_t n = ::send(fd_, bytes.data(), bytes.size(), MSG_DONTWAIT | MSG_NOSIGNAL);
    if (n < 0) return errno;
    return static_cast<size_t>(n) == bytes.size() ? 0 : EMSGSIZE;
}

UdpClient::Received UdpClient::Receive(std::span<uint8_t> buffer) {
    Received r;
    const ssize_t n = ::recv(fd_, buffer.data(), buffer.size(), MSG_DONTWAIT | MSG_TRUNC);
    if (n < 0) {
        if (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) r.error = errno;
        return r;
    }
    r.got = true;
    r.size = static_cast<size_t>(n);
    r.truncated = r.size > buffer.size();
    return r;
}

}  // namespace bimslam::go1_bridge
