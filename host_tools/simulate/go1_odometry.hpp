// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// What a Go1 reports about its own motion while it walks a BodyTrajectory, as the bridge would
// send it over CAN (drivers/can/go1_odometry.dbc): one Go1Sample every 10 ms, with the errors of
// leg odometry (specs/go1-can.md, HighState):
//   vx, vy   = (1 + scale_error) * v_body + N(0, velocity_sigma^2), times slip_factor while a foot
//              slips (Poisson events, slips_per_min, each slip_duration_s long);
//   yaw_rate = true planar yaw rate + yaw drift (a constant bias);
//   odom_x, odom_y, odom_yaw: those integrated from 0 (Unitree's own dead reckoning);
//   gyro, accel: the trunk IMU (true rate and specific force of the base, with the IMU noise);
//   on a flight of stairs: a step onto a tread slips on its nosing with probability 0.2 (0.15 s
//   at slip_factor), and odom_z integrates the vertical speed read 5 % high (0 on one storey);
//   quat: roll and pitch true, yaw the drifting odometry yaw (the Go1's estimator cannot observe
//   yaw); foot contacts from the gait; body height; mode VEL_WALK, gait TROT.
#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include "algorithms/simulation/body_trajectory.hpp"
#include "algorithms/simulation/imu_model.hpp"
#include "drivers/can/go1_sample.hpp"
#include "host_tools/simulate/scenario.hpp"

namespace bimslam::simulate {

struct SlipInterval {
    double begin_s = 0, end_s = 0;
};

class Go1OdometryModel {
public:
    Go1OdometryModel(const simulation::BodyTrajectory& trajectory, const OdometryNoiseSpec& noise,
                     const simulation::ImuNoise& imu_noise, uint64_t seed);

    // The sample at trajectory time t; samples must be asked for in increasing t (the odometry is
    // integrated from one to the next). bridge_time_ns is left to the caller.
    can::Go1Sample Next(double t);

    const std::vector<SlipInterval>& slips() const { return slips_; }
    double yaw_drift_radps() const { return yaw_drift_; }
    size_t nosing_slips() const { return nosing_slips_; }

private:
    // A step up or down a flight: the floor under the body moved by a riser since the last one;
    // it may slip on the nosing (added to slips_).
    void StairSteps(double t, std::mt19937_64& rng);

    const simulation::BodyTrajectory& trajectory_;
    OdometryNoiseSpec noise_;
    simulation::ImuModel imu_;
    uint64_t seed_;
    double yaw_drift_ = 0;
    std::vector<SlipInterval> slips_;
    uint64_t index_ = 0;
    double last_t_ = 0;
    double odom_x_ = 0, odom_y_ = 0, odom_yaw_ = 0, odom_z_ = 0;
    double step_z_ = 0;
    size_t nosing_slips_ = 0;
};

}  // namespace bimslam::simulate
