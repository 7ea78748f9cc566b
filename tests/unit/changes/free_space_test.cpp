// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// JudgeByNeighbours (free_space.hpp): points the free-space votes could not judge take the verdict
// of the judged points around them. The end-to-end case is change_detector_test.cpp's corridor.
#include "algorithms/changes/free_space.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "algorithms/common/status.hpp"

namespace bimslam::changes {
namespace {
namespace BIMSLAM_UNITY_ID {

// A 1 m x 1 m sheet of points 5 cm apart at height z.
void Sheet(double x0, double z, std::vector<Eigen::Vector3f>* points) {
    for (int i = 0; i < 20; ++i) {
        for (int j = 0; j < 20; ++j) {
            points->emplace_back(float(x0 + 0.05 * i), float(0.05 * j), float(z));
        }
    }
}

TEST(FreeSpace, UnjudgedPointsTakeTheVerdictOfMostJudgedPointsAround) {
    std::vector<Eigen::Vector3f> points;
    Sheet(0.0, 0.5, &points);   // a person: judged transient, but for a row of unjudged points
    Sheet(5.0, 0.5, &points);   // a box: judged static, but for the same row
    Sheet(10.0, 0.5, &points);  // a lone sheet nothing judged
    const size_t n = 400;
    std::vector<uint8_t> judged(points.size(), 1), transient(points.size(), 0);
    for (size_t k = 0; k < n; ++k) transient[k] = 1;
    const auto unjudged_row = [](size_t k) { return (k % 400) / 20 == 10; };  // x = x0 + 0.5
    for (size_t k = 0; k < points.size(); ++k) {
        if (unjudged_row(k) || k >= 2 * n) judged[k] = 0, transient[k] = 0;
    }
    const std::vector<uint8_t> before = transient;
    const size_t changed = JudgeByNeighbours(points, judged, transient, 0.15);
    EXPECT_EQ(changed, 20u);
    for (size_t k = 0; k < points.size(); ++k) {
        if (k < n && unjudged_row(k)) {
            EXPECT_EQ(transient[k], 1) << "an unjudged point amid the person, " << k;
        } else {
            EXPECT_EQ(transient[k], before[k]) << "point " << k;
        }
    }
}

TEST(FreeSpace, AnUnjudgedPointBetweenAsManyTransientAsStaticPointsStaysStatic) {
    // One unjudged point with a transient neighbour on one side and a static one on the other.
    const std::vector<Eigen::Vector3f> points = {{0, 0, 0}, {-0.1f, 0, 0}, {0.1f, 0, 0}};
    const std::vector<uint8_t> judged = {0, 1, 1};
    std::vector<uint8_t> transient = {0, 1, 0};
    EXPECT_EQ(JudgeByNeighbours(points, judged, transient, 0.15), 0u);
    EXPECT_EQ(transient[0], 0);
    // Two transient against one static: transient.
    const std::vector<Eigen::Vector3f> more = {
        {0, 0, 0}, {-0.1f, 0, 0}, {0.1f, 0, 0}, {0, 0.1f, 0}};
    const std::vector<uint8_t> more_judged = {0, 1, 1, 1};
    std::vector<uint8_t> more_transient = {0, 1, 0, 1};
    EXPECT_EQ(JudgeByNeighbours(more, more_judged, more_transient, 0.15), 1u);
    EXPECT_EQ(more_transient[0], 1);
    // Radius 0 turns the rule off; a judged point is never changed.
    more_transient = {0, 1, 0, 1};
    EXPECT_EQ(JudgeByNeighbours(more, more_judged, more_transient, 0.0), 0u);
    std::vector<uint8_t> all_judged_transient = {0, 1, 0, 1};
    EXPECT_EQ(JudgeByNeighbours(more, std::vector<uint8_t>{1, 1, 1, 1}, all_judged_transient, 0.15),
              0u);
    EXPECT_EQ(all_judged_transient[0], 0);
}

TEST(FreeSpace, RejectsMismatchedInputsAndANegativeRadius) {
    const std::vector<Eigen::Vector3f> points = {{0, 0, 0}, {0.1f, 0, 0}};
    std::vector<uint8_t> transient = {0, 1};
    EXPECT_THROW(JudgeByNeighbours(points, std::vector<uint8_t>{0}, transient, 0.15),
                 common::Error);
    FreeSpaceConfig config;
    config.unjudged_radius_m = -0.1;
    EXPECT_THROW(config.Validate(), common::Error);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::changes
