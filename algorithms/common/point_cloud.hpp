// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// A point cloud as a structure of arrays.
//
// xyz is always present; intensity, ring and time offset are optional channels, present when
// their array has one entry per point and absent when empty. Keeping channels apart lets the
// hot path touch only what it needs and lets readers fill exactly the fields a file holds.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "algorithms/common/time.hpp"

namespace bimslam::common {

struct PointCloud {
    // Metres, in the frame named by `frame` (e.g. "lidar").
    std::vector<Eigen::Vector3f> xyz;
    // Sensor-specific return strength (Ouster: reflectivity or signal), unitless.
    std::vector<float> intensity;
    // Beam index from the driver, 0 = top beam; never guessed from elevation.
    std::vector<uint16_t> ring;
    // Nanoseconds since `stamp`, the start of the scan this point belongs to.
    std::vector<uint32_t> time_offset_ns;

    SensorTime stamp;  // time of the scan start
    std::string frame = "lidar";

    size_t size() const { return xyz.size(); }
    bool empty() const { return xyz.empty(); }
    bool HasIntensity() const { return !intensity.empty(); }
    bool HasRing() const { return !ring.empty(); }
    bool HasTime() const { return !time_offset_ns.empty(); }

    // Sizes every present channel to n (new entries zero); channels named by the flags are
    // created when missing. Allocation happens here, never in PushBack below capacity.
    void Resize(size_t n, bool with_intensity, bool with_ring, bool with_time);
    void Reserve(size_t n);
    void Clear();

    // Appends to xyz only, or to all four channels. Mixing the two on one cloud leaves the
    // channels inconsistent, which ChannelsConsistent() reports.
    void PushBack(const Eigen::Vector3f& p) { xyz.push_back(p); }
    void PushBack(const Eigen::Vector3f& p, float i, uint16_t r, uint32_t t_ns);

    // True when every optional channel is either empty or as long as xyz.
    bool ChannelsConsistent() const;
};

}  // namespace bimslam::common
