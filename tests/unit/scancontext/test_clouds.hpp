// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Clouds for the Scan Context tests.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>

#include "algorithms/common/point_cloud.hpp"
#include "algorithms/scancontext/config.hpp"
#include "algorithms/scancontext/descriptor.hpp"

namespace bimslam::scancontext::testing {

// Rotates every point counter-clockwise by theta about +z, in double precision.
inline common::PointCloud RotateZ(const common::PointCloud& cloud, double theta) {
    common::PointCloud out = cloud;
    const double c = std::cos(theta), s = std::sin(theta);
    for (Eigen::Vector3f& p : out.xyz) {
        const double x = p.x(), y = p.y();
        p.x() = static_cast<float>(c * x - s * y);
        p.y() = static_cast<float>(s * x + c * y);
    }
    return out;
}

// Points placed well inside their cells: azimuth in the middle 60 % of a sector and range in the
// middle 60 % of a ring, so that rotating by whole sectors cannot move a point across a cell
// boundary through rounding. About 40 % of the cells are occupied, by 1 to 6 points with z in
// [-1.5, 4] m; deterministic in the seed.
inline common::PointCloud MakeCellCentredCloud(const ScanContextConfig& config, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::uniform_int_distribution<int> count(1, 6);
    const double ring_w = config.RingWidth(), sector_w = config.SectorAngle();
    common::PointCloud cloud;
    for (int i = 0; i < config.num_rings; ++i) {
        for (int j = 0; j < config.num_sectors; ++j) {
            if (unit(rng) > 0.4) continue;
            const int n = count(rng);
            for (int k = 0; k < n; ++k) {
                const double r = (i + 0.2 + 0.6 * unit(rng)) * ring_w;
                const double a = (j + 0.2 + 0.6 * unit(rng)) * sector_w;
                const double z = -1.5 + 5.5 * unit(rng);
                cloud.PushBack(Eigen::Vector3f(static_cast<float>(r * std::cos(a)),
                                               static_cast<float>(r * std::sin(a)),
                                               static_cast<float>(z)));
            }
        }
    }
    return cloud;
}

// A random descriptor with about half the cells non-zero (values in (0, 5]).
inline Descriptor RandomDescriptor(int rings, int sectors, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    Descriptor d(rings, sectors);
    for (int i = 0; i < rings; ++i) {
        for (int j = 0; j < sectors; ++j) d(i, j) = unit(rng) < 0.5f ? 5.0f * unit(rng) : 0.0f;
    }
    return d;
}

// b(:, (j + k) mod S) = a(:, j): a rotated counter-clockwise by k sectors.
inline Descriptor ShiftColumns(const Descriptor& a, int k) {
    const auto s = static_cast<int>(a.cols());
    Descriptor b(a.rows(), a.cols());
    for (int j = 0; j < s; ++j) b.col(((j + k) % s + s) % s) = a.col(j);
    return b;
}

inline double Deg(double deg) { return deg * std::numbers::pi / 180.0; }

// The difference of two angles wrapped into (-pi, pi].
inline double AngleDiff(double a, double b) {
    double d = std::remainder(a - b, 2.0 * std::numbers::pi);
    if (d <= -std::numbers::pi) d += 2.0 * std::numbers::pi;
    return d;
}

}  // namespace bimslam::scancontext::testing
