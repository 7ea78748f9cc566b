// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/changes/element_evidence.hpp"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "algorithms/common/status.hpp"
#include "algorithms/common/voxel_hash.hpp"

namespace bimslam::changes {
namespace {

// A cell's value: its agree rays in the low 16 bits, its through rays in the high 16 (saturating).
uint32_t AddRay(uint32_t cell, bool agree) {
    const uint32_t a = cell & 0xFFFFu, t = cell >> 16;
    return agree ? (t << 16) | std::min(a + 1, 0xFFFFu) : (std::min(t + 1, 0xFFFFu) << 16) | a;
}
uint32_t MergeCells(uint32_t x, uint32_t y) {
    const uint32_t a = std::min((x & 0xFFFFu) + (y & 0xFFFFu), 0xFFFFu);
    const uint32_t t = std::min((x >> 16) + (y >> 16), 0xFFFFu);
    return (t << 16) | a;
}
constexpr int64_t kCellOffset = 1 << 19;

// In-plane axes of a plane: the cells of all coplanar triangles of an element share them, so a
// face split into triangles is binned as one (cell coordinates are p . u and p . v).
struct PlaneAxes {
    Eigen::Vector3f u, v;
};
PlaneAxes AxesOf(const Eigen::Vector3f& n) {
    const Eigen::Vector3f helper =
        std::abs(n.z()) < 0.9f ? Eigen::Vector3f::UnitZ() : Eigen::Vector3f::UnitX();
    const Eigen::Vector3f u = n.cross(helper).normalized();
    return {u, n.cross(u)};
}

struct ThreadState {
    common::VoxelHash cells{1 << 16};  // (plane, i, j) -> agree and through rays (AddRay)
    std::vector<uint32_t> counts;      // 3 per element
};

}  // namespace

void ElementEvidenceConfig::Validate() const {
    if (!(agree_tolerance_m > 0)) common::ThrowInvalid("elements.agree_tolerance_m must be > 0");
    if (!(min_cos_incidence >= 0 && min_cos_incidence < 1)) {
        common::ThrowInvalid("elements.min_cos_incidence must be in [0, 1), not " +
                             std::to_string(min_cos_incidence));
    }
    if (!(cell_m > 0))
        common::ThrowInvalid("elements.cell_m must be > 0, not " + std::to_string(cell_m));
    if (!(max_range_m > 0)) common::ThrowInvalid("elements.max_range_m must be > 0");
    if (point_stride < 1) common::ThrowInvalid("elements.point_stride must be >= 1");
}

namespace {

// The mesh's planes: coplanar triangles of one element (normal within 1e-3, offset within 1 mm)
// share a plane id, the first 24 bits of a cell's key. Adds each element's surface area to `out`.
struct Planes {
    std::vector<uint32_t> of_triangle;
    std::vector<PlaneAxes> axes;
    std::vector<uint32_t> element;  // per plane
};

Planes FindPlanes(const common::TriangleMesh& mesh, std::span<const uint32_t> triangle_element,
                  size_t element_count, std::vector<ElementEvidence>& out) {
    Planes p;
    p.of_triangle.resize(mesh.triangles.size());
    common::VoxelHash plane_ids(1024);
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
        const auto& tri = mesh.triangles[t];
        const Eigen::Vector3f a = mesh.vertices[tri[0]], b = mesh.vertices[tri[1]],
                              c = mesh.vertices[tri[2]];
        Eigen::Vector3f n = (b - a).cross(c - a);
        const uint32_t e = triangle_element[t];
        if (e >= element_count)
            common::ThrowInvalid("elements.triangle " + std::to_string(t) + " has no element");
        out[e].surface_area_m2 += 0.5 * double(n.norm());
        n = n.norm() > 0 ? Eigen::Vector3f(n.normalized()) : Eigen::Vector3f::UnitZ();
        const Eigen::Vector3f qn = (n * 1000.0f).array().round();
        const int64_t qd = int64_t(std::llround(double(n.dot(a)) * 1000.0));
        uint64_t key = uint64_t(e) * 0x9E3779B97F4A7C15ull;
        for (const int64_t q : {int64_t(qn.x()), int64_t(qn.y()), int64_t(qn.z()), qd}) {
            key = (key ^ uint64_t(q)) * 0x100000001B3ull;  // FNV-style mix
        }
        bool fresh = false;
        p.of_triangle[t] = plane_ids.FindOrInsert(key, uint32_t(p.axes.size()), &fresh);
        if (fresh) p.axes.push_back(AxesOf(n));
    }
    if (p.axes.size() >= (size_t(1) << 24))
        common::ThrowInvalid("elements.more than 2^24 planes: too many for the cells");
    p.element.resize(p.axes.size());
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
        p.element[p.of_triangle[t]] = triangle_element[t];
    }
    return p;
}

// One keyframe's beams cast into the model: per element, agreeing, through and occluded rays;
// per area cell of the plane hit, its agreeing and through rays.
void CastKeyframe(const simulation::Scene& scene, const Planes& planes,
                  std::span<const uint32_t> triangle_element, const MapKeyframe& keyframe,
                  const ElementEvidenceConfig& config, ThreadState& state) {
    const float cell = float(config.cell_m);
    const float tolerance = float(config.agree_tolerance_m);
    const float min_cos = float(config.min_cos_incidence);
    const float max_range = float(config.max_range_m);
    const Eigen::Isometry3f T = keyframe.T_world_lidar.cast<float>();
    const Eigen::Vector3f origin = T.translation();
    const auto& xyz = keyframe.cloud->xyz;
    for (size_t i = 0; i < xyz.size(); i += size_t(config.point_stride)) {
        const float r = xyz[i].norm();
        if (!(r > 0) || r > max_range) continue;
        const Eigen::Vector3f d = T.linear() * (xyz[i] / r);
        // Model surfaces farther than the point by more than a metre are behind whatever the
        // beam hit: no need to find them.
        const auto hit = scene.Intersect(origin, d, 0.0f, r + 1.0f);
        if (!hit) continue;
        const float cosine = std::abs(hit->normal.dot(d));
        if (cosine < min_cos) continue;
        const float s = (r - hit->t) * cosine;
        const uint32_t e = triangle_element[hit->triangle];
        if (s < -tolerance) {
            ++state.counts[3 * e + 2];
            continue;
        }
        const bool agree = s <= tolerance;
        ++state.counts[3 * e + (agree ? 0 : 1)];
        const uint32_t plane = planes.of_triangle[hit->triangle];
        const Eigen::Vector3f h = origin + hit->t * d;
        const int64_t ci = int64_t(std::floor(h.dot(planes.axes[plane].u) / cell)) + kCellOffset;
        const int64_t cj = int64_t(std::floor(h.dot(planes.axes[plane].v) / cell)) + kCellOffset;
        if (ci < 0 || cj < 0 || ci >= 2 * kCellOffset || cj >= 2 * kCellOffset) continue;
        const uint64_t key = uint64_t(plane) << 40 | uint64_t(ci) << 20 | uint64_t(cj);
        uint32_t& value = state.cells.FindOrInsert(key, 0);
        value = AddRay(value, agree);
    }
}

// The threads' counts and cells into `out`: rays per element, expected and seen area per element.
void Gather(tbb::enumerable_thread_specific<ThreadState>& states, const Planes& planes,
            double cell_m, std::vector<ElementEvidence>& out) {
    common::VoxelHash cells(1 << 16);
    for (ThreadState& s : states) {
        for (size_t e = 0; e < out.size(); ++e) {
            out[e].rays_agree += s.counts[3 * e];
            out[e].rays_through += s.counts[3 * e + 1];
            out[e].rays_occluded += s.counts[3 * e + 2];
        }
        s.cells.ForEach([&](uint64_t key, uint32_t value) {
            uint32_t& merged = cells.FindOrInsert(key, 0);
            merged = MergeCells(merged, value);
        });
    }
    const float cell = float(cell_m);
    const double cell_area = double(cell) * double(cell);
    cells.ForEach([&](uint64_t key, uint32_t value) {
        ElementEvidence& ev = out[planes.element[size_t(key >> 40)]];
        ev.expected_area_m2 += cell_area;
        // Seen: more beams confirmed the cell than went through it (a cell at the edge where a
        // removed cabinet met the wall gets a few agreeing beams among many through it).
        if ((value & 0xFFFFu) >= (value >> 16)) ev.seen_area_m2 += cell_area;
    });
    for (ElementEvidence& ev : out) {
        ev.expected_area_m2 = std::min(ev.expected_area_m2, ev.surface_area_m2);
        ev.seen_area_m2 = std::min(ev.seen_area_m2, ev.surface_area_m2);
    }
}

}  // namespace

std::vector<ElementEvidence> CollectElementEvidence(const simulation::Scene& scene,
                                                    const common::TriangleMesh& mesh,
                                                    std::span<const uint32_t> triangle_element,
                                                    size_t element_count,
                                                    std::span<const MapKeyframe> keyframes,
                                                    const ElementEvidenceConfig& config,
                                                    const std::function<void(double)>& progress) {
    config.Validate();
    if (triangle_element.size() != mesh.triangles.size() ||
        scene.triangle_count() != mesh.triangles.size()) {
        common::ThrowInvalid(
            "elements.the scene, the mesh and the triangle elements differ in size");
    }
    if (mesh.triangles.size() >= (size_t(1) << 24)) {
        common::ThrowInvalid(
            "elements.more than 2^24 opaque triangles: the area cells cannot number them");
    }
    std::vector<ElementEvidence> out(element_count);
    const Planes planes = FindPlanes(mesh, triangle_element, element_count, out);
    tbb::enumerable_thread_specific<ThreadState> states([&] {
        ThreadState s;
        s.counts.assign(3 * element_count, 0);
        return s;
    });
    const size_t chunk = std::max<size_t>(1, keyframes.size() / 40);
    for (size_t first = 0; first < keyframes.size(); first += chunk) {
        const size_t last = std::min(keyframes.size(), first + chunk);
        tbb::parallel_for(tbb::blocked_range<size_t>(first, last, 1), [&](const auto& range) {
            ThreadState& state = states.local();
            for (size_t k = range.begin(); k < range.end(); ++k) {
                CastKeyframe(scene, planes, triangle_element, keyframes[k], config, state);
            }
        });
        if (progress) progress(double(last) / double(keyframes.size()));
    }
    Gather(states, planes, config.cell_m, out);
    return out;
}

}  // namespace bimslam::changes
