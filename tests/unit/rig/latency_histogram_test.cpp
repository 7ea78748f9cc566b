// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// firmware/runtime/latency_histogram: percentiles in fixed memory, against the exact order
// statistics of the same latencies.
#include "firmware/runtime/latency_histogram.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

namespace bimslam::runtime {
namespace {
namespace BIMSLAM_UNITY_ID {

// The old summary's rule: the sorted latencies' element round(p (n - 1)).
double ExactMs(std::vector<int64_t> v, double p) {
    std::sort(v.begin(), v.end());
    return double(v[std::min(v.size() - 1, size_t(p * double(v.size() - 1) + 0.5))]) * 1e-6;
}

TEST(LatencyHistogram, PercentilesWithinHalfAPercentOfTheExactOnes) {
    // A rig-like latency: 8 ms typical, a long tail to 400 ms, a few below 1 us.
    std::mt19937 rng(7);
    std::lognormal_distribution<double> typical(std::log(8e6), 0.3);
    std::exponential_distribution<double> tail(1.0 / 50e6);
    std::vector<int64_t> v;
    LatencyHistogram h;
    for (int i = 0; i < 72000; ++i) {  // two hours at 10 Hz
        const int64_t ns = i % 500 == 0 ? int64_t(tail(rng)) : int64_t(typical(rng));
        v.push_back(i % 9000 == 0 ? 300 : ns);
        h.Add(v.back());
    }
    EXPECT_EQ(h.count(), v.size());
    for (double p : {0.0, 0.01, 0.5, 0.9, 0.99, 0.999}) {
        const double exact = ExactMs(v, p);
        EXPECT_NEAR(h.PercentileMs(p), exact, std::max(0.005 * exact, 1e-3)) << "p " << p;
    }
    EXPECT_DOUBLE_EQ(h.PercentileMs(1.0), ExactMs(v, 1.0));  // the maximum is exact
    EXPECT_EQ(h.max_ns(), *std::max_element(v.begin(), v.end()));
}

TEST(LatencyHistogram, BucketsEdgesAndEmpty) {
    LatencyHistogram h;
    EXPECT_EQ(h.PercentileMs(0.5), 0.0);  // empty
    EXPECT_EQ(LatencyHistogram::Bucket(-5), 0u);
    EXPECT_EQ(LatencyHistogram::Bucket(1000), 0u);
    EXPECT_EQ(LatencyHistogram::Bucket(1011), 2u);  // (1010, 1020.1]
    EXPECT_EQ(LatencyHistogram::Bucket(int64_t(1e12)), LatencyHistogram::kBuckets - 1);
    // Each bucket's middle lies inside it, 0.5 % from either edge.
    for (size_t i : {size_t(1), size_t(500), LatencyHistogram::kBuckets - 2}) {
        const double m = LatencyHistogram::Middle(i);
        EXPECT_EQ(LatencyHistogram::Bucket(int64_t(m)), i);
    }
    // One value: every percentile is it, to the bucket (and never above the maximum).
    h.Add(12'345'678);
    EXPECT_NEAR(h.PercentileMs(0.5), 12.345678, 12.345678 * 0.005);
    EXPECT_LE(h.PercentileMs(0.5), 12.345678);
    EXPECT_DOUBLE_EQ(h.PercentileMs(1.0), 12.345678);
    h.Add(-3);  // a clock step: counted as 0
    EXPECT_EQ(h.count(), 2u);
    EXPECT_EQ(h.PercentileMs(0.0), LatencyHistogram::Middle(0) * 1e-6);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::runtime
