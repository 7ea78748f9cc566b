// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Seconds of wall-clock time since a moment: what host tools and benchmarks report as timings.
#pragma once
#include <chrono>

namespace bimslam::common {

using SteadyClock = std::chrono::steady_clock;

// steady_clock, not the system clock: an NTP step during a run must not change a timing.
inline double SecondsSince(SteadyClock::time_point t0) {
    return std::chrono::duration<double>(SteadyClock::now() - t0).count();
}

}  // namespace bimslam::common
