// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// One writer publishes a small trivially copyable struct that other threads read whole, without
// a lock the writer could wait on (a sequence lock: the writer never blocks; a reader retries
// while a write is in progress). For counters a hot thread exposes to the health thread.
#pragma once

#include <atomic>
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace bimslam::runtime {

template <typename T>
class Seqlock {
    static_assert(std::is_trivially_copyable_v<T>);

public:
    void Store(const T& value) {
        const uint32_t s = seq_.load(std::memory_order_relaxed);
        seq_.store(s + 1, std::memory_order_relaxed);
        std::atomic_thread_fence(std::memory_order_release);
        CopyIn(value);
        std::atomic_thread_fence(std::memory_order_release);
        seq_.store(s + 2, std::memory_order_release);
    }
    T Load() const {
        T out;
        for (;;) {
            const uint32_t s1 = seq_.load(std::memory_order_acquire);
            if (s1 & 1u) continue;
            CopyOut(out);
            std::atomic_thread_fence(std::memory_order_acquire);
            if (seq_.load(std::memory_order_relaxed) == s1) return out;
        }
    }

private:
    // Byte-wise through relaxed atomics would be the pedantic form; a memcpy between fences is
    // what every seqlock in practice does (Boehm, "Can seqlocks get along with programming
    // language memory models?", 2012) and what GCC compiles as intended.
    void CopyIn(const T& v) { std::memcpy(static_cast<void*>(&data_), &v, sizeof(T)); }
    void CopyOut(T& v) const { std::memcpy(static_cast<void*>(&v), &data_, sizeof(T)); }

    std::atomic<uint32_t> seq_{0};
    T data_{};
};

}  // namespace bimslam::runtime
