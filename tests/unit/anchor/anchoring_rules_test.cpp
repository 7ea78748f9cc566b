// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Anchoring's rules on small hand-built inputs whose answer is known (host_tools/anchor/README.md,
// "The method"): the anchor a loop implies, the pairwise consistency of two loops (0.15 m / 2 deg
// plus 3 % / 0.15 deg per metre travelled between them), the cliques of consistent loops, the
// verdict's thresholds (anchored, ambiguous, failed) and the free-space check that contradicts a
// wrong placement.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "algorithms/common/se3.hpp"
#include "algorithms/registration/free_space.hpp"
#include "algorithms/registration/surfel_map.hpp"
#include "host_tools/anchor/anchoring.hpp"
#include "host_tools/anchor/place_recognition.hpp"

namespace bimslam::anchor {
namespace {
namespace BIMSLAM_UNITY_ID {

Eigen::Isometry3d Pose(double x, double y, double z, double yaw_deg) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(x, y, z);
    T.linear() = Eigen::AngleAxisd(yaw_deg * M_PI / 180, Eigen::Vector3d::UnitZ()).matrix();
    return T;
}

// A query walked 1 m a keyframe along x, turning 3 degrees a keyframe, in its own frame; the
// reference (session 0) has no keyframes of its own here.
std::vector<AnchorSession> Walk(size_t keyframes) {
    std::vector<AnchorSession> sessions(2);
    AnchorSession& q = sessions[1];
    for (size_t k = 0; k < keyframes; ++k) {
        q.poses.push_back(Pose(double(k), 0.1 * double(k), 0, 3.0 * double(k)));
        q.path_m.push_back(
            k == 0 ? 0.0
                   : q.path_m.back() +
                         (q.poses[k].translation() - q.poses[k - 1].translation()).norm());
    }
    return sessions;
}

// The default configuration, made once (GCC 12 at -O1 warns, wrongly, of an uninitialised
// registration level when the unity build inlines several default-constructed configurations).
const AnchorConfig& Defaults() {
    static const AnchorConfig config;
    return config;
}

// The anchor the tests place the walk with: far off and turned, as from outside the building.
const Eigen::Isometry3d kAnchor = Pose(103.0, -41.0, 3.2, 170.0);

// The loop of query keyframe k, registered at T_world_query.
LoopRecord Loop(size_t k, const Eigen::Isometry3d& T_world_query) {
    LoopRecord l;
    l.query_session = 1;
    l.query_index = k;
    l.registration.T_target_source = T_world_query;
    return l;
}

// The loop of keyframe k registered where the anchor puts it, then moved by `error` (applied in
// the keyframe's frame: E = predicted^-1 * registered, as Consistent measures it).
LoopRecord TrueLoop(const std::vector<AnchorSession>& s, size_t k,
                    const Eigen::Isometry3d& error = Eigen::Isometry3d::Identity()) {
    return Loop(k, kAnchor * s[1].poses[k] * error);
}

TEST(ImpliedAnchor, IsTheRegisteredPoseTimesTheInverseOfTheKeyframesPose) {
    const auto s = Walk(10);
    for (size_t k : {0u, 4u, 9u}) {
        const Eigen::Isometry3d a = ImpliedAnchor(TrueLoop(s, k), s);
        EXPECT_TRUE(a.isApprox(kAnchor, 1e-12)) << k << "\n" << a.matrix();
    }
    // A registration 0.2 m off along the keyframe's x moves the anchor by that much at the
    // keyframe: the implied anchor places the keyframe where the registration did.
    const Eigen::Isometry3d off = Pose(0.2, 0, 0, 0);
    const Eigen::Isometry3d a = ImpliedAnchor(TrueLoop(s, 5, off), s);
    EXPECT_TRUE((a * s[1].poses[5]).isApprox(kAnchor * s[1].poses[5] * off, 1e-12));
}

TEST(Consistent, TwoTrueLoopsAgree) {
    const auto s = Walk(20);
    const AnchorConfig& config = Defaults();
    EXPECT_TRUE(Consistent(TrueLoop(s, 2), TrueLoop(s, 17), s, config));
    EXPECT_TRUE(Consistent(TrueLoop(s, 17), TrueLoop(s, 2), s, config));
}

TEST(Consistent, WithinFifteenCentimetresAndTwoDegreesAtTheSameKeyframe) {
    // The same keyframe (no distance travelled): the bounds are consistency_m and _deg alone.
    const auto s = Walk(20);
    const AnchorConfig& config = Defaults();
    ASSERT_EQ(config.consistency_m, 0.15);
    ASSERT_EQ(config.consistency_deg, 2.0);
    const LoopRecord a = TrueLoop(s, 6);
    EXPECT_TRUE(Consistent(a, TrueLoop(s, 6, Pose(0.14, 0, 0, 0)), s, config));
    EXPECT_FALSE(Consistent(a, TrueLoop(s, 6, Pose(0.16, 0, 0, 0)), s, config));
    EXPECT_TRUE(Consistent(a, TrueLoop(s, 6, Pose(0, 0, -0.14, 0)), s, config));
    EXPECT_FALSE(Consistent(a, TrueLoop(s, 6, Pose(0, 0.11, 0.11, 0)), s, config));  // 0.156 m
    EXPECT_TRUE(Consistent(a, TrueLoop(s, 6, Pose(0, 0, 0, 1.9)), s, config));
    EXPECT_FALSE(Consistent(a, TrueLoop(s, 6, Pose(0, 0, 0, 2.1)), s, config));
}

TEST(Consistent, ALoopAWallsThicknessOffDisagreesWithItsNeighbour) {
    // Duplex_A's Go1 walk (seed 1): loops of neighbouring keyframes (here 1 m apart), one
    // registered 0.31 m off along y. Under the old 0.3 m floor the pair was consistent (0.31 <=
    // 0.3 + 0.03 x 1), wrong loops joined the clique, and the walk's end was anchored 31 cm off
    // (host_tools/anchor/README.md, "Two registration basins").
    const auto s = Walk(20);
    const AnchorConfig& config = Defaults();
    EXPECT_FALSE(Consistent(TrueLoop(s, 6), TrueLoop(s, 7, Pose(0, -0.31, 0, 0)), s, config));
    EXPECT_FALSE(Consistent(TrueLoop(s, 7, Pose(0, -0.31, 0, 0)), TrueLoop(s, 6), s, config));
}

TEST(Consistent, TheBoundsGrowThreePercentAndAFifteenthOfADegreePerMetre) {
    // Keyframes 0 and 10 of the walk: d metres apart along the path (1.005 m a step).
    const auto s = Walk(20);
    const AnchorConfig& config = Defaults();
    const double d = s[1].path_m[10] - s[1].path_m[0];
    ASSERT_NEAR(d, 10.05, 0.01);
    const double max_m = 0.15 + 0.03 * d;   // 0.45 m
    const double max_deg = 2.0 + 0.15 * d;  // 3.51 deg
    const LoopRecord a = TrueLoop(s, 0);
    EXPECT_TRUE(Consistent(a, TrueLoop(s, 10, Pose(max_m - 0.01, 0, 0, 0)), s, config));
    EXPECT_FALSE(Consistent(a, TrueLoop(s, 10, Pose(max_m + 0.01, 0, 0, 0)), s, config));
    EXPECT_TRUE(Consistent(a, TrueLoop(s, 10, Pose(0, 0, 0, max_deg - 0.05)), s, config));
    EXPECT_FALSE(Consistent(a, TrueLoop(s, 10, Pose(0, 0, 0, max_deg + 0.05)), s, config));
    // The same error at the same keyframe is too much without the distance.
    EXPECT_FALSE(Consistent(TrueLoop(s, 10), TrueLoop(s, 10, Pose(0.4, 0, 0, 0)), s, config));
}

TEST(Consistent, AWrongPlaceIsNotConsistentWithTheRightOne) {
    // A loop registered in the mirror image of the building (anchor turned 180 degrees about a
    // point 10 m away): each loop alone fits, together they disagree.
    const auto s = Walk(20);
    const AnchorConfig& config = Defaults();
    const Eigen::Isometry3d mirror = Pose(10, 0, 0, 180) * kAnchor;
    const LoopRecord wrong = Loop(12, mirror * s[1].poses[12]);
    EXPECT_FALSE(Consistent(TrueLoop(s, 3), wrong, s, config));
    EXPECT_FALSE(Consistent(wrong, TrueLoop(s, 3), s, config));
}

Hypothesis Hyp(size_t covered, size_t loops, const Eigen::Isometry3d& anchor = kAnchor,
               double seen_through = 0.01) {
    Hypothesis h;
    h.covered = covered;
    h.loops = loops;
    h.anchor = anchor;
    h.seen_through = seen_through;
    return h;
}

// RankHypotheses then DecideVerdict, as AnchorQuery runs them; *reason gets the reason.
Verdict Decide(std::vector<Hypothesis> hs, size_t keyframes, std::string* reason = nullptr,
               const std::optional<StartHint>& start = std::nullopt) {
    const AnchorConfig& config = Defaults();
    const auto s = Walk(keyframes);
    const std::vector<size_t> order = RankHypotheses(hs, s[1].poses, config, start);
    std::vector<Hypothesis> ranked;
    for (size_t i : order) ranked.push_back(hs[i]);
    std::string why;
    const Verdict v = DecideVerdict(ranked, s[1].poses, config, &why, start);
    if (reason) *reason = why;
    return v;
}

// Loops of keyframes `ks` placed by `anchor` (each at its keyframe), seeing through the model
// with `seen` of their rays, appended to `records`.
void AddLoops(const std::vector<AnchorSession>& s, const Eigen::Isometry3d& anchor,
              const std::vector<size_t>& ks, double seen, std::vector<LoopRecord>* records) {
    for (size_t k : ks) {
        LoopRecord l = Loop(k, anchor * s[1].poses[k]);
        l.seen_through = seen;
        records->push_back(l);
    }
}

TEST(ConsistentHypotheses, CliquesSeenThroughTheModelArePassedOverForASmallerRightOne) {
    // A walk from outside: two wrong places agree with 5 and 4 loops each (the storey above, 3 m
    // up; 4 m along x), both seeing through the model's surfaces (20 % and 9 % of their rays);
    // the right place has 3 loops (1 % seen through). Searched as before, the three hypotheses
    // would be the two wrong ones and nothing else; now the right one is found and followed.
    const auto s = Walk(40);
    std::vector<LoopRecord> records;
    AddLoops(s, Pose(0, 0, 3, 0) * kAnchor, {10, 12, 14, 16, 18}, 0.20, &records);
    AddLoops(s, Pose(4, 0, 0, 0) * kAnchor, {20, 22, 24, 26}, 0.09, &records);
    AddLoops(s, kAnchor, {5, 30, 36}, 0.01, &records);
    std::vector<size_t> all(records.size());
    for (size_t i = 0; i < all.size(); ++i) all[i] = i;
    AnchorConfig config = Defaults();
    ASSERT_EQ(config.min_clique, 3);
    std::vector<std::vector<size_t>> passed_over;
    const auto cliques = ConsistentHypotheses(records, all, s, config, &passed_over);
    ASSERT_EQ(cliques.size(), 1u);
    EXPECT_EQ(cliques[0], (std::vector<size_t>{9, 10, 11}));
    ASSERT_EQ(passed_over.size(), 2u);  // said in the loops' reasons and the verdict's
    EXPECT_EQ(passed_over[0], (std::vector<size_t>{0, 1, 2, 3, 4}));
    EXPECT_EQ(passed_over[1], (std::vector<size_t>{5, 6, 7, 8}));
    // Seen through less than 5 %, the wrong places are hypotheses as well, largest first (step
    // 4's free-space check on the whole walk judges them).
    for (size_t i = 0; i < 9; ++i) records[i].seen_through = 0.04;
    const auto all_three = ConsistentHypotheses(records, all, s, config);
    ASSERT_EQ(all_three.size(), 3u);
    EXPECT_EQ(all_three[0].size(), 5u);
    EXPECT_EQ(all_three[2], (std::vector<size_t>{9, 10, 11}));
    // The search is bounded: with a single clique searched, the wrong one is passed over and
    // nothing is left.
    for (size_t i = 0; i < 9; ++i) records[i].seen_through = 0.2;
    config.max_hypotheses = 1;
    config.max_cliques = 1;
    EXPECT_TRUE(ConsistentHypotheses(records, all, s, config).empty());
}

TEST(ConsistentHypotheses, ACliqueSeeingThroughOneRemovedWallIsFollowed) {
    // Duplex_A's third visit, told where it starts: the right clique's loops see through the
    // partition that was demolished (18 % of 300 rays each, on one plane patch x = 2.5, the rays
    // ending on the model beyond). Explained by a removed element, the clique is followed; the
    // same share spread over surfaces far apart, or ending where the model has nothing, is passed
    // over.
    auto s = Walk(40);
    s[1].start = StartHint{(kAnchor * s[1].poses.front()).translation().head<2>(), 3.0};
    const auto loops_seeing = [&](bool one_wall, bool on_model) {
        std::vector<LoopRecord> records;
        AddLoops(s, kAnchor, {5, 10, 15, 20, 25}, 0.18, &records);
        for (size_t i = 0; i < records.size(); ++i) {
            registration::FreeSpaceResult& f = records[i].free_space;
            f.rays = 300;
            f.seen_through = 54;
            for (int k = 0; k < 54; ++k) {
                const Eigen::Vector3f at =
                    one_wall
                        ? Eigen::Vector3f(2.5f, -3.5f + 0.05f * float(k), 1.0f + 0.02f * float(i))
                        : Eigen::Vector3f(3.0f * float(k), 2.0f * float(i), 1.0f);
                f.crossings.push_back({at, Eigen::Vector3f(1, 0, 0), on_model});
            }
        }
        return records;
    };
    const std::vector<size_t> all = {0, 1, 2, 3, 4};
    std::vector<std::vector<size_t>> passed_over;
    EXPECT_EQ(
        ConsistentHypotheses(loops_seeing(true, true), all, s, Defaults(), &passed_over).size(),
        1u);
    EXPECT_TRUE(passed_over.empty());
    EXPECT_TRUE(ConsistentHypotheses(loops_seeing(false, true), all, s, Defaults()).empty());
    EXPECT_TRUE(ConsistentHypotheses(loops_seeing(true, false), all, s, Defaults()).empty());
    // Not told where the walk starts: the rays count whole (RankHypotheses).
    s[1].start.reset();
    EXPECT_TRUE(ConsistentHypotheses(loops_seeing(true, true), all, s, Defaults()).empty());
}

TEST(Verdict, NoHypothesisFails) { EXPECT_EQ(Decide({}, 40), Verdict::kFailed); }

TEST(Verdict, AnchoredNeedsFiveLoopsOnTenPercentOfTheKeyframesAndAtLeastFive) {
    // 40 keyframes: 10 % is 4, so 5 keyframes (min_loops) are needed.
    EXPECT_EQ(Decide({Hyp(5, 5)}, 40), Verdict::kAnchored);
    EXPECT_EQ(Decide({Hyp(4, 5)}, 40), Verdict::kFailed);
    EXPECT_EQ(Decide({Hyp(5, 4)}, 40), Verdict::kFailed);
    // 200 keyframes: 10 % is 20.
    EXPECT_EQ(Decide({Hyp(20, 20)}, 200), Verdict::kAnchored);
    std::string why;
    EXPECT_EQ(Decide({Hyp(19, 30)}, 200, &why), Verdict::kFailed);
    EXPECT_NE(why.find("explains 19 of 200 keyframes"), std::string::npos) << why;
}

TEST(Verdict, ARivalWithEightyPercentOfTheKeyframesElsewhereIsAmbiguous) {
    const Eigen::Isometry3d elsewhere = Pose(1.5, 0, 0, 0) * kAnchor;  // 1.5 m off
    std::string why;
    EXPECT_EQ(Decide({Hyp(30, 30), Hyp(24, 24, elsewhere)}, 40, &why), Verdict::kAmbiguous);
    EXPECT_NE(why.find("30 and 24 keyframes"), std::string::npos) << why;
    // 23 of 30 is under 80 %: the best stands.
    EXPECT_EQ(Decide({Hyp(30, 30), Hyp(23, 23, elsewhere)}, 40), Verdict::kAnchored);
    // The order given does not matter: the one explaining more keyframes is the best.
    EXPECT_EQ(Decide({Hyp(23, 23, elsewhere), Hyp(30, 30)}, 40), Verdict::kAnchored);
}

TEST(Verdict, ARivalWithinOneMetreAndFiveDegreesIsTheSamePlacement) {
    // Shifted: every keyframe moves by as much.
    EXPECT_EQ(Decide({Hyp(30, 30), Hyp(30, 30, Pose(0.9, 0, 0, 0) * kAnchor)}, 40),
              Verdict::kAnchored);
    EXPECT_EQ(Decide({Hyp(30, 30), Hyp(30, 30, Pose(1.1, 0, 0, 0) * kAnchor)}, 40),
              Verdict::kAmbiguous);
    // Turned 4 degrees about the walk's start: within 5 degrees, but the 40 m walk's keyframes
    // move by more than 1 m on average.
    EXPECT_EQ(Decide({Hyp(30, 30), Hyp(30, 30, kAnchor * Pose(0, 0, 0, 4.0))}, 40),
              Verdict::kAmbiguous);
    // A 10 m walk turned about its middle: 4 degrees is the same placement, 6 is distinct by
    // its angle alone (its keyframes move by 0.3 m on average).
    const auto s = Walk(10);
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (const auto& p : s[1].poses) centre += p.translation() / double(s[1].poses.size());
    const auto about = [&](double deg) {
        return kAnchor * Eigen::Translation3d(centre) * Pose(0, 0, 0, deg) *
               Eigen::Translation3d(-centre);
    };
    EXPECT_EQ(Decide({Hyp(8, 8), Hyp(8, 8, about(4.0))}, 10), Verdict::kAnchored);
    EXPECT_EQ(Decide({Hyp(8, 8), Hyp(8, 8, about(6.0))}, 10), Verdict::kAmbiguous);
}

TEST(Verdict, AContradictedHypothesisRanksLastAndAloneFails) {
    // Free space above 5 %: contradicted however many keyframes it explains.
    std::string why;
    EXPECT_EQ(Decide({Hyp(30, 30, kAnchor, 0.083)}, 40, &why), Verdict::kFailed);
    EXPECT_NE(why.find("contradicted by free space"), std::string::npos) << why;
    EXPECT_NE(why.find("8.30 %"), std::string::npos) << why;
    EXPECT_EQ(Decide({Hyp(30, 30, kAnchor, 0.0501)}, 40), Verdict::kFailed);
    EXPECT_EQ(Decide({Hyp(30, 30, kAnchor, 0.05)}, 40), Verdict::kAnchored);
    // A right placement explaining fewer keyframes wins over a contradicted one, and it is
    // no rival.
    const Eigen::Isometry3d upstairs = Pose(0, 0, 3.5, 0) * kAnchor;
    EXPECT_EQ(Decide({Hyp(40, 40, upstairs, 0.083), Hyp(20, 20)}, 40), Verdict::kAnchored);
}

TEST(Verdict, AWrongStoreyUnderFivePercentIsOutweighedByFreeSpace) {
    // The handheld walk of README.md: both storeys explain the same keyframes; the wrong one
    // sees through 4.4 % of its rays, the right one 0.65 %.
    const Eigen::Isometry3d upstairs = Pose(0, 0, 3.5, 0) * kAnchor;
    EXPECT_EQ(Decide({Hyp(30, 30, upstairs, 0.044), Hyp(30, 30, kAnchor, 0.0065)}, 40),
              Verdict::kAnchored);
    // The same with alike evidence (a mirror-symmetric building): ambiguous.
    EXPECT_EQ(Decide({Hyp(30, 30, upstairs, 0.010), Hyp(30, 30, kAnchor, 0.011)}, 40),
              Verdict::kAmbiguous);
}

TEST(Verdict, AHintOfWhereTheWalkStartsSetsTheTwinPlacementAside) {
    // Duplex_A: two dwellings, one turned 180 degrees about a point 5 m away; a walk in one fits
    // both alike.
    const Eigen::Isometry3d twin = Pose(10, 0, 0, 180) * kAnchor;
    const std::vector<Hypothesis> both = {Hyp(30, 30, twin, 0.010), Hyp(30, 30, kAnchor, 0.011)};
    EXPECT_EQ(Decide(both, 40), Verdict::kAmbiguous);
    // Told where it starts (within 3 m of its true first keyframe): the twin is off the hint.
    const auto s = Walk(40);
    const Eigen::Vector2d start = (kAnchor * s[1].poses.front()).translation().head<2>();
    const StartHint near{start + Eigen::Vector2d(2.0, 1.0), 3.0};
    std::vector<Hypothesis> hs = both;
    const std::vector<size_t> order = RankHypotheses(hs, s[1].poses, Defaults(), near);
    EXPECT_TRUE(hs[0].off_hint);
    EXPECT_FALSE(hs[1].off_hint);
    EXPECT_EQ(order.front(), 1u);
    EXPECT_EQ(Decide(both, 40, nullptr, near), Verdict::kAnchored);
    // A hint that neither fits: failed, saying so (not the best of the two).
    std::string why;
    EXPECT_EQ(Decide(both, 40, &why, StartHint{start + Eigen::Vector2d(3.5, 0.0), 3.0}),
              Verdict::kFailed);
    EXPECT_NE(why.find("no hypothesis of 2 puts the walk's start within 3.0 m"), std::string::npos)
        << why;
}

TEST(RankHypotheses, MarksAndOrdersByEvidenceThenCoverage) {
    const AnchorConfig& config = Defaults();
    std::vector<Hypothesis> hs = {Hyp(40, 40, kAnchor, 0.09), Hyp(25, 25, kAnchor, 0.04),
                                  Hyp(24, 26, kAnchor, 0.005), Hyp(10, 10, kAnchor, 0.01)};
    const std::vector<size_t> order = RankHypotheses(hs, {}, config);
    EXPECT_TRUE(hs[0].contradicted);
    EXPECT_FALSE(hs[1].contradicted);
    EXPECT_TRUE(hs[1].outweighed);  // 24 >= 80 % of 25, and 0.5 % against 4 %
    EXPECT_FALSE(hs[2].outweighed);
    EXPECT_FALSE(hs[3].outweighed);  // 1 % against 0.5 %: not decisive
    EXPECT_EQ(order, (std::vector<size_t>{2, 3, 1, 0}));
}

TEST(RankHypotheses, APlacementThatFloatsPartOfTheWalkAStoreyOffIsOutweighedByTheWalksHeights) {
    // The sample office's walk up its stair and back (map_cli_test.cpp's two-storey fixture):
    // placed right, 121 of 121 keyframes explained and 0.27 % of rays through the model; placed
    // a storey up, 99 explained (over 80 %), 2.16 % through the model (free space undecided: 1.9
    // points, under the 2-point gap) and the 22 keyframes upstairs above every walk of the model.
    const Eigen::Isometry3d up = Pose(0, 0, 3.2, 0) * kAnchor;
    const auto storey_up = [&](size_t floating) {
        Hypothesis h = Hyp(99, 99, up, 0.0216);
        h.floating = floating;
        return h;
    };
    const Hypothesis right = Hyp(121, 121, kAnchor, 0.0027);
    std::vector<Hypothesis> hs = {storey_up(22), right};
    const std::vector<size_t> order = RankHypotheses(hs, Walk(121)[1].poses, Defaults());
    EXPECT_TRUE(hs[0].outweighed);
    EXPECT_TRUE(hs[0].outweighed_by_heights);
    EXPECT_FALSE(hs[1].outweighed);
    EXPECT_EQ(order.front(), 1u);
    EXPECT_EQ(Decide({right, storey_up(22)}, 121), Verdict::kAnchored);
    // Without the heights, as before: ambiguous.
    EXPECT_EQ(Decide({right, storey_up(0)}, 121), Verdict::kAmbiguous);
    // Under a tenth of the walk floating (12.1 keyframes) is no evidence.
    EXPECT_EQ(Decide({right, storey_up(12)}, 121), Verdict::kAmbiguous);
    EXPECT_EQ(Decide({right, storey_up(13)}, 121), Verdict::kAnchored);
    // Nor when the best floats a third as many itself (a walk where the model's walks did not go).
    Hypothesis floats_too = right;
    floats_too.floating = 8;
    EXPECT_EQ(Decide({floats_too, storey_up(22)}, 121), Verdict::kAmbiguous);
    floats_too.floating = 7;
    EXPECT_EQ(Decide({floats_too, storey_up(22)}, 121), Verdict::kAnchored);
}

TEST(RankHypotheses, WhatARemovedElementExplainsIsNoContradictionOfAPlacementTheHintVouchesFor) {
    // Duplex_A's third visit: its partition demolished, the right placement sees through it with
    // 16 % of its rays, 1 % through anything else.
    Hypothesis right = Hyp(40, 40, kAnchor, 0.16);
    right.removed_surfaces.resize(1);
    right.seen_through_unexplained = 0.01;
    const auto s = Walk(40);
    const Eigen::Vector2d start = (kAnchor * s[1].poses.front()).translation().head<2>();
    const StartHint near{start + Eigen::Vector2d(1.0, 0.5), 3.0};
    // Told where the walk starts, and the placement agrees: explained, not contradicted.
    std::vector<Hypothesis> alone = {right};
    RankHypotheses(alone, s[1].poses, Defaults(), near);
    EXPECT_FALSE(alone[0].contradicted);
    EXPECT_EQ(Decide({right}, 40, nullptr, near), Verdict::kAnchored);
    // Not told: the sample office's ground floor on its first floor looks the same (one extra
    // partition seen through). Contradicted, and the reason says what would accept it.
    std::string why;
    EXPECT_EQ(Decide({right}, 40, &why), Verdict::kFailed);
    EXPECT_NE(why.find("if removed, would explain"), std::string::npos) << why;
    EXPECT_NE(why.find("--near"), std::string::npos) << why;
    // Without the explanation the hint does not help.
    EXPECT_EQ(Decide({Hyp(40, 40, kAnchor, 0.16)}, 40, nullptr, near), Verdict::kFailed);
    // A rival that sees through nothing still outweighs it: the raw share is compared, so a
    // wrong placement that one surface explains never beats a clean one.
    std::vector<Hypothesis> hs = {right, Hyp(38, 38, Pose(0.5, 0, 0, 0) * kAnchor, 0.004)};
    const std::vector<size_t> order = RankHypotheses(hs, s[1].poses, Defaults(), near);
    EXPECT_TRUE(hs[0].outweighed);
    EXPECT_EQ(order.front(), 1u);
}

// CheckFreeSpace on a hand-built map: one wall of surfels across x = 2.2 (inside its 0.5 m
// voxels), facing -x (a sensor at the origin sees it), and query points placed in front of it,
// behind it and just behind it.
registration::SurfelMap Wall(const Eigen::Vector3f& facing) {
    registration::OrientedCloud wall;
    for (float y = -3.0f; y <= 3.0f; y += 0.05f) {
        for (float z = -2.0f; z <= 2.0f; z += 0.05f) {
            wall.points.emplace_back(2.2f, y, z);
            wall.normals.push_back(facing);
        }
    }
    registration::SurfelMap map({.voxel_size = 0.5});
    map.Add(wall, Eigen::Isometry3d::Identity());
    map.Build();
    return map;
}

// A query cloud of points at x = `x` (its sensor at its origin), facing the sensor.
registration::OrientedCloud QueryAt(float x) {
    registration::OrientedCloud q;
    for (float y = -2.0f; y <= 2.0f; y += 0.1f) {
        for (float z = -1.0f; z <= 1.0f; z += 0.1f) {
            q.points.emplace_back(x, y, z);
            q.normals.emplace_back(-1.0f, 0.0f, 0.0f);
        }
    }
    return q;
}

TEST(CheckFreeSpace, PointsBehindAWallTheSensorFacesAreSeenThroughIt) {
    const registration::SurfelMap map = Wall({-1, 0, 0});
    ASSERT_GT(map.size(), 10u);
    const registration::FreeSpaceConfig config;
    const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
    const auto behind = registration::CheckFreeSpace(QueryAt(4.0f), map, I, config);
    EXPECT_GT(behind.rays, 100u);
    // Most: a ray that crosses the wall near a voxel's corner misses the surfel's patch (two
    // standard deviations about its centroid: a voxel's plane need not fill the voxel).
    EXPECT_GT(behind.ratio(), 0.8) << behind.seen_through << " of " << behind.rays;
    // In front of the wall: nothing crossed.
    const auto before = registration::CheckFreeSpace(QueryAt(1.5f), map, I, config);
    EXPECT_GT(before.rays, 100u);
    EXPECT_EQ(before.seen_through, 0u);
    // 0.2 m behind it: within the 0.3 m margin (the point is on the wall, give or take noise).
    const auto on = registration::CheckFreeSpace(QueryAt(2.4f), map, I, config);
    EXPECT_EQ(on.seen_through, 0u);
    // 0.5 m behind it: past the margin.
    const auto past = registration::CheckFreeSpace(QueryAt(2.7f), map, I, config);
    EXPECT_GT(past.ratio(), 0.8);
}

TEST(CheckFreeSpace, AWallFacingAwayIsNotSeenThrough) {
    // The wall's other face: a sensor at the origin looks at its back, which the map would
    // fit in another surfel had anyone seen it; crossing from behind is no evidence.
    const registration::SurfelMap map = Wall({1, 0, 0});
    const auto r = registration::CheckFreeSpace(QueryAt(4.0f), map, Eigen::Isometry3d::Identity(),
                                                registration::FreeSpaceConfig{});
    EXPECT_GT(r.rays, 0u);
    EXPECT_EQ(r.seen_through, 0u);
}

TEST(CheckFreeSpace, ThePlacementDecides) {
    // The same query: placed 3 m further along x, its sensor is behind the wall with its
    // points: nothing is seen through. Placed turned 180 degrees about z, its rays go the other
    // way and miss the wall.
    const registration::SurfelMap map = Wall({-1, 0, 0});
    const registration::FreeSpaceConfig config;
    const auto query = QueryAt(4.0f);
    EXPECT_GT(registration::CheckFreeSpace(query, map, Pose(0, 0, 0, 0), config).ratio(), 0.8);
    EXPECT_EQ(registration::CheckFreeSpace(query, map, Pose(3, 0, 0, 0), config).seen_through, 0u);
    EXPECT_EQ(registration::CheckFreeSpace(query, map, Pose(0, 0, 0, 180), config).seen_through,
              0u);
    // Points beyond max_range are not tested.
    registration::FreeSpaceConfig near = config;
    near.max_range = 3.0;
    EXPECT_EQ(registration::CheckFreeSpace(query, map, Pose(0, 0, 0, 0), near).rays, 0u);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::anchor
