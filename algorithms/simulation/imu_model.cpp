// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/simulation/imu_model.hpp"

#include <cmath>
#include <string>

#include "algorithms/common/status.hpp"
#include "algorithms/simulation/measurement_math.hpp"

namespace bimslam::simulation {
namespace {

// Standard normals number `first`, first + 1, first + 2 of a counter-based stream.
Eigen::Vector3d Normal3(const detail::PixelRandom& r, uint64_t first) {
    return {detail::InverseNormalCdf(r.Uniform(first)),
            detail::InverseNormalCdf(r.Uniform(first + 1)),
            detail::InverseNormalCdf(r.Uniform(first + 2))};
}

}  // namespace

void ImuNoise::Validate() const {
    for (const auto& [name, v] : {std::pair{"accel_sigma_mps2", accel_sigma_mps2},
                                  {"gyro_sigma_radps", gyro_sigma_radps},
                                  {"accel_bias_sigma_mps2", accel_bias_sigma_mps2},
                                  {"gyro_bias_sigma_radps", gyro_bias_sigma_radps}}) {
        if (!(std::isfinite(v) && v >= 0 && v < 10)) {
            throw common::Error(common::StatusCode::kInvalidArgument,
                                std::string("ImuNoise.") + name + " = " + std::to_string(v) +
                                    ": must be in [0, 10)");
        }
    }
}

ImuModel::ImuModel(const ImuNoise& noise, uint64_t seed) : noise_(noise), seed_(seed) {
    noise.Validate();
    // The biases: the stream of "sample" 2^64 - 1, which no capture reaches.
    const detail::PixelRandom r(seed_, ~uint64_t(0));
    accel_bias_ = noise_.accel_bias_sigma_mps2 * Normal3(r, 0);
    gyro_bias_ = noise_.gyro_bias_sigma_radps * Normal3(r, 3);
}

ImuMeasurement ImuModel::Measure(uint64_t index, const Eigen::Vector3d& specific_force,
                                 const Eigen::Vector3d& omega) const {
    const detail::PixelRandom r(seed_, index);
    return {specific_force + accel_bias_ + noise_.accel_sigma_mps2 * Normal3(r, 0),
            omega + gyro_bias_ + noise_.gyro_sigma_radps * Normal3(r, 3)};
}

}  // namespace bimslam::simulation
