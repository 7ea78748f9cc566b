#include "drivers/ouster/xyz_lut.hpp"

#include <cmath>

namespace bimslam::ouster {

template <typename Scalar>
XyzLut<Scalar>::XyzLut(const SensorInfo& info)
    : h_(info.format.pixels_per_column), w_(info.format.columns_per_frame) {
    const size_t n = static_cast<size_t>(h_) * w_;
    direction_.resize(n);
    offset_.resize(n);
    // Everything in double; the table is stored in Scalar.
    const Eigen::Matrix3d R = info.lidar_to_sensor_transform.topLeftCorner<3, 3>();
    const Eigen::Vector3d t_mm = info.lidar_to_sensor_transform.topRightCorner<3, 1>();
    const double n_mm = info.beam_to_lidar_transform(0, 3);
    const double z0_mm = info.beam_to_lidar_transform(2, 3);
    const double d_mm = z0_mm != 0.0 ? std::sqrt(n_mm * n_mm + z0_mm * z0_mm) : n_mm;
    for (int u = 0; u < h_; ++u) {
        const double theta_a = -info.beam_azimuth_angles_deg[u] * M_PI / 180.0;
        const double phi = info.beam_altitude_angles_deg[u] * M_PI / 180.0;
        for (int v = 0; v < w_; ++v) {
            const double theta_e = 2.0 * M_PI - v * 2.0 * M_PI / w_;
            const Eigen::Vector3d dir(std::cos(theta_e + theta_a) * std::cos(phi),
                                      std::sin(theta_e + theta_a) * std::cos(phi), std::sin(phi));
            const Eigen::Vector3d off(n_mm * std::cos(theta_e) - d_mm * dir.x(),
                                      n_mm * std::sin(theta_e) - d_mm * dir.y(),
                                      -d_mm * dir.z() + z0_mm);
            direction_[Index(u, v)] = (R * dir).cast<Scalar>();
            offset_[Index(u, v)] = ((R * off + t_mm) * 0.001).cast<Scalar>();
        }
    }
}

template <typename Scalar>
void XyzLut<Scalar>::Compute(const uint32_t* range_mm, Vec3* xyz) const {
    const size_t n = direction_.size();
    for (size_t i = 0; i < n; ++i) {
        const Scalar r = static_cast<Scalar>(range_mm[i]) * Scalar(0.001);
        xyz[i] = range_mm[i] == 0 ? Vec3::Zero() : Vec3(r * direction_[i] + offset_[i]);
    }
}

template class XyzLut<float>;
template class XyzLut<double>;

}  // namespace bimslam::ouster
