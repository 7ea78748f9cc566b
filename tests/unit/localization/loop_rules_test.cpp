// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The loops' rules that the offline anchoring and the rig's relocaliser share
// (algorithms/localization/loop_rules.hpp): two loops agree within the floor plus the drift over
// the path between their keyframes, and rules the anchoring would refuse are refused on the rig
// too, naming the rig's configuration.
#include "algorithms/localization/loop_rules.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "algorithms/common/status.hpp"
#include "algorithms/localization/relocalizer.hpp"
#include "algorithms/localization/walked_space.hpp"

namespace bimslam::localization {
namespace {
namespace BIMSLAM_UNITY_ID {

Eigen::Isometry3d Off(double x_m, double yaw_deg) {
    Eigen::Isometry3d E = Eigen::Isometry3d::Identity();
    E.translation().x() = x_m;
    E.linear() =
        Eigen::AngleAxisd(yaw_deg * M_PI / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    return E;
}

TEST(LoopRules, TwoLoopsAgreeWithinTheFloorPlusTheDriftOverTheirPath) {
    const LoopRules r;  // 0.15 m and 2 deg, plus 3 % and 0.15 deg a metre
    EXPECT_TRUE(r.Agree(Off(0.14, 0), 0));
    EXPECT_FALSE(r.Agree(Off(0.16, 0), 0));
    EXPECT_TRUE(r.Agree(Off(0, 1.9), 0));
    EXPECT_FALSE(r.Agree(Off(0, 2.1), 0));
    // 10 m apart: 0.45 m and 3.5 deg.
    EXPECT_TRUE(r.Agree(Off(0.44, 3.4), 10));
    EXPECT_FALSE(r.Agree(Off(0.46, 0), 10));
    EXPECT_FALSE(r.Agree(Off(0, 3.6), 10));
}

TEST(LoopRules, TheWalksHeightsPreferThePlacementThatFloatsATenthOfTheWalkLess) {
    const LoopRules r;  // a tenth, and a third as many
    // The sample office's walk up its stair and back (121 keyframes) placed a storey up: 22
    // float above the roof; placed right, none.
    EXPECT_TRUE(r.HeightsPrefer(0, 22, 121, 5));
    EXPECT_FALSE(r.HeightsPrefer(22, 0, 121, 5));
    EXPECT_FALSE(r.HeightsPrefer(0, 12, 121, 5));  // under a tenth (12.1)
    EXPECT_TRUE(r.HeightsPrefer(7, 22, 121, 5));   // 3 x 7 <= 22
    EXPECT_FALSE(r.HeightsPrefer(8, 22, 121, 5));
    // A short window: at least min_count float.
    EXPECT_FALSE(r.HeightsPrefer(0, 3, 20, 4));
    EXPECT_TRUE(r.HeightsPrefer(0, 4, 20, 4));
}

// Two storeys walked 3.2 m apart over x in [0, 20], y = 0 (the reference's keyframes every metre,
// 1.3 m above each floor): positions on either storey's walk stand, a storey above the top one
// or below the lowest float, and where no walk went near nothing floats (outside, or unknown).
TEST(WalkedSpace, APositionFloatsWhereTheWalksPassNearOnlyAtOtherHeights) {
    std::vector<Eigen::Vector3d> walked;
    for (int storey = 0; storey < 2; ++storey) {
        for (int x = 0; x <= 20; ++x) walked.emplace_back(x, 0, 1.3 + 3.2 * storey);
    }
    const WalkedSpace space(walked, 3.0, 1.5);
    EXPECT_FALSE(space.Floats({5.5, 1.0, 1.3}));   // on the ground floor's walk
    EXPECT_FALSE(space.Floats({5.5, 1.0, 4.5}));   // on the first floor's
    EXPECT_FALSE(space.Floats({5.5, -2.5, 2.7}));  // on the flight between, within 1.5 m
    EXPECT_TRUE(space.Floats({5.5, 1.0, 7.7}));    // a storey above the top one
    EXPECT_TRUE(space.Floats({5.5, 1.0, -1.9}));   // a storey below the lowest
    EXPECT_FALSE(space.Floats({5.5, 3.5, 7.7}));   // no walk within 3 m: not known
    EXPECT_FALSE(space.Floats({30.0, 0.0, 7.7}));
    EXPECT_TRUE(space.Floats({-2.9, 0.0, 7.7}));  // across a grid cell's edge
    // Placed: a walk of 10 keyframes in its own frame on the first floor, lifted a storey.
    std::vector<Eigen::Vector3d> walk;
    for (int k = 0; k < 10; ++k) walk.emplace_back(2.0 * k, 0.5, 0.0);
    Eigen::Isometry3d right = Eigen::Isometry3d::Identity();
    right.translation().z() = 4.5;
    Eigen::Isometry3d up = right;
    up.translation().z() += 3.2;
    EXPECT_EQ(space.Floating(walk, right), 0u);
    EXPECT_EQ(space.Floating(walk, up), 10u);
    EXPECT_EQ(WalkedSpace().Floating(walk, up), 0u) << "no walks: nothing floats";
}

TEST(LoopRules, TheRelocaliserRefusesWhatTheAnchoringWouldNamingItsConfiguration) {
    RelocalizerConfig c;
    EXPECT_NO_THROW(c.ValidateLoopRules("RelocalizerConfig"));
    c.consistency_m = 0;
    try {
        c.ValidateLoopRules("RelocalizerConfig");
        ADD_FAILURE() << "consistency_m 0 accepted";
    } catch (const common::Error& e) {
        EXPECT_EQ(e.code(), common::StatusCode::kInvalidArgument);
        EXPECT_NE(std::string(e.what()).find("RelocalizerConfig"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("consistency_m"), std::string::npos) << e.what();
    }
    RelocalizerConfig d;
    d.free_space_level = d.registration.levels.size();
    EXPECT_THROW(d.ValidateLoopRules("RelocalizerConfig"), common::Error);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::localization
