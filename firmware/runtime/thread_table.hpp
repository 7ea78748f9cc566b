// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The rig's threads: one per job, each described by a row of the thread table (name, priority,
// CPU, period or trigger, deadline, what it may block on; firmware/runtime/README.md) and
// started with its scheduling applied. SCHED_FIFO, CPU affinity and mlockall may be refused (an
// unprivileged user, a container): the thread then runs with the normal scheduler, and the
// refusal is returned as a warning naming the thread, what was refused and why.
//
// Every thread reports through its ThreadStats (atomics, written by the thread only): a
// heartbeat (CLOCK_MONOTONIC ns of its last loop turn), cycles, deadline misses and the longest
// cycle since the health thread last read it. The health thread reads them; the watchdog is fed
// only while every heartbeat is fresh.
#pragma once

#include <pthread.h>

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <thread>
#include <vector>

namespace bimslam::runtime {

struct ThreadSpec {
    std::string name;                  // <= 15 characters (pthread_setname_np)
    int priority = 0;                  // SCHED_FIFO 1..99; 0: SCHED_OTHER
    int cpu = -1;                      // pinned CPU; -1: any
    int64_t period_ns = 0;             // a periodic thread's period; 0: triggered by its input
    int64_t deadline_ns = 0;           // per cycle; 0: none
    int64_t stale_ns = 2'000'000'000;  // heartbeat older than this: the thread is stuck
    std::string trigger;    // what wakes it, for the table ("lidar/IMU datagrams", "1 Hz")
    std::string blocks_on;  // what it may block on ("the sockets", "the disk", ...)
};

struct ThreadStats {
    std::atomic<int64_t> heartbeat_ns{0};
    std::atomic<uint64_t> cycles{0};
    std::atomic<uint64_t> deadline_misses{0};
    std::atomic<int64_t> max_cycle_ns{-1};  // since the last exchange(-1) by the reader
    std::atomic<bool> finished{false};      // left its loop (a replay that ended)

    void Beat();  // heartbeat = now
    // A cycle that took `cycle_ns`; a miss when `deadline_ns` > 0 and it was exceeded.
    void Cycle(int64_t cycle_ns, int64_t deadline_ns);
};

class ThreadTable {
public:
    // Adds a row; the thread starts with Start. Returns its index.
    size_t Add(ThreadSpec spec, std::function<void(ThreadStats&)> body);
    // Starts every thread with its scheduling; returns the warnings of what was refused.
    std::vector<std::string> Start();
    void Join();

    size_t size() const { return rows_.size(); }
    const ThreadSpec& spec(size_t i) const { return rows_[i]->spec; }
    ThreadStats& stats(size_t i) { return rows_[i]->stats; }
    // CPU time of thread i so far (ns), from its pthread CPU clock; -1 when unknown.
    int64_t CpuNs(size_t i) const;
    // The table as text (README and --print-threads).
    std::string Describe() const;

private:
    struct Row {
        ThreadSpec spec;
        std::function<void(ThreadStats&)> body;
        ThreadStats stats;
        std::thread thread;
        std::atomic<bool> started{false};
        pthread_t handle{};
    };
    std::vector<std::unique_ptr<Row>> rows_;
};

// mlockall(MCL_CURRENT | MCL_FUTURE): "" when done, else the warning.
std::string LockMemory();

int64_t MonotonicNs();
int64_t RealtimeNs();

}  // namespace bimslam::runtime
