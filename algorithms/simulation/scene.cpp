// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/simulation/scene.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <string>
#include <utility>

#include "algorithms/common/status.hpp"
#include "algorithms/simulation/embree_scene.hpp"

namespace bimslam::simulation {
namespace {
using common::StatusCode;

const char* ErrorName(RTCError e) {
    switch (e) {
        case RTC_ERROR_NONE:
            return "RTC_ERROR_NONE";
        case RTC_ERROR_UNKNOWN:
            return "RTC_ERROR_UNKNOWN";
        case RTC_ERROR_INVALID_ARGUMENT:
            return "RTC_ERROR_INVALID_ARGUMENT";
        case RTC_ERROR_INVALID_OPERATION:
            return "RTC_ERROR_INVALID_OPERATION";
        case RTC_ERROR_OUT_OF_MEMORY:
            return "RTC_ERROR_OUT_OF_MEMORY";
        case RTC_ERROR_UNSUPPORTED_CPU:
            return "RTC_ERROR_UNSUPPORTED_CPU";
        case RTC_ERROR_CANCELLED:
            return "RTC_ERROR_CANCELLED";
    }
    return "RTC_ERROR_?";
}

StatusCode CodeOf(RTCError e) {
    switch (e) {
        case RTC_ERROR_INVALID_ARGUMENT:
            return StatusCode::kInvalidArgument;
        case RTC_ERROR_OUT_OF_MEMORY:
        case RTC_ERROR_UNSUPPORTED_CPU:
            return StatusCode::kUnavailable;
        default:
            return StatusCode::kInternal;
    }
}

void OnEmbreeError(void* user, RTCError code, const char* message) {
    auto* impl = static_cast<Scene::Impl*>(user);
    {
        std::lock_guard lock(impl->error_mutex);
        impl->last_error = std::string(ErrorName(code)) + ": " + (message ? message : "");
    }
    ++impl->error_count;
}

// Throws when Embree reports an error on the device since the last check.
void Check(Scene::Impl& impl, const char* what) {
    const RTCError e = rtcGetDeviceError(impl.device);
    if (e == RTC_ERROR_NONE) return;
    std::string text;
    {
        std::lock_guard lock(impl.error_mutex);
        text = impl.last_error.empty() ? ErrorName(e) : impl.last_error;
    }
    throw common::Error(CodeOf(e), std::string("Embree: ") + what + ": " + text);
}

void Require(bool ok, const std::string& message) {
    if (!ok) throw common::Error(StatusCode::kInvalidArgument, "Scene: " + message);
}

// The point of triangle abc nearest to p: Ericson, "Real-Time Collision Detection" (2005),
// section 5.1.5, by the Voronoi regions of the vertices, edges and face. In double: the region
// tests and barycentrics are differences of products of dot products (vc = d1 d4 - d3 d2 ...),
// of the order of |ab|^2 |ap|^2, divided by |ab x ac|^2. On a sliver triangle (the building's wall
// faces beside openings are 27 m long and 2-9 cm high) float32 loses the barycentrics to
// cancellation and puts the point 20 mm off; double leaves nanometres
// (algorithms/changes/README.md).
Eigen::Vector3d ClosestOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                  const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
    const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
    const double d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= 0 && d2 <= 0) return a;
    const Eigen::Vector3d bp = p - b;
    const double d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0 && d4 <= d3) return b;
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + (d1 / (d1 - d3)) * ab;
    const Eigen::Vector3d cp = p - c;
    const double d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0 && d5 <= d6) return c;
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + (d2 / (d2 - d6)) * ac;
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
    }
    const double denom = 1.0 / (va + vb + vc);
    return a + ab * (vb * denom) + ac * (vc * denom);
}

// The state of one closest-point query, shared by the hint and Embree's callback.
struct PointQueryState {
    const Scene::Impl* impl = nullptr;
    Eigen::Vector3f query = Eigen::Vector3f::Zero();
    float best_d2 = std::numeric_limits<float>::infinity();
    float best_alignment = -1;  // ((query - point) . n)^2 / d^2 of the best triangle
    bool best_front = false;    // the query is in front of the best triangle
    uint32_t best = Scene::kNoHint;
    Eigen::Vector3f point = Eigen::Vector3f::Zero();
    const Eigen::Vector3f* viewpoint = nullptr;  // ClosestFacing: triangles facing it only

    // Takes triangle t when it is nearer, or as near (relative 1e-5: an edge or corner shared by
    // several triangles) with a normal more aligned with query - point; among those equally
    // aligned (two elements touching face to face: opposite normals, the same plane), the one the
    // query is in front of, then the lower index. So the answer does not depend on the order in
    // which Embree's traversal visits the triangles, which varies with its BVH build: without the
    // last two rules the sign and the element of such points changed from run to run.
    void Consider(uint32_t t) {
        const Scene::Impl::TriangleData& tri = impl->triangle_data[t];
        if (viewpoint != nullptr && (*viewpoint - tri.a).dot(tri.normal) <= 0) return;
        const float tie = best_d2 * 1e-5f + 1e-12f;
        // The distance to the triangle's plane is a lower bound of the distance to it.
        const float plane = (query - tri.a).dot(tri.normal);
        if (plane * plane > best_d2 + tie) return;
        // The exact test in double (see ClosestOnTriangle); the vertices are floats, so their
        // differences there are exact.
        const Eigen::Vector3d p = query.cast<double>();
        const Eigen::Vector3d q =
            ClosestOnTriangle(p, tri.a.cast<double>(), tri.b.cast<double>(), tri.c.cast<double>());
        const Eigen::Vector3d d = p - q;
        const auto d2 = float(d.squaredNorm());
        if (d2 > best_d2 + tie) return;
        const auto along = float(d.dot(tri.normal.cast<double>()));
        const float alignment = d2 > 0 ? along * along / d2 : 1.0f;
        const bool front = along > 0;
        if (d2 >= best_d2 - tie) {  // as near as the best: the rules above decide
            constexpr float kSame = 1e-6f;
            if (alignment < best_alignment - kSame) return;
            if (alignment <= best_alignment + kSame) {
                if (front != best_front ? !front : t > best) return;
            }
        }
        best_d2 = d2;  // the chosen triangle's own: the distance reported is its distance
        best_alignment = alignment;
        best_front = front;
        best = t;
        point = q.cast<float>();
    }
};

bool PointQueryCallback(RTCPointQueryFunctionArguments* args) {
    auto* state = static_cast<PointQueryState*>(args->userPtr);
    state->Consider(args->primID);
    // Shrink the search to the best distance, keeping equally near triangles in it.
    const float radius = std::sqrt(state->best_d2) * (1.0f + 1e-5f) + 1e-6f;
    if (radius < args->query->radius) {
        args->query->radius = radius;
        return true;
    }
    return false;
}
}  // namespace

void ThrowIfEmbreeFailed(const Scene::Impl& impl, uint64_t count_before, const char* what) {
    if (impl.error_count.load() == count_before) return;
    std::string text;
    {
        std::lock_guard lock(impl.error_mutex);
        text = impl.last_error;
    }
    throw common::Error(StatusCode::kInternal, std::string("Embree: ") + what + ": " + text);
}

Scene::Impl::~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
}

Scene::Scene(const common::TriangleMesh& mesh, std::vector<uint32_t> triangle_ids,
             std::vector<Material> materials, const SceneConfig& config)
    : Scene(mesh, std::move(triangle_ids), config) {
    Require(materials.empty() || materials.size() == mesh.triangles.size(),
            "materials has " + std::to_string(materials.size()) + " entries, the mesh " +
                std::to_string(mesh.triangles.size()) + " triangles");
    // Kept only when some triangle is special, so that a scene of diffuse triangles takes the
    // plain path however it was built.
    if (std::any_of(materials.begin(), materials.end(),
                    [](Material m) { return m != Material::kDiffuse; })) {
        impl_->materials = std::move(materials);
    }
}

Scene::Scene(const common::TriangleMesh& mesh, std::vector<uint32_t> triangle_ids,
             const SceneConfig& config)
    : impl_(std::make_unique<Impl>()) {
    Require(mesh.IndicesValid(),
            "a triangle index is >= vertices.size() = " + std::to_string(mesh.vertices.size()));
    Require(mesh.triangles.size() < size_t(RTC_INVALID_GEOMETRY_ID),
            std::to_string(mesh.triangles.size()) + " triangles: too many for one geometry");
    Require(triangle_ids.empty() || triangle_ids.size() == mesh.triangles.size(),
            "triangle_ids has " + std::to_string(triangle_ids.size()) + " entries, the mesh " +
                std::to_string(mesh.triangles.size()) + " triangles");
    for (size_t i = 0; i < mesh.vertices.size(); ++i) {
        Require(mesh.vertices[i].allFinite(), "vertex " + std::to_string(i) + " is not finite");
    }
    Impl& impl = *impl_;
    impl.triangles = mesh.triangles.size();
    impl.ids = std::move(triangle_ids);
    if (impl.ids.empty()) {
        impl.ids.resize(impl.triangles);
        for (size_t i = 0; i < impl.triangles; ++i) impl.ids[i] = static_cast<uint32_t>(i);
    }

    impl.device = rtcNewDevice("verbose=0");
    if (!impl.device) {
        const RTCError e = rtcGetDeviceError(nullptr);
        throw common::Error(CodeOf(e), std::string("Embree: rtcNewDevice failed: ") + ErrorName(e));
    }
    rtcSetDeviceErrorFunction(impl.device, OnEmbreeError, &impl);
    impl.scene = rtcNewScene(impl.device);
    Check(impl, "rtcNewScene");
    rtcSetSceneFlags(impl.scene, config.robust ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE);
    rtcSetSceneBuildQuality(
        impl.scene, config.high_quality_build ? RTC_BUILD_QUALITY_HIGH : RTC_BUILD_QUALITY_MEDIUM);
    if (!mesh.empty()) {
        RTCGeometry geometry = rtcNewGeometry(impl.device, RTC_GEOMETRY_TYPE_TRIANGLE);
        Check(impl, "rtcNewGeometry");
        // Embree's own buffers (padded as its SIMD loads need); Vector3f and the index triples
        // are tightly packed floats and uint32s, 12 bytes each.
        static_assert(sizeof(Eigen::Vector3f) == 3 * sizeof(float));
        static_assert(sizeof(std::array<uint32_t, 3>) == 3 * sizeof(uint32_t));
        auto* vertices = static_cast<float*>(
            rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                    3 * sizeof(float), mesh.vertices.size()));
        auto* indices = static_cast<uint32_t*>(
            rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                    3 * sizeof(uint32_t), mesh.triangles.size()));
        if (!vertices || !indices) {
            rtcReleaseGeometry(geometry);
            Check(impl, "rtcSetNewGeometryBuffer");
            throw common::Error(StatusCode::kInternal, "Embree: rtcSetNewGeometryBuffer failed");
        }
        std::memcpy(vertices, mesh.vertices.data(), mesh.vertices.size() * 3 * sizeof(float));
        std::memcpy(indices, mesh.triangles.data(), mesh.triangles.size() * 3 * sizeof(uint32_t));
        impl.triangle_data.resize(mesh.triangles.size());
        for (size_t t = 0; t < mesh.triangles.size(); ++t) {
            const auto& tri = mesh.triangles[t];
            Impl::TriangleData& data = impl.triangle_data[t];
            data.a = mesh.vertices[tri[0]];
            data.b = mesh.vertices[tri[1]];
            data.c = mesh.vertices[tri[2]];
            const Eigen::Vector3f n = (data.b - data.a).cross(data.c - data.a);
            const float length = n.norm();
            data.normal = length > 0 ? Eigen::Vector3f(n / length) : Eigen::Vector3f::Zero();
        }
        rtcCommitGeometry(geometry);
        rtcAttachGeometryByID(impl.scene, geometry, 0);
        rtcReleaseGeometry(geometry);  // the scene holds it
        Check(impl, "rtcCommitGeometry");
    }
    rtcCommitScene(impl.scene);
    Check(impl, "rtcCommitScene");
}

Scene::~Scene() = default;
Scene::Scene(Scene&& other) noexcept = default;
Scene& Scene::operator=(Scene&& other) noexcept = default;

size_t Scene::triangle_count() const { return impl_->triangles; }

uint32_t Scene::TriangleId(uint32_t i) const { return impl_->ids[i]; }

Material Scene::MaterialOf(uint32_t i) const {
    return impl_->materials.empty() ? Material::kDiffuse : impl_->materials[i];
}

bool Scene::has_special_materials() const { return !impl_->materials.empty(); }

Eigen::AlignedBox3f Scene::Bounds() const {
    if (impl_->triangles == 0) return Eigen::AlignedBox3f();
    RTCBounds b;
    rtcGetSceneBounds(impl_->scene, &b);
    return Eigen::AlignedBox3f(Eigen::Vector3f(b.lower_x, b.lower_y, b.lower_z),
                               Eigen::Vector3f(b.upper_x, b.upper_y, b.upper_z));
}

std::optional<Scene::Hit> Scene::Intersect(const Eigen::Vector3f& origin,
                                           const Eigen::Vector3f& direction, float t_near,
                                           float t_far) const {
    const uint64_t errors = impl_->error_count.load();
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh;
    rh.ray.org_x = origin.x();
    rh.ray.org_y = origin.y();
    rh.ray.org_z = origin.z();
    rh.ray.dir_x = direction.x();
    rh.ray.dir_y = direction.y();
    rh.ray.dir_z = direction.z();
    rh.ray.tnear = t_near;
    rh.ray.tfar = t_far;
    rh.ray.time = 0.0f;
    rh.ray.mask = 0xFFFFFFFFu;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(impl_->scene, &context, &rh);
    ThrowIfEmbreeFailed(*impl_, errors, "rtcIntersect1");
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
    Hit hit;
    hit.t = rh.ray.tfar;
    hit.triangle = rh.hit.primID;
    hit.id = impl_->ids[rh.hit.primID];
    const Eigen::Vector3f n(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
    const float norm = n.norm();
    hit.normal = norm > 0 ? Eigen::Vector3f(n / norm) : Eigen::Vector3f::Zero();
    return hit;
}

std::optional<Scene::Closest> Scene::ClosestPoint(const Eigen::Vector3f& query, float max_distance,
                                                  uint32_t hint) const {
    return Nearest(query, nullptr, max_distance, hint);
}

std::optional<Scene::Closest> Scene::ClosestFacing(const Eigen::Vector3f& query,
                                                   const Eigen::Vector3f& viewpoint,
                                                   float max_distance) const {
    return Nearest(query, &viewpoint, max_distance, kNoHint);
}

std::optional<Scene::Closest> Scene::Nearest(const Eigen::Vector3f& query,
                                             const Eigen::Vector3f* viewpoint, float max_distance,
                                             uint32_t hint) const {
    if (impl_->triangles == 0 || !(max_distance >= 0)) return std::nullopt;
    PointQueryState state;
    state.impl = impl_.get();
    state.query = query;
    state.viewpoint = viewpoint;
    if (hint < impl_->triangles) state.Consider(hint);
    const float bound = std::sqrt(state.best_d2) * (1.0f + 1e-5f) + 1e-6f;
    RTCPointQuery q;
    q.x = query.x();
    q.y = query.y();
    q.z = query.z();
    q.time = 0.0f;
    q.radius = std::min(max_distance, bound);
    RTCPointQueryContext context;
    rtcInitPointQueryContext(&context);
    const uint64_t errors = impl_->error_count.load();
    rtcPointQuery(impl_->scene, &q, &context, PointQueryCallback, &state);
    ThrowIfEmbreeFailed(*impl_, errors, "rtcPointQuery");
    if (state.best == kNoHint) return std::nullopt;
    Closest out;
    out.distance = std::sqrt(state.best_d2);
    if (out.distance > max_distance) return std::nullopt;
    out.triangle = state.best;
    out.id = impl_->ids[state.best];
    out.point = state.point;
    out.normal = impl_->triangle_data[state.best].normal;
    out.signed_distance = (query - state.point).dot(out.normal) >= 0 ? out.distance : -out.distance;
    return out;
}

}  // namespace bimslam::simulation
