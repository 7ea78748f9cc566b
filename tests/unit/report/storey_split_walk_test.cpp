// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The walk split by storey on a simulated climb (issue 31, item 6): the sample office's stair
// walked up and back down by a person and by a Go1 (`storey: all`, waypoints a metre before its
// foot and past its head), split from the truth's sensor poses alone, against the simulator's
// own truth of each pose's storey (ground_truth_storeys.csv): every pose off the flight is on its
// true storey's floor, and the walk is floor, flight, floor, flight, floor. About 3 s a platform.
#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "algorithms/io/file_util.hpp"
#include "algorithms/io/trajectory.hpp"
#include "host_tools/bim/building_graph.hpp"
#include "host_tools/bim/ifc_model.hpp"
#include "host_tools/bim/sample_building.hpp"
#include "host_tools/report/storey_split.hpp"
#include "host_tools/simulate/simulate.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::report {
namespace {
namespace BIMSLAM_UNITY_ID {

const bim::BimModel& Office() {
    static const bim::BimModel model = bim::ParseIfc("office.ifc", bim::SampleBuildingIfc());
    return model;
}

// Per pose of the truth: its storey's index and whether it is on the flight.
std::vector<std::pair<int, bool>> StoreyTruth(const std::filesystem::path& csv) {
    std::vector<std::pair<int, bool>> out;
    for (const test::StoreyTruthRow& r : test::ReadStoreyTruth(csv)) {
        int storey = -1;
        for (size_t s = 0; s < Office().storeys.size(); ++s) {
            if (Office().storeys[s].name == r.storey) storey = int(s);
        }
        out.push_back({storey, r.on_flight});
    }
    return out;
}

class StoreySplitWalk : public ::testing::TestWithParam<simulate::Platform> {};

TEST_P(StoreySplitWalk, PosesOffTheFlightAreOnTheirTrueStoreyAndTheClimbIsAFlightEachWay) {
    simulate::Scenario s = simulate::DefaultScenario(GetParam());
    s.storey = simulate::kAllStoreys;
    s.sensor.model = "OS1-16";
    s.sensor.lidar_mode = "512x10";
    const bim::BuildingGraph g = bim::BuildBuildingGraph(
        Office(), {},
        GetParam() == simulate::Platform::kGo1 ? bim::StairLimits::Go1() : bim::StairLimits{}, 0.35,
        0);
    const bim::StairFlight& f = g.flights.at(0);
    const Eigen::Vector2d up = (f.exit - f.entry).normalized();
    s.path.mode = simulate::PathMode::kWaypoints;
    s.path.waypoints = {f.entry - up, f.exit + up, f.entry - up};
    s.path.waypoint_storeys = {"Ground Floor", "First Floor", "Ground Floor"};
    test::TempDir dir;
    simulate::SimulateCapture(s, Office(), "none", dir.path());

    std::vector<Eigen::Vector3d> poses;
    for (const io::StampedPose& p : io::ReadTum(dir / "ground_truth.tum")) {
        poses.push_back(p.translation);
    }
    const auto truth = StoreyTruth(dir / "ground_truth_storeys.csv");
    ASSERT_EQ(truth.size(), poses.size());
    std::vector<double> elevations;
    for (const bim::BimStorey& st : Office().storeys) elevations.push_back(st.elevation_m);
    const std::vector<StoreyRun> runs = SplitByStorey(poses, elevations);

    std::vector<std::pair<int, int>> labels;
    std::vector<std::pair<int, int>> per_pose;  // each pose's run, in order
    for (size_t k = 0; k < runs.size(); ++k) {
        labels.push_back({runs[k].lower, runs[k].upper});
        for (size_t i = k == 0 ? 0 : 1; i < runs[k].points.size(); ++i) {
            per_pose.push_back(labels.back());
        }
    }
    const std::vector<std::pair<int, int>> expected{{0, 0}, {0, 1}, {1, 1}, {0, 1}, {0, 0}};
    EXPECT_EQ(labels, expected);
    ASSERT_EQ(per_pose.size(), poses.size());
    size_t off_flight = 0, on_flight = 0, flight_as_flight = 0;
    for (size_t i = 0; i < poses.size(); ++i) {
        if (truth[i].second) {
            ++on_flight;
            flight_as_flight += per_pose[i].first != per_pose[i].second;
            continue;
        }
        ++off_flight;
        EXPECT_EQ(per_pose[i], std::make_pair(truth[i].first, truth[i].first)) << "pose " << i;
    }
    std::cout << "sensor " << SensorHeightAboveFloor(poses, elevations) << " m above its floor; "
              << off_flight << " poses off the flight, all on their "
              << "storey; " << flight_as_flight << " of " << on_flight
              << " on the flight drawn as flight (the first and last steps: on a floor)\n";
    EXPECT_GT(on_flight, 0u);
    EXPECT_GT(flight_as_flight, on_flight / 2);
}

INSTANTIATE_TEST_SUITE_P(Platforms, StoreySplitWalk,
                         ::testing::Values(simulate::Platform::kHandheld, simulate::Platform::kGo1),
                         [](const auto& param_info) {
                             return param_info.param == simulate::Platform::kGo1 ? "Go1"
                                                                                 : "Handheld";
                         });

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::report
