// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/common/time.hpp"

#include <gtest/gtest.h>

#include <type_traits>

#include "algorithms/common/status.hpp"
#include "algorithms/common/utc_time.hpp"

namespace bimslam::common {
namespace {
namespace BIMSLAM_UNITY_ID {

TEST(Time, ArithmeticStaysInNanoseconds) {
    const SensorTime t0{1'699'999'999'123'456'789};
    const SensorTime t1 = t0 + Duration::FromMilliseconds(100);
    EXPECT_EQ((t1 - t0).ns, 100'000'000);
    EXPECT_EQ(t1 - Duration{100'000'000}, t0);
    EXPECT_LT(t0, t1);
    EXPECT_EQ(Duration::FromSeconds(-0.25).ns, -250'000'000);
    EXPECT_DOUBLE_EQ(Duration{1'500'000'000}.Seconds(), 1.5);
    EXPECT_EQ(SensorTime::FromSeconds(2.5).ns, 2'500'000'000);
}

template <typename A, typename B>
concept Subtractable = requires(A a, B b) {
    a - b;
};
template <typename A, typename B>
concept Comparable = requires(A a, B b) {
    a < b;
};

// Timestamps of different clocks must not mix: these are compile-time checks.
static_assert(Subtractable<SensorTime, SensorTime>);
static_assert(!Subtractable<SensorTime, HostTime>);
static_assert(!Subtractable<MonotonicTime, BridgeTime>);
static_assert(!Comparable<SensorTime, HostTime>);
static_assert(!Subtractable<SensorTime, int64_t>);

TEST(Time, HostClocksAdvance) {
    const MonotonicTime a = MonotonicNow();
    const MonotonicTime b = MonotonicNow();
    EXPECT_GE(b.ns, a.ns);
    EXPECT_GT(HostNow().Seconds(), 1.6e9);  // after 2020
}

// The simulator's default start (1.7e18 ns) and the forms `bimslam simulate --start` takes.
TEST(Time, Iso8601DateTimesParseAndFormatInUtc) {
    constexpr int64_t kS = 1'000'000'000;
    EXPECT_EQ(FormatUtcTime(1'700'000'000 * kS), "2023-11-14T22:13:20Z");
    EXPECT_EQ(ParseUtcTime("2023-11-14T22:13:20Z"), 1'700'000'000 * kS);
    EXPECT_EQ(ParseUtcTime("2023-11-14T23:13:20+01:00"), 1'700'000'000 * kS);
    EXPECT_EQ(ParseUtcTime("2023-11-14T21:13:20.25-01:00"), 1'700'000'000 * kS + kS / 4);
    EXPECT_EQ(ParseUtcTime("1970-01-01"), 0);
    EXPECT_EQ(ParseUtcTime("2024-02-29T00:00"), 1'709'164'800 * kS);  // a leap day
    EXPECT_EQ(FormatUtcDay(1'709'164'800 * kS - 1), "2024-02-28");
    EXPECT_EQ(FormatUtcTime(-1), "1969-12-31T23:59:59Z");
    for (const char* bad : {"2023-02-29", "2023-13-01", "2023-11-14T25:00", "14/11/2023",
                            "2023-11-14T22:13:20Zjunk", ""}) {
        EXPECT_THROW(ParseUtcTime(bad), Error) << bad;
    }
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::common
