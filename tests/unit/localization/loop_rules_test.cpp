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

namespace bimslam::localization {
namespace {
namespace BIMSLAM_UNITY_ID {

Eigen::Isometry3d Off(double x_m, double yaw_deg) {
    Eigen::Isometry3d E = Eigen::Isometry3d::Identity();
    E.translation().x() = x_m;
    E.linear() = Eigen::AngleAxisd(yaw_deg * M_PI / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix();
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
