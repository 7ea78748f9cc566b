// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/odometry/motion_prior.hpp"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>

namespace bimslam::odometry {
namespace {
namespace BIMSLAM_UNITY_ID {
constexpr int64_t kMs = 1'000'000;

// Samples at 100 Hz for `seconds` with constant body velocity and yaw rate.
MotionPrior Constant(Eigen::Vector2d v, double w, double seconds, MotionPriorConfig config = {},
                     std::optional<Eigen::Quaterniond> attitude = std::nullopt) {
    MotionPrior prior(config);
    for (int64_t k = 0; k <= int64_t(seconds * 100); ++k) {
        BodyMotionSample s;
        s.t_ns = 5'000 * kMs + k * 10 * kMs;
        s.v_xy = v;
        s.yaw_rate = w;
        s.attitude = attitude;
        EXPECT_TRUE(prior.Add(s).ok());
    }
    return prior;
}

TEST(MotionPrior, StraightAndSidewaysMotion) {
    const MotionPrior prior = Constant({1.0, 0.25}, 0.0, 5.0);
    const auto r = prior.Between(prior.begin_ns(), prior.end_ns());
    ASSERT_TRUE(r);
    EXPECT_LT((r->T_a_b.translation() - Eigen::Vector3d(5.0, 1.25, 0)).norm(), 1e-9);
    EXPECT_LT(common::RotationAngle(r->T_a_b), 1e-12);
    // Interpolated inside sample intervals.
    const auto part = prior.Between(prior.begin_ns() + 5 * kMs, prior.begin_ns() + 1005 * kMs);
    ASSERT_TRUE(part);
    EXPECT_NEAR(part->T_a_b.translation().x(), 1.0, 1e-9);
}

TEST(MotionPrior, ArcMatchesTheClosedForm) {
    const double v = 1.0, w = 0.5, t = 3.0;
    const MotionPrior prior = Constant({v, 0.0}, w, t);
    const auto r = prior.Between(prior.begin_ns(), prior.end_ns());
    ASSERT_TRUE(r);
    const Eigen::Vector3d expected(v / w * std::sin(w * t), v / w * (1 - std::cos(w * t)), 0);
    EXPECT_LT((r->T_a_b.translation() - expected).norm(), 1e-5);
    EXPECT_NEAR(common::LogSO3(r->T_a_b.linear()).z(), w * t, 1e-9);
    // Composition: a->m->b equals a->b.
    const int64_t m = prior.begin_ns() + 1234 * kMs;
    const auto am = prior.Between(prior.begin_ns(), m), mb = prior.Between(m, prior.end_ns());
    ASSERT_TRUE(am && mb);
    EXPECT_LT(((am->T_a_b * mb->T_a_b).matrix() - r->T_a_b.matrix()).norm(), 1e-5);
}

TEST(MotionPrior, CovarianceGrowsWithTimeAndDistance) {
    const MotionPrior still = Constant({0, 0}, 0, 10.0);
    const MotionPrior moving = Constant({1.5, 0}, 0, 10.0);
    const int64_t t0 = still.begin_ns();
    double last_still = 0, last_moving = 0;
    for (int s = 1; s <= 10; ++s) {
        const auto a = still.Between(t0, t0 + s * 1000 * kMs);
        const auto b = moving.Between(t0, t0 + s * 1000 * kMs);
        ASSERT_TRUE(a && b);
        const double va = a->covariance(0, 0), vb = b->covariance(0, 0);
        EXPECT_GT(va, last_still);  // with time
        EXPECT_GT(vb, va);          // and more with distance
        EXPECT_GT(b->covariance(5, 5), 0.0);
        last_still = va;
        last_moving = vb;
        // Symmetric and positive semi-definite.
        EXPECT_LT((b->covariance - b->covariance.transpose()).norm(), 1e-15);
        Eigen::SelfAdjointEigenSolver<common::Matrix6d> eig(b->covariance);
        EXPECT_GE(eig.eigenvalues().minCoeff(), -1e-15);
    }
    // 10 m at a 5 % scale error: about sqrt(0.05^2 * 15 m * 1 m) in x.
    EXPECT_NEAR(std::sqrt(last_moving), std::sqrt(0.05 * 0.05 * 15 + 0.05 * 0.05 * 10), 0.01);
    // A turn couples yaw uncertainty into the lateral position.
    const MotionPrior turning = Constant({1.0, 0}, 0.3, 5.0);
    EXPECT_GT(std::abs(turning.Between(turning.begin_ns(), turning.end_ns())->covariance(1, 5)),
              0.0);
}

TEST(MotionPrior, InvalidDataAndGapsInflateTheCovariance) {
    MotionPrior good = Constant({1, 0}, 0, 2.0);
    MotionPrior prior;
    for (int64_t k = 0; k <= 200; ++k) {
        BodyMotionSample s;
        s.t_ns = k * 10 * kMs;
        s.v_xy = {1, 0};
        s.velocity_valid = !(k >= 50 && k < 100);  // half a second of invalid velocity
        ASSERT_TRUE(prior.Add(s).ok());
    }
    const auto r = prior.Between(0, 2000 * kMs);
    const auto g = good.Between(good.begin_ns(), good.end_ns());
    ASSERT_TRUE(r && g);
    // 0.5 s at 1 m/s of invalid-data noise: variance 0.5 m^2, against 0.01 m^2 when valid.
    EXPECT_GT(r->covariance(0, 0), 0.45);
    EXPECT_GT(r->covariance(0, 0), 40 * g->covariance(0, 0));
    // The last valid velocity is held through the invalid stretch.
    EXPECT_NEAR(r->T_a_b.translation().x(), 2.0, 1e-9);
    // A 1 s gap between samples.
    MotionPrior gap;
    for (int64_t t : {int64_t{0}, 10 * kMs, 1010 * kMs, 1020 * kMs}) {
        BodyMotionSample s;
        s.t_ns = t;
        s.v_xy = {1, 0};
        ASSERT_TRUE(gap.Add(s).ok());
    }
    EXPECT_GT(gap.Between(0, 1020 * kMs)->covariance(0, 0), 0.5);
}

TEST(MotionPrior, RollAndPitchFromTheImuYawFromTheGyro) {
    const Eigen::Quaterniond tilted(Eigen::AngleAxisd(2.0, Eigen::Vector3d::UnitZ()) *
                                    Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitY()));
    const MotionPrior prior = Constant({0.5, 0}, 0.0, 1.0, {}, tilted);
    const auto r = prior.Between(prior.begin_ns(), prior.end_ns());
    ASSERT_TRUE(r);
    // The same tilt at both ends and no yaw rate: no relative rotation (IMU yaw 2.0 ignored).
    EXPECT_LT(common::RotationAngle(r->T_a_b), 1e-9);
    EXPECT_NEAR(r->covariance(3, 3), 2 * 0.02 * 0.02, 1e-12);
    // Pitch changing from 0 to 0.1 between the ends shows up as a relative pitch.
    MotionPrior changing;
    for (int k = 0; k <= 10; ++k) {
        BodyMotionSample s;
        s.t_ns = k * 10 * kMs;
        s.attitude = Eigen::Quaterniond(Eigen::AngleAxisd(0.01 * k, Eigen::Vector3d::UnitY()));
        ASSERT_TRUE(changing.Add(s).ok());
    }
    const auto p = changing.Between(0, 100 * kMs);
    ASSERT_TRUE(p);
    EXPECT_NEAR(common::LogSO3(p->T_a_b.linear()).y(), 0.1, 1e-9);
}

TEST(MotionPrior, RejectsBadSamplesAndQueriesOutsideTheBuffer) {
    MotionPriorConfig config;
    config.capacity = 50;
    MotionPrior prior(config);
    BodyMotionSample s;
    s.t_ns = 100;
    EXPECT_TRUE(prior.Add(s).ok());
    EXPECT_FALSE(prior.Add(s).ok());  // not later
    s.t_ns = 200;
    s.yaw_rate = std::nan("");
    EXPECT_EQ(prior.Add(s).code(), common::StatusCode::kInvalidArgument);
    EXPECT_EQ(prior.size(), 1u);
    EXPECT_FALSE(prior.Between(100, 100).has_value());  // one sample is no interval
    for (int k = 1; k <= 100; ++k) {
        s.t_ns = 100 + k * 10;
        s.yaw_rate = 0;
        ASSERT_TRUE(prior.Add(s).ok());
    }
    EXPECT_EQ(prior.size(), 50u);  // the oldest were dropped
    EXPECT_EQ(prior.begin_ns(), 100 + 51 * 10);
    EXPECT_FALSE(prior.Between(100, 500).has_value());
    EXPECT_FALSE(prior.Between(prior.end_ns() - 10, prior.end_ns() - 20).has_value());
    EXPECT_TRUE(prior.Between(prior.begin_ns(), prior.end_ns()).has_value());
    config.capacity = 1;
    EXPECT_THROW(MotionPrior{config}, common::Error);
    config = {};
    config.velocity_scale_sigma = 2;
    EXPECT_THROW(MotionPrior{config}, common::Error);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::odometry
