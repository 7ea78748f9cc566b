// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Free-space evidence for map points, in the manner of Removert (Kim & Kim, IROS 2020: range
// images of the keyframes, compared with the map) and OctoMap (a beam proves empty what it passed
// through): a point is transient (a person, something moved away) when one keyframe saw it where
// other keyframes looked through empty space.
//
// Each keyframe becomes a range image in its own lidar frame: a row per beam (the cloud's ring
// channel; elevation bins of elevation_bin_deg without one), azimuth columns of azimuth_bin_deg,
// each pixel the nearest range measured in it. A map point p with its surface normal n (both in
// the model's frame) is put to every keyframe within max_range_m: p goes into that keyframe's lidar
// frame, and the pixels of the two beams nearest p's elevation and the columns around its azimuth
// (as many as patch_radius_m / range spans) are its candidate rays. A ray with direction d
// crosses p's tangent plane at t* = (p . n) / (d . n); when that crossing is within patch_radius_m
// of p and the ray is not grazing the plane (|d . n| >= min_crossing_cos):
//   - measured range > t* + margin: the ray went through p's surface patch: a "free" ray;
//   - |measured range - t*| <= margin: the ray hit p's patch: a "seen" ray;
//   - otherwise something in front hid p: no evidence.
// margin = range_margin_m + range_margin_per_m * t*. A keyframe with a seen ray votes "seen", else
// one with a free ray votes "free". The grazing test matters: a ray that skims a box's top a few
// centimetres above it passes near the top's points without crossing the box.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <span>
#include <vector>

#include "algorithms/changes/aligned_map.hpp"

namespace bimslam::changes {

struct FreeSpaceConfig {
    double azimuth_bin_deg = 0.35;   // OS1 at 1024 columns: 0.35 deg
    double elevation_bin_deg = 1.0;  // rows when a cloud has no ring channel
    double patch_radius_m = 0.08;
    double min_crossing_cos = 0.3;  // rays within ~17 deg of the surface prove nothing
    double range_margin_m = 0.10;
    double range_margin_per_m = 0.01;
    double min_range_m = 1.0;  // nearer points: too many pixels to look at, and the rig's own body
    // Farther keyframes are not asked: their beams are 0.4 m apart at 15 m, and a 0.1 deg error of
    // the pose moves them by 2.6 cm there.
    double max_range_m = 15.0;
    // A point is transient when at least min_free_keyframes looked through it and more than
    // free_over_seen times as many keyframes looked through it as saw it.
    int min_free_keyframes = 2;
    double free_over_seen = 1.0;
    // A point no keyframe could judge (not one free or seen vote, every ray grazing its surface or
    // missing its patch) takes the verdict of the judged points within this radius: transient
    // when more of them are transient than not (JudgeByNeighbours). 0: such points stay static.
    double unjudged_radius_m = 0.15;
    void Validate() const;
};

// Points the votes could not judge, judged by the points around them. A person who walks the same
// line again and again is seen by a sensor at a fixed height at the same heights from many
// keyframes: merged, those rings form horizontal sheets whose normal is vertical, along which
// every other keyframe's beams graze, so no keyframe votes on them, not even the ones that saw them
// (algorithms/changes/README.md, "Transients"). Their judged neighbours, the rest of the person,
// are transient. A box's top, grazed the same way, has its judged sides around it.
// judged[k]: point k had a free or a seen vote; transient[k]: its verdict, updated for the unjudged
// points. Returns how many of them became transient. Neighbours count by their own votes only (one
// pass: a verdict is not carried on from point to point).
size_t JudgeByNeighbours(std::span<const Eigen::Vector3f> points, std::span<const uint8_t> judged,
                         std::span<uint8_t> transient, double radius_m);

class FreeSpaceIndex {
public:
    // The clouds must outlive nothing: the range images are copies.
    FreeSpaceIndex(std::span<const MapKeyframe> keyframes, const FreeSpaceConfig& config);

    struct Votes {
        uint16_t free = 0;  // keyframes that looked through p's surface patch
        uint16_t seen = 0;  // keyframes that hit it
    };
    // Thread-safe.
    Votes Vote(const Eigen::Vector3f& p, const Eigen::Vector3f& normal) const;
    bool Transient(const Votes& v) const;

    size_t keyframe_count() const { return images_.size(); }

private:
    struct RangeImage {
        Eigen::Matrix3f R_lidar_world;
        Eigen::Vector3f t_lidar_world;
        Eigen::Vector3f origin_world;
        std::vector<float> row_elevation;     // radians, ascending
        std::vector<float> row_cos, row_sin;  // of row_elevation
        std::vector<float> range;             // rows x columns, 0 = nothing measured
    };
    void VoteOne(const RangeImage& image, const Eigen::Vector3f& p, const Eigen::Vector3f& n,
                 bool* free, bool* seen) const;

    FreeSpaceConfig config_;
    int columns_ = 0;
    float azimuth_bin_rad_ = 0;
    std::vector<float> column_cos_, column_sin_;  // of each column's centre azimuth
    std::vector<RangeImage> images_;
};

}  // namespace bimslam::changes
