// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// A bounded, lock-free, single-producer single-consumer queue of preallocated slots
// (Lamport's ring with C++11 acquire/release indices). The slots are constructed once, by the
// constructor, with an initialiser that may reserve their buffers (a point cloud's capacity), so
// neither side allocates afterwards: the producer fills a slot in place (BeginPush/CommitPush),
// the consumer reads it in place (Front/Pop).
//
// Full queue: the producer's BeginPush returns nullptr and the producer applies the queue's
// policy (firmware/runtime/README.md, "Queues"): drop the new item and count it (CountDrop), or,
// in a replay (lossless at every speed), wait for room (BeginPushWaiting, PushWaiting). A Wakeup,
// when given, is notified on every commit so that a consumer can sleep on several queues at once.
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "firmware/runtime/wakeup.hpp"

namespace bimslam::runtime {

// What the health thread reads of any queue.
struct QueueStats {
    std::string name;
    size_t capacity = 0;
    size_t depth = 0;
    size_t max_depth = 0;  // since the last ResetMaxDepth
    uint64_t drops = 0;
    uint64_t pushed = 0;
};

class QueueBase {
public:
    virtual ~QueueBase() = default;
    virtual QueueStats Stats() const = 0;
    virtual void ResetMaxDepth() = 0;
};

template <typename T>
class SpscQueue : public QueueBase {
public:
    SpscQueue(std::string name, size_t capacity, const std::function<void(T&)>& init = {},
              Wakeup* wakeup = nullptr)
        : name_(std::move(name)), slots_(capacity + 1), wakeup_(wakeup) {
        if (init) {
            for (T& slot : slots_) init(slot);
        }
    }

    // Producer: the slot to fill, or nullptr when full.
    T* BeginPush() {
        const size_t tail = tail_.load(std::memory_order_relaxed);
        const size_t next = Next(tail);
        if (next == head_.load(std::memory_order_acquire)) return nullptr;
        return &slots_[tail];
    }
    // Producer: publishes the slot BeginPush returned.
    void CommitPush() {
        const size_t tail = tail_.load(std::memory_order_relaxed);
        tail_.store(Next(tail), std::memory_order_release);
        pushed_.fetch_add(1, std::memory_order_relaxed);
        const size_t depth = size();
        size_t seen = max_depth_.load(std::memory_order_relaxed);
        while (depth > seen && !max_depth_.compare_exchange_weak(seen, depth)) {
        }
        if (wakeup_ != nullptr) wakeup_->Notify();
    }
    // Producer: an item it could not queue (the queue was full).
    void CountDrop() { drops_.fetch_add(1, std::memory_order_relaxed); }
    // Producer: copies `item` in, or counts a drop; true when queued.
    bool TryPush(const T& item) {
        T* slot = BeginPush();
        if (slot == nullptr) {
            CountDrop();
            return false;
        }
        *slot = item;
        CommitPush();
        return true;
    }

    // Producer: BeginPush, but while `wait` holds (a replay) and `stop` does not, waits for room
    // instead of giving up. nullptr: the item must be dropped (the caller counts it). The poll
    // is short: the consumer of a replay is running flat out.
    T* BeginPushWaiting(bool wait, const std::atomic<bool>& stop) {
        T* slot = BeginPush();
        while (slot == nullptr && wait && !stop.load(std::memory_order_relaxed)) {
            std::this_thread::sleep_for(std::chrono::microseconds(200));
            slot = BeginPush();
        }
        return slot;
    }
    // Producer: TryPush with BeginPushWaiting's policy; a drop is counted. A waiting push that
    // the stop ended is the run's end, not a drop (a replay stopped by its duration).
    bool PushWaiting(const T& item, bool wait, const std::atomic<bool>& stop) {
        T* slot = BeginPushWaiting(wait, stop);
        if (slot == nullptr) {
            if (!wait) CountDrop();
            return false;
        }
        *slot = item;
        CommitPush();
        return true;
    }

    // Consumer: the oldest item, or nullptr when empty.
    T* Front() {
        const size_t head = head_.load(std::memory_order_relaxed);
        if (head == tail_.load(std::memory_order_acquire)) return nullptr;
        return &slots_[head];
    }
    // Consumer: releases the item Front returned.
    void Pop() {
        const size_t head = head_.load(std::memory_order_relaxed);
        head_.store(Next(head), std::memory_order_release);
        if (wakeup_ != nullptr) wakeup_->Notify();  // a waiting replay producer
    }

    size_t size() const {
        const size_t head = head_.load(std::memory_order_acquire);
        const size_t tail = tail_.load(std::memory_order_acquire);
        return tail >= head ? tail - head : tail + slots_.size() - head;
    }
    size_t capacity() const { return slots_.size() - 1; }
    uint64_t drops() const { return drops_.load(std::memory_order_relaxed); }
    const std::string& name() const { return name_; }

    QueueStats Stats() const override {
        return {name_,   capacity(),
                size(),  max_depth_.load(std::memory_order_relaxed),
                drops(), pushed_.load(std::memory_order_relaxed)};
    }
    void ResetMaxDepth() override { max_depth_.store(size(), std::memory_order_relaxed); }

private:
    size_t Next(size_t i) const { return i + 1 == slots_.size() ? 0 : i + 1; }

    std::string name_;
    std::vector<T> slots_;
    Wakeup* wakeup_;
    alignas(64) std::atomic<size_t> head_{0};  // consumer
    alignas(64) std::atomic<size_t> tail_{0};  // producer
    alignas(64) std::atomic<uint64_t> drops_{0};
    std::atomic<uint64_t> pushed_{0};
    std::atomic<size_t> max_depth_{0};
};

}  // namespace bimslam::runtime
