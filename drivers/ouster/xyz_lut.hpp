// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Range to XYZ exactly as specs/ouster-lidar.md "Range -> XYZ" (the Ouster SDK's lookup table):
// per pixel a unit direction and an offset, both in the sensor frame, so that
//     xyz_m(u, v) = range_mm(u, v) * 0.001 * direction(u, v) + offset(u, v).
// Column v is the measurement id (not the encoder count); the image is staggered.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "drivers/ouster/sensor_info.hpp"

namespace bimslam::ouster {

template <typename Scalar>
class XyzLut {
public:
    using Vec3 = Eigen::Matrix<Scalar, 3, 1>;
    explicit XyzLut(const SensorInfo& info);

    int h() const { return h_; }
    int w() const { return w_; }
    Vec3 direction(int u, int v) const;
    Vec3 offset(int u, int v) const;  // metres

    // XYZ for a whole staggered range image (H x W, mm); zero where the range is 0.
    void Compute(const uint32_t* range_mm, Vec3* xyz) const;

private:
    size_t Index(int u, int v) const { return static_cast<size_t>(u) * w_ + v; }
    int h_, w_;
    // Structure of arrays (x, y, z planes of H x W each), so that Compute vectorises.
    std::vector<Scalar> direction_;
    std::vector<Scalar> offset_;
};

extern template class XyzLut<float>;
extern template class XyzLut<double>;

}  // namespace bimslam::ouster
