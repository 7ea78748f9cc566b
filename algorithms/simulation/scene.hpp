// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// A triangle mesh made ready for ray casting and closest-point queries (an Embree 3 BVH), with one
// id per triangle (for a BIM model the index of the element the triangle belongs to).
//
// Built and committed once in the constructor, read-only afterwards: every query is thread-safe.
// The Embree device and scene are owned here (RAII) and never appear in this header, so users of
// the simulation need no Embree includes. Errors reported by Embree (its error callback and
// rtcGetDeviceError) become common::Error carrying Embree's error code and text.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include "algorithms/common/triangle_mesh.hpp"

namespace bimslam::simulation {

// What a triangle does to a LiDAR beam (lidar_simulator.hpp, "Materials"; README.md has the
// physics). Only the static scene's materials act; an overlay's or rig scene's triangles are
// treated as diffuse.
enum class Material : uint8_t {
    kDiffuse = 0,  // a Lambertian surface: the beam returns from it (the default)
    kGlass = 1,    // a clear pane: the beam mostly passes on, near normal incidence it may return
    kMirror = 2,   // specular: the beam reflects and the sensor reports the whole path's length
};

struct SceneConfig {
    // Embree's RTC_SCENE_FLAG_ROBUST: no optimisations that lose accuracy, so rays through
    // shared edges and vertices of a closed mesh do not slip through. Costs a few per cent.
    bool robust = true;
    // RTC_BUILD_QUALITY_HIGH (SAH with spatial splits): slower to build, faster to trace; worth
    // it for a scene built once and cast against millions of times.
    bool high_quality_build = true;
};

class Scene {
public:
    // triangle_ids: one per triangle of mesh (e.g. the BIM element index); empty means each
    // triangle's id is its own index. Throws common::Error (kInvalidArgument) for an index out of
    // range, a non-finite vertex or an id list of the wrong length; (kInternal, or Embree's own
    // code) when Embree fails, with Embree's message. An empty mesh is a valid scene that every
    // ray misses.
    explicit Scene(const common::TriangleMesh& mesh, std::vector<uint32_t> triangle_ids = {},
                   const SceneConfig& config = {});
    // The same with a material per triangle (empty: all diffuse); throws common::Error
    // (kInvalidArgument) for a list of the wrong length.
    Scene(const common::TriangleMesh& mesh, std::vector<uint32_t> triangle_ids,
          std::vector<Material> materials, const SceneConfig& config = {});
    ~Scene();
    Scene(Scene&& other) noexcept;
    Scene& operator=(Scene&& other) noexcept;
    Scene(const Scene&) = delete;
    Scene& operator=(const Scene&) = delete;

    size_t triangle_count() const;
    // The id of triangle i (i < triangle_count()).
    uint32_t TriangleId(uint32_t i) const;
    // The material of triangle i (i < triangle_count()).
    Material MaterialOf(uint32_t i) const;
    // True when some triangle is not diffuse (SimulateScan then follows beams through glass and
    // off mirrors; without, it takes the plain path).
    bool has_special_materials() const;
    // Bounds of the geometry; an empty box for an empty scene.
    Eigen::AlignedBox3f Bounds() const;

    struct Hit {
        float t = 0;            // distance along the (unit) direction
        uint32_t triangle = 0;  // index into the mesh's triangles
        uint32_t id = 0;        // TriangleId(triangle)
        // Unit geometric normal, on the side the triangle's counter-clockwise winding faces.
        Eigen::Vector3f normal = Eigen::Vector3f::Zero();
    };
    // The closest hit of origin + t * direction for t in [t_near, t_far] (direction need not be
    // unit; t is then in its units), or nullopt. Thread-safe.
    std::optional<Hit> Intersect(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction,
                                 float t_near = 0.0f,
                                 float t_far = std::numeric_limits<float>::infinity()) const;

    struct Closest {
        float distance = 0;     // Euclidean, from the query point to `point`
        uint32_t triangle = 0;  // index into the mesh's triangles
        uint32_t id = 0;        // TriangleId(triangle)
        Eigen::Vector3f point = Eigen::Vector3f::Zero();  // the nearest point of the mesh
        // Unit geometric normal of `triangle` (its counter-clockwise side), as Hit::normal.
        Eigen::Vector3f normal = Eigen::Vector3f::Zero();
        // (query - point) . normal: > 0 in front of the triangle, < 0 behind it. Where several
        // triangles are equally near (an edge or corner of a solid), the one whose normal is most
        // aligned with query - point is taken, so that a point outside a closed mesh is in front
        // of it and a point inside behind it at convex and concave edges alike.
        float signed_distance = 0;
    };
    static constexpr uint32_t kNoHint = std::numeric_limits<uint32_t>::max();
    // The nearest point of the mesh to `query` no farther than max_distance, or nullopt (an empty
    // scene, or nothing that near). `hint`: a triangle likely to be near (the previous answer of
    // a neighbouring query); its distance bounds the search from the start, which makes queries
    // in spatial order several times faster. The answer does not depend on the hint. Embree's
    // rtcPointQuery (BVH traversal) with the closest point on a triangle of Ericson, "Real-Time
    // Collision Detection" 5.1.5. Thread-safe.
    std::optional<Closest> ClosestPoint(const Eigen::Vector3f& query,
                                        float max_distance = std::numeric_limits<float>::infinity(),
                                        uint32_t hint = kNoHint) const;
    // As ClosestPoint, among the triangles whose counter-clockwise (outer) side faces `viewpoint`
    // only: the surfaces a sensor there can have hit. A point on the near face of a thin wall,
    // seen from a pose a few centimetres off, may be nearer the wall's far face; matching it there
    // pulls the pose through the wall (pose_refinement.cpp). Thread-safe.
    std::optional<Closest> ClosestFacing(
        const Eigen::Vector3f& query, const Eigen::Vector3f& viewpoint,
        float max_distance = std::numeric_limits<float>::infinity()) const;

    // The Embree objects, for the simulation's own sources (embree_scene.hpp defines it).
    struct Impl;
    const Impl& impl() const { return *impl_; }

private:
    std::optional<Closest> Nearest(const Eigen::Vector3f& query, const Eigen::Vector3f* viewpoint,
                                   float max_distance, uint32_t hint) const;
    std::unique_ptr<Impl> impl_;
};

}  // namespace bimslam::simulation
