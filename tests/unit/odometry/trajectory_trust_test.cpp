// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/odometry/trajectory_trust.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "algorithms/odometry/lidar_odometry.hpp"

namespace bimslam::odometry {
namespace {
namespace BIMSLAM_UNITY_ID {

TEST(TrajectoryTrust, ARunWithNoFailedScanIsTrusted) {
    TrajectoryTrust t;
    for (size_t i = 0; i < 100; ++i) t.Add(i, 0.1 * double(i), kDegenerate | kDeskewedAgain, 0);
    EXPECT_TRUE(t.trusted());
    EXPECT_EQ(t.Verdict(), "trusted");
    EXPECT_EQ(t.ToJson().at("failed_stretches").size(), 0u);
}

TEST(TrajectoryTrust, FailedScansGatherIntoStretchesWithTheirReasons) {
    TrajectoryTrust t(/*merge_gap=*/3);
    const auto add = [&](size_t i, uint32_t flags, uint32_t reasons) {
        t.Add(i, 0.5 * double(i), flags, reasons);
    };
    for (size_t i = 0; i < 40; ++i) {
        if (i == 10 || i == 13) {
            add(i, kCheckFailed, kFewInliers);  // 3 apart: one stretch
        } else if (i == 14) {
            add(i, kCheckFailed, kHighResidual);
        } else if (i == 30) {
            add(i, kRegistrationFailed | kTooFewPoints, 0);  // 16 later: a second stretch
        } else {
            add(i, 0, 0);
        }
    }
    EXPECT_FALSE(t.trusted());
    EXPECT_EQ(t.Verdict(), "untrusted");
    ASSERT_EQ(t.stretches().size(), 2u);
    const FailedStretch& a = t.stretches()[0];
    EXPECT_EQ(a.first_scan, 10u);
    EXPECT_EQ(a.last_scan, 14u);
    EXPECT_DOUBLE_EQ(a.first_s, 5.0);
    EXPECT_DOUBLE_EQ(a.last_s, 7.0);
    EXPECT_EQ(a.failed, 3u);
    EXPECT_EQ(a.check_reasons, uint32_t(kFewInliers | kHighResidual));
    EXPECT_FALSE(a.registration_failed);
    EXPECT_TRUE(t.stretches()[1].registration_failed);
    const nlohmann::json j = t.ToJson();
    EXPECT_EQ(j.at("verdict"), "untrusted");
    EXPECT_EQ(j.at("failed_stretches")[0].at("reasons"),
              nlohmann::json({"few inliers", "high residual"}));
    EXPECT_EQ(j.at("failed_stretches")[1].at("reasons"), nlohmann::json({"registration failed"}));
    const std::string text = t.Describe();
    EXPECT_NE(text.find("UNTRUSTED: 4 failed scans in 2 stretches"), std::string::npos) << text;
    EXPECT_NE(text.find("scans 10-14 (5.0-7.0 s"), std::string::npos) << text;
}

// Too few correspondences with the gyro or the legs behind the prediction is the designed
// fallback: counted as bridged, not untrusted; without them, or with a failed check, untrusted.
TEST(TrajectoryTrust, AFailedRegistrationBridgedByAMeasuredPriorIsCountedNotUntrusted) {
    TrajectoryTrust t;
    t.Add(5, 0.5, kRegistrationFailed | kImuUsed, 0);
    t.Add(6, 0.6, kRegistrationFailed | kBodyPriorUsed, 0);
    EXPECT_TRUE(t.trusted());
    EXPECT_EQ(t.bridged_by_prior(), 2u);
    EXPECT_EQ(t.ToJson().at("bridged_by_prior"), 2);
    EXPECT_NE(t.Describe().find("2 scans with too few correspondences kept the gyro's or the "
                                "legs' prediction"),
              std::string::npos)
        << t.Describe();
    t.Add(7, 0.7, kRegistrationFailed | kImuUsed | kCheckFailed, kLowOverlap);
    EXPECT_FALSE(t.trusted());
    TrajectoryTrust lidar_only;
    lidar_only.Add(3, 0.3, kRegistrationFailed, 0);
    EXPECT_FALSE(lidar_only.trusted());
    EXPECT_EQ(lidar_only.bridged_by_prior(), 0u);
}

// A scan the budget stopped before its registration began (kOverBudget with kRegistrationFailed,
// lidar_odometry.hpp) kept its prediction, and one whose check failed on a registration the
// deadline stopped (kCutShort) judged an unfinished one: bridged with the gyro or the legs,
// counted as cut by the budget; without them a failed stretch that says so. A check failed on a
// finished registration is never bridged, whatever else the budget cut in that scan.
TEST(TrajectoryTrust, AScanTheBudgetCutIsBridgedByAMeasuredPriorAndSaysSo) {
    TrajectoryTrust t;
    t.Add(5, 0.5, kRegistrationFailed | kOverBudget | kImuUsed | kBodyPriorUsed, 0);
    t.Add(6, 0.6, kRegistrationFailed | kImuUsed, 0);
    t.Add(7, 0.7, kOverBudget | kImuUsed, 0);  // cut after a registration: not failed
    t.Add(8, 0.8, kCheckFailed | kOverBudget | kCutShort | kImuUsed, kHighResidual);
    EXPECT_TRUE(t.trusted());
    EXPECT_EQ(t.bridged_by_prior(), 3u);
    EXPECT_EQ(t.bridged_over_budget(), 2u);
    EXPECT_EQ(t.ToJson().at("bridged_over_budget"), 2);
    EXPECT_NE(t.Describe().find("(2 of them cut by the budget)"), std::string::npos)
        << t.Describe();
    t.Add(9, 0.9, kCheckFailed | kOverBudget | kImuUsed, kLowOverlap);  // a deskew round cut
    EXPECT_FALSE(t.trusted());
    // More than kMaxBridgedCuts in a row: the prior's dead reckoning, a failed stretch.
    TrajectoryTrust run;
    for (size_t i = 20; i < 20 + TrajectoryTrust::kMaxBridgedCuts + 2; ++i) {
        run.Add(i, 0.1 * double(i), kRegistrationFailed | kOverBudget | kImuUsed, 0);
    }
    EXPECT_EQ(run.bridged_over_budget(), TrajectoryTrust::kMaxBridgedCuts);
    ASSERT_EQ(run.stretches().size(), 1u);
    EXPECT_EQ(run.stretches()[0].first_scan, 20 + TrajectoryTrust::kMaxBridgedCuts);
    EXPECT_EQ(run.stretches()[0].failed, 2u);
    TrajectoryTrust lidar_only;
    lidar_only.Add(3, 0.3, kRegistrationFailed | kOverBudget, 0);
    lidar_only.Add(4, 0.4, kCheckFailed | kOverBudget | kCutShort, kHighResidual);
    EXPECT_FALSE(lidar_only.trusted());
    ASSERT_EQ(lidar_only.stretches().size(), 1u);
    EXPECT_TRUE(lidar_only.stretches()[0].cut_by_budget);
    EXPECT_EQ(lidar_only.ToJson().at("failed_stretches")[0].at("reasons"),
              nlohmann::json({"registration failed", "cut by the budget", "high residual"}));
}

// The gyro alone (hand-held: no legs) turns the pose and keeps the velocity: it bridges
// kMaxGyroBridgedS in a row at most, then the scans are a failed stretch. The legs measure the
// motion and bridge any run; a scan registered between two runs starts a new one.
TEST(TrajectoryTrust, TheGyroAloneBridgesASecondInARowTheLegsAnyRun) {
    const auto t_s = [](size_t i) { return 0.125 * double(i); };  // 8 Hz, exact in binary
    TrajectoryTrust gyro;
    for (size_t i = 100; i < 125; ++i) gyro.Add(i, t_s(i), kRegistrationFailed | kImuUsed, 0);
    EXPECT_FALSE(gyro.trusted());
    EXPECT_EQ(gyro.bridged_by_prior(), 9u);  // 12.5 .. 13.5 s
    ASSERT_EQ(gyro.stretches().size(), 1u);
    EXPECT_EQ(gyro.stretches()[0].first_scan, 109u);
    EXPECT_EQ(gyro.stretches()[0].failed, 16u);
    TrajectoryTrust legs;
    for (size_t i = 100; i < 125; ++i)
        legs.Add(i, t_s(i), kRegistrationFailed | kImuUsed | kBodyPriorUsed, 0);
    EXPECT_TRUE(legs.trusted());
    EXPECT_EQ(legs.bridged_by_prior(), 25u);
    TrajectoryTrust apart;  // runs of 7 scans (0.75 s), a registered scan between them
    for (size_t i = 100; i < 132; ++i)
        apart.Add(i, t_s(i), i % 8 == 7 ? kImuUsed : kRegistrationFailed | kImuUsed, 0);
    EXPECT_TRUE(apart.trusted());
    EXPECT_EQ(apart.bridged_by_prior(), 28u);
}

// Scans blind to the height (with the IMU) leave it to the accelerometers' dead reckoning: a run
// longer than kMaxHeightUnseenS is said, with where it was; shorter runs, however many, are not.
// Neither untrusts the run: anchoring the whole walk measured better than in pieces there.
TEST(TrajectoryTrust, TheHeightUnseenForTooLongIsSaidWithWhere) {
    const double limit = TrajectoryTrust::kMaxHeightUnseenS;
    const auto walk = [](TrajectoryTrust* t, double unseen_s, int runs) {
        size_t scan = 0;
        const auto add = [&](uint32_t flags) {
            t->Add(scan, 0.1 * double(scan), flags | kImuUsed, 0, int64_t(scan) * 100000000);
            ++scan;
        };
        for (int r = 0; r < runs; ++r) {
            for (int k = 0; k < 30; ++k) add(0);
            for (int k = 0; k <= int(std::lround(unseen_s * 10)); ++k) add(kHeightUnseen);
        }
        for (int k = 0; k < 30; ++k) add(0);
    };
    TrajectoryTrust short_runs;
    walk(&short_runs, limit - 0.3, 5);
    EXPECT_TRUE(short_runs.height_unseen().empty());
    EXPECT_EQ(short_runs.Describe(), "trusted: every registration passed its checks");

    TrajectoryTrust long_runs;
    walk(&long_runs, limit + 1.0, 2);
    EXPECT_TRUE(long_runs.trusted());
    ASSERT_EQ(long_runs.height_unseen().size(), 2u);
    const FailedStretch& s = long_runs.height_unseen()[0];
    EXPECT_EQ(s.first_scan, 30u);  // from the run's first scan, not where it became too long
    EXPECT_EQ(s.last_scan, 30u + size_t(std::lround((limit + 1.0) * 10)));
    EXPECT_EQ(s.first_ns, 3000000000);
    EXPECT_NEAR(s.seconds, limit + 1.0, 1e-9);
    EXPECT_NE(long_runs.Describe().find("trusted: every registration passed its checks; the height "
                                        "not seen for over 2 s (the accelerometers' alone) at "
                                        "scans 30-60 (3.0-6.0 s), scans 91-121"),
              std::string::npos)
        << long_runs.Describe();
    EXPECT_EQ(long_runs.ToJson().at("height_unseen_stretches").size(), 2u);
    // The session's file carries the stretches within its scans; its verdict stays trusted.
    const nlohmann::json session = long_runs.SessionJson(0, 70);
    EXPECT_EQ(session.at("verdict"), "trusted");
    ASSERT_EQ(session.at("height_unseen_stretches").size(), 1u);
    EXPECT_EQ(session.at("height_unseen_stretches")[0].at("first_stamp_ns"), 3000000000);
    EXPECT_DOUBLE_EQ(session.at("height_unseen_stretches")[0].at("seconds"), limit + 1.0);
}

// A height seen again while the accelerometers' was uncertain (Office_A's Go1 climb: sigma 30 cm,
// then 1 m low on a tread) is said wherever it happens, one scan included, with where; the run
// stays trusted, and the session's file carries the ones within its scans.
TEST(TrajectoryTrust, AHeightSeenAgainWhileUncertainIsSaidWithWhere) {
    TrajectoryTrust t;
    for (size_t scan = 0; scan < 100; ++scan) {
        const uint32_t flags =
            scan == 45 || scan == 80 || scan == 81 ? uint32_t(kHeightAmbiguous) : 0u;
        t.Add(scan, 0.1 * double(scan), flags | kImuUsed, 0, int64_t(scan) * 100000000);
    }
    EXPECT_TRUE(t.trusted());
    ASSERT_EQ(t.height_ambiguous().size(), 2u);
    EXPECT_EQ(t.height_ambiguous()[0].first_scan, 45u);
    EXPECT_EQ(t.height_ambiguous()[0].last_scan, 45u);
    EXPECT_EQ(t.height_ambiguous()[1].first_scan, 80u);
    EXPECT_EQ(t.height_ambiguous()[1].last_scan, 81u);
    EXPECT_NE(t.Describe().find("the height seen again while the accelerometers' was uncertain (it "
                                "may be off by whole stair risers from there on) at scans 45-45 "
                                "(4.5-4.5 s), scans 80-81"),
              std::string::npos)
        << t.Describe();
    EXPECT_EQ(t.ToJson().at("height_ambiguous_stretches").size(), 2u);
    const nlohmann::json session = t.SessionJson(60, 99);
    EXPECT_EQ(session.at("verdict"), "trusted");
    ASSERT_EQ(session.at("height_ambiguous_stretches").size(), 1u);
    EXPECT_EQ(session.at("height_ambiguous_stretches")[0].at("first_stamp_ns"), 8000000000);
    TrajectoryTrust none;
    for (size_t scan = 0; scan < 10; ++scan) none.Add(scan, 0.1 * double(scan), kImuUsed, 0);
    EXPECT_TRUE(none.height_ambiguous().empty());
    EXPECT_EQ(none.Describe(), "trusted: every registration passed its checks");
}

// Degenerate scans take some directions from the prediction (LiDAR-only: the velocity before):
// a run longer than kMaxDegenerateS is said with where it was, as the height unseen is, and
// apart from it; shorter runs are not; the verdict stays what the registrations earned.
// Office_A's stairwell gave LiDAR-only runs of 1.5-3.5 s and a walk 38.55 cm off, called trusted.
TEST(TrajectoryTrust, ADegenerateRunForTooLongIsSaidWithWhere) {
    const double limit = TrajectoryTrust::kMaxDegenerateS;
    TrajectoryTrust t;
    size_t scan = 0;
    const auto add = [&](uint32_t flags, int n) {
        for (int k = 0; k < n; ++k, ++scan) {
            t.Add(scan, 0.1 * double(scan), flags, 0, int64_t(scan) * 100000000);
        }
    };
    add(0, 20);
    add(kDegenerate, int(std::lround(limit * 10)));  // 0.9 s from its first scan to its last
    add(0, 20);
    add(kDegenerate, 36);  // scans 50-85, and with the next five 50-90: 4.0 s
    add(kDegenerate | kHeightUnseen, 5);
    add(0, 20);
    EXPECT_TRUE(t.trusted());
    ASSERT_EQ(t.degenerate().size(), 1u);
    EXPECT_EQ(t.degenerate()[0].first_scan, 50u);
    EXPECT_EQ(t.degenerate()[0].last_scan, 90u);
    EXPECT_NEAR(t.degenerate()[0].seconds, 4.0, 1e-9);
    EXPECT_TRUE(t.height_unseen().empty());  // 0.4 s of it
    EXPECT_EQ(t.Describe(),
              "trusted: every registration passed its checks; degenerate for over 1 s (some "
              "directions the prediction's) at scans 50-90 (5.0-9.0 s)");
    EXPECT_EQ(t.ToJson().at("degenerate_stretches").size(), 1u);
    const nlohmann::json session = t.SessionJson(0, 40);
    EXPECT_EQ(session.at("verdict"), "trusted");
    EXPECT_TRUE(session.at("degenerate_stretches").empty());
    const nlohmann::json later = t.SessionJson(80, 120);
    ASSERT_EQ(later.at("degenerate_stretches").size(), 1u);
    EXPECT_EQ(later.at("degenerate_stretches")[0].at("first_stamp_ns"), 5000000000);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::odometry
