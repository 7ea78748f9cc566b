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
    ValidateLoopRules(c);
    descriptor.Validate();
    graph.Validate();
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
    Require(min_clique >= 2, c, "min_clique", min_clique, "must be at least 2");
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
