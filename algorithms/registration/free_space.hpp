// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Negative evidence for a placement: a query point is "seen through" a surface of the map when
// the ray from the query's sensor to it crosses a surfel facing that sensor well before the point.
// Where the query really is, that happens only where the world differs from the map (a wall that
// was removed); under a wrong placement it happens wherever the two disagree (a partition in one
// storey that the storey above does not have), however well the rest registers. Registration
// fitness counts the agreement; this counts the contradiction (the free-space reasoning of
// occupancy mapping, e.g. OctoMap, Hornung et al. 2013).
#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "algorithms/registration/oriented_cloud.hpp"
#include "algorithms/registration/surfel_map.hpp"

namespace bimslam::registration {

struct FreeSpaceConfig {
    size_t max_rays = 300;    // query points tested, evenly thinned
    double margin = 0.3;      // m: a crossing this close before the point does not count
    double max_range = 12.0;  // m: farther points are not tested (long rays, little evidence)
    // Porosity (MarkPorous): the rays of each of the map's own clouds followed, evenly thinned;
    // a surfel is porous when at least porous_crossings of them cross it (one can be a ray
    // grazing a patch's rounded corner) and they are at least porous_share of those that cross it
    // or end on it. A railing's bars stop few of the rays that reach them; a wall's patch drawn
    // past its end into a doorway stops most (the wall), and stays solid.
    size_t porous_rays = 1000;
    size_t porous_crossings = 2;
    double porous_share = 0.5;
};

// Where a ray was seen through a surface: the crossing on it (map frame), the surface's normal,
// and whether the ray's own point lies on another surface of the map (within half the margin): the
// model seen beyond the crossed surface, as through an element that was removed
// (removed_surfaces.hpp).
struct Crossing {
    Eigen::Vector3f at = Eigen::Vector3f::Zero();
    Eigen::Vector3f normal = Eigen::Vector3f::Zero();
    bool lands_on_map = false;
};

struct FreeSpaceResult {
    size_t rays = 0;  // tested
    size_t seen_through = 0;
    std::vector<Crossing> crossings;  // one per ray seen through, the first surface it crossed
    double ratio() const { return rays ? double(seen_through) / double(rays) : 0.0; }
};

// Marches each ray through `map` in half-voxel steps and looks for a surfel of the voxel it is
// in whose patch (Surfel::Covers: a voxel's plane does not fill the voxel at a door or a wall's
// end) it crosses inside that voxel, from the side the surfel faces. Porous surfels are passed.
FreeSpaceResult CheckFreeSpace(const OrientedCloud& source, const SurfelMap& map,
                               const Eigen::Isometry3d& T_map_source,
                               const FreeSpaceConfig& config);

// The surfels that the rays of one of the map's own clouds (placed as when the map was built)
// cross as CheckFreeSpace would (every crossing along each ray), and those they end on (the ray's
// point within half the margin of the plane, inside the patch): indices into map.surfels(), once
// per ray, config.porous_rays rays at most. Where the map is right, its own rays cross only what
// is not solid: between a railing's bars, or a patch drawn past its wall's end.
struct SurfelRays {
    std::vector<uint32_t> crossed, ended;
};
SurfelRays RaysAtSurfels(const OrientedCloud& cloud, const SurfelMap& map,
                         const Eigen::Isometry3d& T_map_cloud, const FreeSpaceConfig& config);

// Marks porous the surfels that the rays gathered by RaysAtSurfels (over every cloud of the map)
// pass as FreeSpaceConfig says. Returns how many surfels it marked.
size_t MarkPorous(SurfelMap* map, const std::vector<SurfelRays>& rays,
                  const FreeSpaceConfig& config);

}  // namespace bimslam::registration
