// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The free-space rule between hypotheses that explain the loops about equally well
// (host_tools/anchor/anchoring.hpp, FreeSpacePrefers; AnchorConfig::outweigh_ratio, _gap).
#include <gtest/gtest.h>

#include "host_tools/anchor/anchoring.hpp"

namespace bimslam::anchor {
namespace {
namespace BIMSLAM_UNITY_ID {

Hypothesis SeenThrough(double share) {
    Hypothesis h;
    h.seen_through = share;
    return h;
}

TEST(FreeSpacePrefers, AWrongStoreyUnderTheContradictionThresholdIsOutweighed) {
    // The handheld walk's two storeys (README.md): 0.66 % right, 4.4 % one storey up.
    const AnchorConfig config;
    EXPECT_TRUE(FreeSpacePrefers(SeenThrough(0.0066), SeenThrough(0.044), config));
    EXPECT_FALSE(FreeSpacePrefers(SeenThrough(0.044), SeenThrough(0.0066), config));
}

TEST(FreeSpacePrefers, RightPlacementsSpreadIsNoEvidence) {
    // Right placements measured 0.6-1.7 %: the ratio alone (2.8x) is not enough, nor is a
    // large ratio with a small gap.
    const AnchorConfig config;
    EXPECT_FALSE(FreeSpacePrefers(SeenThrough(0.006), SeenThrough(0.017), config));
    EXPECT_FALSE(FreeSpacePrefers(SeenThrough(0.0), SeenThrough(0.015), config));
    // Alike placements (a mirror-symmetric building) never decide, either way.
    EXPECT_FALSE(FreeSpacePrefers(SeenThrough(0.01), SeenThrough(0.011), config));
    EXPECT_FALSE(FreeSpacePrefers(SeenThrough(0.011), SeenThrough(0.01), config));
}

TEST(FreeSpacePrefers, TheRatioAndTheGapBothHold) {
    AnchorConfig config;
    // A gap of 3 points but only 1.75x as often: no decision.
    EXPECT_FALSE(FreeSpacePrefers(SeenThrough(0.04), SeenThrough(0.07), config));
    config.outweigh_ratio = 1.5;
    EXPECT_TRUE(FreeSpacePrefers(SeenThrough(0.04), SeenThrough(0.07), config));
    config.outweigh_gap = 0.05;
    EXPECT_FALSE(FreeSpacePrefers(SeenThrough(0.04), SeenThrough(0.07), config));
}

TEST(FreeSpacePrefers, OneThatStandsOnlyByRemovedElementsLosesToOneThatNeedsNone) {
    // FZK-Haus's attic, its first visit: the right placement saw through 2.9 % of its rays, its
    // twin turned 180 degrees through the stair's railings, which two removed elements would
    // explain. Not decisive by the ratio; the twin needs the explanation, the right one does not.
    const AnchorConfig config;
    Hypothesis twin = SeenThrough(0.065);
    EXPECT_FALSE(FreeSpacePrefers(SeenThrough(0.029), twin, config));
    twin.removed_surfaces.resize(2);
    twin.seen_through_unexplained = 0.01;
    EXPECT_TRUE(FreeSpacePrefers(SeenThrough(0.029), twin, config));
    EXPECT_FALSE(FreeSpacePrefers(twin, SeenThrough(0.029), config));
    // Both need it (a demolished wall seen from both halves of a symmetric building): no decision.
    Hypothesis other = twin;
    other.seen_through = 0.07;
    EXPECT_FALSE(FreeSpacePrefers(twin, other, config));
}

TEST(FreeSpacePrefers, ConfigRejectsARatioUnderOneAndAZeroGap) {
    AnchorConfig config;
    config.outweigh_ratio = 0.5;
    EXPECT_ANY_THROW(config.Validate());
    config = AnchorConfig{};
    config.outweigh_gap = 0;
    EXPECT_ANY_THROW(config.Validate());
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::anchor
