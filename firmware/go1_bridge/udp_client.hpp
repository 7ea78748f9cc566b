// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The bridge's UDP link to the Go1's sport-mode computer: one non-blocking IPv4 socket, bound to a
// local port and connect()ed to the Go1 (as the SDK's UDP class does), so the kernel delivers
// only the Go1's datagrams and send() needs no address. Send and Receive neither allocate nor
// throw; errors come back as errno values for the caller to count.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

namespace bimslam::go1_bridge {

struct UdpClientConfig {
    std::string go1_address = "192.168.123.161";  // dotted IPv4 of the sport-mode computer
    uint16_t go1_port = 8082;                     // its HighCmd/HighState port
    std::string local_address = "0.0.0.0";        // dotted IPv4 to bind; 0.0.0.0: any
    uint16_t local_port = 8090;  // as the SDK examples; 0: the kernel chooses (local_port())

    // Throws common::Error (kInvalidArgument) naming the field and value.
    void Validate() const;
};

// Splits "IP:PORT" (port 1..65535). Throws common::Error (kInvalidArgument) naming `what` and
// the text.
void ParseAddressAndPort(const std::string& text, const std::string& what, std::string& address,
                         uint16_t& port);

class UdpClient {
public:
    // Opens, binds and connects the socket. Throws common::Error: kInvalidArgument for a bad
    // configuration, kUnavailable when the socket cannot be created, bound or connected (the
    // message names the address, the port and the reason).
    explicit UdpClient(const UdpClientConfig& config);
    UdpClient(const UdpClient&) = delete;
    UdpClient& operator=(const UdpClient&) = delete;
    ~UdpClient();

    // Sends one datagram to the Go1. Returns 0, or the errno of a failed send (ECONNREFUSED when
    // an earlier datagram drew an ICMP port unreachable, ENETUNREACH, ...).
    int Send(std::span<const uint8_t> bytes);

    // One queued datagram, if any, without waiting.
    struct Received {
        size_t size = 0;         // the datagram's real size (may exceed the buffer: truncated)
        bool got = false;        // a datagram was read
        bool truncated = false;  // larger than the buffer; its bytes are cut
        int error = 0;           // errno of a failed read other than "nothing queued"
    };
    Received Receive(std::span<uint8_t> buffer);

    int fd() const { return fd_; }
    uint16_t local_port() const { return local_port_; }

private:
    int fd_ = -1;
    uint16_t local_port_ = 0;
};

}  // namespace bimslam::go1_bridge
