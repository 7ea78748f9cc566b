// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Internal to algorithms/simulation: a beam followed through glass and off mirrors (Scene's
// Material). SimulateScan casts packets against the static scene; the few lanes whose hit is on a
// glass or mirror triangle are handed to FollowPath, which carries on with one rtcIntersect1 per
// leg (lidar_simulator.hpp, "Materials"; README.md has the physics).
#pragma once

#include <Eigen/Core>
#include <cstdint>

#include "algorithms/simulation/embree_scene.hpp"
#include "algorithms/simulation/measurement_math.hpp"

namespace bimslam::simulation::detail {

// What a ray (or a whole path) returned.
struct LaneHit {
    bool hit = false;
    float t = 0;  // distance along the ray; for a path, the whole path's length
    uint32_t prim = 0;
    Eigen::Vector3f normal;               // unnormalised geometric normal
    const Scene::Impl* source = nullptr;  // the scene hit (prim indexes its triangles)
};

// The draws of PixelRandom that FollowPath uses: kFirstMaterialDraw + the event's index (draws 0
// and 1 are the dropout's and the range noise's).
inline constexpr uint64_t kFirstMaterialDraw = 2;
// More glass or mirror events than this on one path: no return (a beam trapped between panes
// and mirrors has lost its power long before).
inline constexpr int kMaxMaterialEvents = 16;

struct MaterialModel {
    double glass_return_probability = 0.0;  // NoiseModel's, see lidar_simulator.hpp
    Power glass_return_power{1.0};
    int max_mirror_bounces = 0;
    float t_far = 0;  // the longest path (max_range_m)
};

struct PathEnd {
    LaneHit hit;                // the surface the path ends on, t the path's whole length
    Eigen::Vector3f dir;        // the last leg's unit direction (for the incidence angle)
    bool mirrored = false;      // reflected by a mirror: the point appears behind it (a ghost)
    bool glass_return = false;  // the return of a glass pane
};

// `first` is the static scene's hit of origin + t dir (dir unit) on a glass or mirror triangle.
// Follows the beam: through glass (a return from the pane with probability p0 cos(a)^k, else
// on in the same direction), off mirrors (d' = d - 2 (d.n) n, at most max_mirror_bounces),
// against the static scene and the overlay (may be null), until a diffuse surface, a miss, or a
// path longer than t_far.
PathEnd FollowPath(const Scene::Impl& scene, const Scene::Impl* overlay, const MaterialModel& model,
                   const PixelRandom& random, Eigen::Vector3f origin, Eigen::Vector3f dir,
                   LaneHit first);

}  // namespace bimslam::simulation::detail
