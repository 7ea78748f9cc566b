// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The target of loop registration: a map of planar patches ("surfels") over a voxel grid, built
// from oriented clouds (oriented_cloud.hpp) placed in the map's frame. A voxel keeps one surfel
// per normal bin: the six half-axes (+x, -x, +y, ...) nearest the points' oriented normals. So the
// two faces of a wall, and the two walls of a corner, fit separate planes in the same voxel
// (oriented_cloud.hpp says why that matters).
//
// A surfel is the plane fitted to its points (centroid and the eigenvector of the smallest
// eigenvalue of their covariance), oriented like the mean of their normals, and valid when at
// least min_points lie on it within max_thickness (standard deviation across the plane) and
// spread over at least three times that within it.
//
// Built once, then read-only: Find may run from many threads.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "algorithms/common/voxel_hash.hpp"
#include "algorithms/registration/oriented_cloud.hpp"

namespace bimslam::registration {

struct SurfelMapConfig {
    double voxel_size = 0.5;  // m
    int min_points = 5;
    double max_thickness = 0.03;  // m
    void Validate() const;
};

struct Surfel {
    Eigen::Vector3f normal = Eigen::Vector3f::Zero();  // unit, oriented
    float offset = 0;                                  // normal . x = offset on the plane
    Eigen::Vector3f centroid = Eigen::Vector3f::Zero();
    float thickness = 0;  // m, standard deviation across the plane
    // Its extent within the plane: the direction of largest spread and the standard deviations
    // along it and along normal x axis (a voxel half covered by a wall, at a door, has its
    // centroid and spread in the covered half).
    Eigen::Vector3f axis = Eigen::Vector3f::Zero();
    float spread[2] = {0, 0};
    uint32_t points = 0;
    // Rays of the map's own clouds pass through it (free_space.hpp, MarkPorous): a railing's bars
    // with air between them, which a 0.5 m voxel's plane makes a surface. The free-space check
    // does not count a ray crossing it as seen through.
    bool porous = false;
    // Every field equal (a saved and restored map; the struct's padding is not compared).
    bool operator==(const Surfel&) const = default;
    // Whether a point of the plane lies within two standard deviations of the patch.
    bool Covers(const Eigen::Vector3f& x) const {
        const Eigen::Vector3f d = x - centroid;
        const float u = d.dot(axis) / spread[0];
        const float w = d.dot(normal.cross(axis)) / spread[1];
        return u * u + w * w <= 4.0f;
    }
};

// The normal bin of a unit vector: 2 * (axis of its largest component) + (that component < 0).
int NormalBin(const Eigen::Vector3f& n);
inline constexpr int kNormalBins = 6;

class SurfelMap {
public:
    explicit SurfelMap(const SurfelMapConfig& config = {});

    // Adds a cloud placed by T_map_cloud. Call Build() once after the last Add.
    void Add(const OrientedCloud& cloud, const Eigen::Isometry3d& T_map_cloud);
    // Fits the surfels and frees the sums.
    void Build();

    // The surfel for a point p with normal n (both in the map frame, after Build): of the
    // voxel of p and its 6 face neighbours, in the bin of n and, when n lies between two bins
    // (its second component over 0.5), in that one too, the valid surfel nearest to p whose
    // normal has a cosine of at least min_cos_angle with n. nullptr when none; *distance gets
    // the signed distance of p from its plane.
    const Surfel* Find(const Eigen::Vector3f& p, const Eigen::Vector3f& n, float min_cos_angle,
                       float* distance) const;

    // The surfels of the voxel holding p, in every bin (at most kNormalBins).
    int InVoxel(const Eigen::Vector3f& p, const Surfel* out[kNormalBins]) const;

    size_t size() const { return surfels_.size(); }  // valid surfels
    const std::vector<Surfel>& surfels() const { return surfels_; }
    // Where each surfel sits, in the order of surfels(): its voxel's key (common::VoxelKey) and
    // its normal bin. With surfels(), what a built map is saved as (algorithms/localization's rig
    // map) and Restore() rebuilds it from.
    struct Place {
        uint64_t key = 0;
        uint8_t bin = 0;
    };
    const std::vector<Place>& places() const { return places_; }
    // Marks surfels()[i] porous (Surfel::porous) for each i given; an index out of range throws
    // common::Error (kInvalidArgument).
    void MarkPorous(const std::vector<uint32_t>& indices);
    // A built map from saved surfels and their places. Throws common::Error (kInvalidArgument)
    // on counts that differ, a bin out of range or two surfels in one voxel and bin.
    static SurfelMap Restore(const SurfelMapConfig& config, std::vector<Surfel> surfels,
                             std::vector<Place> places);
    const SurfelMapConfig& config() const { return config_; }
    bool built() const { return built_; }

private:
    struct Sums {
        double n = 0;
        Eigen::Vector3d sum = Eigen::Vector3d::Zero();
        Eigen::Matrix3d sum_sq = Eigen::Matrix3d::Zero();  // about `origin`
        Eigen::Vector3d origin = Eigen::Vector3d::Zero();  // the first point: numerics
        Eigen::Vector3d normal_sum = Eigen::Vector3d::Zero();
        uint64_t key = 0;
        int bin = 0;
    };
    SurfelMapConfig config_;
    float inv_size_;
    std::array<common::VoxelHash, kNormalBins> tables_;  // voxel key -> index into surfels_
    std::vector<Sums> sums_;                             // while building
    std::vector<Surfel> surfels_;
    std::vector<Place> places_;
    bool built_ = false;
};

}  // namespace bimslam::registration
