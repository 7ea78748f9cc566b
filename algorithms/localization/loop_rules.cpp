// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/localization/loop_rules.hpp"

#include <cmath>

#include "algorithms/common/se3.hpp"
#include "algorithms/common/status.hpp"

namespace bimslam::localization {
using common::Require;

void StartHint::Validate() const {
    common::Require(radius_m > 0 && radius_m <= 1000, "StartHint", "radius_m", radius_m,
                    "must be in (0, 1000] m");
    common::Require(xy.allFinite(), "StartHint", "xy", xy.x(), "must be finite");
}

StartHint StartHint::FromList(const std::vector<double>& v) {
    common::Require(v.size() == 2 || v.size() == 3, "StartHint", "values", double(v.size()),
                    "must be X Y or X Y R");
    StartHint h{{v[0], v[1]}, v.size() == 3 ? v[2] : StartHint{}.radius_m};
    h.Validate();
    return h;
}

LoopRules::LoopRules() { registration.information_scale = 0.006; }

void LoopRules::ValidateLoopRules(const char* c) const {
    cloud.Validate();
    registration.Validate();
    Require(ring_key_candidates >= 1, c, "ring_key_candidates", ring_key_candidates,
            "must be >= 1");
    Require(sc_candidates >= 1 && sc_candidates <= ring_key_candidates, c, "sc_candidates",
            sc_candidates, "must be in [1, ring_key_candidates]");
    Require(max_sc_distance > 0 && max_sc_distance <= 2, c, "max_sc_distance", max_sc_distance,
            "must be in (0, 2]");
    Require(min_inlier_ratio >= 0 && min_inlier_ratio <= 1, c, "min_inlier_ratio", min_inlier_ratio,
            "must be in [0, 1]");
    Require(max_inlier_rmse > 0, c, "max_inlier_rmse", max_inlier_rmse, "must be positive");
    Require(consistency_m > 0, c, "consistency_m", consistency_m, "must be positive");
    Require(consistency_deg > 0, c, "consistency_deg", consistency_deg, "must be positive");
    Require(drift_per_m >= 0, c, "drift_per_m", drift_per_m, "must not be negative");
    Require(drift_deg_per_m >= 0, c, "drift_deg_per_m", drift_deg_per_m, "must not be negative");
    Require(rival_min_ratio > 0 && rival_min_ratio <= 1, c, "rival_min_ratio", rival_min_ratio,
            "must be in (0, 1]");
    Require(free_space_level < registration.levels.size(), c, "free_space_level",
            double(free_space_level), "must name a registration level");
    Require(max_seen_through > 0 && max_seen_through <= 1, c, "max_seen_through", max_seen_through,
            "must be in (0, 1]");
    Require(outweigh_ratio >= 1, c, "outweigh_ratio", outweigh_ratio, "must be at least 1");
    Require(outweigh_gap > 0 && outweigh_gap <= 1, c, "outweigh_gap", outweigh_gap,
            "must be in (0, 1]");
    Require(floating_share > 0 && floating_share <= 1, c, "floating_share", floating_share,
            "must be in (0, 1]");
    Require(floating_radius_m > 0, c, "floating_radius_m", floating_radius_m, "must be positive");
    Require(floating_height_m > 0, c, "floating_height_m", floating_height_m, "must be positive");
    const registration::RemovedSurfaceConfig& r = removed_surfaces;
    Require(r.cell > 0, c, "removed_surfaces.cell", r.cell, "must be positive");
    Require(r.max_area_m2 > 0, c, "removed_surfaces.max_area_m2", r.max_area_m2,
            "must be positive");
    Require(r.min_on_map >= 0 && r.min_on_map <= 1, c, "removed_surfaces.min_on_map", r.min_on_map,
            "must be in [0, 1]");
    Require(r.min_share >= 0 && r.min_share <= 1, c, "removed_surfaces.min_share", r.min_share,
            "must be in [0, 1]");
}

bool LoopRules::FreeSpacePrefers(double a, double b, bool b_explained) const {
    const bool decisive = a * outweigh_ratio <= b && b - a >= outweigh_gap;
    const bool needs_less = a <= max_seen_through && b > max_seen_through && b_explained;
    return decisive || needs_less;
}

bool LoopRules::HeightsPrefer(size_t a_floating, size_t b_floating, size_t keyframes,
                              size_t min_count) const {
    const double b = double(b_floating);
    return b >= std::max(double(min_count), floating_share * double(keyframes)) &&
           outweigh_ratio * double(a_floating) <= b;
}

bool LoopRules::Agree(const Eigen::Isometry3d& E, double path_m) const {
    const double max_t = consistency_m + drift_per_m * path_m;
    const double max_r = (consistency_deg + drift_deg_per_m * path_m) * M_PI / 180;
    return E.translation().norm() <= max_t && common::RotationAngle(E) <= max_r;
}

}  // namespace bimslam::localization
