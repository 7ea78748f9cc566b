// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/simulation/material_paths.hpp"

#include <algorithm>
#include <cmath>

namespace bimslam::simulation::detail {
namespace {

// A leg starts 1 mm past the surface it leaves: float rounding puts the new origin up to a few
// micrometres off the plane (a 100 m path in float), and nothing real is 1 mm behind a pane.
constexpr float kLegStartM = 1e-3f;

LaneHit Cast(const Scene::Impl& impl, const Eigen::Vector3f& o, const Eigen::Vector3f& d,
             float t_far) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh{};
    rh.ray.org_x = o.x(), rh.ray.org_y = o.y(), rh.ray.org_z = o.z();
    rh.ray.dir_x = d.x(), rh.ray.dir_y = d.y(), rh.ray.dir_z = d.z();
    rh.ray.tnear = kLegStartM, rh.ray.tfar = t_far;
    rh.ray.mask = 0xFFFFFFFFu;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(impl.scene, &context, &rh);
    LaneHit h;
    h.hit = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
    h.t = rh.ray.tfar, h.prim = rh.hit.primID;
    h.normal = Eigen::Vector3f(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
    h.source = &impl;
    return h;
}

}  // namespace

PathEnd FollowPath(const Scene::Impl& scene, const Scene::Impl* overlay, const MaterialModel& model,
                   const PixelRandom& random, Eigen::Vector3f origin, Eigen::Vector3f dir,
                   LaneHit hit) {
    PathEnd end;
    end.dir = dir;
    float travelled = 0;  // the path's length up to `origin`
    int mirrors = 0;
    for (int event = 0; event < kMaxMaterialEvents; ++event) {
        const Material material = hit.source == &scene && !scene.materials.empty()
                                      ? scene.materials[hit.prim]
                                      : Material::kDiffuse;
        if (material == Material::kDiffuse) {
            // The sensor times the whole path and reports it along the beam it sent: after a
            // mirror the point lies behind the mirror, where the mirror image of the surface is.
            end.hit = hit;
            end.hit.t = travelled + hit.t;
            end.dir = dir;
            return end;
        }
        const float n2 = hit.normal.squaredNorm();
        const Eigen::Vector3f n =
            n2 > 0 ? Eigen::Vector3f(hit.normal / std::sqrt(n2)) : Eigen::Vector3f(-dir);
        const float d_n = dir.dot(n);
        origin += hit.t * dir;
        travelled += hit.t;
        if (material == Material::kGlass) {
            // Fresnel reflection of the pane (4 % a face at normal incidence for n = 1.5) reaches
            // the receiver only near normal incidence: p = p0 cos(a)^k (lidar_simulator.hpp).
            const double cos_a = std::min(1.0, double(std::abs(d_n)));
            const double p = model.glass_return_probability * model.glass_return_power(cos_a);
            if (p > 0 && random.Uniform(kFirstMaterialDraw + uint64_t(event)) < p) {
                end.hit = hit;
                end.hit.t = travelled;
                end.dir = dir;
                end.glass_return = true;
                return end;
            }
            // Otherwise the beam goes on through the pane, undeflected (a thin flat pane shifts
            // it sideways by less than its thickness).
        } else {
            if (++mirrors > model.max_mirror_bounces) return end;  // no return
            dir = (dir - 2.0f * d_n * n).normalized();
            end.mirrored = true;
        }
        const float remaining = model.t_far - travelled;
        if (remaining <= kLegStartM) return end;
        hit = Cast(scene, origin, dir, remaining);
        if (overlay != nullptr) {
            const LaneHit o = Cast(*overlay, origin, dir, hit.hit ? hit.t : remaining);
            if (o.hit) hit = o;
        }
        if (!hit.hit) return end;
    }
    return end;
}

}  // namespace bimslam::simulation::detail
