// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/simulate/go1_odometry.hpp"

#include <cmath>
#include <random>

#include "algorithms/common/se3.hpp"

namespace bimslam::simulate {
namespace {
// On stairs (a building walk's flights): each step onto a new tread may slip on its nosing, the
// foot sliding back off the edge (the velocity reads slip_factor of the truth for a moment); and
// leg kinematics misjudge each step's height, so the climb reads high and odom_z drifts with
// every storey climbed.
constexpr double kNosingSlipProbability = 0.2;
constexpr double kNosingSlipS = 0.15;
constexpr double kStepDetectM = 0.08;  // the floor moved this far: a step onto the next tread
constexpr double kVerticalScaleError = 0.05;
}  // namespace

Go1OdometryModel::Go1OdometryModel(const simulation::BodyTrajectory& trajectory,
                                   const OdometryNoiseSpec& noise,
                                   const simulation::ImuNoise& imu_noise, uint64_t seed)
    : trajectory_(trajectory), noise_(noise), imu_(imu_noise, seed ^ 0x60160160ull), seed_(seed) {
    yaw_drift_ = noise.yaw_drift_deg_per_min * M_PI / 180.0 / 60.0;
    // Slips: a Poisson process over the whole walk, drawn up front so that they are known.
    std::mt19937_64 rng(seed ^ 0x5119ull);
    if (noise.slips_per_min > 0) {
        std::exponential_distribution<double> gap(noise.slips_per_min / 60.0);
        for (double t = gap(rng); t < trajectory.duration_s(); t += gap(rng)) {
            slips_.push_back({t, t + noise.slip_duration_s});
            t += noise.slip_duration_s;
        }
    }
}

void Go1OdometryModel::StairSteps(double t, std::mt19937_64& rng) {
    const double z = trajectory_.FloorZAt(t);
    if (index_ == 0) step_z_ = z;
    if (std::abs(z - step_z_) < kStepDetectM) return;
    step_z_ = z;
    if (std::uniform_real_distribution<double>(0, 1)(rng) < kNosingSlipProbability) {
        slips_.push_back({t, t + kNosingSlipS});
        ++nosing_slips_;
    }
}

can::Go1Sample Go1OdometryModel::Next(double t) {
    const simulation::BodyTrajectory::Planar p = trajectory_.PlanarAt(t);
    const simulation::BodyTrajectory::Kinematics k =
        trajectory_.KinematicsAt(t, Eigen::Isometry3d::Identity());
    std::mt19937_64 rng(seed_ ^ (0x9E3779B97F4A7C15ull * (index_ + 1)));
    std::normal_distribution<double> normal(0.0, 1.0);

    // Leg odometry: the body-frame planar velocity, scaled, noisy, slipping.
    const Eigen::Rotation2Dd R(p.yaw);
    Eigen::Vector2d v = R.inverse() * p.v_xy;
    v *= 1.0 + noise_.scale_error;
    v += noise_.velocity_sigma_mps * Eigen::Vector2d(normal(rng), normal(rng));
    StairSteps(t, rng);
    for (const SlipInterval& s : slips_) {
        if (t >= s.begin_s && t < s.end_s) v *= noise_.slip_factor;
    }
    const double yaw_rate = p.yaw_rate + yaw_drift_;

    // Unitree's dead reckoning integrates what it reports.
    const double dt = index_ == 0 ? 0.0 : t - last_t_;
    odom_yaw_ += yaw_rate * dt;
    odom_x_ += dt * (std::cos(odom_yaw_) * v.x() - std::sin(odom_yaw_) * v.y());
    odom_y_ += dt * (std::sin(odom_yaw_) * v.x() + std::cos(odom_yaw_) * v.y());
    if (trajectory_.FlightAt(t) > 0) {
        // On a flight: the step heights read high, and odom_z integrates them.
        odom_z_ += dt * k.v_world.z() * (1.0 + kVerticalScaleError);
    }
    last_t_ = t;

    can::Go1Sample s;
    s.udp_link_ok = true;
    s.highstate_crc_ok = true;
    s.sample_age_us = 800;
    s.valid = can::kAllGroups;
    s.vx = v.x();
    s.vy = v.y();
    s.yaw_rate = yaw_rate;
    // BST_Vz carries HighState.velocity[2], which comm.h documents as "rotateSpeed in body
    // frame" (velocity[3] = forwardSpeed, sideSpeed, rotateSpeed), not a vertical speed
    // (drivers/go1/README.md, "Field meanings"): the robot's yaw rate, as the SDK says.
    s.vz = yaw_rate;
    s.body_height = k.T_world_frame.translation().z() - trajectory_.FloorZAt(t);
    s.foot_raise_height = 0.08;
    const simulation::ImuMeasurement imu =
        imu_.Measure(index_, k.specific_force_frame, k.omega_frame);
    for (int i = 0; i < 3; ++i) {
        s.gyro[size_t(i)] = imu.gyro[i];
        s.accel[size_t(i)] = imu.accel[i];
    }
    // Roll and pitch as they are, yaw as the Go1 believes it.
    const Eigen::Matrix3d R3 = k.T_world_frame.linear();
    const double true_yaw = common::Heading(R3);
    const Eigen::Quaterniond q(Eigen::AngleAxisd(odom_yaw_ - true_yaw, Eigen::Vector3d::UnitZ()) *
                               R3);
    s.quat_wxyz = {q.w(), q.x(), q.y(), q.z()};
    const simulation::FootContacts contacts = trajectory_.ContactsAt(t);
    for (size_t leg = 0; leg < 4; ++leg) {
        s.foot_contact[leg] = contacts[leg];
        // Raw force: about a quarter of the Go1's 12 kg on each stance foot (trot: two feet).
        s.foot_force_raw[leg] = contacts[leg] ? uint16_t(420 + int(20 * normal(rng))) : uint16_t(8);
    }
    s.odom_x = odom_x_;
    s.odom_y = odom_y_;
    s.odom_z = odom_z_;
    s.odom_yaw = std::remainder(odom_yaw_, 2 * M_PI);
    s.mode = 2;          // VEL_WALK
    s.gait = 1;          // TROT
    s.bridge_state = 1;  // RUNNING
    s.battery_soc = 87;
    s.imu_temperature_c = 38;
    ++index_;
    return s;
}

}  // namespace bimslam::simulate
