// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/registration/free_space.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "algorithms/common/voxel_hash.hpp"

namespace bimslam::registration {
namespace {

// The surfel of the map that p lies on: within `tolerance` of the plane of one of its voxel's
// surfels, inside that surfel's patch; nullptr when none.
const Surfel* SurfelUnder(const SurfelMap& map, const Eigen::Vector3f& p, float tolerance) {
    const Surfel* found[kNormalBins];
    const int n = map.InVoxel(p, found);
    for (int i = 0; i < n; ++i) {
        if (std::abs(found[i]->normal.dot(p) - found[i]->offset) < tolerance &&
            found[i]->Covers(p)) {
            return found[i];
        }
    }
    return nullptr;
}

// Follows the ray from o along the unit dir to its point `length` away in half-voxel steps, and
// calls on_crossing(surfel, where) for each surfel of the voxel it is in whose patch it crosses
// inside that voxel, from the side the surfel faces, more than `margin` from either end. Stops
// when on_crossing returns true. A voxel is looked at once: the steps that stay in it would find
// the same crossings.
template <typename OnCrossing>
void March(const SurfelMap& map, const Eigen::Vector3f& o, const Eigen::Vector3f& dir, float length,
           float margin, OnCrossing&& on_crossing) {
    const float voxel = static_cast<float>(map.config().voxel_size);
    const float step = 0.5f * voxel;
    const float inv = 1.0f / voxel;
    const Surfel* found[kNormalBins];
    Eigen::Vector3i last = Eigen::Vector3i::Constant(std::numeric_limits<int>::min());
    for (float s = step; s < length - margin; s += step) {
        const Eigen::Vector3f x = o + s * dir;
        const Eigen::Vector3i v = common::VoxelOf(x * inv);
        if (v == last) continue;
        last = v;
        const int n = map.InVoxel(x, found);
        for (int i = 0; i < n; ++i) {
            const Surfel& f = *found[i];
            const float cos_in = f.normal.dot(dir);
            if (cos_in > -0.2f) continue;  // faces away from the sensor, or is grazed
            // Where the ray crosses the surfel's plane: inside this voxel, before the point.
            const float t = (f.offset - f.normal.dot(o)) / cos_in;
            if (t < margin || t > length - margin) continue;
            const Eigen::Vector3f c = o + t * dir;
            if (common::VoxelOf(c * inv) == v && f.Covers(c) && on_crossing(f, c)) return;
        }
    }
}

// Calls on_ray(p, dir, length) for the rays from T's origin to `cloud`'s points placed by T (p),
// `rays` of them at most, evenly thinned: those longer than the margin and within max_range.
template <typename OnRay>
void ForEachRay(const OrientedCloud& cloud, const Eigen::Isometry3d& T, size_t rays,
                const FreeSpaceConfig& config, OnRay&& on_ray) {
    const Eigen::Vector3f o = T.translation().cast<float>();
    const Eigen::Matrix3f R = T.linear().cast<float>();
    const float max_range = static_cast<float>(config.max_range);
    const float margin = static_cast<float>(config.margin);
    const size_t stride = std::max<size_t>(1, cloud.size() / std::max<size_t>(1, rays));
    for (size_t k = 0; k < cloud.size(); k += stride) {
        const Eigen::Vector3f p = R * cloud.points[k] + o;
        const Eigen::Vector3f ray = p - o;
        const float length = ray.norm();
        if (!(length > margin) || length > max_range) continue;
        on_ray(p, Eigen::Vector3f(ray / length), length);
    }
}

}  // namespace

FreeSpaceResult CheckFreeSpace(const OrientedCloud& source, const SurfelMap& map,
                               const Eigen::Isometry3d& T, const FreeSpaceConfig& config) {
    FreeSpaceResult out;
    const Eigen::Vector3f o = T.translation().cast<float>();
    const float margin = static_cast<float>(config.margin);
    ForEachRay(source, T, config.max_rays, config,
               [&](const Eigen::Vector3f& p, const Eigen::Vector3f& dir, float length) {
                   ++out.rays;
                   bool through = false;
                   Crossing crossing;
                   March(map, o, dir, length, margin,
                         [&](const Surfel& f, const Eigen::Vector3f& c) {
                             if (f.porous) return false;
                             through = true;
                             crossing.at = c;
                             crossing.normal = f.normal;
                             return true;
                         });
                   if (!through) return;
                   ++out.seen_through;
                   crossing.lands_on_map = SurfelUnder(map, p, 0.5f * margin) != nullptr;
                   out.crossings.push_back(crossing);
               });
    return out;
}

SurfelRays RaysAtSurfels(const OrientedCloud& cloud, const SurfelMap& map,
                         const Eigen::Isometry3d& T, const FreeSpaceConfig& config) {
    SurfelRays out;
    const Eigen::Vector3f o = T.translation().cast<float>();
    const float margin = static_cast<float>(config.margin);
    const Surfel* first = map.surfels().data();
    ForEachRay(cloud, T, config.porous_rays, config,
               [&](const Eigen::Vector3f& p, const Eigen::Vector3f& dir, float length) {
                   March(map, o, dir, length, margin, [&](const Surfel& f, const Eigen::Vector3f&) {
                       out.crossed.push_back(static_cast<uint32_t>(&f - first));
                       return false;
                   });
                   if (const Surfel* end = SurfelUnder(map, p, 0.5f * margin)) {
                       out.ended.push_back(static_cast<uint32_t>(end - first));
                   }
               });
    return out;
}

size_t MarkPorous(SurfelMap* map, const std::vector<SurfelRays>& rays,
                  const FreeSpaceConfig& config) {
    std::vector<uint32_t> crossed(map->size(), 0), ended(map->size(), 0);
    for (const SurfelRays& r : rays) {
        for (const uint32_t i : r.crossed) ++crossed.at(i);
        for (const uint32_t i : r.ended) ++ended.at(i);
    }
    std::vector<uint32_t> porous;
    for (uint32_t i = 0; i < crossed.size(); ++i) {
        if (crossed[i] >= config.porous_crossings &&
            double(crossed[i]) >= config.porous_share * double(crossed[i] + ended[i])) {
            porous.push_back(i);
        }
    }
    map->MarkPorous(porous);
    return porous.size();
}

}  // namespace bimslam::registration
