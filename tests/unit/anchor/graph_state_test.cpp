// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The model's tolerance added to a loop's information, and the priors that hold an earlier
// visit's session (host_tools/anchor/graph_state.hpp).
#include "host_tools/anchor/graph_state.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>

#include "algorithms/common/status.hpp"

namespace bimslam::anchor {
namespace {
namespace BIMSLAM_UNITY_ID {
using Matrix6d = Eigen::Matrix<double, 6, 6>;

Matrix6d Spd(unsigned seed) {
    std::srand(seed);
    const Matrix6d a = Matrix6d::Random();
    return a * a.transpose() * 1e4 + Matrix6d::Identity() * 100;
}

TEST(ModelTolerance, FullRankIsTheInverseOfTheSummedCovariances) {
    const Matrix6d h = Spd(3);
    const double sm = 0.02, sd = 0.2, sr = sd * M_PI / 180;
    Eigen::Matrix<double, 6, 1> v;
    v << sm * sm, sm * sm, sm * sm, sr * sr, sr * sr, sr * sr;
    const Matrix6d expected = (h.inverse() + Matrix6d(v.asDiagonal())).inverse();
    const Matrix6d got = WithModelTolerance(h, sm, sd);
    EXPECT_LT((got - expected).norm() / expected.norm(), 1e-9);
    // Less information than before in every direction.
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<Matrix6d>(h - got).eigenvalues().minCoeff(), -1e-9);
}

TEST(ModelTolerance, ZeroToleranceKeepsTheInformation) {
    const Matrix6d h = Spd(5);
    EXPECT_LT((WithModelTolerance(h, 0, 0) - h).norm(), 1e-9 * h.norm());
}

TEST(ModelTolerance, UnconstrainedDirectionsStayWithoutInformation) {
    // A corridor: the registration constrained everything but x.
    Matrix6d h = Spd(7);
    h.row(0).setZero();
    h.col(0).setZero();
    const Matrix6d got = WithModelTolerance(h, 0.02, 0.2);
    EXPECT_LT(got.row(0).norm(), 1e-9 * got.norm());
    EXPECT_LT(got.col(0).norm(), 1e-9 * got.norm());
    // The constrained block is the full-rank formula on it.
    const Eigen::Matrix<double, 5, 5> hb = h.bottomRightCorner<5, 5>();
    Eigen::Matrix<double, 5, 1> v;
    const double sr = 0.2 * M_PI / 180;
    v << 4e-4, 4e-4, sr * sr, sr * sr, sr * sr;
    const Eigen::Matrix<double, 5, 5> expected =
        (hb.inverse() + Eigen::Matrix<double, 5, 5>(v.asDiagonal())).inverse();
    EXPECT_LT((got.bottomRightCorner<5, 5>() - expected).norm() / expected.norm(), 1e-9);
}

Eigen::Isometry3d At(double x, double y) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() << x, y, 0;
    return T;
}

// The reference fixed, a query free and an earlier visit's session held: only the held one gets
// priors, one per keyframe, at its own (world) poses with the configured sigma; fixed, it gets
// none (while queries are anchored one by one, it is a target like the reference).
TEST(EarlierSessions, AHeldSessionGetsAPriorPerKeyframeAtItsPoses) {
    std::vector<AnchorSession> sessions(3);
    sessions[0].poses = {At(0, 0)};
    sessions[1].poses = {At(5, 0), At(6, 0)};
    sessions[2].poses = {At(1, 2), At(2, 2), At(3, 2)};
    sessions[2].earlier = true;
    AnchorConfig config;
    config.earlier_sigma_m = 0.05;
    config.earlier_sigma_deg = 0.5;
    std::vector<State> state(3);
    for (size_t s = 0; s < 3; ++s) state[s] = {Eigen::Isometry3d::Identity(), sessions[s].poses};
    state[1].fixed = false;
    EXPECT_TRUE(BuildGraph(sessions, state, {}, config).priors().empty());
    state[2].fixed = false;
    state[2].held = true;
    const posegraph::PoseGraph g = BuildGraph(sessions, state, {}, config);
    ASSERT_EQ(g.priors().size(), 3u);
    const double rad = 0.5 * M_PI / 180;
    for (size_t k = 0; k < 3; ++k) {
        const posegraph::PriorFactor& f = g.priors()[k];
        EXPECT_EQ(f.session, 2u);
        EXPECT_EQ(f.index, k);
        EXPECT_TRUE(f.T_world_lidar.isApprox(sessions[2].poses[k]));
        EXPECT_NEAR(f.information(0, 0), 1 / (0.05 * 0.05), 1e-6);
        EXPECT_NEAR(f.information(5, 5), 1 / (rad * rad), 1e-3);
        EXPECT_NEAR(f.information(0, 1), 0.0, 1e-12);
    }
}

// Earlier visits' sessions come after every query (their indices follow the queries').
TEST(EarlierSessions, AnEarlierSessionBeforeAQueryIsRefused) {
    std::vector<AnchorSession> sessions(3);
    sessions[1].earlier = true;
    EXPECT_THROW(Anchor(sessions, AnchorConfig{}), common::Error);
}

// A solution that moves a run of keyframes 0.75 m down against a trusted odometry (the sample
// hall's meeting table: registrations at the table's height) breaks the two edges around the run
// and no other; a few centimetres of bending are no break.
TEST(OdometryBreaks, ARunOfKeyframesMovedAgainstTheOdometryBreaksTheEdgesAroundIt) {
    std::vector<io::SessionEdge> edges;
    std::vector<Eigen::Isometry3d> poses;
    for (uint32_t k = 0; k < 10; ++k) {
        Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
        p.translation() = Eigen::Vector3d(0.5 * k, 0.02 * (k % 2), 0.0);  // bent 2 cm
        if (k >= 4 && k <= 6) p.translation().z() = -0.75;
        poses.push_back(p);
        if (k > 0) {
            io::SessionEdge e;
            e.from = k - 1;
            e.to = k;
            e.T_from_to.translation() = Eigen::Vector3d(0.5, 0.0, 0.0);
            edges.push_back(e);
        }
    }
    const auto breaks = OdometryBreaks(edges, poses, 0.2, 5.0);
    ASSERT_EQ(breaks.size(), 2u);
    EXPECT_EQ(breaks[0].from, 3u);
    EXPECT_EQ(breaks[1].to, 7u);
    EXPECT_NEAR(breaks[0].offset_m, 0.75, 0.01);
    EXPECT_TRUE(OdometryBreaks(edges, poses, 1.0, 5.0).empty());

    // Where the odometry said it did not know its height (edges 3-4 and 6-7), a vertical offset
    // is no break; a horizontal one still is.
    std::vector<bool> unsure(edges.size(), false);
    unsure[3] = unsure[6] = true;
    EXPECT_TRUE(OdometryBreaks(edges, poses, 0.2, 5.0, unsure).empty());
    poses[7].translation().y() += 0.5;
    const auto aside = OdometryBreaks(edges, poses, 0.2, 5.0, unsure);
    ASSERT_EQ(aside.size(), 2u);  // 6-7 across, 7-8 back
    EXPECT_EQ(aside[0].from, 6u);
    EXPECT_NEAR(aside[0].offset_m, 0.5, 0.03);
    EXPECT_EQ(aside[1].from, 7u);
}

// An edge is unsure of its height where a height-unseen or height-ambiguous stretch overlaps the
// times between its keyframes, at either end included; a failed stretch is not that.
TEST(OdometryBreaks, AnEdgeIsUnsureOfItsHeightWhereTheOdometrySaidSo) {
    std::vector<io::SessionEdge> edges(6);
    std::vector<io::SessionKeyframe> keyframes(7);
    for (uint32_t k = 0; k < 7; ++k) {
        keyframes[k].stamp_ns = int64_t(k) * 1'000'000'000;
        if (k > 0) {
            edges[k - 1].from = k - 1;
            edges[k - 1].to = k;
        }
    }
    OdometryVerdict v;
    const auto stretch = [](double a_s, double b_s) {
        OdometryStretch o;
        o.first_ns = int64_t(a_s * 1e9);
        o.last_ns = int64_t(b_s * 1e9);
        return o;
    };
    v.height_unseen = {stretch(1.2, 2.5)};     // edges 1-2 and 2-3
    v.height_ambiguous = {stretch(5.0, 5.0)};  // at keyframe 5: edges 4-5 and 5-6
    v.stretches = {stretch(0.2, 0.4)};         // failed: not this
    EXPECT_EQ(HeightUnsureEdges(edges, keyframes, v),
              (std::vector<bool>{false, true, true, false, true, true}));
    EXPECT_TRUE(HeightUnsureEdges(edges, keyframes, OdometryVerdict{}).empty());
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::anchor
