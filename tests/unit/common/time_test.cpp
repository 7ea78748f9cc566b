#include "algorithms/common/time.hpp"

#include <gtest/gtest.h>

#include <type_traits>

namespace bimslam::common {
namespace {

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

}  // namespace
}  // namespace bimslam::common
