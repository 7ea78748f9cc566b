// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The simulator walking the sample office's stairs (storey: all, building_walk.hpp): a capture of
// waypoints at the flight's foot and head, joined over the 3D graph. The trajectory's height
// follows the flight's treads (within 2 cm on every tread where the foot stands), the capture
// decodes, the truth names each pose's storey, and the Go1's CAN frames carry its climb (odom_z,
// read 5 % high) and its slips on the nosings.
#include "host_tools/simulate/building_walk.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "algorithms/common/se3.hpp"
#include "algorithms/io/file_util.hpp"
#include "algorithms/io/trajectory.hpp"
#include "drivers/can/candump.hpp"
#include "drivers/can/go1_decoder.hpp"
#include "drivers/ouster/metadata.hpp"
#include "host_tools/bim/ifc_model.hpp"
#include "host_tools/bim/sample_building.hpp"
#include "host_tools/bim/stairs.hpp"
#include "host_tools/capture/ouster_capture.hpp"
#include "host_tools/simulate/simulate.hpp"
#include "tests/support/test_support.hpp"
#include "tests/unit/bim/synthetic_floor.hpp"

namespace bimslam::simulate {
namespace {
namespace BIMSLAM_UNITY_ID {

const bim::BimModel& Office() {
    static const bim::BimModel model = bim::ParseIfc("office.ifc", bim::SampleBuildingIfc());
    return model;
}

// Waypoints a metre before the flight's foot and a metre past its head.
Scenario FlightScenario(Platform platform) {
    Scenario s = DefaultScenario(platform);
    s.storey = kAllStoreys;
    s.sensor.model = "OS1-16";
    s.sensor.lidar_mode = "512x10";
    const bim::BuildingGraph g = bim::BuildBuildingGraph(
        Office(), {}, platform == Platform::kGo1 ? bim::StairLimits::Go1() : bim::StairLimits{},
        0.35, 0);
    const bim::StairFlight& f = g.flights.at(0);
    const Eigen::Vector2d up = (f.exit - f.entry).normalized();
    s.path.mode = PathMode::kWaypoints;
    s.path.waypoints = {f.entry - up, f.exit + up};
    s.path.waypoint_storeys = {"Ground Floor", "First Floor"};
    return s;
}

struct Walked {
    test::TempDir dir;
    CaptureReport report;
    bim::StairFlight flight;
};

const Walked& Walk(Platform platform) {
    static std::map<Platform, std::unique_ptr<Walked>> cache;
    auto& w = cache[platform];
    if (!w) {
        w = std::make_unique<Walked>();
        const Scenario s = FlightScenario(platform);
        w->report = SimulateCapture(s, Office(), "none", w->dir.path());
        w->flight = bim::FindStairFlights(Office()).at(0);
    }
    return *w;
}

class FlightWalk : public ::testing::TestWithParam<Platform> {};

TEST_P(FlightWalk, TheHeightFollowsTheTreads) {
    const Walked& w = Walk(GetParam());
    const Scenario s = FlightScenario(GetParam());
    const Eigen::Isometry3d T_sensor_base =
        common::PoseFromXyzRpyDeg(s.sensor.mount_xyz, s.sensor.mount_rpy_deg).inverse();
    const double base_height = GetParam() == Platform::kGo1 ? 0.32 : 1.2;
    const bim::StairFlight& f = w.flight;
    const std::vector<io::StampedPose> truth = io::ReadTum(w.dir.path() / "ground_truth.tum");
    std::vector<int> seen(f.levels.size(), 0);
    double worst = 0;
    for (const io::StampedPose& p : truth) {
        const Eigen::Isometry3d base = p.Pose() * T_sensor_base;
        for (size_t k = 0; k < f.levels.size(); ++k) {
            // Where the foot stands: within an eighth of a run of the tread's centre along the
            // flight (a frame every 4.4 cm at a person's 0.44 m/s falls in it), over the tread.
            const Eigen::Vector2d d = base.translation().head<2>() - f.levels[k].centre.head<2>();
            const Eigen::Vector2d u = (f.levels[std::min(k + 1, f.levels.size() - 1)].centre -
                                       f.levels[k ? k - 1 : 0].centre)
                                          .head<2>()
                                          .normalized();
            if (std::abs(d.dot(u)) > 0.125 * f.run_m ||
                std::abs(d.x() * u.y() - d.y() * u.x()) > 0.3)
                continue;
            const double error = base.translation().z() - base_height - f.levels[k].centre.z();
            worst = std::max(worst, std::abs(error));
            EXPECT_LT(std::abs(error), 0.02) << "tread " << k << " at t " << p.stamp_ns;
            ++seen[k];
        }
    }
    for (size_t k = 0; k < seen.size(); ++k) EXPECT_GT(seen[k], 0) << "tread " << k << " unseen";
    std::cout << "height error on the treads: at most " << worst * 100 << " cm\n";
    // From the ground floor to the first floor's.
    const Eigen::Isometry3d first = truth.front().Pose() * T_sensor_base;
    const Eigen::Isometry3d last = truth.back().Pose() * T_sensor_base;
    // (A person's 2 cm bob on the floors.)
    EXPECT_NEAR(first.translation().z() - base_height, 0.0, 0.021);
    EXPECT_NEAR(last.translation().z() - base_height, 3.2, 0.021);
    EXPECT_EQ(w.report.storeys, (std::vector<std::string>{"Ground Floor", "First Floor"}));
    EXPECT_EQ(w.report.flights_walked, 1u);
}

TEST_P(FlightWalk, TheCaptureDecodesAndNamesEachPosesStorey) {
    const Walked& w = Walk(GetParam());
    const ouster::SensorInfo info = ouster::LoadMetadata(w.dir.path() / "metadata.json");
    capture::OusterCapture capture(w.dir.path() / "lidar.pcap", info);
    size_t frames = 0, complete = 0;
    while (const ouster::LidarFrame* f = capture.NextFrame()) {
        ++frames;
        complete += f->complete;
    }
    EXPECT_EQ(frames, w.report.frames);
    EXPECT_EQ(complete, frames);
    // ground_truth_storeys.csv: a row per frame, from the ground floor over the flight upstairs.
    std::istringstream csv(io::ReadFileToString(w.dir.path() / "ground_truth_storeys.csv"));
    std::string line;
    std::getline(csv, line);
    EXPECT_EQ(line, "stamp_ns,storey,floor_z_m,on_flight");
    std::vector<std::string> storeys;
    size_t rows = 0, on_flight = 0;
    while (std::getline(csv, line)) {
        ++rows;
        const std::string storey = line.substr(
            line.find(',') + 1, line.find(',', line.find(',') + 1) - line.find(',') - 1);
        if (storeys.empty() || storeys.back() != storey) storeys.push_back(storey);
        on_flight += line.back() == '1';
    }
    EXPECT_EQ(rows, w.report.frames);
    EXPECT_EQ(storeys, (std::vector<std::string>{"Ground Floor", "First Floor"}));
    EXPECT_GT(on_flight, 10u);
    const nlohmann::json m =
        nlohmann::json::parse(io::ReadFileToString(w.dir.path() / "capture.json"));
    EXPECT_EQ(m["model"]["storey"], "all");
    EXPECT_EQ(m["walk"]["storeys"].size(), 2u);
}

INSTANTIATE_TEST_SUITE_P(Platforms, FlightWalk,
                         ::testing::Values(Platform::kGo1, Platform::kHandheld),
                         [](const auto& param_info) {
                             return std::string(ToString(param_info.param));
                         });

TEST(FlightWalkGo1, TheCanFramesCarryTheClimbAndTheNosingSlips) {
    const Walked& w = Walk(Platform::kGo1);
    can::CandumpReader log(w.dir.path() / "go1_can.log");
    can::CandumpRecord record;
    can::Go1Decoder decoder;
    double last_odom_z = 0;
    size_t samples = 0;
    while (log.Next(record)) {
        decoder.Feed(record.frame);
        for (const can::Go1Sample& s : decoder.ready()) {
            last_odom_z = s.odom_z;
            ++samples;
        }
    }
    ASSERT_GT(samples, 100u);
    // 3.2 m climbed, read 5 % high: the leg odometry's vertical drift.
    EXPECT_NEAR(last_odom_z, 3.2 * 1.05, 0.05);
    // Nosing slips: some of the 16 steps slipped (probability 0.2 each, seed fixed).
    const nlohmann::json m =
        nlohmann::json::parse(io::ReadFileToString(w.dir.path() / "capture.json"));
    EXPECT_GT(m["go1"]["nosing_slips"].get<int>(), 0);
}

// A waypoint inside an added object (the first floor's crate of the demo's walk) is named as not
// free space, not as a missing way over the stairs; one beyond reach on the same storey as such.
TEST(BuildingWalk, AWaypointWhereThePlatformCannotStandIsNamedAsSuch) {
    Scenario s = DefaultScenario(Platform::kHandheld);
    s.storey = kAllStoreys;
    s.path.mode = PathMode::kWaypoints;
    s.path.waypoints = {{14.0, 3.0}, {19.0, 1.2}};
    s.path.waypoint_storeys = {"Ground Floor", "First Floor"};
    s.edits.boxes.push_back({"crate", {19.0, 1.2, 3.6}, {1.0, 0.6, 0.8}, 0.0});
    try {
        PlanBuildingWalk(Office(), s);
        FAIL() << "a waypoint inside a crate was walked to";
    } catch (const common::Error& e) {
        const std::string m = e.what();
        EXPECT_NE(
            m.find("the waypoint (19, 1.2) on storey 'First Floor': it is not free space with "
                   "the platform's 0.35 m of clearance"),
            std::string::npos)
            << m;
    }
}

TEST(BuildingWalk, AVehicleCannotWalkTheStoreys) {
    Scenario s = DefaultScenario(Platform::kVehicle);
    s.storey = kAllStoreys;
    s.path.mode = PathMode::kWaypoints;
    s.path.waypoints = {{-5, -5}};
    EXPECT_THROW(PlanBuildingWalk(Office(), s), common::Error);
}

TEST(BuildingWalk, TheCoverageOfBothStoreysClimbsAndComesBack) {
    Scenario s = DefaultScenario(Platform::kHandheld);
    s.storey = kAllStoreys;
    const BuildingWalk w = PlanBuildingWalk(Office(), s);
    EXPECT_EQ(w.storeys, (std::vector<int>{0, 1}));
    EXPECT_EQ(w.flights_walked, 2u);  // up and down again
    EXPECT_TRUE(w.notes.empty()) << w.notes.front();
    // Closed: it ends where it began, on the ground floor.
    EXPECT_LT((w.points.back().p - w.points.front().p).norm(), 1e-6);
    size_t upstairs = 0;
    for (const simulation::PathPoint& p : w.points) upstairs += std::abs(p.p.z() - 3.2) < 1e-9;
    EXPECT_GT(upstairs, 100u);
}

// From 5 m outside the entrance (the office with its doors to the outside): in through the door
// to the first waypoint, then up the stairs to the waypoint on the first floor.
TEST(BuildingWalk, AStartOutsideWalksInThenUpTheStairs) {
    bim::SampleBuildingOptions doors;
    doors.exterior_doors = true;
    const bim::BimModel model = bim::ParseIfc("office.ifc", bim::SampleBuildingIfc(doors));
    Scenario s = DefaultScenario(Platform::kGo1);
    s.storey = kAllStoreys;
    s.path.mode = PathMode::kWaypoints;
    s.path.start = Pose2d{{-5.0, 7.5}, 0.0};
    s.path.waypoints = {{2.0, 7.2}, {20.0, 7.2}};
    s.path.waypoint_storeys = {"Ground Floor", "First Floor"};
    const BuildingWalk w = PlanBuildingWalk(model, s);
    EXPECT_TRUE(w.starts_outside);
    EXPECT_EQ(w.flights_walked, 1u);
    EXPECT_EQ(w.storeys, (std::vector<int>{0, 1}));
    ASSERT_FALSE(w.points.empty());
    EXPECT_LT((w.points.front().p - Eigen::Vector3d(-5.0, 7.5, 0.0)).norm(), 1e-6);
    EXPECT_LT((w.points.back().p - Eigen::Vector3d(20.0, 7.2, 3.2)).norm(), 1e-6) << "ends inside";
    // Without a door to the outside, the same start says so.
    EXPECT_THROW(
        {
            try {
                PlanBuildingWalk(Office(), s);
            } catch (const common::Error& e) {
                EXPECT_NE(std::string(e.what()).find("no way leads in"), std::string::npos)
                    << e.what();
                throw;
            }
        },
        common::Error);
}

// A canopy 1.0 m above the ground in front of the entrance, 3 m deep and 2 m wide: a Go1 (0.76 m
// of headroom) walks in under it, a person carrying the rig (1.47 m) goes round it. The way in
// from outside plans on the walk's own grid rules, as the walk inside does (walk.cpp).
TEST(BuildingWalk, AWayInFromOutsideKeepsTheRigUnderTheHeadroom) {
    bim::SampleBuildingOptions doors;
    doors.exterior_doors = true;
    bim::BimModel model = bim::ParseIfc("office.ifc", bim::SampleBuildingIfc(doors));
    const Eigen::AlignedBox2d canopy(Eigen::Vector2d(-4.0, 6.5), Eigen::Vector2d(-1.0, 8.5));
    bim::test_floor::AddSlabFace(model, "canopy", {-4, 6.5, 1}, {-1, 6.5, 1}, {-1, 8.5, 1},
                                 {-4, 8.5, 1});

    const auto under_canopy = [&](Platform platform) {
        Scenario s = DefaultScenario(platform);
        s.storey = kAllStoreys;
        s.path.mode = PathMode::kWaypoints;
        s.path.start = Pose2d{{-5.0, 7.5}, 0.0};
        s.path.waypoints = {{2.0, 7.2}};
        s.path.waypoint_storeys = {"Ground Floor"};
        const BuildingWalk w = PlanBuildingWalk(model, s);
        EXPECT_TRUE(w.starts_outside);
        size_t n = 0;  // 5 cm steps along the walk's polyline under the canopy
        for (size_t k = 1; k < w.points.size(); ++k) {
            const Eigen::Vector2d a = w.points[k - 1].p.head<2>(), b = w.points[k].p.head<2>();
            const int steps = int(std::ceil((b - a).norm() / 0.05));
            for (int i = 0; i < steps; ++i) n += canopy.contains(a + (b - a) * (i / double(steps)));
        }
        return n;
    };
    EXPECT_EQ(under_canopy(Platform::kHandheld), 0u);
    EXPECT_GT(under_canopy(Platform::kGo1), 0u);  // the canopy is in the straight way in
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::simulate
