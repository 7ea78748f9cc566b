// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Sending UDP datagrams in batches with sendmmsg(2): what `bimslam ouster replay` uses to put a
// recording's packets on a real socket at the recorded pace (a bench stand-in for the sensor).
// One socket, optionally bound to a local address and port (a receiver that connect()s to the
// sensor's address needs the datagrams to come from it); buffers allocated by the constructor.
#pragma once

#include <netinet/in.h>
#include <sys/socket.h>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace bimslam::net {

struct UdpSenderConfig {
    std::string bind_address = "0.0.0.0";
    uint16_t bind_port = 0;  // 0: any
    int send_buffer_bytes = 4 << 20;
    size_t batch_size = 64;
    void Validate() const;  // throws common::Error naming the field
};

struct UdpSenderStats {
    uint64_t sent = 0;
    uint64_t bytes = 0;
    uint64_t failed = 0;  // datagrams sendmmsg did not take (counted, not retried)
    int last_error = 0;
};

class UdpSender {
public:
    // Throws common::Error (kUnavailable) naming the address when the socket cannot be set up.
    explicit UdpSender(const UdpSenderConfig& config);
    ~UdpSender();
    UdpSender(const UdpSender&) = delete;
    UdpSender& operator=(const UdpSender&) = delete;

    // Queues one datagram for the next Flush (copies it); flushes first when the batch is full.
    void Add(uint32_t dst_ip, uint16_t dst_port, std::span<const uint8_t> payload);
    // Sends the queued datagrams with one sendmmsg call (more when it takes fewer).
    void Flush();
    const UdpSenderStats& stats() const { return stats_; }

private:
    UdpSenderConfig config_;
    int fd_ = -1;
    std::vector<uint8_t> data_;
    std::vector<sockaddr_in> addresses_;
    std::vector<iovec> iov_;
    std::vector<mmsghdr> messages_;
    size_t count_ = 0;
    UdpSenderStats stats_;
};

}  // namespace bimslam::net
