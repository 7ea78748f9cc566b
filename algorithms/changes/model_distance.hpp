// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Signed distance from every map point to the nearest element of the model, and that element
// (Step 3 of the paper: "point-to-mesh distance against the BIM").
//
// The nearest point comes from simulation::Scene::ClosestPoint (Embree's BVH point query); the
// sign from the face of the nearest triangle: > 0 in front of the surface (outside the element's
// solid), < 0 behind it (inside the solid). Open3D's RaycastingScene.compute_signed_distance
// signs by counting ray crossings instead, which needs a watertight mesh; IFC elements are closed
// solids, and where they are not (an open mesh, a single face) the face normal still says which
// side a point is on.
//
// Speed: the points are processed in blocks of consecutive points (the map comes in Morton order)
// in parallel (TBB); within a block the nearest triangle of the previous point is the hint for the
// next, which bounds Embree's search from the start.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <limits>
#include <span>
#include <vector>

#include "algorithms/simulation/scene.hpp"

namespace bimslam::changes {

struct PointDistances {
    std::vector<float> signed_m;     // per point; +infinity when nothing is within max_distance
    std::vector<uint32_t> triangle;  // per point: the nearest triangle, or kNoElement
};

// `progress` (optional) gets the fraction done, from the calling thread.
PointDistances ComputeDistances(const simulation::Scene& scene,
                                std::span<const Eigen::Vector3f> points,
                                float max_distance = std::numeric_limits<float>::infinity(),
                                const std::function<void(double)>& progress = {});

}  // namespace bimslam::changes
