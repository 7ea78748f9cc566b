// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The earlier visits' keyframes that stand for them as a new visit's targets (EarlierTargets,
// AnchorConfig::earlier_spacing_m) and a session cut to them (KeepKeyframes).
#include <gtest/gtest.h>

#include "host_tools/anchor/anchor_session.hpp"

namespace bimslam::anchor {
namespace {
namespace BIMSLAM_UNITY_ID {

// A session of keyframes at (x, y) along a line, one every `step` metres from x0.
AnchorSession Walk(double x0, double y, double step, size_t n) {
    AnchorSession s;
    for (size_t k = 0; k < n; ++k) {
        Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
        p.translation() = Eigen::Vector3d(x0 + step * double(k), y, 0.0);
        s.poses.push_back(p);
        s.path_m.push_back(step * double(k));
        s.descriptors.emplace_back();
        s.session.keyframes.emplace_back();
    }
    for (uint32_t k = 0; k + 1 < n; ++k) s.session.edges.push_back({k, k + 1});
    s.earlier = true;
    return s;
}

TEST(EarlierTargets, AnOlderVisitKeepsOnlyWhereNoNewerVisitCame) {
    // Visit 0 walked x = 0..9 at y = 0; visit 1 (newer) x = 0..4 at y = 0.3; visit 2 (newest)
    // x = 20..24, elsewhere. Keyframes of one visit 0.5 m apart never thin each other.
    const std::vector<AnchorSession> sessions = {Walk(0, 0, 0.5, 20), Walk(0, 0.3, 1, 5),
                                                 Walk(20, 0, 1, 5)};
    const auto keep = EarlierTargets(sessions, {0, 1, 2}, 1.0);
    EXPECT_EQ(keep[2].size(), 5u);
    EXPECT_EQ(keep[1].size(), 5u);
    // Visit 0's keyframes within 1 m of visit 1's (x < 5 + sqrt(1 - 0.09)) are left out.
    ASSERT_FALSE(keep[0].empty());
    for (const size_t k : keep[0]) EXPECT_GE(sessions[0].poses[k].translation().x(), 4.9) << k;
    EXPECT_EQ(keep[0].size(), 10u);  // x = 5.0 .. 9.5
    // Two recordings of one visit keep each other's keyframes.
    const auto same = EarlierTargets({Walk(0, 0, 1, 5), Walk(0, 0.1, 1, 5)}, {0, 0}, 1.0);
    EXPECT_EQ(same[0].size(), 5u);
    EXPECT_EQ(same[1].size(), 5u);
    // Spacing 0: every keyframe of every visit.
    EXPECT_EQ(EarlierTargets(sessions, {0, 1, 2}, 0.0)[0].size(), 20u);
}

TEST(EarlierTargets, ASessionCutToItsTargetsKeepsTheirIdsAndTheEdgesBetweenThem) {
    AnchorSession s = Walk(0, 0, 1, 6);
    KeepKeyframes(&s, {1, 2, 4});
    ASSERT_EQ(s.keyframes(), 3u);
    EXPECT_EQ(s.KeyframeId(0), 1u);
    EXPECT_EQ(s.KeyframeId(2), 4u);
    EXPECT_DOUBLE_EQ(s.poses[2].translation().x(), 4.0);
    EXPECT_DOUBLE_EQ(s.path_m[1], 2.0);
    EXPECT_EQ(s.session.keyframes.size(), 3u);
    EXPECT_EQ(s.descriptors.size(), 3u);
    ASSERT_EQ(s.session.edges.size(), 1u);  // 1-2 only: 2-3 and 3-4 lost an end
    EXPECT_EQ(s.session.edges[0].from, 0u);
    EXPECT_EQ(s.session.edges[0].to, 1u);
    KeepKeyframes(&s, {0, 2});  // cut again: the folder's ids stay
    EXPECT_EQ(s.KeyframeId(1), 4u);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::anchor
