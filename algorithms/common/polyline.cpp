// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/common/polyline.hpp"

namespace bimslam::common {

std::vector<Eigen::Vector2d> ResamplePolyline(const std::vector<Eigen::Vector2d>& points,
                                              double spacing, bool closed) {
    std::vector<Eigen::Vector2d> out{points.front()};
    const size_t n = points.size();
    const size_t segments = closed ? n : n - 1;
    double carry = 0;  // distance walked since the last output point
    for (size_t i = 0; i < segments; ++i) {
        const Eigen::Vector2d a = points[i], b = points[(i + 1) % n];
        const double len = (b - a).norm();
        double at = spacing - carry;
        while (at <= len) {
            out.push_back(a + (b - a) * (at / len));
            at += spacing;
        }
        carry = len - (at - spacing);
    }
    if (!closed && (out.back() - points.back()).norm() > 1e-6) out.push_back(points.back());
    return out;
}

}  // namespace bimslam::common
