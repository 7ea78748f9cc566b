// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// An IMU's measurement model for the capture simulator: the true angular rate and specific force
// (BodyTrajectory::Kinematics) plus a constant bias per axis, drawn once from N(0, bias_sigma^2),
// and white noise per sample, N(0, sigma^2):
//     gyro  = omega + b_g + n_g,      accel = f + b_a + n_a.
// The noise of sample k comes from a counter-based hash of (seed, k), so a capture is the same
// whatever order samples are drawn in.
#pragma once

#include <Eigen/Core>
#include <cstdint>

namespace bimslam::simulation {

struct ImuNoise {
    double accel_sigma_mps2 = 0.02;
    double gyro_sigma_radps = 0.001;
    double accel_bias_sigma_mps2 = 0.05;
    double gyro_bias_sigma_radps = 0.0035;

    static ImuNoise Noiseless() { return {0, 0, 0, 0}; }
    // Throws common::Error (kInvalidArgument) naming the field and value.
    void Validate() const;
};

struct ImuMeasurement {
    Eigen::Vector3d accel = Eigen::Vector3d::Zero();  // m/s^2, specific force
    Eigen::Vector3d gyro = Eigen::Vector3d::Zero();   // rad/s
};

class ImuModel {
public:
    ImuModel(const ImuNoise& noise, uint64_t seed);

    // Sample number `index` of the true specific force and angular rate.
    ImuMeasurement Measure(uint64_t index, const Eigen::Vector3d& specific_force,
                           const Eigen::Vector3d& omega) const;

    const Eigen::Vector3d& accel_bias() const { return accel_bias_; }
    const Eigen::Vector3d& gyro_bias() const { return gyro_bias_; }

private:
    ImuNoise noise_;
    uint64_t seed_;
    Eigen::Vector3d accel_bias_ = Eigen::Vector3d::Zero();
    Eigen::Vector3d gyro_bias_ = Eigen::Vector3d::Zero();
};

}  // namespace bimslam::simulation
