// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/simulation/lidar_simulator.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <string>

#include "algorithms/common/se3.hpp"
#include "algorithms/common/status.hpp"
#include "algorithms/simulation/embree_scene.hpp"
#include "algorithms/simulation/material_paths.hpp"
#include "algorithms/simulation/measurement_math.hpp"

#if defined(__SSE__)
#include <xmmintrin.h>
#endif

namespace bimslam::simulation {
namespace {
using common::StatusCode;
using detail::LaneHit;
using detail::Mix;
using detail::PathEnd;
using detail::PixelRandom;
using detail::Power;
using detail::RoundNonNegative;

bool NonNegative(double x) { return std::isfinite(x) && x >= 0; }

// ---- Embree packets ----

template <int K>
struct Packet;
template <>
struct Packet<1> {
    using RayHit = RTCRayHit;
    static void Intersect(const int* /*valid*/, RTCScene s, RTCIntersectContext* c, RayHit* rh) {
        rtcIntersect1(s, c, rh);
    }
};
template <>
struct Packet<4> {
    using RayHit = RTCRayHit4;
    static void Intersect(const int* valid, RTCScene s, RTCIntersectContext* c, RayHit* rh) {
        rtcIntersect4(valid, s, c, rh);
    }
};
template <>
struct Packet<8> {
    using RayHit = RTCRayHit8;
    static void Intersect(const int* valid, RTCScene s, RTCIntersectContext* c, RayHit* rh) {
        rtcIntersect8(valid, s, c, rh);
    }
};
template <>
struct Packet<16> {
    using RayHit = RTCRayHit16;
    static void Intersect(const int* valid, RTCScene s, RTCIntersectContext* c, RayHit* rh) {
        rtcIntersect16(valid, s, c, rh);
    }
};

template <int K>
void SetLane(typename Packet<K>::RayHit& rh, int i, const Eigen::Vector3f& o,
             const Eigen::Vector3f& d, float t_near, float t_far) {
    if constexpr (K == 1) {
        (void)i;
        rh.ray.org_x = o.x(), rh.ray.org_y = o.y(), rh.ray.org_z = o.z();
        rh.ray.dir_x = d.x(), rh.ray.dir_y = d.y(), rh.ray.dir_z = d.z();
        rh.ray.tnear = t_near, rh.ray.tfar = t_far, rh.ray.time = 0.0f;
        rh.ray.mask = 0xFFFFFFFFu, rh.ray.id = 0, rh.ray.flags = 0;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    } else {
        rh.ray.org_x[i] = o.x(), rh.ray.org_y[i] = o.y(), rh.ray.org_z[i] = o.z();
        rh.ray.dir_x[i] = d.x(), rh.ray.dir_y[i] = d.y(), rh.ray.dir_z[i] = d.z();
        rh.ray.tnear[i] = t_near, rh.ray.tfar[i] = t_far, rh.ray.time[i] = 0.0f;
        rh.ray.mask[i] = 0xFFFFFFFFu, rh.ray.id[i] = 0, rh.ray.flags[i] = 0;
        rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
    }
}

// Marks lane i as not hit, keeping its ray (and its tfar) for the next scene.
template <int K>
void ClearHit(typename Packet<K>::RayHit& rh, int i) {
    if constexpr (K == 1) {
        (void)i;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    } else {
        rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
    }
}

template <int K>
bool LaneHitSomething(const typename Packet<K>::RayHit& rh, int i) {
    if constexpr (K == 1) {
        (void)i;
        return rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
    } else {
        return rh.hit.geomID[i] != RTC_INVALID_GEOMETRY_ID;
    }
}

template <int K>
LaneHit GetLane(const typename Packet<K>::RayHit& rh, int i) {
    LaneHit h;
    if constexpr (K == 1) {
        (void)i;
        h.hit = LaneHitSomething<K>(rh, i);
        h.t = rh.ray.tfar, h.prim = rh.hit.primID;
        h.normal = Eigen::Vector3f(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
    } else {
        h.hit = LaneHitSomething<K>(rh, i);
        h.t = rh.ray.tfar[i], h.prim = rh.hit.primID[i];
        h.normal = Eigen::Vector3f(rh.hit.Ng_x[i], rh.hit.Ng_y[i], rh.hit.Ng_z[i]);
    }
    return h;
}

// ---- One scan ----

struct Setup {
    const Scene::Impl* scene = nullptr;
    const Scene::Impl* overlay = nullptr;  // SimulatorOptions::overlay, null when none or empty
    const Scene::Impl* rig = nullptr;      // SimulatorOptions::rig, null when none or empty
    bool materials = false;                // the static scene has glass or mirrors
    detail::MaterialModel material_model;
    const NoiseModel* noise = nullptr;
    ScanImage* out = nullptr;
    int h = 0, w = 0;
    // Per beam: cos/sin of theta_a and phi. Per column: cos/sin of theta_e.
    std::vector<double> cos_a, sin_a, cos_phi, sin_phi, cos_e, sin_e;
    double n_m = 0, z0_m = 0, d_m = 0;  // beam origin offsets, metres
    double inv_max_range = 0;           // 1 / NoiseModel::max_range_m
    double steps_per_m = 0;             // 1000 / NoiseModel::range_resolution_mm (no divisions
                                        // per pixel: they were the slowest part of Measure)
    Eigen::Matrix3d R_sensor_lidar;
    Eigen::Vector3d t_sensor_lidar_m;
    const Eigen::Isometry3d* poses = nullptr;  // T_world_sensor of column v: poses[v * stride]
    size_t pose_stride = 0;
    float t_near = 0, t_far = 0;
    uint64_t key = 0;                              // the scan's random key, from the seed
    Power incidence_power{1.0}, range_power{1.0};  // the dropout exponents
};

struct Counts {
    size_t hits = 0, returns = 0, dropouts = 0, too_close = 0, glass_returns = 0, ghosts = 0;
};

// Writes pixel (u, v) from what its ray returned; true when it has a return.
bool Measure(const Setup& s, int u, int v, const Eigen::Vector3f& dir, const LaneHit& hit,
             Counts* counts) {
    ScanImage& out = *s.out;
    const size_t i = out.Index(u, v);
    auto no_return = [&] {
        out.range_mm[i] = 0;
        out.signal[i] = 0;
        out.reflectivity[i] = 0;
        out.element_id[i] = kNoElement;
        return false;
    };
    if (!hit.hit) return no_return();
    ++counts->hits;
    const NoiseModel& nm = *s.noise;
    const double r = hit.t;
    if (r < nm.min_range_m) {
        ++counts->too_close;
        return no_return();
    }
    // cos a = |n . dir| / |n| (dir is unit); a degenerate normal counts as normal incidence.
    const float ng2 = hit.normal.squaredNorm();
    const double cos_inc =
        ng2 > 0 ? std::min(1.0, std::abs(hit.normal.dot(dir)) / std::sqrt(double(ng2))) : 1.0;
    // Dropout (lidar_simulator.hpp): p = base + gain_a (1 - cos a)^e_a + gain_r (r / max)^e_r.
    const PixelRandom random(s.key, i);
    double p = nm.dropout_base;
    if (nm.dropout_incidence_gain > 0) {
        p += nm.dropout_incidence_gain * s.incidence_power(1.0 - cos_inc);
    }
    if (nm.dropout_range_gain > 0) {
        p += nm.dropout_range_gain * s.range_power(r * s.inv_max_range);
    }
    if (p > 0 && random.Uniform(0) <= p) {
        ++counts->dropouts;
        return no_return();
    }
    double measured = r;
    if (nm.range_sigma_m > 0) measured += nm.range_sigma_m * random.Gaussian();
    if (measured < nm.min_range_m) {
        ++counts->too_close;
        return no_return();
    }
    // Quantisation: range_mm = step * round(r' 1000 / step). Below 2^32: r' <= max_range_m (1e6)
    // + 8.2 range_sigma_m (100; the largest |z| of PixelRandom::Gaussian), and the
    // rounding adds at most step / 2 < 2^30 mm.
    const double mm = nm.range_resolution_mm * RoundNonNegative(measured * s.steps_per_m);
    if (mm <= 0) {  // min_range_m = 0 and a range that rounds to 0: 0 would read as no return
        ++counts->too_close;
        return no_return();
    }
    ++counts->returns;
    out.range_mm[i] = static_cast<uint32_t>(mm);
    out.element_id[i] = hit.source->ids[hit.prim];
    // Intensity proxy of a Lambertian target (lidar_simulator.hpp): reflectivity is range-
    // compensated, signal falls with 1 / max(r, 1 m)^2.
    const double lambert = nm.albedo * cos_inc;
    out.reflectivity[i] = static_cast<uint8_t>(RoundNonNegative(100.0 * lambert));
    const double rr = std::max(r, 1.0);
    out.signal[i] = static_cast<uint16_t>(
        RoundNonNegative(std::min(65535.0, nm.signal_at_1m * lambert / (rr * rr))));
    return true;
}

// Casts columns [v0, v1) in packets of K rays: consecutive beams of a column, then the next
// column (column-major), so a packet's rays start within millimetres of each other and fan out
// over a few degrees: coherent rays, which Embree's packet traversal shares work between.
// With an overlay, the same packet is then cast against it: Embree leaves a ray's tfar at its
// static hit's distance (at t_far for a miss), so the overlay is searched only in front of the
// static hit and the nearer hit of the two is the one left in the packet. With a rig scene, the
// packet's rays are then set to their sensor-frame origins and directions (the rig is fixed in
// that frame, and a rigid map keeps distances along a ray), with tfar at the nearest hit so far.
template <int K>
Counts CastColumns(const Setup& s, int v0, int v1) {
    Counts counts;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    if constexpr (K > 1) context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    // Zeroed once: lanes left inactive in the last packet of a block then hold no garbage.
    typename Packet<K>::RayHit rh{};
    alignas(64) int valid[K > 1 ? K : 1] = {};
    int lane_u[K], lane_v[K];
    Eigen::Vector3f lane_dir[K], lane_origin[K], lane_origin_s[K], lane_dir_s[K];
    int lanes = 0;
    LaneHit hits[K];
    const Eigen::Vector3f* hit_dir[K];  // the direction of each lane's last leg
    float first_t[K];                   // where each lane's first leg ends (the rig's tfar)
    uint8_t path[K];                    // 1: a glass return, 2: a ghost (after a mirror)
    PathEnd ends[K];
    auto flush = [&] {
        if constexpr (K > 1) {
            for (int i = lanes; i < K; ++i) valid[i] = 0;
        }
        Packet<K>::Intersect(valid, s.scene->scene, &context, &rh);
        if (s.overlay == nullptr && s.rig == nullptr && !s.materials) {
            for (int i = 0; i < lanes; ++i) {
                LaneHit hit = GetLane<K>(rh, i);
                hit.source = s.scene;
                Measure(s, lane_u[i], lane_v[i], lane_dir[i], hit, &counts);
            }
            lanes = 0;
            return;
        }
        for (int i = 0; i < lanes; ++i) {
            hits[i] = GetLane<K>(rh, i);
            hits[i].source = s.scene;
            hit_dir[i] = &lane_dir[i];
            first_t[i] = hits[i].hit ? hits[i].t : s.t_far;
            path[i] = 0;
            ClearHit<K>(rh, i);  // the ray and its tfar (the static hit's t) stay
        }
        // Glass and mirrors: the rare lanes that hit one follow their path one ray at a time.
        if (s.materials) {
            for (int i = 0; i < lanes; ++i) {
                if (!hits[i].hit || s.scene->materials[hits[i].prim] == Material::kDiffuse) {
                    continue;
                }
                const PixelRandom random(s.key, s.out->Index(lane_u[i], lane_v[i]));
                ends[i] = detail::FollowPath(*s.scene, s.overlay, s.material_model, random,
                                             lane_origin[i], lane_dir[i], hits[i]);
                hits[i] = ends[i].hit;
                hit_dir[i] = &ends[i].dir;
                path[i] = ends[i].glass_return ? 1 : ends[i].mirrored ? 2 : 0;
            }
        }
        if (s.overlay != nullptr) {
            Packet<K>::Intersect(valid, s.overlay->scene, &context, &rh);
            for (int i = 0; i < lanes; ++i) {
                if (LaneHitSomething<K>(rh, i)) {
                    hits[i] = GetLane<K>(rh, i);
                    hits[i].source = s.overlay;
                    hit_dir[i] = &lane_dir[i];
                    first_t[i] = hits[i].t;
                    path[i] = 0;
                    ClearHit<K>(rh, i);
                }
            }
        }
        if (s.rig != nullptr) {
            // Only the first leg passes the rig (a reflection back onto the body is left out).
            for (int i = 0; i < lanes; ++i) {
                SetLane<K>(rh, i, lane_origin_s[i], lane_dir_s[i], s.t_near, first_t[i]);
            }
            Packet<K>::Intersect(valid, s.rig->scene, &context, &rh);
            for (int i = 0; i < lanes; ++i) {
                if (LaneHitSomething<K>(rh, i)) {
                    hits[i] = GetLane<K>(rh, i);
                    hits[i].source = s.rig;
                    // A rig hit's normal is in the sensor frame: its incidence from that ray.
                    hit_dir[i] = &lane_dir_s[i];
                    path[i] = 0;
                }
            }
        }
        for (int i = 0; i < lanes; ++i) {
            if (Measure(s, lane_u[i], lane_v[i], *hit_dir[i], hits[i], &counts) && path[i]) {
                ++(path[i] == 1 ? counts.glass_returns : counts.ghosts);
            }
        }
        lanes = 0;
    };
    for (int v = v0; v < v1; ++v) {
        const Eigen::Isometry3d& T_ws = s.poses[v * s.pose_stride];
        const Eigen::Matrix3d M = T_ws.linear() * s.R_sensor_lidar;  // lidar to world
        const Eigen::Vector3d b = T_ws.linear() * s.t_sensor_lidar_m + T_ws.translation();
        const double ce = s.cos_e[v], se = s.sin_e[v];
        for (int u = 0; u < s.h; ++u) {
            // The spec's ray ("Range -> XYZ", see LidarModel::Direction and Origin), from the
            // per-beam and per-column cos/sin tables: cos and sin of theta_e + theta_a by the
            // angle-sum identities (equal to the direct evaluation to ~1e-16).
            const double c = ce * s.cos_a[u] - se * s.sin_a[u];
            const double sn = se * s.cos_a[u] + ce * s.sin_a[u];
            const Eigen::Vector3d dir(c * s.cos_phi[u], sn * s.cos_phi[u], s.sin_phi[u]);
            const Eigen::Vector3d off(s.n_m * ce - s.d_m * dir.x(), s.n_m * se - s.d_m * dir.y(),
                                      -s.d_m * dir.z() + s.z0_m);
            const Eigen::Vector3f d_w = (M * dir).cast<float>();
            const Eigen::Vector3f o_w = (M * off + b).cast<float>();
            SetLane<K>(rh, lanes, o_w, d_w, s.t_near, s.t_far);
            if constexpr (K > 1) valid[lanes] = -1;
            lane_u[lanes] = u, lane_v[lanes] = v, lane_dir[lanes] = d_w;
            lane_origin[lanes] = o_w;
            if (s.rig != nullptr) {
                lane_dir_s[lanes] = (s.R_sensor_lidar * dir).cast<float>();
                lane_origin_s[lanes] = (s.R_sensor_lidar * off + s.t_sensor_lidar_m).cast<float>();
            }
            if (++lanes == K) flush();
        }
    }
    if (lanes > 0) flush();
    return counts;
}

// Flush-to-zero and denormals-are-zero while casting (Embree's advice), restored afterwards.
// x86: MXCSR's FTZ (bit 15) and DAZ (bit 6). AArch64: FPCR's FZ (bit 24), which flushes both
// denormal inputs and outputs of single and double precision operations (Arm ARM, FPCR.FZ);
// Embree's NEON code (SSE2NEON) runs on those registers. Elsewhere nothing is changed.
class ScopedFlushDenormals {
public:
#if defined(__SSE__)
    ScopedFlushDenormals() : csr_(_mm_getcsr()) { _mm_setcsr(csr_ | 0x8040u); }
    ~ScopedFlushDenormals() { _mm_setcsr(csr_); }

private:
    unsigned csr_;
#elif defined(__aarch64__)
    ScopedFlushDenormals() : fpcr_(ReadFpcr()) { WriteFpcr(fpcr_ | (uint64_t{1} << 24)); }
    ~ScopedFlushDenormals() { WriteFpcr(fpcr_); }

private:
    static uint64_t ReadFpcr() {
        uint64_t v;
        asm volatile("mrs %0, fpcr" : "=r"(v));
        return v;
    }
    static void WriteFpcr(uint64_t v) { asm volatile("msr fpcr, %0" : : "r"(v)); }
    uint64_t fpcr_;
#endif
};

ScanStats Run(const Scene& scene, const LidarModel& model, const Eigen::Isometry3d* poses,
              size_t pose_stride, const NoiseModel& noise, uint64_t seed, ScanImage* out,
              const SimulatorOptions& options) {
    model.Validate();
    noise.Validate();
    options.Validate();
    if (out == nullptr) {
        throw common::Error(StatusCode::kInvalidArgument, "SimulateScan: out is null");
    }
    const size_t pose_count = pose_stride == 0 ? 1 : static_cast<size_t>(model.columns);
    for (size_t k = 0; k < pose_count; ++k) {
        if (!common::IsValidRigid(poses[k])) {
            throw common::Error(StatusCode::kInvalidArgument,
                                "SimulateScan: T_world_sensor of column " + std::to_string(k) +
                                    " is not a rigid transform");
        }
    }
    Setup s;
    s.scene = &scene.impl();
    if (options.overlay != nullptr && options.overlay->triangle_count() > 0) {
        s.overlay = &options.overlay->impl();
    }
    if (options.rig != nullptr && options.rig->triangle_count() > 0) {
        s.rig = &options.rig->impl();
    }
    s.noise = &noise;
    s.out = out;
    if (scene.has_special_materials()) {
        s.materials = true;
        s.material_model.glass_return_probability = noise.glass_return_probability;
        s.material_model.glass_return_power = Power(noise.glass_return_exponent);
        s.material_model.max_mirror_bounces = noise.max_mirror_bounces;
        s.material_model.t_far = static_cast<float>(noise.max_range_m);
    }
    s.h = model.beams();
    s.w = model.columns;
    out->Resize(s.h, s.w);
    constexpr double kDeg = M_PI / 180.0;
    for (int u = 0; u < s.h; ++u) {
        const double theta_a = -model.beam_azimuth_deg[u] * kDeg;
        const double phi = model.beam_altitude_deg[u] * kDeg;
        s.cos_a.push_back(std::cos(theta_a));
        s.sin_a.push_back(std::sin(theta_a));
        s.cos_phi.push_back(std::cos(phi));
        s.sin_phi.push_back(std::sin(phi));
    }
    for (int v = 0; v < s.w; ++v) {
        const double theta_e = 2.0 * M_PI - v * 2.0 * M_PI / s.w;
        s.cos_e.push_back(std::cos(theta_e));
        s.sin_e.push_back(std::sin(theta_e));
    }
    s.n_m = model.beam_origin_mm * 0.001;
    s.z0_m = model.beam_z_mm * 0.001;
    s.d_m = model.BeamOriginDistance();
    s.R_sensor_lidar = model.lidar_to_sensor_transform.topLeftCorner<3, 3>();
    s.t_sensor_lidar_m = model.lidar_to_sensor_transform.topRightCorner<3, 1>() * 0.001;
    s.poses = poses;
    s.pose_stride = pose_stride;
    // Hits closer than the emission point are behind the beam; a negative d (a beam origin on
    // the far side) is clamped to the table origin.
    s.t_near = static_cast<float>(std::max(0.0, s.d_m));
    s.t_far = static_cast<float>(noise.max_range_m);
    s.key = Mix(seed ^ 0x6A09E667F3BCC909ull);
    s.incidence_power = Power(noise.dropout_incidence_exponent);
    s.inv_max_range = 1.0 / noise.max_range_m;
    s.steps_per_m = 1000.0 / noise.range_resolution_mm;
    s.range_power = Power(noise.dropout_range_exponent);

    const uint64_t embree_errors = s.scene->error_count.load();
    const uint64_t overlay_errors = s.overlay ? s.overlay->error_count.load() : 0;
    const uint64_t rig_errors = s.rig ? s.rig->error_count.load() : 0;
    std::atomic<size_t> hits{0}, returns{0}, dropouts{0}, too_close{0}, glass_returns{0}, ghosts{0};
    auto body = [&](const tbb::blocked_range<int>& range) {
        [[maybe_unused]] ScopedFlushDenormals ftz;  // empty where neither applies
        Counts c;
        switch (options.packet_size) {
            case 1:
                c = CastColumns<1>(s, range.begin(), range.end());
                break;
            case 4:
                c = CastColumns<4>(s, range.begin(), range.end());
                break;
            case 8:
                c = CastColumns<8>(s, range.begin(), range.end());
                break;
            default:
                c = CastColumns<16>(s, range.begin(), range.end());
                break;
        }
        hits += c.hits, returns += c.returns, dropouts += c.dropouts, too_close += c.too_close;
        glass_returns += c.glass_returns, ghosts += c.ghosts;
    };
    auto run = [&] {
        tbb::parallel_for(tbb::blocked_range<int>(0, s.w, options.columns_per_task), body);
    };
    if (options.max_threads > 0) {
        tbb::task_arena arena(options.max_threads);
        arena.execute(run);
    } else {
        run();
    }
    ThrowIfEmbreeFailed(*s.scene, embree_errors, "SimulateScan");
    if (s.overlay) ThrowIfEmbreeFailed(*s.overlay, overlay_errors, "SimulateScan (overlay)");
    if (s.rig) ThrowIfEmbreeFailed(*s.rig, rig_errors, "SimulateScan (rig)");
    ScanStats stats;
    stats.rays = model.pixels();
    stats.hits = hits, stats.returns = returns, stats.dropouts = dropouts;
    stats.too_close = too_close;
    stats.glass_returns = glass_returns, stats.ghosts = ghosts;
    return stats;
}
}  // namespace

NoiseModel NoiseModel::Noiseless() {
    NoiseModel m;
    m.range_sigma_m = 0.0;
    m.dropout_base = 0.0;
    m.dropout_incidence_gain = 0.0;
    m.dropout_range_gain = 0.0;
    return m;
}

void NoiseModel::Validate() const {
    const char* t = "NoiseModel";
    common::Require(NonNegative(range_sigma_m) && range_sigma_m <= 100.0, t, "range_sigma_m",
                    range_sigma_m, "must be in [0, 100]");
    common::Require(NonNegative(min_range_m), t, "min_range_m", min_range_m, "must be >= 0");
    common::Require(std::isfinite(max_range_m) && max_range_m > min_range_m && max_range_m <= 1e6,
                    t, "max_range_m", max_range_m, "must be > min_range_m and <= 1e6");
    common::Require(range_resolution_mm >= 1, t, "range_resolution_mm", range_resolution_mm,
                    "must be >= 1");
    common::Require(NonNegative(dropout_base) && dropout_base <= 1, t, "dropout_base", dropout_base,
                    "must be in [0, 1]");
    common::Require(NonNegative(dropout_incidence_gain), t, "dropout_incidence_gain",
                    dropout_incidence_gain, "must be >= 0");
    common::Require(std::isfinite(dropout_incidence_exponent) && dropout_incidence_exponent > 0, t,
                    "dropout_incidence_exponent", dropout_incidence_exponent, "must be > 0");
    common::Require(NonNegative(dropout_range_gain), t, "dropout_range_gain", dropout_range_gain,
                    "must be >= 0");
    common::Require(std::isfinite(dropout_range_exponent) && dropout_range_exponent > 0, t,
                    "dropout_range_exponent", dropout_range_exponent, "must be > 0");
    common::Require(NonNegative(albedo) && albedo <= 1, t, "albedo", albedo, "must be in [0, 1]");
    common::Require(NonNegative(signal_at_1m), t, "signal_at_1m", signal_at_1m, "must be >= 0");
    common::Require(NonNegative(glass_return_probability) && glass_return_probability <= 1, t,
                    "glass_return_probability", glass_return_probability, "must be in [0, 1]");
    common::Require(NonNegative(glass_return_exponent) && glass_return_exponent <= 1000, t,
                    "glass_return_exponent", glass_return_exponent, "must be in [0, 1000]");
    common::Require(max_mirror_bounces >= 0 && max_mirror_bounces <= 8, t, "max_mirror_bounces",
                    max_mirror_bounces, "must be in [0, 8]");
}

void SimulatorOptions::Validate() const {
    const char* t = "SimulatorOptions";
    common::Require(packet_size == 1 || packet_size == 4 || packet_size == 8 || packet_size == 16,
                    t, "packet_size", packet_size, "must be 1, 4, 8 or 16");
    common::Require(columns_per_task >= 1, t, "columns_per_task", columns_per_task, "must be >= 1");
    common::Require(max_threads >= 0, t, "max_threads", max_threads, "must be >= 0");
}

void ScanImage::Resize(int beams, int columns) {
    h = beams;
    w = columns;
    const size_t n = static_cast<size_t>(beams) * columns;
    range_mm.resize(n);
    signal.resize(n);
    reflectivity.resize(n);
    element_id.resize(n);
}

ScanStats SimulateScan(const Scene& scene, const LidarModel& model,
                       const Eigen::Isometry3d& T_world_sensor, const NoiseModel& noise,
                       uint64_t seed, ScanImage* out, const SimulatorOptions& options) {
    return Run(scene, model, &T_world_sensor, 0, noise, seed, out, options);
}

ScanStats SimulateScan(const Scene& scene, const LidarModel& model,
                       std::span<const Eigen::Isometry3d> T_world_sensor_per_column,
                       const NoiseModel& noise, uint64_t seed, ScanImage* out,
                       const SimulatorOptions& options) {
    model.Validate();
    if (T_world_sensor_per_column.size() != static_cast<size_t>(model.columns)) {
        throw common::Error(StatusCode::kInvalidArgument,
                            "SimulateScan: " + std::to_string(T_world_sensor_per_column.size()) +
                                " poses for " + std::to_string(model.columns) + " columns");
    }
    return Run(scene, model, T_world_sensor_per_column.data(), 1, noise, seed, out, options);
}

ScanStats SimulateScan(const Scene& scene, const LidarModel& model,
                       const std::function<Eigen::Isometry3d(int column)>& T_world_sensor_at,
                       const NoiseModel& noise, uint64_t seed, ScanImage* out,
                       const SimulatorOptions& options) {
    model.Validate();
    std::vector<Eigen::Isometry3d> poses(static_cast<size_t>(model.columns));
    for (int v = 0; v < model.columns; ++v) poses[v] = T_world_sensor_at(v);
    return SimulateScan(scene, model, std::span<const Eigen::Isometry3d>(poses), noise, seed, out,
                        options);
}

}  // namespace bimslam::simulation
