#include "algorithms/simulation/lidar_simulator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "algorithms/common/status.hpp"
#include "tests/unit/simulation/simulation_fixtures.hpp"

namespace bimslam::simulation {
namespace {

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

}  // namespace
}  // namespace bimslam::simulation
