// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Live SocketCAN reception (and sending, for the Go1 bridge): one raw CAN socket (PF_CAN,
// SOCK_RAW, CAN_RAW) bound to an interface.
//
// Set up by the constructor: CAN_RAW_FILTER with our identifiers (data frames only: each filter
// masks the EFF and RTR flags too, so the frame format must match and remote frames stay out),
// CAN_RAW_ERR_FILTER for every error class (error frames are counted per class),
// CAN_RAW_FD_FRAMES when asked, SO_TIMESTAMPNS (kernel receive time, CLOCK_REALTIME), SO_RXQ_OVFL
// (the kernel's count of frames dropped because the socket queue was full comes with every
// message; Receive reports how much it grew). Frames are read in batches with recvmmsg(2) into
// buffers allocated once: Receive() does not allocate, does not throw, does not log.
//
// A kernel without CAN (this development machine, specs/go1-can.md) fails socket(PF_CAN) with
// EAFNOSUPPORT: the constructor throws common::Error (kUnavailable) naming the interface and the
// reason. Everything CAN is tested through candump logs and pcaps there; the live test needs vcan.
#pragma once

#include <sys/socket.h>
#include <sys/uio.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "algorithms/common/can_frame.hpp"
#include "algorithms/common/status.hpp"
#include "algorithms/common/time.hpp"

namespace bimslam::net {

// One CAN_RAW_FILTER entry: a data frame of the same format (standard or extended) passes when
// (its id & mask) == (id & mask).
struct CanIdFilter {
    uint32_t id = 0;
    uint32_t mask = common::kCanSffMask;  // the id bits that must match
    bool extended = false;

    // This identifier only.
    static CanIdFilter Exact(uint32_t id, bool extended = false) {
        return {id, extended ? common::kCanEffMask : common::kCanSffMask, extended};
    }
};

struct CanSocketConfig {
    // A CAN network interface ("can0", "vcan0"), or "any" for every CAN interface (receive only).
    std::string interface_name = "can0";
    // Empty: every data frame (the kernel's default filter). At most 512 (CAN_RAW_FILTER_MAX).
    std::vector<CanIdFilter> filters;
    bool error_frames = true;           // CAN_RAW_ERR_FILTER = all classes (CAN_ERR_MASK)
    bool fd_frames = false;             // CAN_RAW_FD_FRAMES: receive and send CAN FD
    bool receive_own_messages = false;  // CAN_RAW_RECV_OWN_MSGS
    int receive_buffer_bytes = 0;       // SO_RCVBUF request (0: the system default)
    size_t batch_size = 64;             // frames per recvmmsg call

    // Throws common::Error (kInvalidArgument) naming the field.
    void Validate() const;
};

// Error classes (linux/can/error.h): bit i of the error frame's class word.
inline constexpr size_t kCanErrorClasses = 10;  // CAN_ERR_TX_TIMEOUT 0x1 ... CAN_ERR_CNT 0x200
// "tx-timeout", "lost-arbitration", "controller", "protocol", "transceiver", "no-ack", "bus-off",
// "bus-error", "restarted", "error-counter"; "unknown" beyond.
std::string_view CanErrorClassName(size_t bit);

struct CanSocketStats {
    uint64_t received = 0;      // frames returned: data, remote and error frames
    uint64_t error_frames = 0;  // of these, error frames
    std::array<uint64_t, kCanErrorClasses> error_classes{};  // error frames with class bit i set
    uint64_t unknown_error_classes = 0;  // error frames with class bits above CAN_ERR_CNT
    uint64_t dropped = 0;                // frames the kernel dropped (SO_RXQ_OVFL), since opening
    uint64_t malformed = 0;              // messages of neither CAN_MTU nor CANFD_MTU bytes; dropped
    uint64_t errors = 0;                 // failed ppoll/recvmmsg calls
    uint64_t batches = 0;                // recvmmsg calls that returned frames
    uint64_t timeouts = 0;               // Receive calls that saw nothing within their timeout
    uint64_t software_timestamps = 0;    // frames without a kernel timestamp
    uint64_t sent = 0;                   // frames sent
    uint64_t send_busy = 0;              // Send refused: transmit queue full (ENOBUFS, EAGAIN)
    uint64_t send_errors = 0;            // Send failed otherwise
};

// One Receive call's result: the frames (valid until the next Receive) and what happened: kOk,
// kDeadlineExceeded (nothing within the timeout, or a signal), kIoError (error_number holds
// errno). `dropped`: frames the kernel dropped since the previous batch.
struct CanBatch {
    std::span<const common::CanFrame> frames;
    uint64_t dropped = 0;
    common::StatusCode code = common::StatusCode::kOk;
    int error_number = 0;
};

// kOk; kInvalidArgument (a frame CanFrameProblem refuses, an error frame, CAN FD without
// fd_frames, sending on "any"); kUnavailable (transmit queue full: try later); kIoError
// (error_number holds errno).
struct CanSendResult {
    common::StatusCode code = common::StatusCode::kOk;
    int error_number = 0;
};

class CanSocket {
public:
    // Opens, configures and binds the socket and allocates every buffer. Throws common::Error:
    // kInvalidArgument for a bad configuration, kUnavailable when the kernel has no CAN, the
    // interface does not exist or an option is refused; the message names the interface, the
    // call and the reason.
    explicit CanSocket(const CanSocketConfig& config);
    CanSocket(const CanSocket&) = delete;
    CanSocket& operator=(const CanSocket&) = delete;
    ~CanSocket();

    // Waits up to `timeout` (0: only what is queued) and reads one batch. Never throws, never
    // allocates.
    CanBatch Receive(common::Duration timeout);
    // Queues one frame for transmission without blocking. Never throws, never allocates.
    CanSendResult Send(const common::CanFrame& frame);

    const CanSocketStats& stats() const { return stats_; }
    const CanSocketConfig& config() const { return config_; }
    int interface_index() const { return interface_index_; }
    // False when SO_TIMESTAMPNS could not be enabled (frames then get software times).
    bool kernel_timestamps() const { return kernel_timestamps_; }
    int fd() const { return fd_; }

private:
    CanSocketConfig config_;
    int fd_ = -1;
    int interface_index_ = 0;
    bool kernel_timestamps_ = false;
    uint32_t last_drop_count_ = 0;  // SO_RXQ_OVFL value of the last message
    CanSocketStats stats_;

    // Buffers for one batch, allocated by the constructor.
    std::vector<uint8_t> data_;  // batch_size x CANFD_MTU
    std::vector<uint8_t> control_;
    size_t control_bytes_ = 0;  // per message
    std::vector<iovec> iov_;
    std::vector<mmsghdr> messages_;
    std::vector<common::CanFrame> frames_;
};

}  // namespace bimslam::net
