// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// LidarOdometry's judgement of its own registrations (registration_check.hpp), apart from
// lidar_odometry.cpp so that Process only calls it.
#include <cmath>

#include "algorithms/odometry/lidar_odometry.hpp"

namespace bimslam::odometry {

void LidarOdometry::JudgeScan(const Eigen::Isometry3d& T_pred, const Eigen::Isometry3d& T,
                              const common::Vector6d& sigma) {
    OdometryResult& r = result_;
    if (r.registration.over_budget) r.flags |= kCutShort;
    r.check_reasons = JudgeRegistration(r.registration, T_pred, T, sigma.head<3>(), config_.check);
    if (r.check_reasons == 0) return;
    r.flags |= kCheckFailed;
    // The gap marked in the motion's covariance (registration_check.hpp).
    const double t2 = config_.check.gap_translation_sigma * config_.check.gap_translation_sigma;
    const double r2 = config_.check.gap_rotation_sigma * config_.check.gap_rotation_sigma;
    r.covariance.diagonal() += (common::Vector6d() << t2, t2, t2, r2, r2, r2).finished();
}

bool LidarOdometry::TryOtherHeadings() {
    OdometryResult& r = result_;
    const Eigen::Isometry3d& T_pred = work_.T_pred;
    const common::Vector6d& sigma = work_.sigma;
    Eigen::Isometry3d* T = &work_.T;
    const Clock::time_point deadline = work_.deadline;
    const RegistrationCheckConfig& c = config_.check;
    if (!c.enabled || c.retry_headings == 0 || (r.flags & kImuUsed) ||
        JudgeRegistration(r.registration, T_pred, *T, sigma.head<3>(), c) == 0) {
        return true;
    }
    // The best so far: the registration from the prediction.
    RegistrationResult best = r.registration;
    Eigen::Isometry3d best_T = *T;
    common::Matrix6d best_cov = r.covariance;
    uint32_t best_flags = r.flags;
    double best_score = RegistrationScore(best);
    const uint32_t flags_before = r.flags;
    work_.start_error = 0;  // how far off another heading is, nothing measured says
    for (int k = 0; k < c.retry_headings; ++k) {
        if (BudgetClockNow() >= deadline) {
            r.budget_cut |= kCutHeadings;  // headings left untried
            break;
        }
        // +1, -1, +2, -2, ... steps.
        const double step = double(k / 2 + 1) * (k % 2 == 0 ? 1.0 : -1.0);
        Eigen::Isometry3d from = T_pred;
        from.linear() =
            T_pred.linear() *
            Eigen::AngleAxisd(step * c.retry_yaw_step_deg * M_PI / 180.0, Eigen::Vector3d::UnitZ())
                .toRotationMatrix();
        r.flags = flags_before;
        if (!Align(from, kCutHeadings)) continue;
        const double score = RegistrationScore(r.registration);
        const bool passes = JudgeRegistration(r.registration, T_pred, *T, sigma.head<3>(), c) == 0;
        // Only a start whose registration passes replaces the prediction's: a scan that fails for
        // another reason (little in view) is not moved to whichever heading scores higher.
        if (passes && score > best_score) {
            best = r.registration;
            best_T = *T;
            best_cov = r.covariance;
            best_flags = r.flags;
            best_score = score;
            break;  // the first start that passes: the scan fits there
        }
    }
    r.registration = best;
    *T = best_T;
    r.covariance = best_cov;
    r.flags = best_flags | kHeadingsTried;
    work_.registered = !best.failed;
    return !best.failed;
}

}  // namespace bimslam::odometry
