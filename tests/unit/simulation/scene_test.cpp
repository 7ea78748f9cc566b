#include "algorithms/simulation/scene.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "algorithms/common/status.hpp"
#include "algorithms/simulation/lidar_simulator.hpp"
#include "tests/unit/simulation/box_room.hpp"

namespace bimslam::simulation {
namespace {

common::TriangleMesh OneTriangle() {
    common::TriangleMesh m;
    m.vertices = {{2, -1, -1}, {2, 1, -1}, {2, 0, 1}};
    m.triangles = {{0, 1, 2}};
    return m;
}

// Expects Scene(mesh, ids) to throw kInvalidArgument with `needle` in the message.
void ExpectBadScene(const common::TriangleMesh& mesh, std::vector<uint32_t> ids,
                    const std::string& needle) {
    try {
        const Scene scene(mesh, std::move(ids));
        ADD_FAILURE() << "no error, expected one saying " << needle;
    } catch (const common::Error& e) {
        EXPECT_EQ(e.code(), common::StatusCode::kInvalidArgument) << e.what();
        EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
}

TEST(Scene, RejectsBadInputWithAMessage) {
    common::TriangleMesh m = OneTriangle();
    m.triangles[0][2] = 3;
    ExpectBadScene(m, {}, "a triangle index is >= vertices.size() = 3");

    m = OneTriangle();
    m.vertices[1].y() = NAN;
    ExpectBadScene(m, {}, "vertex 1 is not finite");
    m.vertices[1].y() = INFINITY;
    ExpectBadScene(m, {}, "vertex 1 is not finite");

    ExpectBadScene(OneTriangle(), {1, 2}, "triangle_ids has 2 entries, the mesh 1 triangles");
}

TEST(Scene, IntersectReturnsDistanceNormalAndId) {
    const Scene scene(OneTriangle(), {42});
    EXPECT_EQ(scene.triangle_count(), 1u);
    EXPECT_EQ(scene.TriangleId(0), 42u);
    const auto hit = scene.Intersect({0, 0, 0}, {1, 0, 0});
    ASSERT_TRUE(hit);
    EXPECT_NEAR(hit->t, 2.0f, 1e-6f);
    EXPECT_EQ(hit->triangle, 0u);
    EXPECT_EQ(hit->id, 42u);
    // (v1 - v0) x (v2 - v0) = (0, 2, 0) x (0, 1, 2) = (4, 0, 0): the counter-clockwise side.
    EXPECT_NEAR(hit->normal.x(), 1.0f, 1e-6f);
    EXPECT_NEAR(hit->normal.norm(), 1.0f, 1e-6f);
    // A non-unit direction: t in its units.
    const auto half = scene.Intersect({0, 0, 0}, {2, 0, 0});
    ASSERT_TRUE(half);
    EXPECT_NEAR(half->t, 1.0f, 1e-6f);
    // The interval [t_near, t_far] bounds the hit.
    EXPECT_FALSE(scene.Intersect({0, 0, 0}, {1, 0, 0}, 0.0f, 1.9f));
    EXPECT_FALSE(scene.Intersect({0, 0, 0}, {1, 0, 0}, 2.1f));
    EXPECT_FALSE(scene.Intersect({0, 0, 0}, {-1, 0, 0}));
    EXPECT_FALSE(scene.Intersect({0, 0, 0}, {1, 0, 0.9f}));  // passes above the apex
    const Eigen::AlignedBox3f b = scene.Bounds();
    EXPECT_EQ(b.min(), Eigen::Vector3f(2, -1, -1));
    EXPECT_EQ(b.max(), Eigen::Vector3f(2, 1, 1));
}

TEST(Scene, DefaultIdsAreTriangleIndices) {
    const test::BoxRoom room({0, 0, 0}, {6, 4, 3});
    const Scene scene(room.mesh);
    ASSERT_EQ(scene.triangle_count(), 12u);
    for (uint32_t i = 0; i < 12; ++i) EXPECT_EQ(scene.TriangleId(i), i);
    const Scene with_ids(room.mesh, room.ids);
    const auto hit = with_ids.Intersect({1, 1, 1}, {0, 0, 1});  // the ceiling: z hi, wall 5
    ASSERT_TRUE(hit);
    EXPECT_NEAR(hit->t, 2.0f, 1e-6f);
    EXPECT_EQ(hit->id, test::BoxRoom::kIdBase + 5);
    EXPECT_NEAR(hit->normal.z(), -1.0f, 1e-6f);  // walls face into the room
}

TEST(Scene, EmptyMeshIsMissedByEveryRay) {
    const Scene scene{common::TriangleMesh{}};
    EXPECT_EQ(scene.triangle_count(), 0u);
    EXPECT_TRUE(scene.Bounds().isEmpty());
    EXPECT_FALSE(scene.Intersect({0, 0, 0}, {1, 0, 0}));
    // Vertices without triangles are empty too.
    common::TriangleMesh only_vertices;
    only_vertices.vertices = {{1, 2, 3}};
    EXPECT_EQ(Scene(only_vertices).triangle_count(), 0u);

    ScanImage img;
    const LidarModel model = LidarModel::DefaultOs1_32(512);
    for (const int packet : {1, 16}) {
        SimulatorOptions options;
        options.packet_size = packet;
        const ScanStats stats = SimulateScan(scene, model, Eigen::Isometry3d::Identity(),
                                             NoiseModel(), 1, &img, options);
        EXPECT_EQ(stats.rays, model.pixels());
        EXPECT_EQ(stats.hits, 0u);
        EXPECT_EQ(stats.returns, 0u);
        ASSERT_EQ(img.range_mm.size(), model.pixels());
        for (size_t i = 0; i < model.pixels(); ++i) {
            ASSERT_EQ(img.range_mm[i], 0u);
            ASSERT_EQ(img.signal[i], 0u);
            ASSERT_EQ(img.reflectivity[i], 0u);
            ASSERT_EQ(img.element_id[i], kNoElement);
        }
    }
}

TEST(Scene, MovesKeepTheScene) {
    Scene a(OneTriangle(), {7});
    Scene b(std::move(a));
    ASSERT_TRUE(b.Intersect({0, 0, 0}, {1, 0, 0}));
    EXPECT_EQ(b.Intersect({0, 0, 0}, {1, 0, 0})->id, 7u);
    Scene c{common::TriangleMesh{}};
    c = std::move(b);
    EXPECT_EQ(c.triangle_count(), 1u);
    EXPECT_TRUE(c.Intersect({0, 0, 0}, {1, 0, 0}));
}

}  // namespace
}  // namespace bimslam::simulation
