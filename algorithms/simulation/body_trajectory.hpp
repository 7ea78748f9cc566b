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

    static GaitConfig Go1Trot();
    // A person walking at 1.8 steps/s, the sensor held at chest height (base 1.2 m).
    static GaitConfig Handheld();
    // A car on a road: its body rides on the suspension at about 1.2 Hz with millimetres of heave
    // and tenths of a degree of pitch and roll; the base is the roof, 1.5 m above the road.
    static GaitConfig Vehicle();
    void Validate() const;
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

    double duration_s() const { return duration_s_ - start_s_; }
    // Where time 0 lies in the walk (PathTiming::start_at_speed; else 0).
    double start_s() const { return start_s_; }
    double length_m() const { return length_m_; }
    double floor_z() const { return floor_z_; }

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
    Eigen::Vector3d SplineAt(double t, int derivative) const;  // (x, y, yaw) or its derivative

    GaitConfig gait_;
    double floor_z_ = 0;
    double duration_s_ = 0;  // of the whole walk, standing included
    double start_s_ = 0;
    double length_m_ = 0;
    double knot_s_ = 0.01;
    std::vector<Eigen::Vector3d> control_;  // (x, y, yaw) every knot_s_
    std::array<double, 9> wobble_phase_{};
};

}  // namespace bimslam::simulation
