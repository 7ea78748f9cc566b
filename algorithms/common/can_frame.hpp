// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// A CAN or CAN FD frame as every CAN source and sink of the project exchanges it (SocketCAN,
// candump logs, pcaps of link type 227, the Go1 bridge). Plain data: no allocation.
#pragma once

#include <array>
#include <cstdint>

namespace bimslam::common {

struct CanFrame {
    int64_t timestamp_ns = 0;  // receive (or log) time; the clock is the source's to name
    uint32_t id = 0;           // 11-bit (standard) or 29-bit (extended) identifier, no flag bits
    bool extended = false;     // 29-bit identifier (EFF)
    bool remote = false;       // remote transmission request (RTR): no data; len is the DLC asked
    bool error = false;        // an error frame (ERR): id holds the error class bits
    bool fd = false;           // CAN FD frame (up to 64 data bytes)
    uint8_t len = 0;           // data bytes: 0..8 classic, 0..64 FD
    // CAN FD flags as candump and SocketCAN hold them: BRS 0x1, ESI 0x2, and FDF 0x4, which
    // Linux >= 6.2 sets on every FD frame it receives. 0 for classic frames.
    uint8_t fd_flags = 0;
    std::array<uint8_t, 64> data{};
    // Classic CAN with 8 data bytes only: the raw DLC 9..15 the frame was sent with (SocketCAN
    // len8_dlc, candump's "_<dlc>" suffix); 0 otherwise.
    uint8_t len8_dlc = 0;
};

// SocketCAN identifier flags and masks (linux/can.h), for the sources and sinks that hold the
// identifier as one 32-bit word.
inline constexpr uint32_t kCanEffFlag = 0x80000000U;  // extended frame format
inline constexpr uint32_t kCanRtrFlag = 0x40000000U;  // remote transmission request
inline constexpr uint32_t kCanErrFlag = 0x20000000U;  // error frame
inline constexpr uint32_t kCanSffMask = 0x000007FFU;
inline constexpr uint32_t kCanEffMask = 0x1FFFFFFFU;
inline constexpr uint8_t kCanFdFlagsMask = 0x0F;  // candump writes the flags as one hex digit

// True for the payload lengths a CAN FD DLC can give: 0..8, 12, 16, 20, 24, 32, 48, 64.
constexpr bool IsCanFdLength(unsigned len) {
    return len <= 8 || len == 12 || len == 16 || len == 20 || len == 24 || len == 32 || len == 48 ||
           len == 64;
}

// nullptr when `frame` is a frame SocketCAN could carry, else what is wrong (a static string).
// Timestamps are not checked.
constexpr const char* CanFrameProblem(const CanFrame& frame) {
    if (frame.error) {
        if (frame.extended || frame.remote || frame.fd) {
            return "an error frame cannot be extended, remote or CAN FD";
        }
        if (frame.id > kCanEffMask) return "error class bits above 0x1FFFFFFF";
    } else if (frame.extended ? frame.id > kCanEffMask : frame.id > kCanSffMask) {
        return frame.extended ? "extended identifier above 0x1FFFFFFF"
                              : "standard identifier above 0x7FF";
    }
    if (frame.fd) {
        if (frame.remote) return "CAN FD has no remote frames";
        if (!IsCanFdLength(frame.len)) return "CAN FD length that no DLC gives";
        if (frame.fd_flags > kCanFdFlagsMask) return "CAN FD flags above 0xF";
    } else {
        if (frame.len > 8) return "classic CAN frame with more than 8 data bytes";
        if (frame.fd_flags != 0) return "CAN FD flags on a classic frame";
    }
    if (frame.len8_dlc != 0 &&
        (frame.fd || frame.len != 8 || frame.len8_dlc < 9 || frame.len8_dlc > 15)) {
        return "raw DLC (len8_dlc) other than 9..15 on a classic frame of 8 bytes";
    }
    return nullptr;
}

}  // namespace bimslam::common
