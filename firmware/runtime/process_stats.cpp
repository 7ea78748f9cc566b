// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "firmware/runtime/process_stats.hpp"

#include <sys/statvfs.h>
#include <unistd.h>

#include <cstdio>
#include <ctime>

namespace bimslam::runtime {

int64_t ProcessCpuNs() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return int64_t(t.tv_sec) * 1'000'000'000 + t.tv_nsec;
}

int64_t ThreadCpuNs() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return int64_t(t.tv_sec) * 1'000'000'000 + t.tv_nsec;
}

int64_t ResidentBytes() {
    FILE* f = std::fopen("/proc/self/statm", "r");
    if (f == nullptr) return -1;
    long size = 0, resident = 0;
    const int n = std::fscanf(f, "%ld %ld", &size, &resident);
    std::fclose(f);
    return n == 2 ? int64_t(resident) * sysconf(_SC_PAGESIZE) : -1;
}

int64_t FreeDiskBytes(const std::string& path) {
    struct statvfs s {};
    if (statvfs(path.c_str(), &s) != 0) return -1;
    return int64_t(s.f_bavail) * int64_t(s.f_frsize);
}

void Log(const char* level, const std::string& message) {
    timespec t{};
    clock_gettime(CLOCK_MONOTONIC, &t);
    std::fprintf(stderr, "bimslam-rig [%8.3f] %s: %s\n", double(t.tv_sec) + t.tv_nsec * 1e-9, level,
                 message.c_str());
    std::fflush(stderr);
}

bool RateLimiter::Allow(int64_t now_ns) {
    if (last_ns_ >= 0 && now_ns - last_ns_ < interval_ns_) {
        ++suppressed_;
        return false;
    }
    last_ns_ = now_ns;
    suppressed_ = 0;
    return true;
}

}  // namespace bimslam::runtime
