// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The motion of a platform (a Go1 trotting, a person carrying the sensor, or a vehicle) along a
// planar path, as a continuous-time trajectory that is smooth in SE(3): the pose of the platform's
// base at any time, from which the capture simulator takes the sensor's pose per LiDAR column
// (the rolling shutter), the IMU's specific force and angular rate, and the leg odometry.
//
// Construction:
// 1. Timing: the path is resampled every 5 cm, its heading smoothed over half a metre; the speed
//    at each point is the least of the cruise speed, max_yaw_rate / curvature and
//    sqrt(max_lateral_accel / curvature); a forward and a backward pass limit acceleration and
//    braking to max_accel (v_i^2 <= v_{i-1}^2 + 2 a ds), from rest at the start to rest at the
//    end; a step also lasts at least its heading change / max_yaw_rate (a turn on the spot).
//    Before the walk, a turn on the spot from the start yaw to the path's heading; one second of
//    standing still at each end.
// 2. The planar motion (x, y, yaw) sampled at 100 Hz is smoothed by a Gaussian (sigma 0.1 s) and
//    taken as the control points of a uniform cubic B-spline (knots 10 ms apart): C2, so the
//    velocity and acceleration the IMU sees are continuous.
// 3. The gait rides on it, as sinusoids of the gait phase (GaitConfig): a trotting Go1 bounces
//    twice per gait cycle and rolls towards its stance pair; a person's steps bob the sensor,
//    sway it sideways and rock it.
// Pose: T_world_base = Trans(x, y, floor_z + base_height + bounce) * Rz(yaw + yaw_osc) *
// Ry(pitch_osc) * Rx(roll_osc) * Trans(0, sway, 0).
//
// Stairs (the PathPoint constructor): the path carries the floor's height under the platform, the
// flight's slope and a lower pace on flights. The floor height, a step function on a flight (each
// riser a step up), is smoothed with the planar motion: the body rises one riser per step over
// about 0.3 s, which is both the bob of climbing and the vertical jolt of each step in the IMU.
// On a flight the gait's bounce fades out (the steps replace it) and the body pitches by
// stair_pitch_share of the flight's slope (nose up climbing): Ry(pitch_osc - share * climb).
//
// Derivatives (velocities, accelerations, angular rates) are taken by central differences of
// the pose with h = 0.5 ms: the pose is C2, and the error, O(h^2) times the fourth derivative,
// is below 1e-3 m/s^2 for the gaits below (far below any IMU's noise).
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <vector>

namespace bimslam::simulation {

struct PathTiming {
    double speed_mps = 0.5;
    double max_accel_mps2 = 0.5;
    double max_yaw_rate_radps = 1.0;
    double max_lateral_accel_mps2 = 0.5;
    double stand_s = 1.0;  // standing still before and after the walk
    // Time 0 is where the walk first reaches 95 % of its cruise speed instead of standing still
    // before it: a recording that starts in motion (issue 17, item 2).
    bool start_at_speed = false;

    // Throws common::Error (kInvalidArgument) naming the field and value.
    void Validate() const;
};

struct GaitConfig {
    double base_height_m = 0.32;  // the base above the floor (Go1 trunk centre when standing)
    double frequency_hz = 2.0;    // gait cycles per second (a Go1 trot: each diagonal pair once)
    double bounce_m = 0.005;      // vertical, at twice the gait frequency
    double sway_m = 0.0;          // sideways, at the gait frequency
    double roll_deg = 1.5;        // at the gait frequency
    double pitch_deg = 0.8;       // at twice the gait frequency
    double yaw_deg = 0.5;         // at the gait frequency
    double duty_factor = 0.55;    // the share of a cycle a foot is on the ground
    // Slow hand wobble (handheld): three incommensurate sinusoids (0.31, 0.53, 0.87 Hz) per
    // rotation axis, this amplitude each.
    double wobble_deg = 0.0;
    // On a flight of stairs the body pitches by this share of the flight's slope: a Go1's trunk
    // lies along the flight (1); a person holding the rig leans and looks along it (0.5).
    double stair_pitch_share = 1.0;

    static GaitConfig Go1Trot();
    // A person walking at 1.8 steps/s, the sensor held at chest height (base 1.2 m).
    static GaitConfig Handheld();
    // A car on a road: its body rides on the suspension at about 1.2 Hz with millimetres of heave
    // and tenths of a degree of pitch and roll; the base is the roof, 1.5 m above the road.
    static GaitConfig Vehicle();
    void Validate() const;
};

// A point of a walk over floors and stairs.
struct PathPoint {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();  // x, y, and the floor's height under the platform
    double climb_rad = 0.0;      // the floor's slope along the walk, positive up (a flight's pitch)
    double flight = 0.0;         // 1 on a flight of stairs, 0 on a floor
    double max_speed_mps = 0.0;  // a slower pace here (a flight); 0: the cruise speed
};

// Legs FR, FL, RR, RL (the Go1's order).
using FootContacts = std::array<bool, 4>;

class BodyTrajectory {
public:
    // `path`: the planar walk in world x y (at least one point; consecutive duplicates are
    // dropped), starting where the walk starts; `start_yaw` the heading the platform stands at
    // first; `floor_z` the floor's height. `seed` fixes the phases of the wobble. Throws
    // common::Error for invalid configurations or a non-finite path.
    BodyTrajectory(const std::vector<Eigen::Vector2d>& path, double start_yaw, double floor_z,
                   const PathTiming& timing, const GaitConfig& gait, uint64_t seed = 0);
    // A walk over floors and stairs (file comment, "Stairs"). floor_z() is the first point's.
    BodyTrajectory(const std::vector<PathPoint>& path, double start_yaw, const PathTiming& timing,
                   const GaitConfig& gait, uint64_t seed = 0);

    double duration_s() const { return duration_s_ - start_s_; }
    // Where time 0 lies in the walk (PathTiming::start_at_speed; else 0).
    double start_s() const { return start_s_; }
    double length_m() const { return length_m_; }
    double floor_z() const { return floor_z_; }
    // The floor under the platform at time t (smoothed over each step on a flight), and how much
    // the platform is on a flight (0 on a floor, 1 on a flight; between while stepping on or off).
    double FloorZAt(double t) const;
    double FlightAt(double t) const;

    // T_world_base at time t (seconds from the start; clamped to [0, duration]).
    Eigen::Isometry3d Pose(double t) const;
    // The planar motion without the gait: x, y, yaw and their rates (yaw_rate about world z),
    // what leg odometry estimates.
    struct Planar {
        Eigen::Vector2d xy = Eigen::Vector2d::Zero();
        double yaw = 0;
        Eigen::Vector2d v_xy = Eigen::Vector2d::Zero();  // world frame
        double yaw_rate = 0;
    };
    Planar PlanarAt(double t) const;
    FootContacts ContactsAt(double t) const;

    // Kinematics of a frame rigidly attached to the base (T_base_frame), at time t: its pose,
    // its velocity and acceleration in the world, its angular velocity in its own frame, and the
    // specific force an accelerometer there measures, in its own frame: R^T (a - g), with
    // g = (0, 0, -9.80665).
    struct Kinematics {
        Eigen::Isometry3d T_world_frame = Eigen::Isometry3d::Identity();
        Eigen::Vector3d v_world = Eigen::Vector3d::Zero();
        Eigen::Vector3d a_world = Eigen::Vector3d::Zero();
        Eigen::Vector3d omega_frame = Eigen::Vector3d::Zero();
        Eigen::Vector3d specific_force_frame = Eigen::Vector3d::Zero();
    };
    Kinematics KinematicsAt(double t, const Eigen::Isometry3d& T_base_frame) const;

private:
    // The path every 5 cm with its attributes; for a path of Vector2d (flat) exactly as before.
    struct Resampled {
        std::vector<Eigen::Vector2d> xy;
        std::vector<Eigen::Vector3d> profile;  // (floor z, climb, flight); empty when flat
        std::vector<double> max_speed;         // empty when flat
    };
    void Build(const Resampled& path, double start_yaw, const PathTiming& timing, uint64_t seed);
    Eigen::Vector3d SplineAt(double t, int derivative) const;  // (x, y, yaw) or its derivative
    Eigen::Vector3d ProfileAt(double t) const;  // (floor z, climb, flight); flat: (floor_z, 0, 0)

    GaitConfig gait_;
    double floor_z_ = 0;
    double duration_s_ = 0;  // of the whole walk, standing included
    double start_s_ = 0;
    double length_m_ = 0;
    double knot_s_ = 0.01;
    std::vector<Eigen::Vector3d> control_;  // (x, y, yaw) every knot_s_
    std::vector<Eigen::Vector3d> profile_;  // (floor z, climb, flight) every knot_s_; empty: flat
    std::array<double, 9> wobble_phase_{};
};

}  // namespace bimslam::simulation
