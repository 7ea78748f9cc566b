// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// LOAM edge features (Zhang & Singh, "LOAM: Lidar Odometry and Mapping in Real-time", RSS 2014,
// section V-A), as an option of the odometry: off by default, because on the project's captures
// they did not pay for their time (README.md, "Why point-to-plane ...").
//
// Along each ring, in column order, LOAM rates each point by its smoothness over its 2K
// neighbours, c_i = |sum_{j != i} (p_j - p_i)|^2 (A-LOAM's form of eq. 1), and takes the least
// smooth as edges. With an OS1's 1-3 cm range noise that picks noise: in a bare room 38 % of the
// points it took lay on no edge (measured with edge_features_test's room). c_i grows with the
// square of the point spacing, so a threshold that keeps corners at 4 m keeps 3-sigma noise too.
// Here a point's sharpness is instead the turn between its chords to the K-th neighbour on
// either side, 1 - cos(angle): a corner of walls turns 90 degrees at any range, while 1 cm of
// noise turns chords of K x 3 cm by a few degrees. Each ring is cut into `sectors` equal parts,
// and each part yields at most `max_per_sector` points of greatest sharpness above
// min_angle_deg, none within K of another (LOAM's non-maximum rule). Chords under min_chord are
// too short to tell a corner from noise.
//
// Rings come from the driver's ring index, never from elevation: an OS1's beams are unevenly
// spaced and offset in azimuth, so points of equal elevation need not share a ring (DESIGN.md,
// drivers/ouster). A window that spans a gap in the columns (lost, cropped or no-return points)
// or a range jump (an occlusion boundary, whose far side moves with the viewpoint) is skipped.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "algorithms/common/point_cloud.hpp"

namespace bimslam::odometry {

struct EdgeFeatureConfig {
    int neighbours = 5;         // K on each side
    int sectors = 6;            // per ring
    int max_per_sector = 20;    // A-LOAM's "less sharp" count
    double min_angle_deg = 45;  // the turn between the chords
    // Chords shorter than this (points close by, densely spaced) are left out: over a few
    // centimetres the range noise turns them as much as a corner would.
    double min_chord = 0.1;       // m
    double max_range_jump = 0.3;  // m between consecutive points of a window
    size_t max_edges = 1500;      // per scan, to bound the registration's time
    int max_rings = 128;

    void Validate() const;
};

class EdgeExtractor {
public:
    explicit EdgeExtractor(const EdgeFeatureConfig& config = {}, size_t max_points = 262144);

    // Edge points of `scan` (deskewed, with ring and time offsets; without rings none are
    // found), in its frame. Valid until the next Run(); no allocation after construction.
    std::span<const Eigen::Vector3f> Run(const common::PointCloud& scan);

    const EdgeFeatureConfig& config() const { return config_; }

private:
    EdgeFeatureConfig config_;
    std::vector<uint32_t> order_;       // point indices grouped by ring, column order within
    std::vector<uint32_t> ring_start_;  // ring r is order_[ring_start_[r], ring_start_[r + 1])
    std::vector<uint32_t> next_;        // counting sort: the next free slot of each ring
    std::vector<float> curvature_;      // sharpness per position in order_, < 0 when unusable
    std::vector<uint8_t> taken_;        // per position in order_: picked or suppressed
    std::vector<uint32_t> candidates_;  // positions of one sector, sorted by curvature
    std::vector<Eigen::Vector3f> edges_;
};

}  // namespace bimslam::odometry
