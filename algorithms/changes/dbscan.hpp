// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// DBSCAN (Ester, Kriegel, Sander, Xu, KDD 1996) on 3D points, exact, in O(n log n): the grid
// variant of Gunawan (2013) / Gan & Tao (SIGMOD 2015). Cells have side eps / sqrt(3), so any two
// points of a cell are within eps: a cell holding a core point belongs to one cluster as a whole,
// and clusters are unions of cells. Steps:
//   1. core points: at least min_points points (the point itself included, as Open3D's
//      cluster_dbscan and scikit-learn count) within eps. A cell with min_points points is all
//      core; otherwise each point counts its neighbours in the 5 x 5 x 5 cells around it.
//   2. cells with core points are joined (union-find) when some core point of one is within eps of
//      a core point of the other; pairs already joined are not compared again.
//   3. border points (not core, within eps of a core point) take the cluster of their nearest core
//      point; the rest is noise (-1).
// Cluster labels are 0, 1, ... in the order of the first core point of each cluster, so the result
// depends only on the points and their order, never on the number of threads. Steps 1 and 3 run
// in parallel (TBB).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <span>
#include <vector>

namespace bimslam::changes {

struct DbscanConfig {
    double eps_m = 0.15;  // neighbourhood radius
    int min_points = 8;   // neighbours (itself included) that make a core point
    // Throws common::Error (kInvalidArgument) naming the field and the value.
    void Validate() const;
};

struct DbscanResult {
    std::vector<int32_t> labels;  // per point: cluster 0 ... clusters - 1, or -1 for noise
    int32_t clusters = 0;
    size_t core_points = 0;
};

DbscanResult Dbscan(std::span<const Eigen::Vector3f> points, const DbscanConfig& config);

// The axis-aligned box of the points that `indices` names (a cluster's points).
Eigen::AlignedBox3d ClusterBox(std::span<const Eigen::Vector3f> points,
                               std::span<const uint32_t> indices);

}  // namespace bimslam::changes
