// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The walking platform's trajectory and the IMU model (algorithms/simulation/body_trajectory.hpp,
// imu_model.hpp).
#include "algorithms/simulation/body_trajectory.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "algorithms/common/se3.hpp"
#include "algorithms/common/status.hpp"
#include "algorithms/simulation/imu_model.hpp"

namespace bimslam::simulation {
namespace {
namespace BIMSLAM_UNITY_ID {

// An L: 10 m east, then 6 m north.
std::vector<Eigen::Vector2d> LPath() { return {{0, 0}, {10, 0}, {10, 6}}; }

double SegmentDistance(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                       const Eigen::Vector2d& b) {
    const double f = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
    return (a + f * (b - a) - p).norm();
}

TEST(BodyTrajectory, StartsAndEndsAtRestAndFollowsThePath) {
    const BodyTrajectory t(LPath(), 0.0, 0.0, PathTiming{}, GaitConfig::Go1Trot());
    EXPECT_NEAR(t.length_m(), 16.0, 0.05);
    const auto start = t.PlanarAt(0.5), end = t.PlanarAt(t.duration_s() - 0.5);
    EXPECT_LT(start.v_xy.norm(), 1e-3);
    EXPECT_LT(end.v_xy.norm(), 1e-3);
    EXPECT_LT((start.xy - Eigen::Vector2d(0, 0)).norm(), 1e-3);
    EXPECT_LT((end.xy - Eigen::Vector2d(10, 6)).norm(), 1e-3);
    double max_speed = 0, max_yaw_rate = 0, max_off_path = 0;
    for (double s = 0; s < t.duration_s(); s += 0.05) {
        const auto p = t.PlanarAt(s);
        max_speed = std::max(max_speed, p.v_xy.norm());
        max_yaw_rate = std::max(max_yaw_rate, std::abs(p.yaw_rate));
        max_off_path = std::max(max_off_path, std::min(SegmentDistance(p.xy, {0, 0}, {10, 0}),
                                                       SegmentDistance(p.xy, {10, 0}, {10, 6})));
    }
    EXPECT_LE(max_speed, 0.5 * 1.02);  // the cruise speed, give or take the smoothing
    EXPECT_GT(max_speed, 0.45);
    EXPECT_LE(max_yaw_rate, 1.0 * 1.1);
    EXPECT_LT(max_off_path, 0.1);  // the corner is rounded by a few centimetres
}

TEST(BodyTrajectory, TurnsOnTheSpotToThePathHeadingFirst) {
    const BodyTrajectory t({{0, 0}, {5, 0}}, M_PI_2, 0.0, PathTiming{}, GaitConfig::Go1Trot());
    EXPECT_NEAR(t.PlanarAt(0.0).yaw, M_PI_2, 1e-3);
    const auto mid = t.PlanarAt(t.duration_s() / 2);
    EXPECT_NEAR(mid.yaw, 0.0, 0.02);
}

TEST(BodyTrajectory, IsSmoothAndItsKinematicsAreConsistent) {
    const BodyTrajectory t(LPath(), 0.0, 1.0, PathTiming{}, GaitConfig::Handheld(), 7);
    Eigen::Isometry3d mount = Eigen::Isometry3d::Identity();
    mount.translation() << 0.1, 0.0, 0.2;
    for (double s = 1.0; s < t.duration_s() - 1.0; s += 0.37) {
        const auto k = t.KinematicsAt(s, mount);
        // Velocity integrates to displacement over a short step.
        const double h = 1e-3;
        const Eigen::Vector3d dp =
            (t.Pose(s + h) * mount).translation() - (t.Pose(s - h) * mount).translation();
        EXPECT_LT((dp / (2 * h) - k.v_world).norm(), 1e-3) << s;
        // Specific force is gravity plus acceleration, rotated into the frame.
        const Eigen::Vector3d f = k.T_world_frame.linear() * k.specific_force_frame;
        EXPECT_LT((f - k.a_world - Eigen::Vector3d(0, 0, 9.80665)).norm(), 1e-9);
        // Accelerations stay those of walking (no spikes: the trajectory is C2).
        EXPECT_LT(k.a_world.norm(), 6.0) << s;
        EXPECT_LT(k.omega_frame.norm(), 1.5) << s;
    }
}

TEST(BodyTrajectory, GaitBouncesAtTwiceItsFrequencyAndAveragesToGravity) {
    GaitConfig gait = GaitConfig::Go1Trot();
    const BodyTrajectory t({{0, 0}}, 0.0, 0.0, PathTiming{}, gait);  // trotting in place
    EXPECT_NEAR(t.Pose(0.0).translation().z(), gait.base_height_m + gait.bounce_m, 1e-9);
    EXPECT_NEAR(t.Pose(0.25 / gait.frequency_hz).translation().z(),
                gait.base_height_m - gait.bounce_m, 1e-9);
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    const int n = 200;  // one gait cycle
    for (int i = 0; i < n; ++i) {
        mean += t.KinematicsAt(0.5 + i / (n * gait.frequency_hz), Eigen::Isometry3d::Identity())
                    .specific_force_frame;
    }
    mean /= n;
    EXPECT_NEAR(mean.z(), 9.80665, 0.01);
    // Sideways only what the products of bounce and tilt leave (second order, ~0.015).
    EXPECT_NEAR(mean.head<2>().norm(), 0.0, 0.03);
    // Diagonal pairs alternate.
    const FootContacts c0 = t.ContactsAt(0.1 / gait.frequency_hz);
    const FootContacts c1 = t.ContactsAt(0.6 / gait.frequency_hz);
    EXPECT_TRUE(c0[0] && c0[3] && !c0[1] && !c0[2]);
    EXPECT_TRUE(c1[1] && c1[2] && !c1[0] && !c1[3]);
}

// A flight in the walk (PathPoint): 2 m flat, 10 risers of 0.18 m over 2.8 m, 2 m flat.
std::vector<PathPoint> FlightPath() {
    std::vector<PathPoint> out;
    const double climb = std::atan2(0.18, 0.28);
    out.push_back({{0, 0, 0}, 0, 0, 0});
    out.push_back({{2, 0, 0}, 0, 0, 0});
    for (int k = 0; k < 10; ++k) {
        const double x = 2 + 0.28 * k;
        out.push_back({{x, 0, 0.18 * k}, climb, 1, 0.25});
        out.push_back({{x + 0.001, 0, 0.18 * (k + 1)}, climb, 1, 0.25});
    }
    out.push_back({{4.8, 0, 1.8}, climb, 1, 0.25});
    out.push_back({{6.8, 0, 1.8}, 0, 0, 0});
    return out;
}

TEST(BodyTrajectory, AFlightLiftsTheBodyTreadByTreadAtItsPaceAndPitch) {
    GaitConfig gait = GaitConfig::Go1Trot();
    const BodyTrajectory t(FlightPath(), 0.0, PathTiming{}, gait);
    EXPECT_NEAR(t.floor_z(), 0.0, 1e-12);
    double max_speed_on_flight = 0, max_pitch = 0;
    for (double s = 0; s < t.duration_s(); s += 0.02) {
        const Eigen::Isometry3d T = t.Pose(s);
        const double x = T.translation().x();
        if (x > 2.3 && x < 4.5) {
            max_speed_on_flight = std::max(max_speed_on_flight, t.PlanarAt(s).v_xy.norm());
            // Nose up (negative about y) by the flight's slope, the trot's 0.8 degrees aside.
            max_pitch = std::max(max_pitch, -std::asin(-T.linear()(2, 0)));
            // Over a tread's middle the floor is the tread's; the body above it by its height.
            const double along = x - 2;
            const double f = along / 0.28 - std::floor(along / 0.28);
            if (std::abs(f - 0.5) < 0.1) {
                const double tread = 0.18 * (std::floor(along / 0.28) + 1);
                EXPECT_NEAR(t.FloorZAt(s), tread, 0.005) << "x " << x;
                EXPECT_NEAR(T.translation().z(), tread + gait.base_height_m, 0.005) << "x " << x;
                EXPECT_GT(t.FlightAt(s), 0.99);
            }
        }
    }
    EXPECT_LT(max_speed_on_flight, 0.25 + 1e-3);
    EXPECT_NEAR(max_pitch, std::atan2(0.18, 0.28), 0.02);
    EXPECT_NEAR(t.FloorZAt(t.duration_s()), 1.8, 1e-6);
    EXPECT_NEAR(t.FlightAt(t.duration_s()), 0.0, 1e-6);
}

TEST(BodyTrajectory, AFlatWalkOfPathPointsIsTheWalkOfItsPoints) {
    // The same walk as a Vector2d path and as PathPoints on a floor at 1.5 m: the same motion.
    const std::vector<Eigen::Vector2d> flat = LPath();
    std::vector<PathPoint> points;
    for (const Eigen::Vector2d& p : flat) points.push_back({{p.x(), p.y(), 1.5}, 0, 0, 0});
    const BodyTrajectory a(flat, 0.0, 1.5, PathTiming{}, GaitConfig::Handheld(), 3);
    const BodyTrajectory b(points, 0.0, PathTiming{}, GaitConfig::Handheld(), 3);
    EXPECT_NEAR(a.duration_s(), b.duration_s(), 1e-9);
    for (double s = 0; s < a.duration_s(); s += 0.37) {
        EXPECT_LT((a.Pose(s).matrix() - b.Pose(s).matrix()).norm(), 1e-6) << s;
    }
}

TEST(BodyTrajectory, RejectsBadInput) {
    EXPECT_THROW(BodyTrajectory({}, 0, 0, PathTiming{}, GaitConfig{}), common::Error);
    EXPECT_THROW(BodyTrajectory({{0, NAN}}, 0, 0, PathTiming{}, GaitConfig{}), common::Error);
    PathTiming timing;
    timing.speed_mps = -1;
    try {
        BodyTrajectory({{0, 0}}, 0, 0, timing, GaitConfig{});
        FAIL();
    } catch (const common::Error& e) {
        EXPECT_NE(std::string(e.what()).find("speed_mps"), std::string::npos) << e.what();
    }
}

TEST(ImuModel, BiasesAreFixedAndNoiseHasItsSigma) {
    ImuNoise noise;
    const ImuModel a(noise, 3), b(noise, 3), c(noise, 4);
    EXPECT_EQ(a.gyro_bias(), b.gyro_bias());
    EXPECT_NE(a.gyro_bias(), c.gyro_bias());
    const Eigen::Vector3d f(0, 0, 9.8), w(0.1, 0, 0);
    double sum = 0, sum2 = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
        const ImuMeasurement m = a.Measure(uint64_t(i), f, w);
        EXPECT_EQ(m.gyro, b.Measure(uint64_t(i), f, w).gyro);  // a pure function of the index
        const double e = m.gyro.x() - w.x() - a.gyro_bias().x();
        sum += e;
        sum2 += e * e;
    }
    EXPECT_NEAR(sum / n, 0.0, 5 * noise.gyro_sigma_radps / std::sqrt(n));
    EXPECT_NEAR(std::sqrt(sum2 / n), noise.gyro_sigma_radps, 0.03 * noise.gyro_sigma_radps);
    const ImuModel exact(ImuNoise::Noiseless(), 3);
    EXPECT_EQ(exact.Measure(5, f, w).accel, f);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::simulation
