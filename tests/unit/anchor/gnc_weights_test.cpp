// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Graduated non-convexity with a truncated least squares cost (host_tools/anchor/graph_state.hpp):
// Yang, Antonante, Tzoumas, Carlone, "Graduated Non-Convexity for Robust Spatial Perception: From
// Non-Minimal Solvers to Global Outlier Rejection", RA-L 5(2) 2020. The weight rule (Prop. 4,
// Eq. (14)) and the first mu (Remark 5) on residuals whose weights are worked out by hand, then
// GncWeights on a small graph with one wrong loop among right ones.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "host_tools/anchor/graph_state.hpp"

namespace bimslam::anchor {
namespace {
namespace BIMSLAM_UNITY_ID {

// Eq. (14) at c2 = 1, mu = 1: weight 1 up to r2 = mu / (mu + 1) = 0.5, 0 from (mu + 1) / mu = 2,
// sqrt(c2 mu (mu + 1) / r2) - mu = sqrt(2 / r2) - 1 between.
TEST(GncTlsWeight, HandWorkedValuesAtMuOne) {
    EXPECT_EQ(GncTlsWeight(0.0, 1.0, 1.0), 1.0);
    EXPECT_EQ(GncTlsWeight(0.5, 1.0, 1.0), 1.0);
    EXPECT_NEAR(GncTlsWeight(1.0, 1.0, 1.0), std::sqrt(2.0) - 1.0, 1e-12);  // 0.41421356
    EXPECT_NEAR(GncTlsWeight(1.5, 1.0, 1.0), std::sqrt(4.0 / 3.0) - 1.0, 1e-12);
    EXPECT_EQ(GncTlsWeight(2.0, 1.0, 1.0), 0.0);
    EXPECT_EQ(GncTlsWeight(50.0, 1.0, 1.0), 0.0);
}

// c2 = 9 (c-bar 3), mu = 4: the band is [4/5 * 9, 5/4 * 9] = [7.2, 11.25]; at r2 = c2 the weight
// is sqrt(4 * 5) - 4 = 0.47213595.
TEST(GncTlsWeight, HandWorkedValuesAtAnotherThresholdAndMu) {
    EXPECT_EQ(GncTlsWeight(7.2, 9.0, 4.0), 1.0);
    EXPECT_NEAR(GncTlsWeight(9.0, 9.0, 4.0), std::sqrt(20.0) - 4.0, 1e-12);
    EXPECT_EQ(GncTlsWeight(11.25, 9.0, 4.0), 0.0);
    // Continuous at both ends of the band, and decreasing inside it.
    EXPECT_NEAR(GncTlsWeight(7.2 + 1e-9, 9.0, 4.0), 1.0, 1e-8);
    EXPECT_NEAR(GncTlsWeight(11.25 - 1e-9, 9.0, 4.0), 0.0, 1e-8);
    EXPECT_GT(GncTlsWeight(8.0, 9.0, 4.0), GncTlsWeight(10.0, 9.0, 4.0));
}

// As mu grows the band closes on c2: the weights become TLS's 0 or 1 (inlier iff r2 < c2).
TEST(GncTlsWeight, LargeMuIsTruncatedLeastSquares) {
    const double c2 = 22.5;  // AnchorConfig::max_loop_chi2
    EXPECT_EQ(GncTlsWeight(0.99 * c2, c2, 1e4), 1.0);
    EXPECT_EQ(GncTlsWeight(1.01 * c2, c2, 1e4), 0.0);
}

// Remark 5: mu0 = c2 / (2 max_r2 - c2). Then the band's upper end, (mu0 + 1) / mu0 c2, is
// 2 max_r2: no residual starts with weight 0. c2 = 1, max_r2 = 5: mu0 = 1/9, and the largest
// residual's weight is sqrt((1/9)(10/9) / 5) - 1/9 = 0.0460218.
TEST(GncInitialMu, NoLoopStartsExcluded) {
    const double mu0 = GncInitialMu(5.0, 1.0);
    EXPECT_NEAR(mu0, 1.0 / 9.0, 1e-15);
    EXPECT_NEAR((mu0 + 1) / mu0 * 1.0, 2 * 5.0, 1e-12);
    EXPECT_NEAR(GncTlsWeight(5.0, 1.0, mu0), std::sqrt(10.0 / 405.0) - 1.0 / 9.0, 1e-12);
    for (const double r2 : {0.0, 0.5, 1.0, 3.0, 5.0}) EXPECT_GT(GncTlsWeight(r2, 1.0, mu0), 0.0);
}

Eigen::Isometry3d AlongX(double x) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation().x() = x;
    return T;
}

// A reference (session 0, fixed) and a query (session 1) of four keyframes 1 m apart along x,
// the query's anchor 0.3 m off. Loops k -> k with T_target_query = identity (1 cm sigma), and one
// wrong loop: query keyframe 0 said to be at reference keyframe 3, 3 m away (a repeated room).
struct TwoSessions {
    std::vector<AnchorSession> sessions = std::vector<AnchorSession>(2);
    std::vector<State> state = std::vector<State>(2);
    std::vector<LoopRecord> loops;

    TwoSessions() {
        for (int k = 0; k < 4; ++k) {
            state[0].poses.push_back(AlongX(k));
            state[1].poses.push_back(AlongX(k));
        }
        state[1].fixed = false;
        state[1].anchor.translation() << 0.3, -0.2, 0.0;
        for (uint32_t k = 0; k + 1 < 4; ++k) {
            sessions[1].session.edges.push_back(
                {k, k + 1, AlongX(1.0), common::Matrix6d::Identity() * 1e5});
        }
        for (size_t k = 0; k < 4; ++k) AddLoop(k, k);
    }
    void AddLoop(size_t target, size_t query) {
        LoopRecord l;
        l.target_session = 0;
        l.target_index = target;
        l.query_session = 1;
        l.query_index = query;
        l.T_target_query = Eigen::Isometry3d::Identity();
        l.registration.information = common::Matrix6d::Identity() * 1e4;
        loops.push_back(l);
    }
};

TEST(GncWeights, AllLoopsConsistentKeepsEveryWeightAtOne) {
    TwoSessions t;
    StageTimes times;
    const std::vector<double> w = GncWeights(t.sessions, &t.state, t.loops, AnchorConfig{}, &times);
    EXPECT_EQ(w, std::vector<double>(4, 1.0));
    EXPECT_LT(t.state[1].anchor.translation().norm(), 1e-3);
}

TEST(GncWeights, TheWrongLoopEndsAtZeroAndTheRightOnesAtOne) {
    TwoSessions t;
    t.AddLoop(3, 0);
    StageTimes times;
    const std::vector<double> w = GncWeights(t.sessions, &t.state, t.loops, AnchorConfig{}, &times);
    EXPECT_EQ(w, (std::vector<double>{1.0, 1.0, 1.0, 1.0, 0.0}));
    // The query is where the right loops put it, not pulled towards the wrong one.
    EXPECT_LT(t.state[1].anchor.translation().norm(), 1e-3);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::anchor
