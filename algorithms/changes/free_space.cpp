// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/changes/free_space.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string>

#include "algorithms/changes/point_grid.hpp"
#include "algorithms/common/status.hpp"

namespace bimslam::changes {
namespace {
constexpr float kPi = float(M_PI);

}  // namespace

void FreeSpaceConfig::Validate() const {
    const auto positive = [](double v, const char* name) {
        if (!(v > 0) || !std::isfinite(v))
            common::ThrowInvalid("free_space." + std::string(name) + " must be > 0, not " +
                                 std::to_string(v));
    };
    positive(azimuth_bin_deg, "azimuth_bin_deg");
    positive(elevation_bin_deg, "elevation_bin_deg");
    positive(patch_radius_m, "patch_radius_m");
    positive(range_margin_m, "range_margin_m");
    positive(max_range_m, "max_range_m");
    if (!(min_crossing_cos >= 0 && min_crossing_cos < 1)) {
        common::ThrowInvalid("free_space.min_crossing_cos must be in [0, 1), not " +
                             std::to_string(min_crossing_cos));
    }
    if (!(range_margin_per_m >= 0))
        common::ThrowInvalid("free_space.range_margin_per_m must be >= 0");
    if (!(min_range_m >= 0 && min_range_m < max_range_m)) {
        common::ThrowInvalid("free_space.min_range_m must be in [0, max_range_m), not " +
                             std::to_string(min_range_m));
    }
    if (min_free_keyframes < 1) common::ThrowInvalid("free_space.min_free_keyframes must be >= 1");
    if (!(free_over_seen >= 0)) common::ThrowInvalid("free_space.free_over_seen must be >= 0");
    common::Require(unjudged_radius_m >= 0 && std::isfinite(unjudged_radius_m), "free_space",
                    "unjudged_radius_m", unjudged_radius_m, "must be >= 0 (0: off)");
}

size_t JudgeByNeighbours(std::span<const Eigen::Vector3f> points, std::span<const uint8_t> judged,
                         std::span<uint8_t> transient, double radius_m) {
    if (judged.size() != points.size() || transient.size() != points.size()) {
        common::ThrowInvalid("JudgeByNeighbours: " + std::to_string(points.size()) + " points, " +
                             std::to_string(judged.size()) + " judged flags and " +
                             std::to_string(transient.size()) + " verdicts");
    }
    if (!(radius_m > 0) || points.empty()) return 0;
    const float radius = float(radius_m);
    const PointGrid grid(points, radius);
    const std::vector<uint8_t> voted(transient.begin(), transient.end());
    size_t changed = 0;
    for (size_t k = 0; k < points.size(); ++k) {
        if (judged[k] || voted[k]) continue;
        size_t moving = 0, still = 0;
        grid.ForEachPointWithin(points[k], radius, [&](uint32_t j) {
            if (!judged[j]) return;
            (voted[j] ? moving : still) += 1;
        });
        if (moving > still) {
            transient[k] = 1;
            ++changed;
        }
    }
    return changed;
}

FreeSpaceIndex::FreeSpaceIndex(std::span<const MapKeyframe> keyframes,
                               const FreeSpaceConfig& config)
    : config_(config) {
    config.Validate();
    azimuth_bin_rad_ = float(config.azimuth_bin_deg * M_PI / 180.0);
    columns_ = int(std::ceil(2 * kPi / azimuth_bin_rad_));
    for (int c = 0; c < columns_; ++c) {
        const float azimuth = (float(c) + 0.5f) * azimuth_bin_rad_ - kPi;
        column_cos_.push_back(std::cos(azimuth));
        column_sin_.push_back(std::sin(azimuth));
    }
    const float elevation_bin = float(config.elevation_bin_deg * M_PI / 180.0);
    images_.reserve(keyframes.size());
    for (const MapKeyframe& kf : keyframes) {
        const common::PointCloud& cloud = *kf.cloud;
        RangeImage image;
        const Eigen::Isometry3f T = kf.T_world_lidar.cast<float>();
        image.R_lidar_world = T.linear().transpose();
        image.t_lidar_world = -(image.R_lidar_world * T.translation());
        image.origin_world = T.translation();
        // Rows: per ring, at the median elevation of its points, ordered by elevation; without
        // rings, elevation bins.
        std::vector<int> row_of_point(cloud.size(), -1);
        if (cloud.HasRing()) {
            std::map<uint16_t, std::vector<float>> by_ring;
            for (size_t i = 0; i < cloud.size(); ++i) {
                const Eigen::Vector3f& q = cloud.xyz[i];
                const float r = q.norm();
                if (r > 0 && std::isfinite(r))
                    by_ring[cloud.ring[i]].push_back(std::asin(q.z() / r));
            }
            std::vector<std::pair<float, uint16_t>> rings;
            for (auto& [ring, el] : by_ring) {
                std::nth_element(el.begin(), el.begin() + el.size() / 2, el.end());
                rings.emplace_back(el[el.size() / 2], ring);
            }
            std::sort(rings.begin(), rings.end());
            std::map<uint16_t, int> row_of_ring;
            for (size_t k = 0; k < rings.size(); ++k) {
                image.row_elevation.push_back(rings[k].first);
                row_of_ring[rings[k].second] = int(k);
            }
            for (size_t i = 0; i < cloud.size(); ++i) {
                const auto it = row_of_ring.find(cloud.ring[i]);
                if (it != row_of_ring.end()) row_of_point[i] = it->second;
            }
        } else {
            const int bins = int(std::ceil(kPi / elevation_bin));
            for (int b = 0; b < bins; ++b) {
                image.row_elevation.push_back(-kPi / 2 + (float(b) + 0.5f) * elevation_bin);
            }
            for (size_t i = 0; i < cloud.size(); ++i) {
                const Eigen::Vector3f& q = cloud.xyz[i];
                const float r = q.norm();
                if (!(r > 0) || !std::isfinite(r)) continue;
                const int b = int((std::asin(q.z() / r) + kPi / 2) / elevation_bin);
                row_of_point[i] = std::clamp(b, 0, bins - 1);
            }
        }
        for (const float el : image.row_elevation) {
            image.row_cos.push_back(std::cos(el));
            image.row_sin.push_back(std::sin(el));
        }
        image.range.assign(image.row_elevation.size() * size_t(columns_), 0.0f);
        for (size_t i = 0; i < cloud.size(); ++i) {
            if (row_of_point[i] < 0) continue;
            const Eigen::Vector3f& q = cloud.xyz[i];
            const float r = q.norm();
            const int col = std::clamp(int((std::atan2(q.y(), q.x()) + kPi) / azimuth_bin_rad_), 0,
                                       columns_ - 1);
            float& pixel = image.range[size_t(row_of_point[i]) * size_t(columns_) + size_t(col)];
            if (pixel == 0.0f || r < pixel) pixel = r;
        }
        images_.push_back(std::move(image));
    }
}

void FreeSpaceIndex::VoteOne(const RangeImage& image, const Eigen::Vector3f& p_world,
                             const Eigen::Vector3f& n_world, bool* free, bool* seen) const {
    const Eigen::Vector3f p = image.R_lidar_world * p_world + image.t_lidar_world;
    const Eigen::Vector3f n = image.R_lidar_world * n_world;
    const float r = p.norm();
    if (r < float(config_.min_range_m) || r > float(config_.max_range_m)) return;
    const float elevation = std::asin(p.z() / r);
    const float azimuth = std::atan2(p.y(), p.x());
    const auto& rows = image.row_elevation;
    const auto above = std::lower_bound(rows.begin(), rows.end(), elevation) - rows.begin();
    const float patch = float(config_.patch_radius_m);
    const int reach = std::min(8, int(std::ceil(patch / (r * azimuth_bin_rad_))));
    const int center = int((azimuth + kPi) / azimuth_bin_rad_);
    const float pn = p.dot(n);
    for (auto row = above - 1; row <= above; ++row) {
        if (row < 0 || row >= std::ptrdiff_t(rows.size())) continue;
        for (int dc = -reach; dc <= reach; ++dc) {
            const int col = ((center + dc) % columns_ + columns_) % columns_;
            const float measured = image.range[size_t(row) * size_t(columns_) + size_t(col)];
            if (measured <= 0) continue;
            const float rc = image.row_cos[size_t(row)];
            const Eigen::Vector3f d(rc * column_cos_[size_t(col)], rc * column_sin_[size_t(col)],
                                    image.row_sin[size_t(row)]);
            const float cosine = d.dot(n);
            if (std::abs(cosine) < float(config_.min_crossing_cos)) continue;
            const float t = pn / cosine;
            if (t <= 0 || (t * d - p).squaredNorm() > patch * patch) continue;
            const float margin =
                float(config_.range_margin_m) + float(config_.range_margin_per_m) * t;
            if (measured > t + margin) {
                *free = true;
            } else if (measured >= t - margin) {
                *seen = true;
            }
        }
    }
}

FreeSpaceIndex::Votes FreeSpaceIndex::Vote(const Eigen::Vector3f& p,
                                           const Eigen::Vector3f& normal) const {
    Votes v;
    const float max2 = float(config_.max_range_m * config_.max_range_m);
    for (const RangeImage& image : images_) {
        if ((image.origin_world - p).squaredNorm() > max2) continue;
        bool free = false, seen = false;
        VoteOne(image, p, normal, &free, &seen);
        if (seen) {
            if (v.seen < UINT16_MAX) ++v.seen;
        } else if (free) {
            if (v.free < UINT16_MAX) ++v.free;
        }
    }
    return v;
}

bool FreeSpaceIndex::Transient(const Votes& v) const {
    return v.free >= config_.min_free_keyframes &&
           double(v.free) > config_.free_over_seen * double(v.seen);
}

}  // namespace bimslam::changes
