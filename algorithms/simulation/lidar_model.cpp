// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/simulation/lidar_model.hpp"

#include <Eigen/LU>  // determinant()
#include <cmath>
#include <string>

#include "algorithms/common/status.hpp"
#include "algorithms/simulation/measurement_math.hpp"

namespace bimslam::simulation {
namespace {
using common::StatusCode;

void Require(bool ok, const std::string& field, double value, const char* rule) {
    if (!ok) {
        throw common::Error(StatusCode::kInvalidArgument,
                            "LidarModel." + field + " = " + std::to_string(value) + ": " + rule);
    }
}

using detail::kDegToRad;
}  // namespace

void LidarModel::Validate() const {
    Require(!beam_altitude_deg.empty(), "beam_altitude_deg.size()", 0, "must be >= 1");
    Require(beam_azimuth_deg.size() == beam_altitude_deg.size(), "beam_azimuth_deg.size()",
            double(beam_azimuth_deg.size()), "must equal beam_altitude_deg.size()");
    for (size_t u = 0; u < beam_altitude_deg.size(); ++u) {
        const std::string i = "[" + std::to_string(u) + "]";
        Require(std::isfinite(beam_altitude_deg[u]) && std::abs(beam_altitude_deg[u]) <= 90.0,
                "beam_altitude_deg" + i, beam_altitude_deg[u], "must be in [-90, 90]");
        Require(std::isfinite(beam_azimuth_deg[u]) && std::abs(beam_azimuth_deg[u]) <= 360.0,
                "beam_azimuth_deg" + i, beam_azimuth_deg[u], "must be in [-360, 360]");
    }
    Require(columns >= 1, "columns", columns, "must be >= 1");
    Require(std::isfinite(frame_rate_hz) && frame_rate_hz > 0, "frame_rate_hz", frame_rate_hz,
            "must be > 0");
    Require(std::isfinite(beam_origin_mm), "beam_origin_mm", beam_origin_mm, "must be finite");
    Require(std::isfinite(beam_z_mm), "beam_z_mm", beam_z_mm, "must be finite");
    const Eigen::Matrix4d& T = lidar_to_sensor_transform;
    Require(T.allFinite(), "lidar_to_sensor_transform", 0, "must be finite");
    const Eigen::Matrix3d R = T.topLeftCorner<3, 3>();
    const double orthonormality = (R.transpose() * R - Eigen::Matrix3d::Identity()).norm();
    Require(orthonormality < 1e-6 && R.determinant() > 0, "lidar_to_sensor_transform",
            orthonormality, "rotation part must be orthonormal with determinant +1");
    Require(T.row(3).isApprox(Eigen::RowVector4d(0, 0, 0, 1)), "lidar_to_sensor_transform[3]",
            T(3, 3), "last row must be 0 0 0 1");
}

namespace {
// specs/ouster-lidar.md "Range -> XYZ", in the lidar frame (before lidar_to_sensor_transform):
//     theta_e = 2 pi - v 2 pi / W,  theta_a = -azimuth[u],  phi = altitude[u]
//     dir = (cos(theta_e + theta_a) cos phi, sin(theta_e + theta_a) cos phi, sin phi)
//     off = (n cos theta_e - d dir.x, n sin theta_e - d dir.y, -d dir.z + z0)   [mm]
// The same expressions, in the same order, as drivers/ouster XyzLut, so both agree to rounding.
struct LidarRay {
    Eigen::Vector3d dir;
    Eigen::Vector3d off_mm;
};

LidarRay RayInLidarFrame(const LidarModel& m, int u, int v) {
    const double theta_e = 2.0 * M_PI - v * 2.0 * M_PI / m.columns;
    const double theta_a = -m.beam_azimuth_deg[u] * kDegToRad;
    const double phi = m.beam_altitude_deg[u] * kDegToRad;
    LidarRay r;
    r.dir = Eigen::Vector3d(std::cos(theta_e + theta_a) * std::cos(phi),
                            std::sin(theta_e + theta_a) * std::cos(phi), std::sin(phi));
    const double n = m.beam_origin_mm, z0 = m.beam_z_mm;
    const double d = z0 != 0.0 ? std::sqrt(n * n + z0 * z0) : n;
    r.off_mm = Eigen::Vector3d(n * std::cos(theta_e) - d * r.dir.x(),
                               n * std::sin(theta_e) - d * r.dir.y(), -d * r.dir.z() + z0);
    return r;
}
}  // namespace

// dir' = R dir (spec, "Range -> XYZ").
Eigen::Vector3d LidarModel::Direction(int u, int v) const {
    return lidar_to_sensor_transform.topLeftCorner<3, 3>() * RayInLidarFrame(*this, u, v).dir;
}

// off' = R off + t, in mm in the spec; metres here.
Eigen::Vector3d LidarModel::Origin(int u, int v) const {
    const Eigen::Matrix3d R = lidar_to_sensor_transform.topLeftCorner<3, 3>();
    const Eigen::Vector3d t = lidar_to_sensor_transform.topRightCorner<3, 1>();
    return (R * RayInLidarFrame(*this, u, v).off_mm + t) * 0.001;
}

// The spec's d: the table's origin is d behind the emission point along the ray (off has the
// -d dir term), so a ray's emission point is Origin + d Direction.
double LidarModel::BeamOriginDistance() const {
    const double n = beam_origin_mm, z0 = beam_z_mm;
    return (z0 != 0.0 ? std::sqrt(n * n + z0 * z0) : n) * 0.001;
}

// Columns are evenly spaced in time over one rotation (spec: ~97.7 us apart in 1024x10).
int64_t LidarModel::ColumnTimeOffsetNs(int v) const {
    return std::llround(v * 1e9 / (frame_rate_hz * columns));
}

LidarModel LidarModel::DefaultOs1_32(int columns, double rate_hz) {
    LidarModel m;
    m.columns = columns;
    m.frame_rate_hz = rate_hz;
    const double column_azimuth_deg[4] = {4.23, 1.41, -1.41, -4.23};
    for (int u = 0; u < 32; ++u) {
        m.beam_altitude_deg.push_back(22.5 - 45.0 * u / 31.0);
        m.beam_azimuth_deg.push_back(column_azimuth_deg[u % 4]);
    }
    m.beam_origin_mm = 15.806;
    m.beam_z_mm = 0.0;
    m.lidar_to_sensor_transform << -1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1, 36.18, 0, 0, 0, 1;
    m.Validate();
    return m;
}

}  // namespace bimslam::simulation
