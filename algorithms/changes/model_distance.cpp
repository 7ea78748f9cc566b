// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/changes/model_distance.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <limits>

#include "algorithms/changes/change_model.hpp"

namespace bimslam::changes {

PointDistances ComputeDistances(const simulation::Scene& scene,
                                std::span<const Eigen::Vector3f> points, float max_distance,
                                const std::function<void(double)>& progress) {
    PointDistances out;
    out.signed_m.assign(points.size(), std::numeric_limits<float>::infinity());
    out.triangle.assign(points.size(), kNoElement);
    constexpr size_t kBlock = 2048;
    const size_t blocks = (points.size() + kBlock - 1) / kBlock;
    std::atomic<size_t> done{0};
    // Progress is reported by the calling thread only: split the work in chunks and report
    // between them.
    const size_t chunk_blocks = std::max<size_t>(1, blocks / 50);
    for (size_t first = 0; first < blocks; first += chunk_blocks) {
        const size_t last = std::min(blocks, first + chunk_blocks);
        tbb::parallel_for(tbb::blocked_range<size_t>(first, last, 1), [&](const auto& range) {
            for (size_t b = range.begin(); b < range.end(); ++b) {
                uint32_t hint = simulation::Scene::kNoHint;
                const size_t end = std::min(points.size(), (b + 1) * kBlock);
                for (size_t i = b * kBlock; i < end; ++i) {
                    const auto c = scene.ClosestPoint(points[i], max_distance, hint);
                    if (!c) continue;
                    out.signed_m[i] = c->signed_distance;
                    out.triangle[i] = c->triangle;
                    hint = c->triangle;
                }
                done.fetch_add(1, std::memory_order_relaxed);
            }
        });
        if (progress) progress(double(done.load()) / double(blocks));
    }
    return out;
}

}  // namespace bimslam::changes
