// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/evaluation/trajectory_metrics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "algorithms/common/se3.hpp"
#include "algorithms/common/status.hpp"

namespace bimslam::evaluation {
namespace {
namespace BIMSLAM_UNITY_ID {

using io::StampedPose;
constexpr int64_t kStart_ns = 42'000'000'000;  // a sensor clock that does not start at 0
constexpr int64_t kStep_ns = 100'000'000;      // 10 Hz

Eigen::Isometry3d Pose(const Eigen::Vector3d& t, double yaw, double pitch = 0.0,
                       double roll = 0.0) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                  Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                  Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                     .toRotationMatrix();
    T.translation() = t;
    return T;
}

// A walk that turns, climbs a little and rolls: no three of its positions on one line.
std::vector<StampedPose> Walk(int n = 200) {
    std::vector<StampedPose> out;
    for (int k = 0; k < n; ++k) {
        const double a = 0.05 * k;
        const Eigen::Vector3d p(5.0 * std::cos(a) + 0.1 * k, 5.0 * std::sin(a),
                                0.5 * std::sin(2 * a));
        out.push_back(StampedPose::FromIsometry(kStart_ns + k * kStep_ns,
                                                Pose(p, a, 0.1 * std::sin(a), 0.05 * k / n)));
    }
    return out;
}

// Each pose's stamp kept, its pose mapped by f.
template <typename F>
std::vector<StampedPose> Map(const std::vector<StampedPose>& in, F f) {
    std::vector<StampedPose> out;
    for (size_t k = 0; k < in.size(); ++k) {
        out.push_back(StampedPose::FromIsometry(in[k].stamp_ns, f(k, in[k].Pose())));
    }
    return out;
}

EvaluationConfig Config(Alignment align) {
    EvaluationConfig c;
    c.align = align;
    return c;
}

TEST(TrajectoryMetrics, IdenticalTrajectoriesHaveNoError) {
    const auto ref = Walk();
    for (Alignment align : {Alignment::kNone, Alignment::kSe3}) {
        const EvaluationResult r = Evaluate(ref, ref, Config(align));
        EXPECT_EQ(r.matched, ref.size());
        EXPECT_EQ(r.est_poses, ref.size());
        EXPECT_EQ(r.ref_poses, ref.size());
        EXPECT_FALSE(r.alignment.degenerate);
        EXPECT_NEAR(r.ape_trans_m.rmse, 0.0, 1e-9);
        EXPECT_NEAR(r.ape_trans_m.max, 0.0, 1e-9);
        EXPECT_NEAR(r.ape_rot_deg.max, 0.0, 1e-6);
        EXPECT_GT(r.rpe_trans_m.count, 150u);
        EXPECT_NEAR(r.rpe_trans_m.max, 0.0, 1e-9);
        EXPECT_NEAR(r.rpe_rot_deg.rmse, 0.0, 1e-6);
        EXPECT_GT(r.drift_segments, 100u);
        EXPECT_NEAR(r.drift_percent, 0.0, 1e-7);
        EXPECT_FALSE(r.drift_segment_shortened);
        EXPECT_NEAR(r.duration_s, 19.9, 1e-12);
        EXPECT_GT(r.distance_m, 30.0);
    }
}

TEST(TrajectoryMetrics, Se3AlignmentRemovesARigidOffsetThatNoAlignmentReports) {
    const auto ref = Walk();
    const double angle = 30.0 * std::numbers::pi / 180.0;
    Eigen::Isometry3d T_est_ref = Eigen::Isometry3d::Identity();
    T_est_ref.linear() =
        Eigen::AngleAxisd(angle, Eigen::Vector3d(0.2, -0.1, 1.0).normalized()).toRotationMatrix();
    T_est_ref.translation() = Eigen::Vector3d(3.0, -2.0, 1.0);
    const auto est = Map(ref, [&](size_t, const Eigen::Isometry3d& T) { return T_est_ref * T; });

    const EvaluationResult se3 = Evaluate(est, ref, Config(Alignment::kSe3));
    EXPECT_NEAR(se3.ape_trans_m.max, 0.0, 1e-9);
    EXPECT_NEAR(se3.ape_rot_deg.max, 0.0, 1e-6);
    EXPECT_TRUE(se3.alignment.T_ref_est.isApprox(T_est_ref.inverse(), 1e-9));

    // Unaligned, every pose is off by the whole transform: the rotation angle exactly, and the
    // translation by how far the transform moves that position.
    const EvaluationResult none = Evaluate(est, ref, Config(Alignment::kNone));
    EXPECT_NEAR(none.ape_rot_deg.min, 30.0, 1e-9);
    EXPECT_NEAR(none.ape_rot_deg.max, 30.0, 1e-9);
    std::vector<double> expected;
    for (const auto& p : ref)
        expected.push_back((T_est_ref * p.translation - p.translation).norm());
    const ErrorStats want = ComputeStats(expected);
    EXPECT_NEAR(none.ape_trans_m.rmse, want.rmse, 1e-12);
    EXPECT_NEAR(none.ape_trans_m.max, want.max, 1e-12);
    EXPECT_GT(none.ape_trans_m.min, 1.0);
    // Relative motion does not see a rigid transform of the whole trajectory.
    EXPECT_NEAR(none.rpe_trans_m.max, 0.0, 1e-9);
    EXPECT_NEAR(none.drift_percent, 0.0, 1e-7);
}

TEST(TrajectoryMetrics, WithoutAlignmentAConstantOffsetIsTheError) {
    const auto ref = Walk();
    const Eigen::Vector3d offset(0.3, -0.4, 0.0);  // 0.5 m
    const auto est = Map(ref, [&](size_t, Eigen::Isometry3d T) {
        T.translation() += offset;
        return T;
    });
    const EvaluationResult r = Evaluate(est, ref, Config(Alignment::kNone));
    for (double v : {r.ape_trans_m.rmse, r.ape_trans_m.mean, r.ape_trans_m.median,
                     r.ape_trans_m.min, r.ape_trans_m.max}) {
        EXPECT_NEAR(v, 0.5, 1e-12);
    }
    EXPECT_NEAR(r.ape_trans_m.std, 0.0, 1e-12);
    EXPECT_NEAR(r.ape_rot_deg.max, 0.0, 1e-6);
}

TEST(TrajectoryMetrics, KnownPerPoseNoiseGivesItsStatistics) {
    const auto ref = Walk();
    std::mt19937 rng(7);
    std::normal_distribution<double> gauss;
    // Errors of 1 cm and 3 cm in turn, in random directions.
    const auto est = Map(ref, [&](size_t k, Eigen::Isometry3d T) {
        const Eigen::Vector3d dir =
            Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)).normalized();
        T.translation() += (k % 2 == 0 ? 0.01 : 0.03) * dir;
        return T;
    });
    const EvaluationResult r = Evaluate(est, ref, Config(Alignment::kNone));
    EXPECT_NEAR(r.ape_trans_m.rmse, std::sqrt(0.5 * (0.01 * 0.01 + 0.03 * 0.03)), 1e-12);
    EXPECT_NEAR(r.ape_trans_m.mean, 0.02, 1e-12);
    EXPECT_NEAR(r.ape_trans_m.median, 0.02, 1e-12);
    EXPECT_NEAR(r.ape_trans_m.std, 0.01, 1e-12);
    EXPECT_NEAR(r.ape_trans_m.min, 0.01, 1e-12);
    EXPECT_NEAR(r.ape_trans_m.max, 0.03, 1e-12);
    // Alignment can only lower the error of the best rigid fit.
    const EvaluationResult aligned = Evaluate(est, ref, Config(Alignment::kSe3));
    EXPECT_LE(aligned.ape_trans_m.rmse, r.ape_trans_m.rmse + 1e-12);
    EXPECT_GT(aligned.ape_trans_m.rmse, 0.015);
}

// A straight 50 m path with poses every 12.5 cm (exact in binary, so path lengths are too).
std::vector<StampedPose> StraightLine(int n) {
    std::vector<StampedPose> out;
    for (int k = 0; k < n; ++k) {
        out.push_back(StampedPose::FromIsometry(kStart_ns + k * kStep_ns,
                                                Pose(Eigen::Vector3d(0.125 * k, 0, 0), 0.0)));
    }
    return out;
}

TEST(TrajectoryMetrics, LinearDriftOfOneCentimetrePerMetre) {
    const auto ref = StraightLine(401);
    // Along the path (a scale error) and across it (a heading error, position only).
    const auto along = Map(ref, [](size_t, Eigen::Isometry3d T) {
        T.translation().x() *= 1.01;
        return T;
    });
    const auto across = Map(ref, [](size_t, Eigen::Isometry3d T) {
        T.translation().y() = 0.01 * T.translation().x();
        return T;
    });
    for (const auto* est : {&along, &across}) {
        for (Alignment align : {Alignment::kNone, Alignment::kSe3}) {
            const EvaluationResult r = Evaluate(*est, ref, Config(align));
            EXPECT_DOUBLE_EQ(r.distance_m, 50.0);
            EXPECT_EQ(r.rpe_trans_m.count, 401u - 8u);  // every start with 1 m of path after it
            EXPECT_NEAR(r.rpe_trans_m.rmse, 0.01, 1e-9);
            EXPECT_NEAR(r.rpe_trans_m.mean, 0.01, 1e-9);
            EXPECT_NEAR(r.rpe_trans_m.max, 0.01, 1e-9);
            EXPECT_NEAR(r.rpe_rot_deg.rmse, 0.0, 1e-6);
            EXPECT_EQ(r.drift_segments, 401u - 80u);
            EXPECT_DOUBLE_EQ(r.drift_segment_m, 10.0);
            EXPECT_NEAR(r.drift_percent, 1.0, 1e-7);
            // A line leaves the alignment's rotation about it free, and the result says so.
            EXPECT_EQ(r.alignment.degenerate, align == Alignment::kSe3);
        }
    }
}

TEST(TrajectoryMetrics, DriftUsesTheWholePathWhenShorterThanTheSegment) {
    const auto ref = StraightLine(41);  // 5 m
    const auto est = Map(ref, [](size_t, Eigen::Isometry3d T) {
        T.translation().x() *= 1.01;
        return T;
    });
    const EvaluationResult r = Evaluate(est, ref, Config(Alignment::kNone));
    EXPECT_TRUE(r.drift_segment_shortened);
    EXPECT_DOUBLE_EQ(r.drift_segment_m, 5.0);
    EXPECT_EQ(r.drift_segments, 1u);
    EXPECT_NEAR(r.drift_percent, 1.0, 1e-9);

    // Standing still: nothing to divide by, and no RPE pair either.
    const auto still = Map(ref, [](size_t, Eigen::Isometry3d) { return Pose({1, 2, 3}, 0.3); });
    const EvaluationResult s = Evaluate(still, still, Config(Alignment::kNone));
    EXPECT_EQ(s.drift_segments, 0u);
    EXPECT_TRUE(std::isnan(s.drift_percent));
    EXPECT_EQ(s.rpe_trans_m.count, 0u);
    EXPECT_TRUE(std::isnan(s.rpe_trans_m.rmse));
}

StampedPose At(double t_s) {
    return StampedPose::FromIsometry(std::llround(t_s * 1e9), Eigen::Isometry3d::Identity());
}

TEST(TrajectoryMetrics, AssociationKeepsPosesWithinTheWindowOnce) {
    std::vector<StampedPose> ref, est;
    for (int k = 0; k < 20; ++k) ref.push_back(At(0.1 * k));
    for (int k = 0; k < 20; ++k) {
        double t = 0.1 * k;
        if (k == 3) t += 0.030;                     // outside 10 ms
        if (k == 7) t -= 0.011;                     // just outside
        if (k == 10) t += 0.004;                    // inside
        if (k == 12) t += 0.010;                    // on the edge: inside
        if (k == 15) est.push_back(At(t - 0.003));  // a second estimate near ref 15, further off
        est.push_back(At(t));
    }
    const std::vector<MatchedPair> pairs = Associate(est, ref);
    ASSERT_EQ(pairs.size(), 18u);
    for (const MatchedPair& p : pairs) {
        EXPECT_NE(p.ref, 3u);
        EXPECT_NE(p.ref, 7u);
        EXPECT_LE(std::abs(est[p.est].stamp_ns - ref[p.ref].stamp_ns), 10'000'000);
    }
    // Ref 15 goes to the closer estimate (index 16, after the extra one at 15).
    EXPECT_EQ(pairs[13], (MatchedPair{16, 15}));
    EXPECT_EQ(Associate(est, ref, 31'000'000).size(), 20u);

    // Poses are at the origin: only the counts matter here.
    const EvaluationResult r = Evaluate(est, ref, Config(Alignment::kNone));
    EXPECT_EQ(r.matched, 18u);
    EXPECT_EQ(r.est_poses, 21u);
    EXPECT_EQ(r.ref_poses, 20u);
}

TEST(TrajectoryMetrics, AssociationNeverCrossesPairs) {
    // Greedy alone pairs (1.0, 0.9) first, then (0.0, 1.5): crossed. In time order instead.
    const std::vector<StampedPose> est = {At(0.0), At(1.0)}, ref = {At(0.9), At(1.5)};
    EXPECT_EQ(Associate(est, ref, 2'000'000'000), (std::vector<MatchedPair>{{0, 0}, {1, 1}}));
}

TEST(TrajectoryMetrics, FewerThanThreeMatchesIsAnErrorNamingBothFiles) {
    const auto ref = Walk(50);
    auto est = Walk(50);
    for (auto& p : est) p.stamp_ns += 5'000'000'000;  // another clock: 45 poses miss
    try {
        (void)Evaluate(std::vector<StampedPose>(est.end() - 2, est.end()), ref, {}, "est.tum",
                       "ref.tum");
        FAIL() << "no error";
    } catch (const common::Error& e) {
        EXPECT_EQ(e.code(), common::StatusCode::kInvalidArgument);
        const std::string what = e.what();
        for (const char* part : {"est.tum (2 poses)", "ref.tum (50 poses)", "10 ms", "0 poses"}) {
            EXPECT_NE(what.find(part), std::string::npos) << part << " not in: " << what;
        }
    }
    // Exactly 3 are enough.
    est.resize(3);
    for (auto& p : est) p.stamp_ns -= 5'000'000'000;
    EXPECT_EQ(Evaluate(est, ref, {}).matched, 3u);
    EXPECT_THROW((void)Evaluate({}, ref, {}), common::Error);
}

TEST(TrajectoryMetrics, ConfigAndStatistics) {
    EvaluationConfig c;
    EXPECT_NO_THROW(c.Validate());
    c.rpe_delta_m = 0.0;
    EXPECT_THROW(c.Validate(), common::Error);
    c = {};
    c.drift_segment_m = std::nan("");
    EXPECT_THROW(c.Validate(), common::Error);
    c = {};
    c.max_dt_ns = -1;
    EXPECT_THROW(c.Validate(), common::Error);

    const ErrorStats odd = ComputeStats({3.0, 1.0, 2.0});
    EXPECT_DOUBLE_EQ(odd.median, 2.0);
    EXPECT_DOUBLE_EQ(odd.rmse, std::sqrt(14.0 / 3.0));
    EXPECT_DOUBLE_EQ(ComputeStats({4.0, 1.0, 2.0, 3.0}).median, 2.5);
    const ErrorStats none = ComputeStats({});
    EXPECT_EQ(none.count, 0u);
    EXPECT_TRUE(std::isnan(none.rmse));
}

TEST(TrajectoryMetrics, UmeyamaRecoversARigidTransform) {
    std::vector<Eigen::Vector3d> a, b;
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-5.0, 5.0);
    const Eigen::Isometry3d T = Pose({1.0, -2.0, 0.5}, 2.5, -0.3, 0.7);  // yaw beyond 90 deg
    for (int k = 0; k < 10; ++k) {
        a.emplace_back(u(rng), u(rng), u(rng));
        b.push_back(T * a.back());
    }
    const RigidAlignment r = AlignUmeyama(a, b);
    EXPECT_FALSE(r.degenerate);
    EXPECT_TRUE(r.T_ref_est.isApprox(T, 1e-12));
    // A planar set (a ground robot) still fixes the rotation; a point does not.
    for (auto& p : a) p.z() = 0.0;
    for (size_t k = 0; k < a.size(); ++k) b[k] = T * a[k];
    EXPECT_TRUE(AlignUmeyama(a, b).T_ref_est.isApprox(T, 1e-12));
    EXPECT_TRUE(AlignUmeyama({a[0], a[0], a[0]}, {b[0], b[0], b[0]}).degenerate);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::evaluation
