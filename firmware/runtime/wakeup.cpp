// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "firmware/runtime/wakeup.hpp"

#include <linux/futex.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <ctime>

namespace bimslam::runtime {
namespace {
long Futex(std::atomic<uint32_t>* addr, int op, uint32_t value, const timespec* timeout) {
    return syscall(SYS_futex, reinterpret_cast<uint32_t*>(addr), op, value, timeout, nullptr, 0);
}
}  // namespace

void Wakeup::Notify() {
    seq_.fetch_add(1, std::memory_order_acq_rel);
    if (sleepers_.load(std::memory_order_acquire) > 0) {
        Futex(&seq_, FUTEX_WAKE_PRIVATE, 0x7fffffff, nullptr);
    }
}

void Wakeup::Wait(uint32_t seen, int64_t timeout_ns) {
    if (timeout_ns <= 0) return;
    sleepers_.fetch_add(1, std::memory_order_acq_rel);
    if (seq_.load(std::memory_order_acquire) == seen) {
        const timespec t{static_cast<time_t>(timeout_ns / 1'000'000'000),
                         static_cast<long>(timeout_ns % 1'000'000'000)};
        Futex(&seq_, FUTEX_WAIT_PRIVATE, seen, &t);  // EAGAIN when it changed meanwhile
    }
    sleepers_.fetch_sub(1, std::memory_order_acq_rel);
}

}  // namespace bimslam::runtime
