// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Glass and mirrors (Scene's Material, lidar_simulator.hpp "Materials"): a mirror's ghost lies
// at the mirror image of what the reflected beam hit; glass returns with p0 cos(a)^k and lets the
// rest through; images stay deterministic; a scene of diffuse triangles is unchanged.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "algorithms/common/status.hpp"
#include "algorithms/simulation/lidar_simulator.hpp"
#include "tests/unit/simulation/simulation_fixtures.hpp"

namespace bimslam::simulation {
namespace {
namespace BIMSLAM_UNITY_ID {

using namespace fixtures;

// Appends `part` with id and material to a scene's mesh, ids and materials.
struct SceneParts {
    common::TriangleMesh mesh;
    std::vector<uint32_t> ids;
    std::vector<Material> materials;

    void Add(const common::TriangleMesh& part, uint32_t id, Material material) {
        const auto base = static_cast<uint32_t>(mesh.vertices.size());
        mesh.vertices.insert(mesh.vertices.end(), part.vertices.begin(), part.vertices.end());
        for (auto t : part.triangles)
            mesh.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
        ids.insert(ids.end(), part.triangles.size(), id);
        materials.insert(materials.end(), part.triangles.size(), material);
    }
    Scene Build() const { return Scene(mesh, ids, materials); }
};

// The plane x = x0, |y| <= hy, |z| <= hz.
common::TriangleMesh PlaneX(double x0, double hy, double hz) {
    common::TriangleMesh m;
    AddQuad(&m, {x0, -hy, -hz}, {x0, hy, -hz}, {x0, hy, hz});
    return m;
}

constexpr uint32_t kWall = 1, kMirror = 2, kTarget = 3;
constexpr double kMirrorX = 3.99;  // a mirror 1 cm in front of the wall at x = 4
constexpr double kTargetX = -2.0;  // behind the sensor, where the reflected beams land

TEST(SimulateScanMaterials, AMirrorGhostLiesAtTheMirrorImageOfWhatTheReflectedBeamHit) {
    SceneParts parts;
    parts.Add(PlaneX(4.0, 5, 5), kWall, Material::kDiffuse);
    parts.Add(PlaneX(kMirrorX, 1.0, 0.8), kMirror, Material::kMirror);
    parts.Add(PlaneX(kTargetX, 10, 10), kTarget, Material::kDiffuse);
    const Scene scene = parts.Build();
    const LidarModel model = SimpleModel(Linspace(-20, 20, 21), 512);
    ScanImage img;
    const ScanStats stats = SimulateScan(scene, model, Pose(0, 0, 0), Exact(), 3, &img);
    size_t checked = 0;
    for (int u = 0; u < img.h; ++u) {
        for (int v = 0; v < img.w; ++v) {
            const Eigen::Vector3d d = model.Direction(u, v);
            if (d.x() <= 0) continue;
            const Eigen::Vector3d on_mirror = d * (kMirrorX / d.x());
            // Clear of the mirror's edges by 1 cm: there the beam may take either side.
            if (std::abs(on_mirror.y()) > 0.99 || std::abs(on_mirror.z()) > 0.79) continue;
            const size_t i = img.Index(u, v);
            // The reflected beam, d' = (-dx, dy, dz), lands on the target plane.
            const Eigen::Vector3d reflected(-d.x(), d.y(), d.z());
            const Eigen::Vector3d truth = on_mirror + reflected * ((kMirrorX - kTargetX) / d.x());
            const double path = (kMirrorX + (kMirrorX - kTargetX)) / d.x();
            ASSERT_EQ(img.element_id[i], kTarget) << u << " " << v;  // the surface finally hit
            EXPECT_NEAR(img.range_mm[i] * 1e-3, path, 1e-3);
            // The point the sensor reports (along the beam it sent) lies behind the mirror...
            const Eigen::Vector3d ghost = img.range_mm[i] * 1e-3 * d + model.Origin(u, v);
            EXPECT_GT(ghost.x(), 4.0);
            // ... at the mirror image of the target's point, to the millimetre.
            const Eigen::Vector3d mirrored(2 * kMirrorX - ghost.x(), ghost.y(), ghost.z());
            EXPECT_LT((mirrored - truth).norm(), 1.5e-3) << u << " " << v;
            ++checked;
        }
    }
    EXPECT_GT(checked, 300u);
    EXPECT_GE(stats.ghosts, checked);

    // No bounces allowed: the mirror's pixels return nothing.
    NoiseModel none = Exact();
    none.max_mirror_bounces = 0;
    SimulateScan(scene, model, Pose(0, 0, 0), none, 3, &img);
    const int u = 10, v = 0;  // straight ahead, the mirror's centre
    ASSERT_GT(model.Direction(u, v).x(), 0.99);
    EXPECT_EQ(img.range_mm[img.Index(u, v)], 0u);
    EXPECT_EQ(img.element_id[img.Index(u, v)], kNoElement);
}

constexpr uint32_t kPane = 10, kBehind = 11;

// A pane at x = 3 (|y|, |z| < 2) in front of a wall at x = 6, seen from the origin.
Scene PaneScene() {
    SceneParts parts;
    parts.Add(PlaneX(3.0, 2, 2), kPane, Material::kGlass);
    parts.Add(PlaneX(6.0, 10, 10), kBehind, Material::kDiffuse);
    return parts.Build();
}

TEST(SimulateScanMaterials, GlassReturnsWithItsProbabilityAndTheRestHitsWhatIsBehind) {
    const Scene scene = PaneScene();
    const LidarModel model = SimpleModel(Linspace(-10, 10, 64), 2048);
    for (const double exponent : {0.0, 30.0}) {
        NoiseModel noise = Exact();
        noise.glass_return_probability = 0.4;
        noise.glass_return_exponent = exponent;
        ScanImage img;
        const ScanStats stats = SimulateScan(scene, model, Pose(0, 0, 0), noise, 11, &img);
        double expected = 0, variance = 0;
        size_t on_pane = 0, from_pane = 0;
        for (int u = 0; u < img.h; ++u) {
            for (int v = 0; v < img.w; ++v) {
                const Eigen::Vector3d d = model.Direction(u, v);
                const Eigen::Vector3d p = d * (3.0 / d.x());
                if (d.x() <= 0 || std::abs(p.y()) > 1.98 || std::abs(p.z()) > 1.98) continue;
                ++on_pane;
                const double pr = 0.4 * std::pow(d.x(), exponent);  // cos a = d . x
                expected += pr, variance += pr * (1 - pr);
                const size_t i = img.Index(u, v);
                if (img.element_id[i] == kPane) {
                    ++from_pane;
                    EXPECT_NEAR(img.range_mm[i] * 1e-3, 3.0 / d.x(), 1e-3);
                } else {
                    ASSERT_EQ(img.element_id[i], kBehind);  // through the pane
                    EXPECT_NEAR(img.range_mm[i] * 1e-3, 6.0 / d.x(), 1e-3);
                }
            }
        }
        ASSERT_GT(on_pane, 20000u);
        EXPECT_NEAR(double(from_pane), expected, 4 * std::sqrt(variance)) << "k " << exponent;
        EXPECT_GE(stats.glass_returns, from_pane);  // and the 2 cm margin's
        if (exponent == 0) {                        // p0 at every angle: the configured fraction
            EXPECT_NEAR(double(from_pane) / double(on_pane), 0.4, 0.01);
        }
    }
}

TEST(SimulateScanMaterials, GlassAtGrazingIncidenceAlmostNeverReturns) {
    // A long pane in the plane y = 1 along the beams (x in [0.5, 40]), a wall at x = 41.
    SceneParts parts;
    common::TriangleMesh pane;
    AddQuad(&pane, {0.5, 1, -2}, {40, 1, -2}, {40, 1, 2});
    parts.Add(pane, kPane, Material::kGlass);
    parts.Add(PlaneX(41.0, 10, 10), kBehind, Material::kDiffuse);
    const Scene scene = parts.Build();
    const LidarModel model = SimpleModel(Linspace(-2, 2, 16), 2048);
    ScanImage img;
    SimulateScan(scene, model, Pose(0, 0, 0), Exact(), 5, &img);  // the defaults: 0.5, k = 30
    size_t grazing = 0;
    for (int u = 0; u < img.h; ++u) {
        for (int v = 0; v < img.w; ++v) {
            const Eigen::Vector3d d = model.Direction(u, v);
            if (d.y() <= 0 || d.x() <= 0) continue;
            const Eigen::Vector3d p = d / d.y();  // where the beam meets y = 1
            if (p.x() < 0.6 || p.x() > 39.9 || std::abs(p.z()) > 1.9) continue;
            if (d.y() > std::cos(70 * M_PI / 180)) continue;  // incidence above 70 degrees
            ++grazing;
            EXPECT_NE(img.element_id[img.Index(u, v)], kPane) << u << " " << v;
        }
    }
    EXPECT_GT(grazing, 1000u);
}

TEST(SimulateScanMaterials, IdenticalForAnyThreadsPacketAndBlockSize) {
    // The furnished room with mirrors and glass on some of its triangles, people in an overlay.
    const common::TriangleMesh room = FurnishedRoom();
    std::vector<Material> materials(room.triangles.size(), Material::kDiffuse);
    for (size_t t = 0; t < materials.size(); ++t) {
        if (t % 7 == 0) materials[t] = Material::kMirror;
        if (t % 5 == 0) materials[t] = Material::kGlass;
    }
    const Scene scene(room, {}, materials);
    const BoxRoom person({0.8, -0.6, -1.2}, {1.2, -0.2, 0.6});
    const Scene overlay(person.mesh, std::vector<uint32_t>(person.mesh.triangles.size(), 999));
    const LidarModel model = LidarModel::DefaultOs1_32(1024);
    NoiseModel noise;
    noise.glass_return_exponent = 4;  // many glass returns, so that their draws are exercised
    SimulatorOptions base;
    base.overlay = &overlay;
    base.packet_size = 1, base.columns_per_task = 1, base.max_threads = 1;
    ScanImage reference;
    const ScanStats ref =
        SimulateScan(scene, model, Pose(0.3, 0.4, 0.1, 20, 2, -3), noise, 99, &reference, base);
    EXPECT_GT(ref.ghosts, 1000u);
    EXPECT_GT(ref.glass_returns, 1000u);
    for (const int threads : {1, 2, 0}) {
        for (const int packet : {1, 4, 8, 16}) {
            for (const int block : {1, 8, 100000}) {
                SimulatorOptions options = base;
                options.packet_size = packet, options.columns_per_task = block;
                options.max_threads = threads;
                ScanImage img;
                const ScanStats stats = SimulateScan(scene, model, Pose(0.3, 0.4, 0.1, 20, 2, -3),
                                                     noise, 99, &img, options);
                ASSERT_TRUE(SameImage(img, reference))
                    << "threads " << threads << " packet " << packet << " block " << block;
                EXPECT_EQ(stats.ghosts, ref.ghosts);
                EXPECT_EQ(stats.glass_returns, ref.glass_returns);
            }
        }
    }
}

TEST(SimulateScanMaterials, DiffuseMaterialsLeaveTheImageUnchanged) {
    const common::TriangleMesh room = FurnishedRoom();
    const Scene plain(room);
    const Scene diffuse(room, {}, std::vector<Material>(room.triangles.size()));
    EXPECT_FALSE(diffuse.has_special_materials());
    const LidarModel model = LidarModel::DefaultOs1_32(512);
    ScanImage a, b;
    SimulateScan(plain, model, Pose(0.3, 0.4, 0.1, 20), NoiseModel{}, 4, &a);
    SimulateScan(diffuse, model, Pose(0.3, 0.4, 0.1, 20), NoiseModel{}, 4, &b);
    EXPECT_TRUE(SameImage(a, b));
}

TEST(SimulateScanMaterials, RejectsAWrongMaterialCountAndBadParameters) {
    const common::TriangleMesh room = FurnishedRoom();
    EXPECT_THROW(Scene(room, {}, std::vector<Material>(3, Material::kGlass)), common::Error);
    NoiseModel n;
    n.glass_return_probability = 1.5;
    EXPECT_THROW(n.Validate(), common::Error);
    n = NoiseModel{};
    n.max_mirror_bounces = -1;
    EXPECT_THROW(n.Validate(), common::Error);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::simulation
