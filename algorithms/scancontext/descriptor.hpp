// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The Scan Context descriptor of one scan and its ring and sector keys ([SC] = Kim & Kim, IROS
// 2018; see config.hpp).
//
// Layout: rows are rings, columns are sectors. Ring i holds the points whose horizontal range
// r = sqrt(x^2 + y^2) lies in [i, i + 1) * max_radius / num_rings ([SC] eq. (1); r == max_radius
// goes to the last ring). Sector j holds the azimuths theta = atan2(y, x), taken in [0, 2 pi), in
// [j, j + 1) * 2 pi / num_sectors: sector 0 starts at the +x axis and the index grows
// counter-clockwise seen from +z. Rotating a scan counter-clockwise by k sectors about z therefore
// moves every column k places to the right (cyclically), which is what the distance undoes.
//
// A point is skipped (and counted) when a coordinate is not finite, when r > max_radius, or when
// r == 0 (on the sensor's z axis, where the azimuth is undefined; this includes the exact origin
// that Ouster drivers emit for beams without a return).
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "algorithms/common/point_cloud.hpp"
#include "algorithms/scancontext/config.hpp"

namespace bimslam::scancontext {

// rings x sectors, row-major: the session files (SCDs/*.scd) store it as one line per ring.
using Descriptor = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// What happened to the points of one scan.
struct DescriptorStats {
    size_t used = 0;          // fell into a cell
    size_t non_finite = 0;    // skipped: a NaN or infinite coordinate
    size_t beyond_range = 0;  // ignored: horizontal range > max_radius
    size_t on_axis = 0;       // ignored: horizontal range exactly 0 (includes the origin)
};

// Builds descriptors with preallocated scratch: after the first call with a given output
// matrix, Build allocates nothing and throws nothing (usable on the rig's hot path). Not
// thread-safe; use one builder per thread.
class DescriptorBuilder {
public:
    // Validates the configuration (throws common::Error) and allocates the scratch.
    explicit DescriptorBuilder(const ScanContextConfig& config);

    // Resizes *out to rings x sectors when its shape differs, then fills it; with the z_stack rule
    // its scratch (the scan's heights by cell) grows to the largest scan seen, and nothing else
    // allocates. Empty input gives an all-zero descriptor.
    DescriptorStats Build(std::span<const Eigen::Vector3f> points, Descriptor* out);
    DescriptorStats Build(const common::PointCloud& cloud, Descriptor* out) {
        return Build(std::span<const Eigen::Vector3f>(cloud.xyz), out);
    }

    const ScanContextConfig& config() const { return config_; }

private:
    void TallestStacks(float* d);  // the z_stack rule into d (cells in descriptor order)

    ScanContextConfig config_;
    // Per cell (row-major like the descriptor): maximum and minimum z and the point count.
    std::vector<float> z_max_;
    std::vector<float> z_min_;
    std::vector<uint32_t> count_;
    // z_stack only: (cell, z) of every binned point; the heights grouped by cell (cell c's from
    // start_[c]), and each cell's next free slot while grouping.
    std::vector<std::pair<uint32_t, float>> cell_z_;
    std::vector<float> z_by_cell_;
    std::vector<uint32_t> start_;
    std::vector<uint32_t> fill_;
};

// Convenience for set-up code and tests: validates config, allocates.
Descriptor MakeDescriptor(const common::PointCloud& cloud, const ScanContextConfig& config,
                          DescriptorStats* stats = nullptr);

// Ring key ([SC] Sec. IV-A, eq. (7)): one number per ring, the mean of that ring's cells over all
// sectors (the row means). Invariant to rotation about z, so it can be searched in a KD-tree.
Eigen::VectorXf RingKey(const Descriptor& descriptor);

// Sector key: the mean of each sector's cells over all rings (the column means). Rotating the scan
// shifts it cyclically like the columns; the distance uses it to pre-align the yaw (the reference
// implementation's "variant key" alignment).
Eigen::VectorXf SectorKey(const Descriptor& descriptor);

}  // namespace bimslam::scancontext
