// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/scancontext/distance.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

namespace bimslam::scancontext {
namespace {

using ColumnScratch = std::array<double, kMaxSectors>;
using DotScratch = std::array<float, kMaxSectors>;

bool Comparable(const Descriptor& a, const Descriptor& b) {
    return a.rows() == b.rows() && a.cols() == b.cols() && a.rows() >= 1 && a.cols() >= 1 &&
           a.cols() <= kMaxSectors && a.allFinite() && b.allFinite();
}

// Euclidean norm of every column.
void ColumnNorms(const Descriptor& d, ColumnScratch* norms) {
    const Eigen::Index rows = d.rows(), cols = d.cols();
    std::fill_n(norms->begin(), cols, 0.0);
    for (Eigen::Index i = 0; i < rows; ++i) {
        const float* row = d.data() + i * cols;
        for (Eigen::Index j = 0; j < cols; ++j) {
            (*norms)[j] += static_cast<double>(row[j]) * row[j];
        }
    }
    for (Eigen::Index j = 0; j < cols; ++j) (*norms)[j] = std::sqrt((*norms)[j]);
}

// Column means (the sector key) without allocating.
void SectorKeyInto(const Descriptor& d, std::array<float, kMaxSectors>* key) {
    const Eigen::Index rows = d.rows(), cols = d.cols();
    std::array<double, kMaxSectors> sum{};
    for (Eigen::Index i = 0; i < rows; ++i) {
        const float* row = d.data() + i * cols;
        for (Eigen::Index j = 0; j < cols; ++j) sum[j] += row[j];
    }
    for (Eigen::Index j = 0; j < cols; ++j) {
        (*key)[j] = static_cast<float>(sum[j] / static_cast<double>(rows));
    }
}

int AlignKeys(const float* key_a, const float* key_b, int n) {
    int best_shift = 0;
    double best = std::numeric_limits<double>::infinity();
    for (int k = 0; k < n; ++k) {
        // key_a[j] meets key_b[j + k]; two runs instead of a modulo per element.
        float ssd = 0.0f;
        const int split = n - k;
        for (int j = 0; j < split; ++j) {
            const float diff = key_a[j] - key_b[j + k];
            ssd += diff * diff;
        }
        for (int j = split; j < n; ++j) {
            const float diff = key_a[j] - key_b[j - split];
            ssd += diff * diff;
        }
        if (ssd < best) {
            best = ssd;
            best_shift = k;
        }
    }
    return best_shift;
}

// [SC] eq. (5) with precomputed column norms; shift in [0, cols).
double ShiftDistance(const Descriptor& a, const Descriptor& b, const ColumnScratch& norms_a,
                     const ColumnScratch& norms_b, int shift, DotScratch* dots) {
    const Eigen::Index rows = a.rows(), cols = a.cols();
    std::fill_n(dots->begin(), cols, 0.0f);
    // Row by row, so both descriptors are read contiguously (they are row-major); column j of a
    // meets column j + shift of b, split in two runs to avoid a modulo per cell. Float sums of
    // num_rings products vectorise and are exact to ~1e-6 relative, far below what matters.
    const Eigen::Index split = cols - shift;
    for (Eigen::Index i = 0; i < rows; ++i) {
        const float* ra = a.data() + i * cols;
        const float* rb = b.data() + i * cols;
        for (Eigen::Index j = 0; j < split; ++j) {
            (*dots)[j] += ra[j] * rb[j + shift];
        }
        for (Eigen::Index j = split; j < cols; ++j) {
            (*dots)[j] += ra[j] * rb[j - split];
        }
    }
    double sum_similarity = 0.0;
    int used = 0;
    for (Eigen::Index j = 0; j < cols; ++j) {
        const Eigen::Index jb = j < split ? j + shift : j - split;
        const double na = norms_a[j], nb = norms_b[jb];
        if (na == 0.0 || nb == 0.0) continue;  // an empty column on either side
        // Clamp: rounding can push the cosine of identical columns a hair past 1.
        sum_similarity += std::clamp((*dots)[j] / (na * nb), -1.0, 1.0);
        ++used;
    }
    if (used == 0) return kNoOverlapDistance;
    return 1.0 - sum_similarity / used;
}

}  // namespace

int WrapShift(int shift, int num_sectors) {
    if (num_sectors <= 0) return 0;
    int s = shift % num_sectors;
    if (s < 0) s += num_sectors;
    if (2 * s > num_sectors) s -= num_sectors;
    return s;
}

double ShiftToYaw(int shift, int num_sectors) {
    if (num_sectors <= 0) return 0.0;
    return WrapShift(shift, num_sectors) * (2.0 * std::numbers::pi / num_sectors);
}

int AlignSectorKeys(const Eigen::VectorXf& key_a, const Eigen::VectorXf& key_b) {
    if (key_a.size() != key_b.size() || key_a.size() == 0) return 0;
    const int n = static_cast<int>(key_a.size());
    return WrapShift(AlignKeys(key_a.data(), key_b.data(), n), n);
}

double ColumnShiftDistance(const Descriptor& a, const Descriptor& b, int shift) {
    if (!Comparable(a, b)) return kIncomparableDistance;
    const int cols = static_cast<int>(a.cols());
    ColumnScratch norms_a, norms_b;
    DotScratch dots;
    ColumnNorms(a, &norms_a);
    ColumnNorms(b, &norms_b);
    int s = shift % cols;
    if (s < 0) s += cols;
    return ShiftDistance(a, b, norms_a, norms_b, s, &dots);
}

DistanceResult Distance(const Descriptor& a, const Descriptor& b, double search_ratio) {
    DistanceResult result;
    if (!Comparable(a, b)) {
        result.distance = kIncomparableDistance;
        return result;
    }
    const int cols = static_cast<int>(a.cols());

    // Yaw pre-alignment on the sector keys (n^2 operations on n numbers, far cheaper than a full
    // eq. (5) per shift).
    std::array<float, kMaxSectors> key_a, key_b;
    SectorKeyInto(a, &key_a);
    SectorKeyInto(b, &key_b);
    const int center = AlignKeys(key_a.data(), key_b.data(), cols);

    ColumnScratch norms_a, norms_b;
    DotScratch dots;
    ColumnNorms(a, &norms_a);
    ColumnNorms(b, &norms_b);

    if (!std::isfinite(search_ratio)) search_ratio = 0.0;
    search_ratio = std::clamp(search_ratio, 0.0, 1.0);
    const int radius = std::min(static_cast<int>(std::lround(0.5 * search_ratio * cols)), cols / 2);

    // Offsets 0, +1, -1, +2, -2, ...: with strict '<' ties go to the shift nearest the
    // pre-alignment. When 2 * offset == cols, +offset and -offset are the same shift.
    double best = std::numeric_limits<double>::infinity();
    int best_shift = center;
    for (int offset = 0; offset <= radius; ++offset) {
        for (int sign : {+1, -1}) {
            if (sign < 0 && (offset == 0 || 2 * offset == cols)) continue;
            int s = (center + sign * offset) % cols;
            if (s < 0) s += cols;
            const double d = ShiftDistance(a, b, norms_a, norms_b, s, &dots);
            if (d < best) {
                best = d;
                best_shift = s;
            }
        }
    }
    result.distance = best;
    result.shift = WrapShift(best_shift, cols);
    result.yaw = ShiftToYaw(best_shift, cols);
    return result;
}

}  // namespace bimslam::scancontext
