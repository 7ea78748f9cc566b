// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/odometry/edge_features.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "algorithms/common/status.hpp"

namespace bimslam::odometry {
using common::Require;

void EdgeFeatureConfig::Validate() const {
    const char* c = "EdgeFeatureConfig";
    Require(neighbours >= 1 && neighbours <= 20, c, "neighbours", neighbours, "must be in [1, 20]");
    Require(sectors >= 1 && sectors <= 64, c, "sectors", sectors, "must be in [1, 64]");
    Require(max_per_sector >= 1 && max_per_sector <= 1000, c, "max_per_sector", max_per_sector,
            "must be in [1, 1000]");
    Require(min_angle_deg > 0 && min_angle_deg < 180, c, "min_angle_deg", min_angle_deg,
            "must be in (0, 180)");
    Require(min_chord >= 0 && min_chord < 10, c, "min_chord", min_chord, "must be in [0, 10) m");
    Require(max_range_jump > 0, c, "max_range_jump", max_range_jump, "must be > 0");
    Require(max_edges >= 1, c, "max_edges", double(max_edges), "must be >= 1");
    Require(max_rings >= 1 && max_rings <= 256, c, "max_rings", max_rings, "must be in [1, 256]");
}

EdgeExtractor::EdgeExtractor(const EdgeFeatureConfig& config, size_t max_points) : config_(config) {
    config_.Validate();
    order_.resize(max_points);
    ring_start_.resize(size_t(config_.max_rings) + 1);
    next_.resize(size_t(config_.max_rings));
    curvature_.resize(max_points);
    taken_.resize(max_points);
    candidates_.reserve(max_points);
    edges_.reserve(config_.max_edges);
}

std::span<const Eigen::Vector3f> EdgeExtractor::Run(const common::PointCloud& scan) {
    edges_.clear();
    const size_t n = std::min(scan.size(), order_.size());
    if (scan.ring.size() != scan.size() || n == 0) return {};
    const bool timed = scan.HasTime();

    // Counting sort by ring (stable: the scan is in column order, so each ring is too).
    const size_t rings = size_t(config_.max_rings);
    std::fill(ring_start_.begin(), ring_start_.end(), 0u);
    for (size_t i = 0; i < n; ++i) {
        if (scan.ring[i] < rings) ++ring_start_[scan.ring[i] + 1u];
    }
    for (size_t r = 0; r < rings; ++r) ring_start_[r + 1] += ring_start_[r];
    std::copy(ring_start_.begin(), ring_start_.end() - 1, next_.begin());
    for (size_t i = 0; i < n; ++i) {
        if (scan.ring[i] < rings) order_[next_[scan.ring[i]]++] = static_cast<uint32_t>(i);
    }
    const auto point = [&](int k) { return scan.xyz[order_[size_t(k)]]; };
    const auto time = [&](int k) { return timed ? scan.time_offset_ns[order_[size_t(k)]] : 0u; };

    // The column period: the smallest step in time between neighbours of a ring.
    uint32_t period = std::numeric_limits<uint32_t>::max();
    if (timed) {
        for (size_t r = 0; r < rings; ++r) {
            for (int k = int(ring_start_[r]) + 1; k < int(ring_start_[r + 1]); ++k) {
                if (time(k) > time(k - 1)) period = std::min(period, time(k) - time(k - 1));
            }
        }
    }
    const uint64_t max_step = timed ? uint64_t(period) * 3 / 2 : ~uint64_t(0);

    const int K = config_.neighbours;
    const float min_chord = static_cast<float>(config_.min_chord);
    const float min_sharpness =
        static_cast<float>(1 - std::cos(config_.min_angle_deg * M_PI / 180));
    const float jump = static_cast<float>(config_.max_range_jump);
    for (size_t r = 0; r < rings && edges_.size() < config_.max_edges; ++r) {
        const int begin = int(ring_start_[r]), end = int(ring_start_[r + 1]);
        if (end - begin < 2 * K + 1) continue;
        // Sharpness, or -1 where the window has a column gap or a range jump.
        for (int k = begin; k < end; ++k) {
            curvature_[size_t(k)] = -1;
            taken_[size_t(k)] = 0;
            if (k - K < begin || k + K >= end) continue;
            bool usable = true;
            for (int j = k - K + 1; j <= k + K && usable; ++j) {
                usable = time(j) >= time(j - 1) && time(j) - time(j - 1) <= max_step &&
                         std::abs(point(j).norm() - point(j - 1).norm()) <= jump;
            }
            if (!usable) continue;
            // The turn between the chords to the K-th neighbour on either side, as 1 - cos.
            const Eigen::Vector3f a = point(k) - point(k - K), b = point(k + K) - point(k);
            if (std::min(a.norm(), b.norm()) < min_chord) continue;  // noise would dominate
            curvature_[size_t(k)] = 1.f - a.normalized().dot(b.normalized());
        }
        // Per sector, the sharpest points first, none within K of one already taken.
        for (int s = 0; s < config_.sectors; ++s) {
            const int lo = begin + (end - begin) * s / config_.sectors;
            const int hi = begin + (end - begin) * (s + 1) / config_.sectors;
            candidates_.clear();
            for (int k = lo; k < hi; ++k) {
                if (curvature_[size_t(k)] > min_sharpness) candidates_.push_back(uint32_t(k));
            }
            std::sort(candidates_.begin(), candidates_.end(),
                      [&](uint32_t a, uint32_t b) { return curvature_[a] > curvature_[b]; });
            int picked = 0;
            for (const uint32_t k : candidates_) {
                if (picked >= config_.max_per_sector || edges_.size() >= config_.max_edges) break;
                if (taken_[k]) continue;
                edges_.push_back(point(int(k)));
                ++picked;
                for (int j = std::max(begin, int(k) - K); j <= std::min(end - 1, int(k) + K); ++j) {
                    taken_[size_t(j)] = 1;
                }
            }
        }
    }
    return edges_;
}

}  // namespace bimslam::odometry
