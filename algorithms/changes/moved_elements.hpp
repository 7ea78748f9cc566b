// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Elements that were moved: the element is (partly) missing where the model has it, and a new
// object nearby has its shape. For every element judged missing, or seen over less than
// max_seen_fraction of its expected area (a desk moved by less than its size still covers part of
// its old place: its top's beams agree there), each new object within pair_radius_m of
// the element's box is tried: the element's surface is fitted to the object's points (and to the
// points still supporting the element, a move may overlap its old place) by point-to-plane ICP in
// four degrees of freedom (translation and yaw about the element's box centre, as things are moved
// on a floor), with Cauchy weights, from a few starting yaws. A fit that puts min_inlier_fraction
// of those points within inlier_m of the moved surface, and explains min_object_fraction of the
// object's own points, and whose inliers, taken back to the element's place, span
// min_extent_fraction of its height and of its longer side (the object has the element's size, not
// only a patch of its surface: a low box fits a tall cabinet's lower half), makes the element
// "moved": its verdict becomes deviating, its offset the
// translation of its box centre, and the object is no longer a new object; nor are the other
// objects within pair_radius_m of which the moved element explains min_object_fraction (a moved
// desk may come apart into a cluster per end).
// A move must also leave the moved element where the beams found it, not where they passed: its
// surface at the new place, sampled every sample_spacing_m and at least sample_inset_m inside each
// face (a free-space vote judges a patch of 8 cm about its point: a beam beside a desk's 5 cm leg
// crosses that patch, and the Go1's low sensor had its moved desk refused so), is put to the
// keyframes' range images (free_space.hpp), and a move whose judged samples were looked through
// more than max_looked_through of the time is refused. Duplex_A's partition between entry and
// living room, demolished, was "moved" 0.35 m and turned 9 degrees onto a new 1.4 m partition at
// one end and the wall's remains at the other, through the 2 m opening every beam between the rooms
// passed.
#pragma once

#include <Eigen/Geometry>
#include <span>
#include <vector>

#include "algorithms/changes/change_model.hpp"
#include "algorithms/changes/element_check.hpp"
#include "algorithms/changes/free_space.hpp"

namespace bimslam::changes {

struct MovedConfig {
    bool enabled = true;
    double max_seen_fraction = 0.6;
    double pair_radius_m = 1.5;
    double inlier_m = 0.05;
    double min_inlier_fraction = 0.7;
    double min_object_fraction = 0.6;
    double min_extent_fraction = 0.5;
    double sample_spacing_m = 0.1;
    double sample_inset_m = 0.1;      // over FreeSpaceConfig::patch_radius_m
    double max_looked_through = 0.2;  // of the samples judged (a free or seen vote)
    size_t min_judged_samples = 20;   // fewer: the check says nothing
    void Validate() const;
};

// A rigid motion in the floor plane fitted to points.
struct MotionFit {
    Eigen::Vector3d translation = Eigen::Vector3d::Zero();  // of the element's box centre
    double yaw_rad = 0;                                     // about that centre
    double inlier_fraction = 0;
    std::vector<uint8_t> inlier;  // per point given
};

// Fits the element (its triangles in model.mesh) to `points`: returns the motion M with M(element)
// through the points. Exposed for tests.
MotionFit FitElementMotion(const ChangeModel& model, uint32_t element,
                           std::span<const Eigen::Vector3f> points, const MovedConfig& config);

// How much of the element's box the inliers of `motion` cover, once moved back to the element's
// place: their extent over the box's, vertically and along its longer horizontal side. Exposed
// for tests.
struct ExtentCoverage {
    double height = 0, length = 0;
};
ExtentCoverage InlierCoverage(const Eigen::AlignedBox3d& element_box, const MotionFit& motion,
                              std::span<const Eigen::Vector3f> points);

// The triangles of one element as a mesh of their own, and their box.
common::TriangleMesh ElementMesh(const ChangeModel& model, uint32_t element,
                                 Eigen::AlignedBox3d* box = nullptr);
// The fraction of `points` within inlier_m of the element moved by `motion`.
double InlierFraction(const ChangeModel& model, uint32_t element, const MotionFit& motion,
                      std::span<const Eigen::Vector3f> points, double inlier_m);

// The element's surface moved by `motion`: a point every `spacing` m on each of its triangles,
// `inset` m or more from the triangle's edges, with the triangle's normal. Exposed for tests.
void MovedSurfaceSamples(const ChangeModel& model, uint32_t element,
                         const Eigen::AlignedBox3d& element_box, const MotionFit& motion,
                         double spacing, double inset, std::vector<Eigen::Vector3f>* points,
                         std::vector<Eigen::Vector3f>* normals);

// The share of the moved surface's judged samples that the keyframes looked through (a sample
// judged when it has a vote; more free votes than seen ones: looked through), and how many were
// judged.
struct LookedThrough {
    double share = 0;
    size_t judged = 0;
};
LookedThrough MovedSurfaceLookedThrough(const ChangeModel& model, uint32_t element,
                                        const Eigen::AlignedBox3d& element_box,
                                        const MotionFit& motion, const FreeSpaceIndex& free_space,
                                        const MovedConfig& config);

// objects: the points (indices into map_xyz) of each new object; element_support: per element, the
// indices of its support points; free_space: the keyframes' range images (nullptr: no
// looked-through check). Updates `reports` of moved elements and returns, per object, the element
// it is explained by (or kNoElement).
std::vector<uint32_t> FindMovedElements(const ChangeModel& model,
                                        std::span<const Eigen::Vector3f> map_xyz,
                                        const std::vector<std::vector<uint32_t>>& objects,
                                        const std::vector<std::vector<uint32_t>>& element_support,
                                        std::vector<ElementReport>& reports,
                                        const MovedConfig& config,
                                        const FreeSpaceIndex* free_space = nullptr);

}  // namespace bimslam::changes
