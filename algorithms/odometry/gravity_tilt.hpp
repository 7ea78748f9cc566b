// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The odometry frame's tilt from the accelerometers: gravity as the reference that holds roll and
// pitch, which scan-to-map registration lets wander (issue 31, item 4).
//
// Why. Registered to its own local map, the odometry keeps its tilt only as well as the map it
// built: the Go1's stair walks drift 0.2-0.4 deg in roll and pitch over a minute, and across 10 m
// of floor that is 4-6 cm of height (README.md, "Gravity holds the tilt"). Gravity does not drift.
//
// Why not the accelerometers' mean. Their bias (0.05 m/s^2 per axis in the simulator, as MEMS
// parts have) tilts the mean by 0.3 deg, as much as the drift; and the walk's accelerations are in
// it. So the filter holds the bias apart: the bias is fixed in the sensor, the tilt in the
// odometry frame, and as the walk turns they separate (as LIO filters do, e.g. FAST-LIO's
// gravity in the state; here only roll, pitch and the bias, the rest is the registration's).
//
// Model. A Kalman filter of x = [t t0 b]: t = t1 e1 + t2 e2 (e1, e2 across `up`) the true up's
// offset from `up` in the poses' frame now, t0 the same at the start, and b the accelerometers'
// bias (lidar frame). Over a window between scans a and b, the accelerometers turned into the
// frame by the poses' rotations and the gyro, less the change of the mean velocity the registered
// positions give (each end's mean over velocity_scans, the accelerometers weighted by the same
// trapezoid so that both sides are the same integral):
//   sum w R f dt - (v_b - v_a) = g T (up + t) + (sum w R dt) b + noise,   T = sum w dt.
// The tilt walks (the map the poses are registered to drifts), the bias too, slowly; t0 stays. At
// the start the accelerometers' mean gave `up`, so up + t0 and the mean differ by the bias and the
// walk's own acceleration (a prior). The frame is levelled back to t0, not to gravity: a start
// that was not level (in motion) would otherwise bend the walk where the levelling began.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <deque>

namespace bimslam::odometry {

struct GravityTiltConfig {
    int window_scans = 10;            // scans between two updates (1 s at 10 Hz)
    int velocity_scans = 5;           // each end's mean velocity over these many scans
    double accel_noise = 0.03;        // m/s^2/sqrt(Hz): the specific force's white noise
    double position_sigma = 0.003;    // m: a registered scan's position, for the mean velocities
    double tilt_walk = 1e-3;          // rad/sqrt(s): the registered frame's tilt wanders
    double bias_walk = 1e-4;          // m/s^2/sqrt(s)
    double initial_bias_sigma = 0.1;  // m/s^2 per axis
    // At the start, the true up against the accelerometers' mean less the bias: the walk's own
    // acceleration over the mean's window (rad; at rest a tenth of it).
    double start_sigma = 0.01;
    // The tilt corrects the poses once known to this (1-sigma, rad: 0.17 deg).
    double ready_sigma = 0.003;

    // Throws common::Error naming the field and value when out of range.
    void Validate() const;
};

class GravityTilt {
public:
    explicit GravityTilt(const GravityTiltConfig& config = {});

    // Starts with `up` (unit, odometry frame), the accelerometers' mean direction at the start,
    // with the lidar at rotation R0 then; at_rest: the start's motion is nil.
    void Reset(const Eigen::Vector3d& up, const Eigen::Matrix3d& R0, bool at_rest);
    bool initialized() const { return initialized_; }

    // One scan at stamp_ns, its registered position p, and the accelerometers since the last
    // scan: sum R f dt and sum R dt over dt seconds (R: the lidar's rotation, odometry frame).
    // ok = false (the IMU did not cover the interval, or the scan's registration is not to be
    // trusted): the window starts again after it. Returns the rotation to level the scan's pose
    // with (applied to its rotation, about its position): at the end of a window, once the drift
    // is known to ready_sigma, the tilt the frame drifted by since the start; else the identity.
    Eigen::Matrix3d AddScan(int64_t stamp_ns, const Eigen::Vector3d& p,
                            const Eigen::Vector3d& Rf_dt, const Eigen::Matrix3d& R_dt, double dt,
                            bool ok);
    bool ready() const;
    // The true up's offset from `up` (odometry frame) now and at the start; the 1-sigma of their
    // difference, the drift (rad, the larger axis).
    Eigen::Vector3d tilt() const { return x_(0) * e1_ + x_(1) * e2_; }
    Eigen::Vector3d start_tilt() const { return x_(2) * e1_ + x_(3) * e2_; }
    double drift_sigma() const;
    Eigen::Vector3d bias() const { return x_.tail<3>(); }
    size_t updates() const { return updates_; }

private:
    struct Step {
        int64_t stamp_ns;
        Eigen::Vector3d p, Rf_dt;
        Eigen::Matrix3d R_dt;
        double dt;
    };
    bool Update();  // false when the window cannot be measured

    GravityTiltConfig config_;
    bool initialized_ = false;
    Eigen::Vector3d up_ = Eigen::Vector3d::UnitZ(), e1_ = Eigen::Vector3d::UnitX(),
                    e2_ = Eigen::Vector3d::UnitY();
    Eigen::Matrix<double, 7, 1> x_ = Eigen::Matrix<double, 7, 1>::Zero();  // [t t0 b]
    Eigen::Matrix<double, 7, 7> P_ = Eigen::Matrix<double, 7, 7>::Identity();
    std::deque<Step> steps_;  // the window's scans and the velocity's before it
    int since_update_ = 0;
    size_t updates_ = 0;
};

}  // namespace bimslam::odometry
