// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The walk split by storey for the report's plans: a two-storey walk (floor, up a flight, the upper
// floor, down again) gives its five runs, whatever the sensor's height above its floor (a Go1's,
// a hand-held rig's); a bump on a floor is no flight; a start outside below the lowest floor is on
// it; the runs join.
#include "host_tools/report/storey_split.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <utility>
#include <vector>

namespace bimslam::report {
namespace {
namespace BIMSLAM_UNITY_ID {

const std::vector<double> kElevations{0.0, 3.2};

// n points along x at floor height z0 + sensor, with a gait's bob of +-2 cm.
void Floor(std::vector<Eigen::Vector3d>& p, int n, double floor_z, double sensor) {
    for (int i = 0; i < n; ++i) {
        p.emplace_back(0.1 * double(p.size()), 0.0,
                       floor_z + sensor + 0.02 * std::sin(double(p.size())));
    }
}

// A flight of 16 risers of 0.2 m, two poses per step, from z0 to z1.
void Flight(std::vector<Eigen::Vector3d>& p, double z0, double z1, double sensor) {
    for (int i = 1; i <= 32; ++i) {
        const double z = z0 + (z1 - z0) * std::floor(double(i) / 2.0) / 16.0;
        p.emplace_back(0.1 * double(p.size()), 1.0, z + sensor);
    }
}

std::vector<std::pair<int, int>> Labels(const std::vector<StoreyRun>& runs) {
    std::vector<std::pair<int, int>> out;
    for (const StoreyRun& r : runs) out.push_back({r.lower, r.upper});
    return out;
}

TEST(StoreySplit, AWalkUpAndDownAFlightGivesFloorFlightFloorFlightFloor) {
    for (const double sensor : {0.45, 1.5}) {  // a Go1's lidar, a hand-held rig's
        std::vector<Eigen::Vector3d> p;
        Floor(p, 200, 0.0, sensor);
        Flight(p, 0.0, 3.2, sensor);
        Floor(p, 150, 3.2, sensor);
        Flight(p, 3.2, 0.0, sensor);
        Floor(p, 100, 0.0, sensor);
        EXPECT_NEAR(SensorHeightAboveFloor(p, kElevations), sensor, 0.05);
        const std::vector<StoreyRun> runs = SplitByStorey(p, kElevations);
        const std::vector<std::pair<int, int>> expected{{0, 0}, {0, 1}, {1, 1}, {0, 1}, {0, 0}};
        ASSERT_EQ(Labels(runs), expected) << "sensor " << sensor;
        EXPECT_TRUE(runs[1].OnFlight());
        EXPECT_TRUE(runs[1].On(0) && runs[1].On(1));
        EXPECT_FALSE(runs[2].On(0));
        // Every point is in one run, each run after the first starting with the last before.
        size_t total = runs[0].points.size();
        for (size_t k = 1; k < runs.size(); ++k) {
            EXPECT_EQ(runs[k].points.front(), runs[k - 1].points.back()) << k;
            total += runs[k].points.size() - 1;
        }
        EXPECT_EQ(total, p.size());
        // The floor runs hold the floors' poses: 200 below, most of the 150 above (the flight's
        // first and last steps are within the tolerance of a floor).
        EXPECT_GE(runs[0].points.size(), 200u);
        EXPECT_GE(runs[2].points.size(), 150u);
        for (const Eigen::Vector3d& q : runs[2].points) EXPECT_GT(q.z(), 3.2 + sensor - 0.6);
    }
}

TEST(StoreySplit, ABumpOnAFloorIsNoFlightAndAStartBelowTheLowestFloorIsOnIt) {
    std::vector<Eigen::Vector3d> p;
    Floor(p, 50, -0.3, 0.45);  // outside, 0.3 m below the ground floor
    Floor(p, 100, 0.0, 0.45);
    for (int i = 0; i < 10; ++i) p.emplace_back(0.0, 0.0, 0.45 + 0.27);  // a 27 cm threshold
    Floor(p, 100, 0.0, 0.45);
    const std::vector<StoreyRun> runs = SplitByStorey(p, kElevations);
    ASSERT_EQ(runs.size(), 1u);
    EXPECT_EQ(runs[0].lower, 0);
    EXPECT_EQ(runs[0].upper, 0);
    EXPECT_TRUE(SplitByStorey({}, kElevations).empty());
    EXPECT_TRUE(SplitByStorey(p, {}).empty());
}

TEST(StoreySplit, ABadConfigIsRefused) {
    StoreySplitConfig c;
    c.tolerance_m = 0;
    EXPECT_THROW(c.Validate(), std::exception);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::report
