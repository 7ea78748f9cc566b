// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The systemd notification protocol (sd_notify(3)), without libsystemd: one datagram per call to
// the AF_UNIX socket named by $NOTIFY_SOCKET ('@' first: the abstract namespace). READY=1 once
// the threads run, WATCHDOG=1 from the health thread while every heartbeat is fresh,
// STATUS=<text>, STOPPING=1. Without $NOTIFY_SOCKET (not under systemd) every call does nothing.
#pragma once

#include <cstdint>
#include <string>

namespace bimslam::runtime {

class SdNotifier {
public:
    SdNotifier();  // reads $NOTIFY_SOCKET and $WATCHDOG_USEC
    ~SdNotifier();
    SdNotifier(const SdNotifier&) = delete;
    SdNotifier& operator=(const SdNotifier&) = delete;

    bool enabled() const { return fd_ >= 0; }
    // The watchdog period systemd asked for (WatchdogSec), 0 when none.
    int64_t watchdog_ns() const { return watchdog_ns_; }
    // Sends "READY=1" etc.; false when not enabled or the send failed.
    bool Notify(const std::string& state);

private:
    int fd_ = -1;
    std::string address_;
    int64_t watchdog_ns_ = 0;
};

}  // namespace bimslam::runtime
