// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/anchor/anchor_config.hpp"

#include "algorithms/common/status.hpp"

namespace bimslam::anchor {
using common::Require;

std::string_view ToString(OutlierMethod m) {
    switch (m) {
        case OutlierMethod::kPcm:
            return "pcm";
        case OutlierMethod::kGnc:
            return "gnc";
        case OutlierMethod::kNone:
            return "none";
    }
    return "?";
}

bool ParseOutlierMethod(std::string_view name, OutlierMethod* out) {
    for (OutlierMethod m : {OutlierMethod::kPcm, OutlierMethod::kGnc, OutlierMethod::kNone}) {
        if (name == ToString(m)) {
            *out = m;
            return true;
        }
    }
    return false;
}

void AnchorConfig::Validate() const {
    const char* c = "AnchorConfig";
    descriptor.Validate();
    cloud.Validate();
    registration.Validate();
    graph.Validate();
    Require(ring_key_candidates >= 1, c, "ring_key_candidates", ring_key_candidates,
            "must be >= 1");
    Require(sc_candidates >= 1 && sc_candidates <= ring_key_candidates, c, "sc_candidates",
            sc_candidates, "must be in [1, ring_key_candidates]");
    Require(max_sc_distance > 0 && max_sc_distance <= 2, c, "max_sc_distance", max_sc_distance,
            "must be in (0, 2]");
    Require(min_inlier_ratio >= 0 && min_inlier_ratio <= 1, c, "min_inlier_ratio", min_inlier_ratio,
            "must be in [0, 1]");
    Require(odometry_information_scale > 0, c, "odometry_information_scale",
            odometry_information_scale, "must be positive");
    Require(model_tolerance_m >= 0 && model_tolerance_m <= 1, c, "model_tolerance_m",
            model_tolerance_m, "must be in [0, 1] m");
    Require(model_tolerance_deg >= 0 && model_tolerance_deg <= 10, c, "model_tolerance_deg",
            model_tolerance_deg, "must be in [0, 10] degrees");
    Require(earlier_sigma_m > 0, c, "earlier_sigma_m", earlier_sigma_m, "must be positive");
    Require(earlier_sigma_deg > 0, c, "earlier_sigma_deg", earlier_sigma_deg, "must be positive");
    Require(earlier_spacing_m >= 0, c, "earlier_spacing_m", earlier_spacing_m,
            "must not be negative");
    Require(max_inlier_rmse > 0, c, "max_inlier_rmse", max_inlier_rmse, "must be positive");
    Require(consistency_m > 0, c, "consistency_m", consistency_m, "must be positive");
    Require(consistency_deg > 0, c, "consistency_deg", consistency_deg, "must be positive");
    Require(drift_per_m >= 0, c, "drift_per_m", drift_per_m, "must not be negative");
    Require(drift_deg_per_m >= 0, c, "drift_deg_per_m", drift_deg_per_m, "must not be negative");
    Require(min_clique >= 2, c, "min_clique", min_clique, "must be at least 2");
    Require(rival_min_ratio > 0 && rival_min_ratio <= 1, c, "rival_min_ratio", rival_min_ratio,
            "must be in (0, 1]");
    Require(max_hypotheses >= 1, c, "max_hypotheses", max_hypotheses, "must be at least 1");
    Require(max_cliques >= max_hypotheses, c, "max_cliques", max_cliques,
            "must be at least max_hypotheses");
    Require(proximity_radius_m > 0, c, "proximity_radius_m", proximity_radius_m,
            "must be positive");
    Require(proximity_height_m > 0, c, "proximity_height_m", proximity_height_m,
            "must be positive");
    Require(proximity_gate_m > 0, c, "proximity_gate_m", proximity_gate_m, "must be positive");
    Require(proximity_gate_deg > 0, c, "proximity_gate_deg", proximity_gate_deg,
            "must be positive");
    Require(proximity_first_level < registration.levels.size(), c, "proximity_first_level",
            double(proximity_first_level), "must name a registration level");
    Require(max_rounds >= 0, c, "max_rounds", max_rounds, "must not be negative");
    Require(max_loop_chi2 > 0, c, "max_loop_chi2", max_loop_chi2, "must be positive");
    Require(free_space_level < registration.levels.size(), c, "free_space_level",
            double(free_space_level), "must name a registration level");
    Require(max_seen_through > 0 && max_seen_through <= 1, c, "max_seen_through", max_seen_through,
            "must be in (0, 1]");
    Require(outweigh_ratio >= 1, c, "outweigh_ratio", outweigh_ratio, "must be at least 1");
    Require(outweigh_gap > 0 && outweigh_gap <= 1, c, "outweigh_gap", outweigh_gap,
            "must be in (0, 1]");
    Require(min_loops >= 1, c, "min_loops", min_loops, "must be at least 1");
    Require(min_coverage >= 0 && min_coverage <= 1, c, "min_coverage", min_coverage,
            "must be in [0, 1]");
    Require(ambiguity_ratio > 0 && ambiguity_ratio <= 1, c, "ambiguity_ratio", ambiguity_ratio,
            "must be in (0, 1]");
    Require(inject_false_loops >= 0 && inject_false_loops < 1, c, "inject_false_loops",
            inject_false_loops, "must be in [0, 1)");
    Require(threads >= 0, c, "threads", threads, "must not be negative");
}

}  // namespace bimslam::anchor
