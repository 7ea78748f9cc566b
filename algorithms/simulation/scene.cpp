#include "algorithms/simulation/scene.hpp"

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

}  // namespace bimslam::simulation
