// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Keyframe selection for a rig session: a scan becomes a keyframe when it is distance_m or
// angle_deg away from the last keyframe (SC-A-LOAM's rule; the paper used 1 m and 10 degrees).
// A keyframe carries its deskewed cloud in its own lidar frame, its indoor Scan Context
// descriptor and the odometry edge from the previous keyframe with the covariance accumulated
// over the scans between them. It hands out io::SessionKeyframe and io::SessionEdge; writing them
// is the caller's (io::SessionWriter), so this stays free of I/O.
#pragma once

#include <cstddef>
#include <optional>

#include "algorithms/common/point_cloud.hpp"
#include "algorithms/common/se3.hpp"
#include "algorithms/io/session.hpp"
#include "algorithms/odometry/lidar_odometry.hpp"
#include "algorithms/scancontext/config.hpp"
#include "algorithms/scancontext/descriptor.hpp"

namespace bimslam::keyframes {

struct KeyframeConfig {
    double distance_m = 1.0;
    double angle_deg = 10.0;
    // A scan with fewer points (all columns lost, a blocked sensor) never becomes a keyframe:
    // its cloud and descriptor would be empty. The next scan with points takes its place.
    size_t min_points = 1000;
    scancontext::ScanContextConfig descriptor = scancontext::ScanContextConfig::Indoor();

    void Validate() const;
};

class KeyframeSelector {
public:
    explicit KeyframeSelector(const KeyframeConfig& config = {});

    // One scan's odometry and its deskewed cloud. True when it becomes a keyframe: keyframe()
    // then holds it and edge() the odometry edge from the previous keyframe (none for the first).
    // After the first keyframe of a given cloud size, this allocates nothing.
    bool Add(const odometry::OdometryResult& scan, const common::PointCloud& deskewed);

    const io::SessionKeyframe& keyframe() const { return keyframe_; }
    const std::optional<io::SessionEdge>& edge() const { return edge_; }
    size_t count() const { return count_; }
    const KeyframeConfig& config() const { return config_; }

private:
    KeyframeConfig config_;
    scancontext::DescriptorBuilder descriptor_builder_;
    io::SessionKeyframe keyframe_;
    std::optional<io::SessionEdge> edge_;
    size_t count_ = 0;
    Eigen::Isometry3d T_odom_last_ = Eigen::Isometry3d::Identity();
    // Covariance of T_last_current (right perturbation), accumulated scan by scan.
    common::Matrix6d covariance_ = common::Matrix6d::Zero();
};

}  // namespace bimslam::keyframes
