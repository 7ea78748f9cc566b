// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "firmware/runtime/thread_table.hpp"

#include <sched.h>
#include <sys/mman.h>

#include <cerrno>
#include <cstring>
#include <ctime>
#include <memory>
#include <sstream>

namespace bimslam::runtime {

int64_t MonotonicNs() {
    timespec t{};
    clock_gettime(CLOCK_MONOTONIC, &t);
    return int64_t(t.tv_sec) * 1'000'000'000 + t.tv_nsec;
}

int64_t RealtimeNs() {
    timespec t{};
    clock_gettime(CLOCK_REALTIME, &t);
    return int64_t(t.tv_sec) * 1'000'000'000 + t.tv_nsec;
}

void ThreadStats::Beat() { heartbeat_ns.store(MonotonicNs(), std::memory_order_relaxed); }

void ThreadStats::Cycle(int64_t cycle_ns, int64_t deadline_ns) {
    cycles.fetch_add(1, std::memory_order_relaxed);
    if (deadline_ns > 0 && cycle_ns > deadline_ns) {
        deadline_misses.fetch_add(1, std::memory_order_relaxed);
    }
    int64_t seen = max_cycle_ns.load(std::memory_order_relaxed);
    while (cycle_ns > seen && !max_cycle_ns.compare_exchange_weak(seen, cycle_ns)) {
    }
}

size_t ThreadTable::Add(ThreadSpec spec, std::function<void(ThreadStats&)> body) {
    auto row = std::make_unique<Row>();
    row->spec = std::move(spec);
    row->body = std::move(body);
    rows_.push_back(std::move(row));
    return rows_.size() - 1;
}

std::vector<std::string> ThreadTable::Start() {
    std::vector<std::string> warnings;
    for (auto& r : rows_) {
        Row* row = r.get();
        row->stats.Beat();
        row->thread = std::thread([row] {
            row->stats.Beat();
            row->body(row->stats);
            row->stats.finished.store(true);
        });
        row->handle = row->thread.native_handle();
        row->started = true;
        pthread_setname_np(row->handle, row->spec.name.substr(0, 15).c_str());
        const ThreadSpec& s = row->spec;
        if (s.priority > 0) {
            sched_param p{};
            p.sched_priority = s.priority;
            const int e = pthread_setschedparam(row->handle, SCHED_FIFO, &p);
            if (e != 0) {
                warnings.push_back("thread " + s.name + ": SCHED_FIFO priority " +
                                   std::to_string(s.priority) + " refused (" + std::strerror(e) +
                                   "); it runs with the normal scheduler");
            }
        }
        if (s.cpu >= 0) {
            cpu_set_t set;
            CPU_ZERO(&set);
            CPU_SET(s.cpu, &set);
            const int e = pthread_setaffinity_np(row->handle, sizeof(set), &set);
            if (e != 0) {
                warnings.push_back("thread " + s.name + ": affinity to CPU " +
                                   std::to_string(s.cpu) + " refused (" + std::strerror(e) +
                                   "); it runs on any CPU");
            }
        }
    }
    return warnings;
}

void ThreadTable::Join() {
    for (auto& r : rows_) {
        if (r->thread.joinable()) r->thread.join();
    }
}

int64_t ThreadTable::CpuNs(size_t i) const {
    if (!rows_[i]->started || rows_[i]->stats.finished.load()) return -1;
    clockid_t id;
    if (pthread_getcpuclockid(rows_[i]->handle, &id) != 0) return -1;
    timespec t{};
    if (clock_gettime(id, &t) != 0) return -1;
    return int64_t(t.tv_sec) * 1'000'000'000 + t.tv_nsec;
}

std::string ThreadTable::Describe() const {
    std::ostringstream s;
    s << "thread       priority  cpu  period/trigger               deadline  may block on\n";
    for (const auto& r : rows_) {
        const ThreadSpec& t = r->spec;
        char line[256];
        std::snprintf(
            line, sizeof(line), "%-12s %8s  %3s  %-28s %8s  %s\n", t.name.c_str(),
            t.priority > 0 ? ("FIFO " + std::to_string(t.priority)).c_str() : "normal",
            t.cpu >= 0 ? std::to_string(t.cpu).c_str() : "any",
            t.period_ns > 0 ? (std::to_string(t.period_ns / 1'000'000) + " ms").c_str()
                            : t.trigger.c_str(),
            t.deadline_ns > 0 ? (std::to_string(t.deadline_ns / 1'000'000) + " ms").c_str() : "-",
            t.blocks_on.c_str());
        s << line;
    }
    return s.str();
}

std::string LockMemory() {
    if (mlockall(MCL_CURRENT | MCL_FUTURE) == 0) return "";
    return std::string("mlockall refused (") + std::strerror(errno) +
           "); memory may be paged out (raise RLIMIT_MEMLOCK, LimitMEMLOCK=infinity in the unit)";
}

}  // namespace bimslam::runtime
