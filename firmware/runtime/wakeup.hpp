// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// A sleep-until-notified for a thread that consumes several queues: a futex on a sequence number.
// Notify is one atomic increment plus a FUTEX_WAKE system call only when someone sleeps; Wait
// returns at once when anything was notified since the sequence number the caller read.
#pragma once

#include <atomic>
#include <cstdint>

namespace bimslam::runtime {

class Wakeup {
public:
    uint32_t Sequence() const { return seq_.load(std::memory_order_acquire); }
    void Notify();
    // Sleeps until the sequence differs from `seen` or `timeout_ns` passed (<= 0: no sleep).
    void Wait(uint32_t seen, int64_t timeout_ns);

private:
    std::atomic<uint32_t> seq_{0};
    std::atomic<uint32_t> sleepers_{0};
};

}  // namespace bimslam::runtime
