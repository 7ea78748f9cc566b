// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Time as int64 nanoseconds in a named clock (DESIGN.md, "Conventions").
//
// A Timestamp<Clock> cannot be mixed with a timestamp of another clock: the sensor's clock, this
// host's clocks and the Go1 bridge's clock are unrelated until something estimates the offset,
// and the type system keeps them apart until then.
#pragma once

#include <cmath>
#include <compare>
#include <cstdint>

namespace bimslam::common {

enum class Clock : uint8_t {
    kSensor,     // the LiDAR's own timestamps (Ouster TIME_FROM_INTERNAL_OSC, PTP, ...)
    kHost,       // this host's CLOCK_REALTIME, UNIX epoch; used for publish times
    kMonotonic,  // this host's CLOCK_MONOTONIC; used for deadlines and timeouts
    kBridge,     // the Go1 bridge's CLOCK_MONOTONIC (GO1_SYNC BridgeTime)
};

// A signed span of time in nanoseconds; clock-free.
struct Duration {
    int64_t ns = 0;

    static constexpr Duration FromSeconds(double s) {
        return Duration{static_cast<int64_t>(s * 1e9 + (s >= 0 ? 0.5 : -0.5))};
    }
    static constexpr Duration FromMilliseconds(int64_t ms) { return Duration{ms * 1'000'000}; }
    constexpr double Seconds() const { return static_cast<double>(ns) * 1e-9; }

    constexpr auto operator<=>(const Duration&) const = default;
    constexpr Duration operator+(Duration o) const { return Duration{ns + o.ns}; }
    constexpr Duration operator-(Duration o) const { return Duration{ns - o.ns}; }
    constexpr Duration operator-() const { return Duration{-ns}; }
};

template <Clock C>
struct Timestamp {
    int64_t ns = 0;

    static constexpr Clock kClock = C;
    // Rounds to the nearest nanosecond. A double holds UNIX-epoch seconds to ~240 ns only:
    // files that need exact times keep integer nanoseconds (see io/trajectory.hpp).
    static constexpr Timestamp FromSeconds(double s) {
        return Timestamp{Duration::FromSeconds(s).ns};
    }
    constexpr double Seconds() const { return static_cast<double>(ns) * 1e-9; }

    constexpr auto operator<=>(const Timestamp&) const = default;
    constexpr Timestamp operator+(Duration d) const { return Timestamp{ns + d.ns}; }
    constexpr Timestamp operator-(Duration d) const { return Timestamp{ns - d.ns}; }
    constexpr Duration operator-(Timestamp o) const { return Duration{ns - o.ns}; }
};

using SensorTime = Timestamp<Clock::kSensor>;
using HostTime = Timestamp<Clock::kHost>;
using MonotonicTime = Timestamp<Clock::kMonotonic>;
using BridgeTime = Timestamp<Clock::kBridge>;

// Reads this host's clocks (clock_gettime; no allocation, safe on the hot path).
HostTime HostNow();
MonotonicTime MonotonicNow();

}  // namespace bimslam::common
