// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/registration/free_space.hpp"

#include <algorithm>
#include <cmath>

#include "algorithms/common/voxel_hash.hpp"

namespace bimslam::registration {
namespace {

// Whether p lies on a surfel of the map: within `tolerance` of the plane of one of its voxel's
// surfels, inside that surfel's patch.
bool OnMap(const SurfelMap& map, const Eigen::Vector3f& p, float tolerance) {
    const Surfel* found[kNormalBins];
    const int n = map.InVoxel(p, found);
    for (int i = 0; i < n; ++i) {
        if (std::abs(found[i]->normal.dot(p) - found[i]->offset) < tolerance &&
            found[i]->Covers(p)) {
            return true;
        }
    }
    return false;
}

}  // namespace

FreeSpaceResult CheckFreeSpace(const OrientedCloud& source, const SurfelMap& map,
                               const Eigen::Isometry3d& T, const FreeSpaceConfig& config) {
    FreeSpaceResult out;
    const Eigen::Vector3f o = T.translation().cast<float>();
    const Eigen::Matrix3f R = T.linear().cast<float>();
    const float voxel = static_cast<float>(map.config().voxel_size);
    const float step = 0.5f * voxel;
    const float inv = 1.0f / voxel;
    const float max_range = static_cast<float>(config.max_range);
    const float margin = static_cast<float>(config.margin);
    const size_t stride = std::max<size_t>(1, source.size() / std::max<size_t>(1, config.max_rays));
    const Surfel* found[kNormalBins];
    for (size_t k = 0; k < source.size(); k += stride) {
        const Eigen::Vector3f p = R * source.points[k] + o;
        const Eigen::Vector3f ray = p - o;
        const float length = ray.norm();
        if (!(length > margin) || length > max_range) continue;
        ++out.rays;
        const Eigen::Vector3f dir = ray / length;
        bool through = false;
        Crossing crossing;
        for (float s = step; s < length - margin && !through; s += step) {
            const Eigen::Vector3f x = o + s * dir;
            const Eigen::Vector3i v = common::VoxelOf(x * inv);
            const int n = map.InVoxel(x, found);
            for (int i = 0; i < n && !through; ++i) {
                const Surfel& f = *found[i];
                const float cos_in = f.normal.dot(dir);
                if (cos_in > -0.2f) continue;  // faces away from the sensor, or is grazed
                // Where the ray crosses the surfel's plane: inside this voxel, before the point.
                const float t = (f.offset - f.normal.dot(o)) / cos_in;
                if (t < margin || t > length - margin) continue;
                const Eigen::Vector3f c = o + t * dir;
                if (common::VoxelOf(c * inv) == v && f.Covers(c)) {
                    through = true;
                    crossing.at = c;
                    crossing.normal = f.normal;
                }
            }
        }
        if (!through) continue;
        ++out.seen_through;
        crossing.lands_on_map = OnMap(map, p, 0.5f * margin);
        out.crossings.push_back(crossing);
    }
    return out;
}

}  // namespace bimslam::registration
