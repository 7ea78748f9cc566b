// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/localization/walked_space.hpp"

#include <cmath>

namespace bimslam::localization {

WalkedSpace::WalkedSpace(const std::vector<Eigen::Vector3d>& walked, double radius, double height)
    : radius_(radius), height_(height) {
    for (const Eigen::Vector3d& p : walked) {
        cells_[Key(int64_t(std::floor(p.x() / radius_)), int64_t(std::floor(p.y() / radius_)))]
            .push_back(p);
    }
}

bool WalkedSpace::Floats(const Eigen::Vector3d& p) const {
    const int64_t ci = int64_t(std::floor(p.x() / radius_));
    const int64_t cj = int64_t(std::floor(p.y() / radius_));
    bool near = false;
    for (int64_t i = ci - 1; i <= ci + 1; ++i) {
        for (int64_t j = cj - 1; j <= cj + 1; ++j) {
            const auto it = cells_.find(Key(i, j));
            if (it == cells_.end()) continue;
            for (const Eigen::Vector3d& w : it->second) {
                if ((w - p).head<2>().squaredNorm() > radius_ * radius_) continue;
                if (std::abs(w.z() - p.z()) <= height_) return false;
                near = true;
            }
        }
    }
    return near;
}

size_t WalkedSpace::Floating(const std::vector<Eigen::Vector3d>& positions,
                             const Eigen::Isometry3d& T) const {
    size_t n = 0;
    for (const Eigen::Vector3d& p : positions) n += Floats(T * p);
    return n;
}

}  // namespace bimslam::localization
