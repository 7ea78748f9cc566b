// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/common/time.hpp"

#include <ctime>

namespace bimslam::common {
namespace {
int64_t Read(clockid_t id) {
    timespec ts{};
    clock_gettime(id, &ts);
    return static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}
}  // namespace

HostTime HostNow() { return HostTime{Read(CLOCK_REALTIME)}; }
MonotonicTime MonotonicNow() { return MonotonicTime{Read(CLOCK_MONOTONIC)}; }

}  // namespace bimslam::common
