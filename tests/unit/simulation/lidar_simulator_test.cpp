// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/simulation/lidar_simulator.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "algorithms/common/status.hpp"
#include "tests/unit/simulation/simulation_fixtures.hpp"

namespace bimslam::simulation {
namespace {
namespace BIMSLAM_UNITY_ID {

using namespace fixtures;  // the shared scenes and sensors

// ---- Geometry: a closed box room, every pixel against the analytic intersection ----

TEST(SimulateScan, NoiselessBoxRoomGivesTheAnalyticRangeOfEveryPixel) {
    const BoxRoom room({0, 0, 0}, {6, 4, 3});
    const Scene scene(room.mesh, room.ids);
    const NoiseModel noise = Exact();
    for (const Eigen::Isometry3d& T :
         {Pose(2.2, 1.7, 1.3), Pose(3.9, 1.1, 0.8, 37, 0, 4), Pose(1.0, 3.0, 2.2, -120, 3, -6)}) {
        for (const int columns : {512, 1024, 2048}) {
            const LidarModel model = LidarModel::DefaultOs1_32(columns);
            ScanImage img;
            const ScanStats stats = SimulateScan(scene, model, T, noise, 7, &img);
            ASSERT_EQ(img.h, 32);
            ASSERT_EQ(img.w, columns);
            EXPECT_EQ(stats.rays, model.pixels());
            EXPECT_EQ(stats.hits, model.pixels());  // a closed room: every ray hits
            EXPECT_EQ(stats.returns, model.pixels());
            EXPECT_EQ(stats.dropouts + stats.too_close, 0u);
            double worst = 0;
            size_t checked_ids = 0;
            for (int u = 0; u < model.beams(); ++u) {
                for (int v = 0; v < model.columns; ++v) {
                    const size_t i = img.Index(u, v);
                    const Eigen::Vector3d o = T * model.Origin(u, v);
                    const Eigen::Vector3d d = T.linear() * model.Direction(u, v);
                    const BoxRoom::Exit e = room.Cast(o, d);
                    ASSERT_NE(img.range_mm[i], 0u) << u << " " << v;
                    const double err = std::abs(img.range_mm[i] * 1e-3 - e.t);
                    worst = std::max(worst, err);
                    ASSERT_LE(err, 1e-3) << "pixel " << u << " " << v;
                    // Away from the room's edges (where two walls meet) the wall is certain.
                    if (e.margin < 1e-4) continue;
                    ++checked_ids;
                    ASSERT_EQ(img.element_id[i], BoxRoom::kIdBase + e.wall) << u << " " << v;
                    // Intensity proxy: Lambertian, 100 * albedo * cos(incidence).
                    const double cos_inc = std::abs(d[e.wall / 2]);
                    EXPECT_NEAR(img.reflectivity[i], 100 * noise.albedo * cos_inc, 0.5 + 1e-4);
                    const double r = std::max(e.t, 1.0);
                    EXPECT_NEAR(img.signal[i],
                                noise.signal_at_1m * noise.albedo * cos_inc / (r * r), 0.5 + 1e-3);
                }
            }
            EXPECT_GT(checked_ids, model.pixels() * 95 / 100);
            // Quantisation to 1 mm bounds the error by 0.5 mm (plus float rounding).
            EXPECT_LE(worst, 0.5e-3 + 2e-6) << "worst range error " << worst;
        }
    }
}

// ---- Determinism ----

TEST(SimulateScan, IdenticalForAnyThreadsPacketAndBlockSize) {
    const Scene scene(FurnishedRoom());
    // 32 beams (2 packets of 16 a column) and 7 beams (packets spanning columns).
    for (const LidarModel& model :
         {LidarModel::DefaultOs1_32(1024), SimpleModel(Linspace(30, -40, 7), 512)}) {
        NoiseModel noise;  // the default: noise, dropouts
        noise.range_sigma_m = 0.02;
        ScanImage reference;
        const ScanStats ref_stats = SimulateScan(scene, model, Pose(0.3, 0.4, 0.1, 20, 2, -3),
                                                 noise, 99, &reference, {1, 1, 1});
        EXPECT_GT(ref_stats.dropouts, 0u);
        for (const int threads : {1, 2, 0}) {
            for (const int packet : {1, 4, 8, 16}) {
                for (const int block : {1, 3, 8, 64, 100000}) {
                    SimulatorOptions options;
                    options.packet_size = packet;
                    options.columns_per_task = block;
                    options.max_threads = threads;
                    ScanImage img;
                    const ScanStats stats = SimulateScan(
                        scene, model, Pose(0.3, 0.4, 0.1, 20, 2, -3), noise, 99, &img, options);
                    ASSERT_TRUE(SameImage(img, reference))
                        << "threads " << threads << " packet " << packet << " block " << block
                        << " beams " << model.beams();
                    EXPECT_EQ(stats.hits, ref_stats.hits);
                    EXPECT_EQ(stats.returns, ref_stats.returns);
                    EXPECT_EQ(stats.dropouts, ref_stats.dropouts);
                    EXPECT_EQ(stats.too_close, ref_stats.too_close);
                }
            }
        }
    }
}

TEST(SimulateScan, SeedsChangeTheNoiseOnly) {
    const Scene scene(FurnishedRoom());
    const LidarModel model = LidarModel::DefaultOs1_32(512);
    NoiseModel noise;
    noise.range_sigma_m = 0.02;
    ScanImage a, b, c, exact;
    SimulateScan(scene, model, Eigen::Isometry3d::Identity(), noise, 1, &a);
    SimulateScan(scene, model, Eigen::Isometry3d::Identity(), noise, 2, &b);
    SimulateScan(scene, model, Eigen::Isometry3d::Identity(), noise, 1, &c);
    SimulateScan(scene, model, Eigen::Isometry3d::Identity(), Exact(), 1, &exact);
    EXPECT_TRUE(SameImage(a, c));
    size_t differ = 0, both = 0, dropped_a = 0, dropped_b = 0, dropped_both = 0;
    for (size_t i = 0; i < a.range_mm.size(); ++i) {
        if (a.range_mm[i] && b.range_mm[i]) ++both, differ += a.range_mm[i] != b.range_mm[i];
        dropped_a += a.range_mm[i] == 0, dropped_b += b.range_mm[i] == 0;
        dropped_both += a.range_mm[i] == 0 && b.range_mm[i] == 0;
        // Noise moves the range, never the element hit.
        if (a.range_mm[i]) {
            EXPECT_EQ(a.element_id[i], exact.element_id[i]);
        }
    }
    EXPECT_GT(differ, both * 9 / 10);  // sigma 20 mm, 1 mm steps: almost all differ
    EXPECT_GT(dropped_a, 0u);
    EXPECT_LT(dropped_both, std::min(dropped_a, dropped_b));  // independent dropouts
}

// ---- Rolling shutter ----

TEST(SimulateScan, RollingShutterCastsEachColumnFromItsPose) {
    const BoxRoom room({0, 0, 0}, {6, 4, 3});
    const Scene scene(room.mesh, room.ids);
    const LidarModel model = LidarModel::DefaultOs1_32(1024, 10);
    const Eigen::Isometry3d start = Pose(2.0, 2.0, 1.2, 25, 0, 3);
    // 1 m/s along the world's x over the 100 ms rotation.
    std::vector<Eigen::Isometry3d> poses;
    for (int v = 0; v < model.columns; ++v) {
        Eigen::Isometry3d T = start;
        T.translation().x() += 1.0 * model.ColumnTimeOffsetNs(v) * 1e-9;
        poses.push_back(T);
    }
    const Eigen::Vector3d first = poses.front() * model.Origin(0, 0);
    const Eigen::Vector3d last = poses.back() * model.Origin(0, model.columns - 1);
    const Eigen::Vector3d first_in_last = poses.back() * model.Origin(0, 0);
    EXPECT_NEAR((first_in_last - first).norm(), 0.1 * (model.columns - 1) / model.columns, 1e-9);
    EXPECT_GT((last - first).norm(), 0.09);

    ScanImage moving, still;
    const ScanStats stats =
        SimulateScan(scene, model, std::span<const Eigen::Isometry3d>(poses), Exact(), 3, &moving);
    EXPECT_EQ(stats.returns, model.pixels());
    SimulateScan(scene, model, start, Exact(), 3, &still);
    size_t moved = 0;
    for (int u = 0; u < model.beams(); ++u) {
        for (int v = 0; v < model.columns; ++v) {
            const Eigen::Isometry3d& T = poses[v];
            const BoxRoom::Exit e =
                room.Cast(T * model.Origin(u, v), T.linear() * model.Direction(u, v));
            const size_t i = moving.Index(u, v);
            ASSERT_LE(std::abs(moving.range_mm[i] * 1e-3 - e.t), 1e-3) << u << " " << v;
            moved += std::abs(double(moving.range_mm[i]) - double(still.range_mm[i])) > 5;
        }
    }
    EXPECT_GT(moved, model.pixels() / 4);  // the motion shows in the ranges (32 % by > 5 mm)

    // The callable form: evaluated once per column, in order, gives the same image.
    int next = 0;
    ScanImage from_callable;
    SimulateScan(
        scene, model,
        [&](int v) {
            EXPECT_EQ(v, next++);
            return poses[v];
        },
        Exact(), 3, &from_callable);
    EXPECT_EQ(next, model.columns);
    EXPECT_TRUE(SameImage(from_callable, moving));
}

TEST(SimulateScan, StaticPoseArrayEqualsTheStaticOverload) {
    const Scene scene(FurnishedRoom());
    const LidarModel model = LidarModel::DefaultOs1_32(512);
    const Eigen::Isometry3d T = Pose(0.5, -0.2, 0.3, 70, 1, 2);
    const std::vector<Eigen::Isometry3d> poses(model.columns, T);
    ScanImage a, b;
    SimulateScan(scene, model, T, NoiseModel(), 5, &a);
    SimulateScan(scene, model, std::span<const Eigen::Isometry3d>(poses), NoiseModel(), 5, &b);
    EXPECT_TRUE(SameImage(a, b));
}

// ---- Overlay: a second scene cast with the same rays ----

// Appends `part` to `mesh`, its triangles with element id `id`.
void Append(common::TriangleMesh* mesh, std::vector<uint32_t>* ids,
            const common::TriangleMesh& part, uint32_t id) {
    const auto base = static_cast<uint32_t>(mesh->vertices.size());
    mesh->vertices.insert(mesh->vertices.end(), part.vertices.begin(), part.vertices.end());
    for (const auto& t : part.triangles) {
        mesh->triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    }
    ids->insert(ids->end(), part.triangles.size(), id);
}

// Every pixel, every field and every count equal.
void ExpectSameScan(const ScanImage& a, const ScanStats& sa, const ScanImage& b,
                    const ScanStats& sb, const std::string& what) {
    EXPECT_TRUE(SameImage(a, b)) << what;
    EXPECT_EQ(sa.hits, sb.hits) << what;
    EXPECT_EQ(sa.returns, sb.returns) << what;
    EXPECT_EQ(sa.dropouts, sb.dropouts) << what;
    EXPECT_EQ(sa.too_close, sb.too_close) << what;
}

TEST(SimulateScanOverlay, EqualsTheSameBoxesMergedIntoTheStaticScene) {
    // Static: a wall at x = 5 and a floor at z = -1.2 (rays upwards and sideways miss).
    common::TriangleMesh static_mesh;
    std::vector<uint32_t> static_ids;
    Append(&static_mesh, &static_ids, WallAt(5.0, 3.0), 1);
    Append(&static_mesh, &static_ids, FloorAt(-1.2, 8.0), 2);
    // Overlay: two "people", one between the sensor and the wall (the static scene has a hit
    // behind it), one behind the sensor where only the floor is (above the horizon the static
    // scene has no hit at all), and one beyond the wall (hidden).
    const uint32_t kPersonA = 1000, kPersonB = 1001, kHidden = 1002;
    common::TriangleMesh people;
    std::vector<uint32_t> people_ids;
    Append(&people, &people_ids, BoxRoom({2.5, -0.4, -1.15}, {2.9, 0.3, 0.5}).mesh, kPersonA);
    Append(&people, &people_ids, BoxRoom({-3.3, -0.3, -1.15}, {-2.9, 0.2, 0.6}).mesh, kPersonB);
    Append(&people, &people_ids, BoxRoom({5.5, -0.5, -1.15}, {5.9, 0.5, 0.6}).mesh, kHidden);
    common::TriangleMesh merged_mesh = static_mesh;
    std::vector<uint32_t> merged_ids = static_ids;
    Append(&merged_mesh, &merged_ids, people, 0);
    merged_ids.resize(static_ids.size());  // the people's own ids
    merged_ids.insert(merged_ids.end(), people_ids.begin(), people_ids.end());

    const Scene static_scene(static_mesh, static_ids);
    const Scene overlay(people, people_ids);
    const Scene merged(merged_mesh, merged_ids);
    const LidarModel model = LidarModel::DefaultOs1_32(1024);
    const Eigen::Isometry3d T = Pose(0.1, 0.05, 0.0, 10, 2, -3);
    NoiseModel noisy;  // the default: noise and dropouts, drawn per pixel as without an overlay
    noisy.range_sigma_m = 0.02;
    for (const NoiseModel& noise : {Exact(), noisy}) {
        const bool exact = noise.range_sigma_m == 0;
        ScanImage alone;
        SimulateScan(static_scene, model, T, noise, 11, &alone);
        for (const int packet : {1, 4, 8, 16}) {
            for (const int threads : {1, 0}) {
                SimulatorOptions options;
                options.packet_size = packet;
                options.max_threads = threads;
                ScanImage reference, img;
                const ScanStats ref_stats =
                    SimulateScan(merged, model, T, noise, 11, &reference, options);
                options.overlay = &overlay;
                const ScanStats stats =
                    SimulateScan(static_scene, model, T, noise, 11, &img, options);
                const std::string what = "packet " + std::to_string(packet) + " threads " +
                                         std::to_string(threads) + (exact ? " exact" : " noisy");
                ExpectSameScan(img, stats, reference, ref_stats, what);
                if (!exact) continue;
                // The overlay's ids, in front of the wall and where the static scene has none.
                size_t over_wall = 0, over_nothing = 0, person_a = 0, person_b = 0;
                for (size_t i = 0; i < img.element_id.size(); ++i) {
                    const uint32_t id = img.element_id[i];
                    ASSERT_NE(id, kHidden) << what;
                    person_a += id == kPersonA, person_b += id == kPersonB;
                    if (id == kPersonA || id == kPersonB) {
                        ASSERT_NE(img.range_mm[i], 0u);
                        if (alone.element_id[i] == 1) {
                            ++over_wall;
                            EXPECT_LT(img.range_mm[i], alone.range_mm[i]) << what;
                        }
                        over_nothing += alone.range_mm[i] == 0;
                    } else {
                        // Elsewhere the static scene's pixel, untouched.
                        ASSERT_EQ(img.range_mm[i], alone.range_mm[i]) << what << " pixel " << i;
                        ASSERT_EQ(img.element_id[i], alone.element_id[i]) << what;
                        ASSERT_EQ(img.reflectivity[i], alone.reflectivity[i]) << what;
                    }
                }
                EXPECT_GT(person_a, 300u) << what;
                EXPECT_GT(person_b, 200u) << what;
                EXPECT_GT(over_wall, 100u) << what;
                EXPECT_GT(over_nothing, 50u) << what;
            }
        }
    }
}

TEST(SimulateScanOverlay, OverlayBehindTheStaticSceneChangesNothing) {
    NoiseModel noise;  // with noise and dropouts
    noise.range_sigma_m = 0.02;
    const LidarModel model = LidarModel::DefaultOs1_32(1024);
    // A closed room and boxes outside it: every overlay hit is behind a wall.
    const BoxRoom room({0, 0, 0}, {6, 4, 3});
    const Scene room_scene(room.mesh, room.ids);
    common::TriangleMesh outside;
    std::vector<uint32_t> outside_ids;
    Append(&outside, &outside_ids, BoxRoom({6.2, 1.0, 0.0}, {6.7, 1.6, 1.8}).mesh, 1000);
    Append(&outside, &outside_ids, BoxRoom({-1.0, -1.0, -1.0}, {7.0, 5.0, -0.1}).mesh, 1001);
    const Scene outside_scene(outside, outside_ids);
    // A wall, and a box beyond max_range_m where the static scene has no hit.
    NoiseModel short_range = noise;
    short_range.max_range_m = 20;
    const Scene wall(WallAt(5.0, 2.0));
    const Scene far_box(BoxRoom({-24.0, -2.0, -2.0}, {-21.0, 2.0, 2.0}).mesh);
    struct Case {
        const Scene* scene;
        const Scene* overlay;
        const NoiseModel* noise;
        const char* name;
    };
    for (const Case& c : {Case{&room_scene, &outside_scene, &noise, "behind the walls"},
                          Case{&wall, &far_box, &short_range, "beyond max range"}}) {
        for (const int packet : {1, 4, 8, 16}) {
            const Eigen::Isometry3d T = Pose(2.2, 1.7, 1.3, 37, 0, 4);
            SimulatorOptions options;
            options.packet_size = packet;
            ScanImage without, with;
            const ScanStats s0 = SimulateScan(*c.scene, model, T, *c.noise, 5, &without, options);
            options.overlay = c.overlay;
            const ScanStats s1 = SimulateScan(*c.scene, model, T, *c.noise, 5, &with, options);
            ExpectSameScan(with, s1, without, s0,
                           std::string(c.name) + " packet " + std::to_string(packet));
        }
    }
    // Without the room, the boxes outside it are seen: the overlay was cast.
    const Scene empty{common::TriangleMesh()};
    SimulatorOptions options;
    options.overlay = &outside_scene;
    ScanImage img;
    const ScanStats stats =
        SimulateScan(empty, model, Pose(2.2, 1.7, 1.3), noise, 5, &img, options);
    EXPECT_GT(stats.hits, 1000u);
    EXPECT_GT(std::count(img.element_id.begin(), img.element_id.end(), 1000u), 100);
    EXPECT_GT(std::count(img.element_id.begin(), img.element_id.end(), 1001u), 1000);
}

TEST(SimulateScanOverlay, EmptyOverlayEqualsNoOverlayBitForBit) {
    const Scene scene(FurnishedRoom());
    const Scene empty{common::TriangleMesh()};
    ASSERT_EQ(empty.triangle_count(), 0u);
    NoiseModel noise;
    noise.range_sigma_m = 0.02;
    for (const LidarModel& model :
         {LidarModel::DefaultOs1_32(1024), SimpleModel(Linspace(30, -40, 7), 512)}) {
        for (const int packet : {1, 4, 8, 16}) {
            SimulatorOptions options;
            options.packet_size = packet;
            ScanImage without, with;
            const Eigen::Isometry3d T = Pose(0.3, 0.4, 0.1, 20, 2, -3);
            const ScanStats s0 = SimulateScan(scene, model, T, noise, 99, &without, options);
            options.overlay = &empty;
            const ScanStats s1 = SimulateScan(scene, model, T, noise, 99, &with, options);
            ExpectSameScan(with, s1, without, s0, "packet " + std::to_string(packet));
        }
    }
}

// ---- Invalid arguments ----

void ExpectInvalid(const std::function<void()>& f, const std::string& needle) {
    try {
        f();
        ADD_FAILURE() << "no error, expected one naming " << needle;
    } catch (const common::Error& e) {
        EXPECT_EQ(e.code(), common::StatusCode::kInvalidArgument) << e.what();
        EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
}

// The rig's own body: a roof plate under the sensor and an operator behind it, fixed in the
// sensor frame.
common::TriangleMesh RigBody() {
    common::TriangleMesh m = FloorAt(-0.3, 1.0);
    std::vector<uint32_t> unused;
    Append(&m, &unused, BoxRoom({-0.7, -0.25, -1.2}, {-0.4, 0.25, 0.3}).mesh, 0);
    return m;
}

common::TriangleMesh Mapped(common::TriangleMesh m, const Eigen::Isometry3d& T) {
    for (Eigen::Vector3f& p : m.vertices) p = (T * p.cast<double>()).cast<float>();
    return m;
}

// Equal up to float rounding: the rays and the mapped mesh are single precision in different
// frames, so a hit's distance may differ by a few micrometres (a range 1 mm step apart after
// quantisation, a reflectivity 1 apart) and a ray grazing an edge may hit or miss it.
void ExpectNearlySameScan(const ScanImage& a, const ScanImage& b, const std::string& what) {
    ASSERT_EQ(a.range_mm.size(), b.range_mm.size()) << what;
    size_t other_hit = 0;
    for (size_t i = 0; i < a.range_mm.size(); ++i) {
        if (a.element_id[i] != b.element_id[i] || (a.range_mm[i] == 0) != (b.range_mm[i] == 0)) {
            ++other_hit;
            continue;
        }
        ASSERT_LE(std::abs(int64_t(a.range_mm[i]) - int64_t(b.range_mm[i])), 1) << what << i;
        ASSERT_LE(std::abs(int(a.reflectivity[i]) - int(b.reflectivity[i])), 1) << what << i;
    }
    EXPECT_LE(other_hit, a.range_mm.size() / 2000) << what;  // 0.05 %
}

TEST(SimulateScanRig, EqualsItsMeshMappedByAStaticPoseUpToRounding) {
    common::TriangleMesh static_mesh;
    std::vector<uint32_t> static_ids;
    Append(&static_mesh, &static_ids, WallAt(5.0, 3.0), 1);
    Append(&static_mesh, &static_ids, FloorAt(-1.5, 8.0), 2);
    const uint32_t kPerson = 1000, kRig = 2000;
    common::TriangleMesh people;
    std::vector<uint32_t> people_ids;
    Append(&people, &people_ids, BoxRoom({2.5, -0.4, -1.45}, {2.9, 0.3, 0.5}).mesh, kPerson);
    const common::TriangleMesh body = RigBody();
    const std::vector<uint32_t> body_ids(body.triangles.size(), kRig);
    const Eigen::Isometry3d T = Pose(0.1, 0.05, 0.0, 10, 2, -3);
    common::TriangleMesh merged_mesh = static_mesh;
    std::vector<uint32_t> merged_ids = static_ids;
    Append(&merged_mesh, &merged_ids, people, kPerson);
    Append(&merged_mesh, &merged_ids, Mapped(body, T), kRig);

    const Scene static_scene(static_mesh, static_ids), overlay(people, people_ids);
    const Scene rig(body, body_ids), merged(merged_mesh, merged_ids);
    const LidarModel model = LidarModel::DefaultOs1_32(1024);
    NoiseModel noisy;
    noisy.range_sigma_m = 0.02;
    for (const NoiseModel& noise : {Exact(), noisy}) {
        for (const int packet : {1, 4, 16}) {
            for (const bool with_overlay : {false, true}) {
                SimulatorOptions options;
                options.packet_size = packet;
                const std::string what = "packet " + std::to_string(packet) +
                                         (with_overlay ? " overlay" : "") +
                                         (noise.range_sigma_m == 0 ? " exact" : " noisy");
                ScanImage reference, img;
                with_overlay ? SimulateScan(merged, model, T, noise, 5, &reference, options)
                             : SimulateScan(Scene(Mapped(body, T), body_ids), model, T, noise, 5,
                                            &reference, options);
                if (!with_overlay) {
                    // The reference without the static scene and the person: the body alone.
                    options.rig = &rig;
                    const Scene nothing(WallAt(500.0, 1.0), {9, 9});  // out of range
                    SimulateScan(nothing, model, T, noise, 5, &img, options);
                    ExpectNearlySameScan(img, reference, what);
                    continue;
                }
                options.overlay = &overlay;
                options.rig = &rig;
                SimulateScan(static_scene, model, T, noise, 5, &img, options);
                ExpectNearlySameScan(img, reference, what);
                const size_t body_pixels =
                    size_t(std::count(img.element_id.begin(), img.element_id.end(), kRig));
                EXPECT_GT(body_pixels, 2000u) << what;  // the roof under the lower beams
                EXPECT_GT(std::count(img.element_id.begin(), img.element_id.end(), kPerson), 100)
                    << what;
            }
        }
    }
}

TEST(SimulateScanRig, MovesWithTheSensorUnderTheRollingShutter) {
    // A sensor spinning and driving fast during the scan: the world's hits smear, the body's do
    // not (each column's body hits equal a static scan's).
    const LidarModel model = LidarModel::DefaultOs1_32(512);
    std::vector<Eigen::Isometry3d> poses;
    for (int v = 0; v < model.columns; ++v) {
        const double f = double(v) / model.columns;
        poses.push_back(Pose(3.0 * f, 0.5 * f, 0.0, 40.0 * f, 3.0 * f, -2.0 * f));
    }
    const common::TriangleMesh body = RigBody();
    const Scene rig(body, std::vector<uint32_t>(body.triangles.size(), 7));
    common::TriangleMesh world = FloorAt(-1.5, 20.0);
    const Scene scene(world, std::vector<uint32_t>(world.triangles.size(), 1));
    SimulatorOptions options;
    options.rig = &rig;
    ScanImage moving, still;
    SimulateScan(scene, model, std::span<const Eigen::Isometry3d>(poses), Exact(), 3, &moving,
                 options);
    SimulateScan(scene, model, Eigen::Isometry3d::Identity(), Exact(), 3, &still, options);
    size_t body_pixels = 0, floor_differs = 0;
    for (size_t i = 0; i < moving.element_id.size(); ++i) {
        ASSERT_EQ(moving.element_id[i] == 7, still.element_id[i] == 7) << i;
        if (moving.element_id[i] == 7) {
            ++body_pixels;
            ASSERT_EQ(moving.range_mm[i], still.range_mm[i]) << i;
        } else if (moving.range_mm[i] != still.range_mm[i]) {
            ++floor_differs;
        }
    }
    EXPECT_GT(body_pixels, 1000u);
    EXPECT_GT(floor_differs, 1000u);  // the world did move
}

TEST(SimulateScan, RejectsInvalidArguments) {
    const Scene scene(WallAt(5.0, 0.5));
    const LidarModel model = LidarModel::DefaultOs1_32(512);
    const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
    ScanImage img;
    auto scan = [&](const NoiseModel& n, const SimulatorOptions& o) {
        return [&scene, &model, &I, &img, n, o] { SimulateScan(scene, model, I, n, 0, &img, o); };
    };
    NoiseModel n;
    n.range_sigma_m = -1;
    ExpectInvalid(scan(n, {}), "NoiseModel.range_sigma_m");
    n = NoiseModel();
    n.max_range_m = 0.1;
    ExpectInvalid(scan(n, {}), "NoiseModel.max_range_m");
    n = NoiseModel();
    n.range_resolution_mm = 0;
    ExpectInvalid(scan(n, {}), "NoiseModel.range_resolution_mm");
    n = NoiseModel();
    n.dropout_base = 1.5;
    ExpectInvalid(scan(n, {}), "NoiseModel.dropout_base");
    n = NoiseModel();
    n.albedo = NAN;
    ExpectInvalid(scan(n, {}), "NoiseModel.albedo");
    SimulatorOptions o;
    o.packet_size = 2;
    ExpectInvalid(scan(NoiseModel(), o), "SimulatorOptions.packet_size");
    o = SimulatorOptions();
    o.columns_per_task = 0;
    ExpectInvalid(scan(NoiseModel(), o), "SimulatorOptions.columns_per_task");
    o = SimulatorOptions();
    o.max_threads = -1;
    ExpectInvalid(scan(NoiseModel(), o), "SimulatorOptions.max_threads");
    ExpectInvalid([&] { SimulateScan(scene, model, I, NoiseModel(), 0, nullptr); }, "out is null");
    Eigen::Isometry3d skew = I;
    skew.linear()(0, 1) = 0.5;
    ExpectInvalid([&] { SimulateScan(scene, model, skew, NoiseModel(), 0, &img); },
                  "not a rigid transform");
    std::vector<Eigen::Isometry3d> poses(model.columns - 1, I);
    ExpectInvalid(
        [&] {
            SimulateScan(scene, model, std::span<const Eigen::Isometry3d>(poses), NoiseModel(), 0,
                         &img);
        },
        "511 poses for 512 columns");
    poses.push_back(skew);
    ExpectInvalid(
        [&] {
            SimulateScan(scene, model, std::span<const Eigen::Isometry3d>(poses), NoiseModel(), 0,
                         &img);
        },
        "column 511");
    LidarModel bad = model;
    bad.columns = 0;
    ExpectInvalid([&] { SimulateScan(scene, bad, I, NoiseModel(), 0, &img); }, "columns");
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::simulation
