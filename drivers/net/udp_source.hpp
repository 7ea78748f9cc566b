// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Live UDP reception for the sensor's lidar and IMU streams.
//
// One socket, bound to an address and port; datagrams are read in batches with recvmmsg(2) into
// buffers allocated once by the constructor: Receive() does not allocate, does not throw and does
// not log. Each datagram carries the kernel's receive time (SO_TIMESTAMPNS, CLOCK_REALTIME) or,
// when a message comes without it, clock_gettime(CLOCK_REALTIME) right after recvmmsg returned
// (counted in stats().software_timestamps). IP_PKTINFO gives each datagram's destination address.
//
// The receive buffer: Linux doubles the SO_RCVBUF value it is given (the extra half is for its own
// bookkeeping, socket(7)) and caps the request at net.core.rmem_max, silently. The constructor
// reads the value back and, when the kernel gave less than asked, says so once in
// receive_buffer_warning() for the caller to log at start-up.
#pragma once

#include <netinet/in.h>
#include <sys/socket.h>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "algorithms/common/status.hpp"
#include "algorithms/common/time.hpp"
#include "drivers/net/ipv4.hpp"

namespace bimslam::net {

struct UdpSourceConfig {
    std::string bind_address = "0.0.0.0";  // dotted IPv4; 0.0.0.0: every interface
    uint16_t port = 7502;                  // 0: let the kernel choose (see UdpSource::port())
    // Accept datagrams from this source address only ("" accepts every source); others are
    // counted in stats().filtered.
    std::string sensor_address;
    // SO_RCVBUF request in bytes (0: keep the system default). A 1024x10 OS1-128 sends ~16 MB/s;
    // 8 MiB holds half a second.
    int receive_buffer_bytes = 8 << 20;
    size_t batch_size = 64;             // datagrams per recvmmsg call
    size_t max_datagram_bytes = 65536;  // larger datagrams are cut (MSG_TRUNC) and dropped
    bool reuse_address = false;         // SO_REUSEADDR

    // Throws common::Error (kInvalidArgument) naming the field.
    void Validate() const;
};

struct UdpSourceStats {
    uint64_t received = 0;             // datagrams returned
    uint64_t filtered = 0;             // from another source than sensor_address; dropped
    uint64_t truncated = 0;            // larger than max_datagram_bytes (MSG_TRUNC); dropped
    uint64_t errors = 0;               // failed poll/recvmmsg calls
    uint64_t batches = 0;              // recvmmsg calls that returned datagrams
    uint64_t timeouts = 0;             // Receive calls that saw nothing within their timeout
    uint64_t software_timestamps = 0;  // datagrams without a kernel timestamp
};

// One Receive call's result: the accepted datagrams (spans valid until the next Receive) and
// what happened: kOk (datagrams may still be empty when all were filtered out),
// kDeadlineExceeded (nothing arrived within the timeout), kIoError (error_number holds errno).
struct UdpBatch {
    std::span<const UdpDatagram> datagrams;
    bool full = false;  // the read took batch_size datagrams: more may be queued
    common::StatusCode code = common::StatusCode::kOk;
    int error_number = 0;
};

class UdpSource {
public:
    // Opens, configures and binds the socket and allocates every buffer. Throws common::Error:
    // kInvalidArgument for a bad configuration, kUnavailable when the socket cannot be bound
    // (the message names the address and port and the reason).
    explicit UdpSource(const UdpSourceConfig& config);
    UdpSource(const UdpSource&) = delete;
    UdpSource& operator=(const UdpSource&) = delete;
    ~UdpSource();

    // Waits up to `timeout` (0: only what is queued) and reads one batch. Never throws, never
    // allocates.
    UdpBatch Receive(common::Duration timeout);

    const UdpSourceStats& stats() const { return stats_; }
    // The bound port (the kernel's choice when the configuration said 0).
    uint16_t port() const { return bound_port_; }
    // SO_RCVBUF as getsockopt reports it (Linux: twice the usable size).
    int receive_buffer_bytes() const { return receive_buffer_bytes_; }
    // Empty, or one sentence for the start-up log saying that the kernel gave less receive
    // buffer than asked and how to raise the limit.
    const std::string& receive_buffer_warning() const { return receive_buffer_warning_; }
    // False when SO_TIMESTAMPNS could not be enabled (every datagram then has a software time).
    bool kernel_timestamps() const { return kernel_timestamps_; }
    int fd() const { return fd_; }

private:
    UdpSourceConfig config_;
    int fd_ = -1;
    uint16_t bound_port_ = 0;
    uint32_t sensor_ip_ = 0;
    bool filter_ = false;
    bool kernel_timestamps_ = false;
    int receive_buffer_bytes_ = 0;
    std::string receive_buffer_warning_;
    UdpSourceStats stats_;

    // Buffers for one batch, allocated by the constructor.
    std::vector<uint8_t> data_;
    std::vector<uint8_t> control_;
    size_t control_bytes_ = 0;  // per message
    std::vector<iovec> iov_;
    std::vector<mmsghdr> messages_;
    std::vector<sockaddr_in> sources_;
    std::vector<UdpDatagram> datagrams_;
};

}  // namespace bimslam::net
