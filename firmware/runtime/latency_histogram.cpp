// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "firmware/runtime/latency_histogram.hpp"

#include <algorithm>
#include <cmath>

namespace bimslam::runtime {

size_t LatencyHistogram::Bucket(int64_t ns) {
    if (double(ns) <= kLowestNs) return 0;
    // Bucket i holds (kLowestNs g^(i-1), kLowestNs g^i]: the smallest i with g^i >= ns / lowest.
    const double i = std::ceil(std::log(double(ns) / kLowestNs) / std::log(kGrowth));
    return std::min(kBuckets - 1, size_t(i));
}

double LatencyHistogram::Middle(size_t i) {
    if (i == 0) return kLowestNs;
    return kLowestNs * std::pow(kGrowth, double(i) - 0.5);
}

void LatencyHistogram::Add(int64_t ns) {
    ns = std::max<int64_t>(ns, 0);
    uint32_t& c = counts_[Bucket(ns)];
    if (c < UINT32_MAX) ++c;  // 4e9 scans: 13 years at 10 Hz
    ++count_;
    max_ns_ = std::max(max_ns_, ns);
}

double LatencyHistogram::PercentileMs(double p) const {
    if (count_ == 0) return 0;
    if (p >= 1) return double(max_ns_) * 1e-6;
    const uint64_t rank = uint64_t(std::max(0.0, p) * double(count_ - 1) + 0.5);
    uint64_t seen = 0;
    for (size_t i = 0; i < kBuckets; ++i) {
        seen += counts_[i];
        // The maximum's bucket: its middle may lie above the maximum itself.
        if (seen > rank) return std::min(Middle(i), double(max_ns_)) * 1e-6;
    }
    return double(max_ns_) * 1e-6;
}

}  // namespace bimslam::runtime
