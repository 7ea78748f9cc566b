// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// What the health thread reads of the process and the machine: CPU time, resident memory, free
// disk space. Plain system calls, no allocation.
#pragma once

#include <cstdint>
#include <string>

namespace bimslam::runtime {

int64_t ProcessCpuNs();   // CLOCK_PROCESS_CPUTIME_ID
int64_t ThreadCpuNs();    // CLOCK_THREAD_CPUTIME_ID: the calling thread's
int64_t ResidentBytes();  // /proc/self/statm, -1 when unreadable
// Free bytes for unprivileged users on the file system of `path` (statvfs), -1 when unknown.
int64_t FreeDiskBytes(const std::string& path);

// Logging from the slow threads (never the hot paths): one line on stderr with the monotonic
// time and the level. RateLimiter says whether a message of a given kind may go out now.
void Log(const char* level, const std::string& message);
class RateLimiter {
public:
    explicit RateLimiter(int64_t interval_ns) : interval_ns_(interval_ns) {}
    // True at most once per interval; `suppressed` counts the others since the last true.
    bool Allow(int64_t now_ns);
    uint64_t suppressed() const { return suppressed_; }

private:
    int64_t interval_ns_;
    int64_t last_ns_ = -1;
    uint64_t suppressed_ = 0;
};

}  // namespace bimslam::runtime
