// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The local map of LiDAR odometry: a voxel hash of a bounded number of points, each voxel
// holding a few points and the plane fitted to them (its centroid and normal, from the
// eigen-decomposition of their covariance). Scan points are registered to these planes
// (point-to-plane, Chen & Medioni 1992); a voxel whose points do not lie on a plane (a corner, an
// edge, clutter) offers none.
//
// Bounded: at most max_voxels voxels of at most kMaxPointsPerVoxel points, all allocated at
// construction. Voxels farther than max_distance from the sensor are dropped (what lies far
// behind); when the map is still full, the radius shrinks until it is three-quarters full. A full
// voxel takes no more points, so the map of what was seen first stays fixed (KISS-ICP's rule),
// but for one case: a voxel seen so far only from beyond 10 m, seen again from under half the
// nearest of those ranges, starts again from the nearer view. A point's error from the pose's
// rotation grows with its range (0.1 degree is 3.5 cm at 20 m, 7 cm at 40 m), and a long corridor's
// walls and floor are first seen from far ahead: kept, that far view was the map the rig registered
// to when it got there (README.md, "A long corridor"). Within 10 m a view's error is mostly the
// range noise, and a voxel started again holds one scan's points: started again from any range, the
// stair walks lost more than they gained.
//
// A plane has a front: the side its points were seen from (the mean of the unit vectors from each
// point to the sensor that saw it). A surface can only be seen from its front, so a plane whose
// front faces away from the sensor cannot be what a scan point lies on: FindPlane passes over it.
// Without this, the two faces of a wall thinner than a voxel (0.2 m against 0.6 m) are one plane
// to a scan seeing the other face, and the scan slid 8-13 cm onto it (README.md, "One-sided
// planes"). A point seen from behind its cell's one-sided plane goes into the cell's back twin (a
// second voxel under the same key), which fits the other face's plane: the first face filled the
// cell, and the second would otherwise never enter the map (a full voxel takes no more points).
// The same test is the normal compatibility check of projective association
// (Newcombe et al. 2011, KinectFusion; Behley & Stachniss 2018, SuMa), and the reason the anchoring
// orients its normals (algorithms/registration/oriented_cloud.hpp).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "algorithms/common/voxel_hash.hpp"

namespace bimslam::odometry {

inline constexpr int kMaxPointsPerVoxel = 24;

struct VoxelMapConfig {
    double voxel_size = 0.6;        // m
    int max_points_per_voxel = 24;  // <= kMaxPointsPerVoxel
    double min_point_spacing =
        0.08;                     // m: a new point closer than this to one in its voxel is dropped
    size_t max_voxels = 40000;    // about 40 MB at 24 points per voxel
    double max_distance = 100.0;  // m from the sensor (LidarOdometry prunes to the extent)
    // Plane test: at least min_plane_points, and the standard deviation across the plane at most
    // max_plane_thickness while the spread within it is at least three times that.
    int min_plane_points = 5;
    double max_plane_thickness = 0.04;  // m
    // A plane whose spread within it is under this in its second direction was fitted through
    // points on a line (one ring crossing the voxel, as the ground 10-23 m out): any plane
    // through the line fits them, and the fit turns about it with the noise. It registers (its
    // constraint across the line is real: dropping such planes made four of eight stair walks
    // worse by 0.06-1.25 cm, README.md, "Planes through a line are no evidence") but is no
    // evidence of fit for the registration check (VoxelPlane::line_like).
    // A tenth of the voxel, as the anchoring's normals require (registration/oriented_cloud.hpp).
    double min_judged_spread = 0.06;  // m
    // LOAM's edge map (edge_features.hpp): each voxel fits a line instead, valid when the spread
    // across it is at most max_plane_thickness in both directions and the spread along it at
    // least three times that.
    bool fit_lines = false;

    void Validate() const;
};

struct VoxelPlane {
    Eigen::Vector3f normal = Eigen::Vector3f::Zero();  // towards the front when one_sided
    float offset = 0;                                  // normal . x = offset on the plane
    bool valid = false;
    // Seen from one side: the points' mean view direction leaves the plane by at least
    // kMinFacing (sine of the angle). Points inserted without a viewpoint leave it two-sided.
    bool one_sided = false;
    // Fitted through points on a line (VoxelMapConfig::min_judged_spread): it registers, but a
    // point's distance to it says little about whether the point fits.
    bool line_like = false;
};

inline constexpr float kMinFacing = 0.05f;  // about 3 degrees

struct VoxelLine {
    Eigen::Vector3f point = Eigen::Vector3f::Zero();  // the centroid
    Eigen::Vector3f direction = Eigen::Vector3f::Zero();
    bool valid = false;
};

class VoxelMap {
public:
    explicit VoxelMap(const VoxelMapConfig& config = {});

    // Adds points (map frame), then refits the planes of the voxels that changed. `viewpoint`:
    // the sensor that saw them (map frame), which gives the planes their front.
    void Insert(std::span<const Eigen::Vector3f> points);
    void Insert(std::span<const Eigen::Vector3f> points, const Eigen::Vector3f& viewpoint);
    // Drops the voxels beyond `radius` (at most max_distance; <= 0: max_distance) of `sensor`
    // (map frame), then more if still full.
    void Prune(const Eigen::Vector3d& sensor, double radius = 0);
    void Clear();

    // The plane for a point (map frame): of its voxel and its 6 face neighbours, the valid plane
    // nearest to it; nullptr when none. *distance gets the signed point-to-plane distance.
    // With `sensor` (map frame), one-sided planes whose front faces away from it are passed over.
    const VoxelPlane* FindPlane(const Eigen::Vector3f& p, float* distance,
                                const Eigen::Vector3f* sensor = nullptr) const;
    // FindPlane in two steps, for a point looked up again and again while it stays in its voxel
    // (the registration's outer iterations, scan_registration.cpp): KeyOf(p), then the valid
    // planes of that voxel and its face neighbours in the order FindPlane considers them (a
    // back twin after its front), each passed to `visit`; NearestPlane chooses among them.
    Eigen::Vector3i KeyOf(const Eigen::Vector3f& p) const;
    template <typename Visit>
    void ForNeighbourPlanes(const Eigen::Vector3i& key, Visit&& visit) const;
    // With fit_lines: the nearest valid line the same way; *distance gets the distance to it.
    const VoxelLine* FindLine(const Eigen::Vector3f& p, float* distance) const;

    size_t voxels() const { return voxels_.size(); }
    size_t points() const { return points_; }
    size_t dropped_points() const { return dropped_; }  // no room: map full
    const VoxelMapConfig& config() const { return config_; }
    // Changes whenever the map's planes may have (Insert, a Prune that dropped voxels, Clear); two
    // maps share one only as copies, unchanged since. What a copy of its planes (the
    // registration's per-point neighbourhoods) checks to know it still holds.
    uint64_t version() const { return version_; }

private:
    struct Voxel {
        Eigen::Vector3i key;
        int count = 0;
        int viewed = 0;  // points inserted with a viewpoint
        bool dirty = false;
        bool back = false;      // the back twin of its cell: the other face of a thin wall
        bool has_back = false;  // (the cell's front voxel) a back twin exists
        Eigen::Vector3f view_sum = Eigen::Vector3f::Zero();  // their unit vectors to the sensor
        float seen_from = 0;  // m: the nearest range its points were seen from (0: no viewpoint)
        VoxelPlane plane;
        VoxelLine line;
        std::array<Eigen::Vector3f, kMaxPointsPerVoxel> points;
    };
    // The slot holding the voxel (key, back), else the empty slot where it would go.
    size_t Slot(const Eigen::Vector3i& key, bool back) const;
    int32_t Find(const Eigen::Vector3i& key, bool back) const;  // index into voxels_ or -1
    int32_t FindOrAdd(const Eigen::Vector3i& key, bool back);   // -1: the map is full
    // The voxel a point seen from `viewpoint` goes in: the cell's, or its back twin's when seen
    // from behind the cell's one-sided plane; -1 when the map is full.
    int32_t Resolve(const Eigen::Vector3i& key, const Eigen::Vector3f* viewpoint);
    // Takes voxel i out of the map (and its slot out of the table); the last voxel moves to i.
    void Remove(size_t i);
    void EraseSlot(size_t hole);
    void InsertPoints(std::span<const Eigen::Vector3f> points, const Eigen::Vector3f* viewpoint);
    // Empties v for a nearer view (header); its plane is fitted again when points come.
    void StartAgain(Voxel& v);
    void Fit(Voxel& v) const;

    VoxelMapConfig config_;
    float inv_size_;
    std::vector<Voxel> voxels_;   // capacity max_voxels, never exceeded
    std::vector<int32_t> slots_;  // open addressing: index into voxels_ or -1
    std::vector<int32_t> touched_;
    size_t points_ = 0;
    size_t dropped_ = 0;
    uint64_t version_;
};

// FindPlane's choice among the planes offered in order: the nearest to p, passing over a
// one-sided plane whose front faces away from `sensor` (when given); the first of equals.
class NearestPlane {
public:
    NearestPlane(const Eigen::Vector3f& p, const Eigen::Vector3f* sensor)
        : p_(p), sensor_(sensor) {}
    void Consider(const VoxelPlane& plane) {
        if (!plane.valid) return;
        // The sensor behind a one-sided plane: that surface cannot be seen from here (header).
        if (sensor_ && plane.one_sided && plane.normal.dot(*sensor_) < plane.offset) return;
        const float r = plane.normal.dot(p_) - plane.offset;
        if (!best_ || std::abs(r) < std::abs(distance_)) {
            best_ = &plane;
            distance_ = r;
        }
    }
    const VoxelPlane* best() const { return best_; }
    float distance() const { return distance_; }  // signed; valid when best() is not null

private:
    Eigen::Vector3f p_;
    const Eigen::Vector3f* sensor_;
    const VoxelPlane* best_ = nullptr;
    float distance_ = 0;
};

template <typename Visit>
void VoxelMap::ForNeighbourPlanes(const Eigen::Vector3i& key, Visit&& visit) const {
    for (const Eigen::Vector3i& d : common::kVoxelAndFaceNeighbours) {
        const int32_t i = Find(key + d, false);
        if (i < 0) continue;
        if (voxels_[size_t(i)].plane.valid) visit(voxels_[size_t(i)].plane);
        if (!voxels_[size_t(i)].has_back) continue;
        if (const int32_t j = Find(key + d, true); j >= 0 && voxels_[size_t(j)].plane.valid) {
            visit(voxels_[size_t(j)].plane);
        }
    }
}

}  // namespace bimslam::odometry
