// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Seen-through rays that a removed element explains. A placement whose keyframes see through the
// map (free_space.hpp) is wrong, or the building lost an element since the map was made: a
// partition demolished between two visits is seen through by every keyframe that looks across
// where it stood, at the right placement. The two differ in where the crossings are and where the
// rays end:
//   - a removed element: the crossings lie on one or two compact plane patches (the element's
//     faces), crossed from several keyframes, and the rays end on the map's surfaces beyond (the
//     rest of the building is where the map has it);
//   - a wrong placement: the crossings are spread over the surfaces that disagree, and the rays
//     end where the map has nothing.
// A mirror image of the building, or a storey placed on its twin, can look like the first; such
// a placement is still outweighed by a rival that sees through nothing (FreeSpacePrefers judges
// the raw share), so this only keeps a right placement from being called contradicted.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "algorithms/registration/free_space.hpp"

namespace bimslam::registration {

struct RemovedSurfaceConfig {
    double cell = 0.5;          // m: the crossings' grid; a wall's two faces share its cells
    size_t max_surfaces = 2;    // removed elements one placement may explain
    size_t min_views = 3;       // keyframes that must cross a surface (one view is no evidence)
    double max_area_m2 = 20.0;  // a partition or a wall of a room, not a storey's worth
    double min_on_map = 0.5;    // share of its crossing rays that must end on the map beyond
    double min_share = 0.1;     // share of all the crossings a surface must hold
};

// A plane patch of the map seen through from several views.
struct RemovedSurface {
    Eigen::Vector3f center = Eigen::Vector3f::Zero();  // mean of its crossings
    int axis = 0;        // 0, 1, 2: the axis its normal is nearest (x, y, z)
    double area_m2 = 0;  // of its cells projected on its plane
    size_t crossings = 0;
    size_t views = 0;
    double on_map = 0;            // share of its crossing rays that end on the map
    std::vector<uint64_t> cells;  // its cells (common::PackVoxel, on its axis), sorted
};

// The surfaces that removed elements explain among the crossings of `views` (each the
// CheckFreeSpace result of one keyframe at one placement, in one map frame): the connected
// groups of crossed cells of one normal axis, largest first, that meet every bound of `config`.
std::vector<RemovedSurface> FindRemovedSurfaces(const std::vector<const FreeSpaceResult*>& views,
                                                const RemovedSurfaceConfig& config);

// The share of `view`'s rays seen through a surface that is not one of `removed`.
double UnexplainedRatio(const FreeSpaceResult& view, const std::vector<RemovedSurface>& removed,
                        const RemovedSurfaceConfig& config);

// The median over the views that tested rays of UnexplainedRatio (0 when none did).
double MedianUnexplained(const std::vector<const FreeSpaceResult*>& views,
                         const std::vector<RemovedSurface>& removed,
                         const RemovedSurfaceConfig& config);

}  // namespace bimslam::registration
