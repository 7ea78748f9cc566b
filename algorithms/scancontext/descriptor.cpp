// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/scancontext/descriptor.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace bimslam::scancontext {

DescriptorBuilder::DescriptorBuilder(const ScanContextConfig& config) : config_(config) {
    config_.Validate();
    const size_t cells =
        static_cast<size_t>(config_.num_rings) * static_cast<size_t>(config_.num_sectors);
    z_max_.resize(cells);
    z_min_.resize(cells);
    count_.resize(cells);
}

DescriptorStats DescriptorBuilder::Build(std::span<const Eigen::Vector3f> points, Descriptor* out) {
    const int rings = config_.num_rings;
    const int sectors = config_.num_sectors;
    if (out->rows() != rings || out->cols() != sectors) out->resize(rings, sectors);

    constexpr float kLowest = std::numeric_limits<float>::lowest();
    constexpr float kHighest = std::numeric_limits<float>::max();
    std::fill(z_max_.begin(), z_max_.end(), kLowest);
    std::fill(z_min_.begin(), z_min_.end(), kHighest);
    std::fill(count_.begin(), count_.end(), 0u);
    cell_z_.clear();

    // Binning in double: the ring and sector edges must not move with float rounding of r and
    // theta for points that are well inside a cell.
    const double max_r = config_.max_radius;
    const double ring_scale = static_cast<double>(rings) / max_r;
    const double sector_scale = static_cast<double>(sectors) / (2.0 * std::numbers::pi);
    const bool outdoor = config_.kind == DescriptorKind::kOutdoor;
    const float z_offset = outdoor ? static_cast<float>(config_.lidar_height) : 0.0f;
    const bool stack = !outdoor && config_.indoor_rule == IndoorCellRule::kZStack;

    DescriptorStats stats;
    for (const Eigen::Vector3f& p : points) {
        if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || !std::isfinite(p.z())) {
            ++stats.non_finite;
            continue;
        }
        const double x = p.x(), y = p.y();
        const double r = std::sqrt(x * x + y * y);
        if (r == 0.0) {
            ++stats.on_axis;
            continue;
        }
        if (r > max_r) {
            ++stats.beyond_range;
            continue;
        }
        double theta = std::atan2(y, x);  // (-pi, pi]
        if (theta < 0.0) theta += 2.0 * std::numbers::pi;
        // min() keeps r == max_r in the last ring and theta rounded up to 2 pi in the last sector.
        const int ring = std::min(static_cast<int>(r * ring_scale), rings - 1);
        const int sector = std::min(static_cast<int>(theta * sector_scale), sectors - 1);
        const size_t cell =
            static_cast<size_t>(ring) * static_cast<size_t>(sectors) + static_cast<size_t>(sector);
        const float z = p.z() + z_offset;
        z_max_[cell] = std::max(z_max_[cell], z);
        z_min_[cell] = std::min(z_min_[cell], z);
        if (stack) cell_z_.emplace_back(uint32_t(cell), z);
        ++count_[cell];
        ++stats.used;
    }

    float* d = out->data();
    const size_t cells = z_max_.size();
    if (outdoor) {
        // [SC] eq. (2): the maximum height of the cell's points; empty cells are 0.
        for (size_t c = 0; c < cells; ++c) d[c] = count_[c] > 0 ? z_max_[c] : 0.0f;
    } else if (stack) {
        TallestStacks(d);
    } else {
        // Indoor variant (config.hpp), z_span: the z-span of occupied cells.
        const auto min_points = static_cast<uint32_t>(config_.indoor_min_points);
        const auto min_span = static_cast<float>(config_.indoor_min_z_span);
        for (size_t c = 0; c < cells; ++c) {
            const float span = z_max_[c] - z_min_[c];
            d[c] = (count_[c] >= min_points && span >= min_span) ? span : 0.0f;
        }
    }
    return stats;
}

void DescriptorBuilder::TallestStacks(float* d) {
    // Indoor variant (config.hpp), z_stack: per cell, its points by height; a gap over
    // indoor_min_z_span starts a new stack; the tallest stack of at least indoor_min_points
    // points spanning at least indoor_min_z_span is the cell's value, and a cell of at least
    // indoor_min_points points with no such stack (open floor, ceiling) holds indoor_min_z_span.
    const auto min_points = static_cast<uint32_t>(config_.indoor_min_points);
    const auto min_span = static_cast<float>(config_.indoor_min_z_span);
    const size_t cells = count_.size();
    // The heights grouped by cell (a counting sort: the counts are known), then each cell's few
    // sorted: a quarter of the time of sorting (cell, z) pairs of a whole 32k-point scan.
    start_.resize(cells + 1);
    start_[0] = 0;
    for (size_t c = 0; c < cells; ++c) start_[c + 1] = start_[c] + count_[c];
    fill_.assign(start_.begin(), start_.end() - 1);
    z_by_cell_.resize(cell_z_.size());
    for (const auto& [cell, z] : cell_z_) z_by_cell_[fill_[cell]++] = z;
    for (size_t c = 0; c < cells; ++c) {
        d[c] = 0.0f;
        if (count_[c] < min_points) continue;
        float* z = z_by_cell_.data() + start_[c];
        const uint32_t n = count_[c];
        std::sort(z, z + n);
        float bottom = z[0], best = 0.0f;
        uint32_t in_stack = 0;
        for (uint32_t i = 0; i < n; ++i) {
            if (i > 0 && z[i] - z[i - 1] > min_span) {
                bottom = z[i];
                in_stack = 0;
            }
            ++in_stack;
            if (in_stack >= min_points && z[i] - bottom >= min_span) {
                best = std::max(best, z[i] - bottom);
            }
        }
        d[c] = std::max(best, min_span);
    }
}

Descriptor MakeDescriptor(const common::PointCloud& cloud, const ScanContextConfig& config,
                          DescriptorStats* stats) {
    DescriptorBuilder builder(config);
    Descriptor d;
    const DescriptorStats s = builder.Build(cloud, &d);
    if (stats != nullptr) *stats = s;
    return d;
}

Eigen::VectorXf RingKey(const Descriptor& descriptor) {
    if (descriptor.cols() == 0) return Eigen::VectorXf::Zero(descriptor.rows());
    return descriptor.rowwise().mean();
}

Eigen::VectorXf SectorKey(const Descriptor& descriptor) {
    if (descriptor.rows() == 0) return Eigen::VectorXf::Zero(descriptor.cols());
    return descriptor.colwise().mean().transpose();
}

}  // namespace bimslam::scancontext
