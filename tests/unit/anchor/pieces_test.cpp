// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// A session whose odometry failed in places, split for anchoring (host_tools/anchor/pieces.hpp,
// anchor_pieces.hpp): where the pieces end, what a piece holds, the verdict of a split session,
// the loops renumbered, the scans placed only from keyframes the odometry joins them to, and the
// verdict file as the odometry writes it (algorithms/odometry/trajectory_trust.hpp).
#include "host_tools/anchor/pieces.hpp"

#include <gtest/gtest.h>

#include "algorithms/common/status.hpp"
#include "algorithms/io/file_util.hpp"
#include "algorithms/odometry/lidar_odometry.hpp"
#include "algorithms/odometry/trajectory_trust.hpp"
#include "host_tools/anchor/anchor_output.hpp"
#include "host_tools/anchor/anchor_pieces.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::anchor {
namespace {
namespace BIMSLAM_UNITY_ID {

constexpr int64_t kSecond = 1'000'000'000;

OdometryStretch Stretch(double first_s, double last_s) {
    OdometryStretch s;
    s.first_ns = int64_t(first_s * kSecond);
    s.last_ns = int64_t(last_s * kSecond);
    s.first_scan = size_t(first_s * 10);
    s.last_scan = size_t(last_s * 10);
    s.first_s = first_s;
    s.last_s = last_s;
    s.failed = 1;
    return s;
}

// Keyframes at 0, 1, ..., n-1 s.
std::vector<int64_t> Seconds(size_t n) {
    std::vector<int64_t> t;
    for (size_t k = 0; k < n; ++k) t.push_back(int64_t(k) * kSecond);
    return t;
}

TEST(SplitAtStretches, NoStretchIsOnePiece) {
    const SessionSplit s = SplitAtStretches(Seconds(5), {});
    ASSERT_EQ(s.pieces.size(), 1u);
    EXPECT_EQ(s.pieces[0], (KeyframeSpan{0, 4}));
    EXPECT_TRUE(s.inside.empty());
}

TEST(SplitAtStretches, AStretchBetweenTwoKeyframesCutsTheEdgeBetweenThem) {
    // Scans 3.2-3.6 s failed: keyframes 3 and 4 stay, the odometry from 3 to 4 does not.
    const SessionSplit s = SplitAtStretches(Seconds(8), {Stretch(3.2, 3.6)});
    ASSERT_EQ(s.pieces.size(), 2u);
    EXPECT_EQ(s.pieces[0], (KeyframeSpan{0, 3}));
    EXPECT_EQ(s.pieces[1], (KeyframeSpan{4, 7}));
    EXPECT_TRUE(s.inside.empty());
}

TEST(SplitAtStretches, KeyframesInsideAStretchAreInNoPiece) {
    // 2.5-4.0 s: keyframes 3 and 4 (4.0 s, the stretch's last scan) are inside.
    const SessionSplit s = SplitAtStretches(Seconds(8), {Stretch(2.5, 4.0)});
    ASSERT_EQ(s.pieces.size(), 2u);
    EXPECT_EQ(s.pieces[0], (KeyframeSpan{0, 2}));
    EXPECT_EQ(s.pieces[1], (KeyframeSpan{5, 7}));
    EXPECT_EQ(s.inside, (std::vector<size_t>{3, 4}));
}

TEST(SplitAtStretches, StretchesAtBothEndsAndTwoInTheMiddle) {
    const SessionSplit s = SplitAtStretches(
        Seconds(10), {Stretch(0.0, 0.5), Stretch(3.1, 3.2), Stretch(3.5, 3.9), Stretch(8.5, 9.5)});
    // Keyframe 0 inside; 1-3; 4-8; keyframe 9 inside.
    ASSERT_EQ(s.pieces.size(), 2u);
    EXPECT_EQ(s.pieces[0], (KeyframeSpan{1, 3}));
    EXPECT_EQ(s.pieces[1], (KeyframeSpan{4, 8}));
    EXPECT_EQ(s.inside, (std::vector<size_t>{0, 9}));
}

TEST(SplitAtStretches, AKeyframeAloneBetweenTwoStretchesIsAPieceOfOne) {
    const SessionSplit s = SplitAtStretches(Seconds(5), {Stretch(1.5, 1.6), Stretch(2.4, 2.6)});
    ASSERT_EQ(s.pieces.size(), 3u);
    EXPECT_EQ(s.pieces[1], (KeyframeSpan{2, 2}));
    EXPECT_EQ(s.pieces[1].size(), 1u);
}

TEST(SplitAtStretches, EveryKeyframeInsideLeavesNoPiece) {
    const SessionSplit s = SplitAtStretches(Seconds(3), {Stretch(0, 10)});
    EXPECT_TRUE(s.pieces.empty());
    EXPECT_EQ(s.inside.size(), 3u);
}

// A session of n keyframes 1 m apart along x at 0, 1, ... s, with an odometry edge between
// consecutive keyframes and one loop edge 0 -> n-1, and scans every 0.25 s.
AnchorSession Line(size_t n) {
    AnchorSession s;
    s.name = "walk";
    for (size_t k = 0; k < n; ++k) {
        io::SessionKeyframe kf;
        kf.stamp_ns = int64_t(k) * kSecond;
        kf.T_world_lidar = Eigen::Translation3d(double(k), 0, 0) * Eigen::Isometry3d::Identity();
        s.session.keyframes.push_back(kf);
        s.poses.push_back(kf.T_world_lidar);
        s.path_m.push_back(double(k));
        s.descriptors.push_back(scancontext::Descriptor{});
        s.clouds.emplace_back();
        s.clouds.back().points.assign(k + 1, Eigen::Vector3f::Zero());  // told apart by size
        if (k > 0) s.session.edges.push_back({uint32_t(k - 1), uint32_t(k), {}, {}});
    }
    s.session.edges.push_back({0, uint32_t(n - 1), {}, {}});
    for (int64_t t = 0; t <= int64_t(n - 1) * kSecond; t += kSecond / 4) {
        s.session.trajectory.push_back(io::StampedPose::FromIsometry(
            t, Eigen::Translation3d(double(t) / kSecond, 0, 0) * Eigen::Isometry3d::Identity()));
    }
    return s;
}

TEST(MakePiece, HoldsItsKeyframesTheEdgesWithinAndItsScans) {
    const AnchorSession s = Line(8);
    const AnchorSession p = MakePiece(s, {3, 5});
    EXPECT_EQ(p.name, "walk[3-5]");
    ASSERT_EQ(p.keyframes(), 3u);
    EXPECT_DOUBLE_EQ(p.poses[0].translation().x(), 3.0);
    EXPECT_EQ(p.session.keyframes[2].stamp_ns, 5 * kSecond);
    EXPECT_EQ(p.clouds[0].size(), 4u);
    EXPECT_EQ(p.descriptors.size(), 3u);
    EXPECT_EQ(p.path_m, (std::vector<double>{0, 1, 2}));
    // 3->4 and 4->5 renumbered; 2->3, 5->6 and the loop 0->7 reach outside.
    ASSERT_EQ(p.session.edges.size(), 2u);
    EXPECT_EQ(p.session.edges[0].from, 0u);
    EXPECT_EQ(p.session.edges[0].to, 1u);
    EXPECT_EQ(p.session.edges[1].to, 2u);
    ASSERT_EQ(p.session.trajectory.size(), 9u);  // 3.00 ... 5.00 s
    EXPECT_EQ(p.session.trajectory.front().stamp_ns, 3 * kSecond);
    EXPECT_EQ(p.session.trajectory.back().stamp_ns, 5 * kSecond);
}

TEST(CombinePieces, NeverAnchoredWhole) {
    using V = Verdict;
    EXPECT_EQ(CombinePieces({V::kAnchored, V::kAnchored}), V::kAnchoredInParts);
    EXPECT_EQ(CombinePieces({V::kFailed, V::kAnchored, V::kAmbiguous}), V::kAnchoredInParts);
    EXPECT_EQ(CombinePieces({V::kFailed, V::kAmbiguous}), V::kAmbiguous);
    EXPECT_EQ(CombinePieces({V::kFailed}), V::kFailed);
    EXPECT_EQ(CombinePieces({}), V::kFailed);
    EXPECT_LT(Severity(V::kAnchored), Severity(V::kAnchoredInParts));
    EXPECT_LT(Severity(V::kAnchoredInParts), Severity(V::kAmbiguous));
    EXPECT_LT(Severity(V::kAmbiguous), Severity(V::kFailed));
    EXPECT_EQ(ToString(V::kAnchoredInParts), "anchored-in-parts");
}

// The walk's start hint (--near) goes to every piece, widened by the way from the start to the
// piece's first keyframe (Line: a metre a keyframe), the first keyframes taken by a failed
// stretch or not.
TEST(SplitAtUntrustedOdometry, EveryPieceKeepsTheStartHintWidenedByTheWayToIt) {
    std::vector<AnchorSession> sessions{Line(3), Line(10)};
    sessions[1].start = StartHint{{0.5, 0.0}, 3.0};
    sessions[1].odometry.verdict = "untrusted";
    sessions[1].odometry.stretches = {Stretch(0.0, 1.5), Stretch(5.5, 6.5)};
    const SplitQueries parts = SplitAtUntrustedOdometry(sessions);
    ASSERT_EQ(parts.sessions.size(), 3u);  // the reference, keyframes 2-5, keyframes 7-9
    EXPECT_EQ(parts.origin[1].span, (KeyframeSpan{2, 5}));
    ASSERT_TRUE(parts.sessions[1].start.has_value());
    EXPECT_DOUBLE_EQ(parts.sessions[1].start->radius_m, 5.0);  // 3 m and the 2 m to keyframe 2
    EXPECT_EQ(parts.sessions[1].start->xy, Eigen::Vector2d(0.5, 0.0));
    ASSERT_TRUE(parts.sessions[2].start.has_value());
    EXPECT_DOUBLE_EQ(parts.sessions[2].start->radius_m, 10.0);  // and the 7 m to keyframe 7
    sessions[1].start.reset();
    EXPECT_FALSE(SplitAtUntrustedOdometry(sessions).sessions[1].start.has_value());
}

TEST(MergePieces, ASplitSessionGetsItsPiecesVerdictsPosesAndLoopsInItsOwnNumbers) {
    std::vector<AnchorSession> sessions{Line(3), Line(8)};
    sessions[0].name = "reference";
    sessions[1].odometry.verdict = "untrusted";
    sessions[1].odometry.stretches = {Stretch(2.5, 4.0)};
    const SplitQueries parts = SplitAtUntrustedOdometry(sessions);
    ASSERT_EQ(parts.sessions.size(), 3u);  // the reference, keyframes 0-2, keyframes 5-7
    EXPECT_EQ(parts.sessions[2].name, "walk[5-7]");
    EXPECT_EQ(parts.origin[2].session, 1u);
    EXPECT_EQ(parts.origin[2].span, (KeyframeSpan{5, 7}));

    // As the anchoring would return it: the first piece failed, the second anchored 10 m up.
    AnchorResult r;
    SessionResult failed;
    failed.verdict = Verdict::kFailed;
    failed.reason = "no hypothesis";
    failed.keyframes = 3;
    failed.candidates = 4;
    SessionResult good;
    good.verdict = Verdict::kAnchored;
    good.keyframes = 3;
    good.candidates = 6;
    good.accepted_loops = 5;
    good.covered = 3;
    for (size_t k = 0; k < 3; ++k)
        good.world_poses.push_back(Eigen::Translation3d(0, 0, 10) * parts.sessions[2].poses[k]);
    r.sessions = {failed, good};
    LoopRecord loop;
    loop.query_session = 2;
    loop.query_index = 1;
    loop.target_session = 0;
    loop.target_index = 2;
    LoopRecord between = loop;  // from the second piece to the first
    between.target_session = 1;
    between.target_index = 2;
    r.loops = {loop, between};

    const AnchorResult m = MergePieces(sessions, parts, r);
    ASSERT_EQ(m.sessions.size(), 1u);
    const SessionResult& s = m.sessions[0];
    EXPECT_EQ(s.verdict, Verdict::kAnchoredInParts);
    EXPECT_EQ(s.name, "walk");
    EXPECT_EQ(s.keyframes, 8u);
    EXPECT_EQ(s.candidates, 10u);
    EXPECT_EQ(s.accepted_loops, 5u);
    ASSERT_EQ(s.pieces.size(), 2u);
    EXPECT_EQ(s.pieces[0].result.verdict, Verdict::kFailed);
    EXPECT_EQ(s.inside, (std::vector<size_t>{3, 4}));
    EXPECT_EQ(s.placed, (std::vector<bool>{false, false, false, false, false, true, true, true}));
    EXPECT_DOUBLE_EQ(s.world_poses[6].translation().z(), 10.0);
    EXPECT_DOUBLE_EQ(s.world_poses[6].translation().x(), 6.0);
    for (const char* said : {"untrusted", "scans 25-40 (2.5-4.0 s)", "keyframes 0-2 failed",
                             "keyframes 5-7 anchored", "3 of 8 keyframes anchored"}) {
        EXPECT_NE(s.reason.find(said), std::string::npos) << said << " in: " << s.reason;
    }
    ASSERT_EQ(m.loops.size(), 2u);
    EXPECT_EQ(m.loops[0].query_session, 1u);
    EXPECT_EQ(m.loops[0].query_index, 6u);
    EXPECT_EQ(m.loops[0].target_session, 0u);
    EXPECT_EQ(m.loops[0].target_index, 2u);
    EXPECT_EQ(m.loops[1].target_session, 1u);
    EXPECT_EQ(m.loops[1].target_index, 2u);
}

TEST(MergePieces, ASessionWithTrustedOdometryKeepsItsResult) {
    std::vector<AnchorSession> sessions{Line(3), Line(4)};
    sessions[1].odometry.verdict = "trusted";
    const SplitQueries parts = SplitAtUntrustedOdometry(sessions);
    ASSERT_EQ(parts.sessions.size(), 2u);
    AnchorResult r;
    r.sessions.resize(1);
    r.sessions[0].verdict = Verdict::kAnchored;
    r.sessions[0].keyframes = 4;
    r.sessions[0].reason = "as it was";
    const AnchorResult m = MergePieces(sessions, parts, r);
    EXPECT_EQ(m.sessions[0].verdict, Verdict::kAnchored);
    EXPECT_EQ(m.sessions[0].reason, "as it was");
    EXPECT_TRUE(m.sessions[0].pieces.empty());
    EXPECT_EQ(m.sessions[0].placed, std::vector<bool>(4, true));
}

TEST(WorldTrajectory, ScansArePlacedOnlyFromKeyframesTheOdometryJoinsThemTo) {
    AnchorSession s = Line(6);
    s.odometry.verdict = "untrusted";
    s.odometry.stretches = {Stretch(2.4, 2.6)};
    // Pieces 0-2 (moved 1 m in y) and 3-5 (moved 2 m in y); keyframe 5 not placed.
    std::vector<Eigen::Isometry3d> world;
    for (size_t k = 0; k < 6; ++k)
        world.push_back(Eigen::Translation3d(0, k < 3 ? 1.0 : 2.0, 0) * s.poses[k]);
    const std::vector<bool> placed{true, true, true, true, true, false};
    const std::vector<io::StampedPose> t = WorldTrajectory(s, world, placed);
    std::map<int64_t, double> y;
    for (const io::StampedPose& p : t) y[p.stamp_ns] = p.translation.y();
    EXPECT_DOUBLE_EQ(y.at(2 * kSecond + kSecond / 4), 1.0) << "2.25 s: keyframe 2's side";
    EXPECT_FALSE(y.count(2 * kSecond + kSecond / 2)) << "2.5 s lies inside the stretch";
    EXPECT_DOUBLE_EQ(y.at(2 * kSecond + 3 * kSecond / 4), 2.0) << "2.75 s: keyframe 3's side";
    EXPECT_DOUBLE_EQ(y.at(4 * kSecond), 2.0);
    // After keyframe 4 only keyframe 4 is placed: its correction, not keyframe 5's.
    EXPECT_DOUBLE_EQ(y.at(4 * kSecond + kSecond / 2), 2.0);
    // Without a stretch and with every keyframe placed: the plain interpolation.
    s.odometry = {};
    const auto plain = WorldTrajectory(s, world, std::vector<bool>(6, true));
    const auto same = WorldTrajectory(s, world);
    ASSERT_EQ(plain.size(), same.size());
    for (size_t k = 0; k < plain.size(); ++k) EXPECT_EQ(plain[k].translation, same[k].translation);
}

TEST(OdometryVerdictFile, WrittenByTheOdometryReadByTheAnchoring) {
    odometry::TrajectoryTrust trust(/*merge_gap=*/3);
    for (size_t scan = 0; scan < 60; ++scan) {
        const bool failed = scan == 20 || scan == 22 || scan == 50;
        const uint32_t ambiguous = scan == 45 ? uint32_t(odometry::kHeightAmbiguous) : 0u;
        trust.Add(scan, 0.1 * double(scan),
                  (failed ? uint32_t(odometry::kCheckFailed) : 0u) | ambiguous,
                  failed ? uint32_t(odometry::kLowOverlap) : 0u,
                  1000 * kSecond + int64_t(scan) * kSecond / 10);
    }
    test::TempDir tmp;
    // A session of scans 0-39 holds the first stretch only.
    io::WriteFileAtomic(tmp / kOdometryVerdictFile, trust.SessionJson(0, 39).dump());
    const OdometryVerdict v = ReadOdometryVerdict(tmp.path());
    EXPECT_EQ(v.verdict, "untrusted");
    ASSERT_EQ(v.stretches.size(), 1u);
    EXPECT_EQ(v.stretches[0].first_scan, 20u);
    EXPECT_EQ(v.stretches[0].last_scan, 22u);
    EXPECT_EQ(v.stretches[0].first_ns, 1002 * kSecond);
    EXPECT_EQ(v.stretches[0].last_ns, 1000 * kSecond + 22 * kSecond / 10);
    EXPECT_EQ(v.stretches[0].failed, 2u);
    EXPECT_EQ(v.stretches[0].Describe(), "scans 20-22 (2.0-2.2 s: low overlap with the map)");
    EXPECT_TRUE(v.height_ambiguous.empty());
    // Scans 40-59: trusted until scan 50; a session of scans 23-49 is trusted, its height
    // seen again while uncertain at scan 45 (the relocaliser reads it: bimslam localize).
    io::WriteFileAtomic(tmp / kOdometryVerdictFile, trust.SessionJson(23, 49).dump());
    const OdometryVerdict later = ReadOdometryVerdict(tmp.path());
    EXPECT_EQ(later.verdict, "trusted");
    EXPECT_TRUE(later.stretches.empty());
    ASSERT_EQ(later.height_ambiguous.size(), 1u);
    EXPECT_EQ(later.height_ambiguous[0].first_scan, 45u);
    EXPECT_EQ(later.height_ambiguous[0].first_ns, 1000 * kSecond + 45 * kSecond / 10);
}

TEST(OdometryVerdictFile, NoneIsNotJudgedAndABadOneNamesTheFile) {
    test::TempDir tmp;
    EXPECT_EQ(ReadOdometryVerdict(tmp.path()).verdict, "");
    for (const char* bad :
         {"{\"verdict\": \"untrusted\", \"failed_stretches\": []}",
          "{\"verdict\": \"maybe\", \"failed_stretches\": []}",
          "{\"verdict\": \"untrusted\", \"failed_stretches\": [{\"first_scan\": 5}]}",
          "{\"verdict\": \"untrusted\", \"failed_stretches\": [{\"first_scan\": 5, \"last_scan\": "
          "6, \"first_s\": 1, \"last_s\": 2, \"first_stamp_ns\": 9, \"last_stamp_ns\": 8}]}",
          "{\"verdict\": \"trusted\", \"failed_stretches\": [], \"height_ambiguous_stretches\": "
          "[{\"first_scan\": 5}]}",
          "not json"}) {
        io::WriteFileAtomic(tmp / kOdometryVerdictFile, bad);
        try {
            ReadOdometryVerdict(tmp.path());
            ADD_FAILURE() << "accepted: " << bad;
        } catch (const common::FileError& e) {
            EXPECT_NE(std::string(e.what()).find(kOdometryVerdictFile), std::string::npos)
                << e.what();
        }
    }
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::anchor
