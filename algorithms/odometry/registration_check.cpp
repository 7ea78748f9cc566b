// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/odometry/registration_check.hpp"

#include <algorithm>

#include "algorithms/common/status.hpp"

namespace bimslam::odometry {

void RegistrationCheckConfig::Validate() const {
    const char* c = "RegistrationCheckConfig";
    common::Require(min_overlap >= 0 && min_overlap <= 1, c, "min_overlap", min_overlap,
                    "must be in [0, 1]");
    common::Require(min_inlier_ratio >= 0 && min_inlier_ratio <= 1, c, "min_inlier_ratio",
                    min_inlier_ratio, "must be in [0, 1]");
    common::Require(min_inlier_fit >= 0 && min_inlier_fit <= 1, c, "min_inlier_fit", min_inlier_fit,
                    "must be in [0, 1]");
    common::Require(max_rms > 0, c, "max_rms", max_rms, "must be > 0");
    common::Require(max_prediction_sigmas >= 0, c, "max_prediction_sigmas", max_prediction_sigmas,
                    "must be >= 0");
    common::Require(gap_translation_sigma >= 0 && gap_rotation_sigma >= 0, c,
                    "gap_translation_sigma", gap_translation_sigma,
                    "and gap_rotation_sigma must be >= 0");
    common::Require(retry_headings >= 0 && retry_headings <= 16, c, "retry_headings",
                    retry_headings, "must be in [0, 16]");
    common::Require(retry_yaw_step_deg > 0 && retry_yaw_step_deg <= 90, c, "retry_yaw_step_deg",
                    retry_yaw_step_deg, "must be in (0, 90]");
}

// The evidence leaves out the points matched to line-like planes (VoxelPlane::line_like): their
// distances neither confirm nor contradict the pose.
double RegistrationScore(const RegistrationResult& reg) {
    const int judged = reg.points - reg.unjudged;
    return judged > 0 ? double(reg.inliers) / double(judged) : 0.0;
}

uint32_t JudgeRegistration(const RegistrationResult& reg, const Eigen::Isometry3d& T_pred,
                           const Eigen::Isometry3d& T, const Eigen::Vector3d& translation_sigma,
                           const RegistrationCheckConfig& config) {
    if (!config.enabled || reg.failed || reg.points <= 0) return 0;
    uint32_t reasons = 0;
    const double points = double(reg.points);
    // A point matched to a line-like plane found the map there: it counts for the overlap.
    if (double(reg.correspondences) < config.min_overlap * points) reasons |= kLowOverlap;
    // Few inliers among all the points and among those matched (both without the points matched
    // to line-like planes): a right scan with much of its view new or moving (a door leaf) has
    // the first low, not the second.
    if (RegistrationScore(reg) < config.min_inlier_ratio &&
        double(reg.inliers) < config.min_inlier_fit * double(reg.correspondences - reg.unjudged)) {
        reasons |= kFewInliers;
    }
    if (reg.rms > config.max_rms) reasons |= kHighResidual;
    if (config.max_prediction_sigmas > 0 && (translation_sigma.array() > 0).all()) {
        // In the predicted frame, per axis: the estimate's offset in sigmas of the prediction.
        const Eigen::Vector3d d = common::Between(T_pred, T).translation();
        if (d.cwiseQuotient(translation_sigma).norm() > config.max_prediction_sigmas) {
            reasons |= kFarFromPrediction;
        }
    }
    return reasons;
}

std::string CheckReasonText(uint32_t reasons) {
    std::string s;
    const auto add = [&](uint32_t bit, const char* text) {
        if (!(reasons & bit)) return;
        if (!s.empty()) s += ", ";
        s += text;
    };
    add(kLowOverlap, "low overlap with the map");
    add(kFewInliers, "few inliers");
    add(kHighResidual, "high residual");
    add(kFarFromPrediction, "far from the prediction");
    return s;
}

}  // namespace bimslam::odometry
