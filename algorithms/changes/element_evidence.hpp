// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// What the session's rays say about each element of the model (the negative differences of Step 3,
// the paper's future work). For every point of every keyframe, the model's opaque elements are
// ray-cast along the beam that measured it: from the keyframe's sensor origin through the point.
// Where the model's first surface is hit at range r_m and the beam measured r (its perpendicular
// offset s = (r - r_m) |cos a|, a the incidence angle on the model's triangle):
//   |s| <= agree_tolerance_m   the element is there: an "agree" ray;
//   s  >  agree_tolerance_m    the beam went through where the element should be: a "through" ray;
//   s  < -agree_tolerance_m    something not in the model stood in front: "occluded", no evidence.
// Beams at grazing incidence (|cos a| < min_cos_incidence) are left out.
//
// These are the rays of the sensor's own beam pattern, motion-compensated (the keyframe clouds are
// deskewed) and without the pixels that returned nothing: the expected surface and the evidence
// come from the same beams, so an element hidden behind a new object is "occluded", not missing.
//
// Areas: each hit is binned into square cells of cell_m in its face's plane (coplanar triangles of
// an element share the cells); an element's expected area is the area of its cells hit by agree or
// through rays, its seen area that of the cells with at least as many agree rays as through rays,
// both capped at the element's surface area.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "algorithms/changes/aligned_map.hpp"
#include "algorithms/common/triangle_mesh.hpp"
#include "algorithms/simulation/scene.hpp"

namespace bimslam::changes {

struct ElementEvidenceConfig {
    double agree_tolerance_m = 0.10;
    double min_cos_incidence = 0.15;  // ~81 deg
    double cell_m = 0.10;
    double max_range_m = 25.0;  // beams measured farther are not used
    int point_stride = 1;       // use every n-th point of a keyframe (1: all)
    void Validate() const;
};

struct ElementEvidence {
    uint32_t rays_agree = 0;
    uint32_t rays_through = 0;
    uint32_t rays_occluded = 0;
    double expected_area_m2 = 0;  // cells hit by agree or through rays
    double seen_area_m2 = 0;      // cells with agree rays >= through rays
    double surface_area_m2 = 0;   // of the element's triangles in the cast mesh
};

// `mesh` and `triangle_element` are the opaque elements the scene was built from (the scene's
// triangle i is mesh.triangles[i]); the result has one entry per element, element_count of them.
// `progress` gets the fraction of keyframes done, from the calling thread.
std::vector<ElementEvidence> CollectElementEvidence(
    const simulation::Scene& scene, const common::TriangleMesh& mesh,
    std::span<const uint32_t> triangle_element, size_t element_count,
    std::span<const MapKeyframe> keyframes, const ElementEvidenceConfig& config,
    const std::function<void(double)>& progress = {});

}  // namespace bimslam::changes
