// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// A latency distribution in fixed memory, for a rig that runs for hours: the percentiles of
// every scan's latency without keeping every scan's latency (issue 32, the soak: a vector of
// 8 bytes a scan grew the rig's RSS by about 1.6 MB an hour, 5 % over two hours).
//
// Buckets are spaced logarithmically, each 1 % wider than the one before it, from 1 us to
// 100 s (1853 buckets, 7.4 KB); a percentile is the geometric middle of its bucket, so it is
// within 0.5 % of the exact order statistic (and exact for the maximum, which is kept as
// well). Values below 1 us fall in the first bucket, above 100 s in the last one.
// One writer, no locking: read it after the writer has stopped, as the rig's summary does.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace bimslam::runtime {

class LatencyHistogram {
public:
    static constexpr double kLowestNs = 1e3;  // 1 us
    static constexpr double kGrowth = 1.01;   // each bucket 1 % wider
    static constexpr size_t kBuckets = 1853;  // 1 + ceil(ln(1e8) / ln(1.01)): up to 100 s

    void Add(int64_t ns);
    uint64_t count() const { return count_; }
    int64_t max_ns() const { return max_ns_; }
    // The value of rank round(p (n - 1)) in the sorted latencies (p in [0, 1]), as the old
    // sort-based percentile took it, to the bucket's 0.5 %; in ms. 0 when empty. p = 1 is the
    // exact maximum.
    double PercentileMs(double p) const;
    // The bucket holding `ns`, and the geometric middle of bucket `i` (ns): for tests.
    static size_t Bucket(int64_t ns);
    static double Middle(size_t i);

private:
    std::array<uint32_t, kBuckets> counts_{};
    uint64_t count_ = 0;
    int64_t max_ns_ = 0;
};

}  // namespace bimslam::runtime
