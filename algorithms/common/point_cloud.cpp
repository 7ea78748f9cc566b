// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/common/point_cloud.hpp"

namespace bimslam::common {

void PointCloud::Resize(size_t n, bool with_intensity, bool with_ring, bool with_time) {
    xyz.resize(n, Eigen::Vector3f::Zero());
    if (with_intensity || HasIntensity()) intensity.resize(n, 0.0f);
    if (with_ring || HasRing()) ring.resize(n, 0);
    if (with_time || HasTime()) time_offset_ns.resize(n, 0);
}

void PointCloud::Reserve(size_t n) {
    xyz.reserve(n);
    intensity.reserve(n);
    ring.reserve(n);
    time_offset_ns.reserve(n);
}

void PointCloud::Clear() {
    xyz.clear();
    intensity.clear();
    ring.clear();
    time_offset_ns.clear();
}

void PointCloud::PushBack(const Eigen::Vector3f& p, float i, uint16_t r, uint32_t t_ns) {
    xyz.push_back(p);
    intensity.push_back(i);
    ring.push_back(r);
    time_offset_ns.push_back(t_ns);
}

bool PointCloud::ChannelsConsistent() const {
    const size_t n = xyz.size();
    auto ok = [n](size_t m) { return m == 0 || m == n; };
    return ok(intensity.size()) && ok(ring.size()) && ok(time_offset_ns.size());
}

}  // namespace bimslam::common
