// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// LiDAR simulation throughput (algorithms/simulation): rays per second for 32 x 1024 OS1 scans of
// a synthetic office storey (~30 k triangles: walls with doors and windows, tiled floor and
// ceiling, pillars, furnished rooms), generated here so the figures need no data. Arguments:
// threads (SimulatorOptions::max_threads), packet size, robust BVH, and overlay (six walking
// people, 384 triangles, cast as SimulatorOptions::overlay). Target: >= 10 M rays/s on two cores.
#include <benchmark/benchmark.h>

#include <cmath>
#include <utility>
#include <vector>

#include "algorithms/simulation/lidar_simulator.hpp"

namespace bimslam::simulation {
namespace {

using Eigen::Vector3d;

// Triangles with one element id each, the way a BIM ingest hands them over.
struct Builder {
    common::TriangleMesh mesh;
    std::vector<uint32_t> ids;
    uint32_t element = 0;

    void Quad(const Vector3d& a, const Vector3d& b, const Vector3d& c, const Vector3d& d) {
        const auto base = static_cast<uint32_t>(mesh.vertices.size());
        for (const Vector3d& p : {a, b, c, d}) mesh.vertices.push_back(p.cast<float>());
        mesh.triangles.push_back({base, base + 1, base + 2});
        mesh.triangles.push_back({base, base + 2, base + 3});
        ids.insert(ids.end(), 2, element);
    }
    // An axis-aligned box: 12 triangles, one element.
    void Box(const Vector3d& lo, const Vector3d& hi) {
        auto p = [&](int i) {
            return Vector3d(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(),
                            i & 4 ? hi.z() : lo.z());
        };
        Quad(p(0), p(2), p(3), p(1));  // bottom
        Quad(p(4), p(5), p(7), p(6));  // top
        Quad(p(0), p(1), p(5), p(4));  // y lo
        Quad(p(2), p(6), p(7), p(3));  // y hi
        Quad(p(0), p(4), p(6), p(2));  // x lo
        Quad(p(1), p(3), p(7), p(5));  // x hi
        ++element;
    }
    // A vertical cylinder of `segments` facets with caps.
    void Cylinder(double cx, double cy, double r, double z0, double z1, int segments) {
        const auto centre_lo = static_cast<uint32_t>(mesh.vertices.size());
        mesh.vertices.emplace_back(float(cx), float(cy), float(z0));
        mesh.vertices.emplace_back(float(cx), float(cy), float(z1));
        const uint32_t ring = centre_lo + 2;
        for (int i = 0; i < segments; ++i) {
            const double a = 2 * M_PI * i / segments;
            const double x = cx + r * std::cos(a), y = cy + r * std::sin(a);
            mesh.vertices.emplace_back(float(x), float(y), float(z0));
            mesh.vertices.emplace_back(float(x), float(y), float(z1));
        }
        for (uint32_t i = 0; i < uint32_t(segments); ++i) {
            const uint32_t j = (i + 1) % segments;
            const uint32_t a0 = ring + 2 * i, a1 = a0 + 1, b0 = ring + 2 * j, b1 = b0 + 1;
            mesh.triangles.push_back({a0, b0, b1});
            mesh.triangles.push_back({a0, b1, a1});
            mesh.triangles.push_back({centre_lo, b0, a0});
            mesh.triangles.push_back({centre_lo + 1, a1, b1});
        }
        ids.insert(ids.end(), 4 * size_t(segments), element++);
    }
};

constexpr double kLength = 48, kDepth = 18, kHeight = 3, kWall = 0.15;
constexpr double kCorridorLo = 8, kCorridorHi = 10, kRoomWidth = 4;

// A wall along x at y in [y0, y1] from x0 to x1 with openings (doors to 2.1 m, windows from 0.9
// to 2.2 m), as boxes: the segments between openings, and lintels and sills in them.
struct Opening {
    double x0, x1, z0, z1;
};
void WallAlongX(Builder& b, double x0, double x1, double y0, double y1,
                const std::vector<Opening>& openings) {
    double x = x0;
    for (const Opening& o : openings) {
        if (o.x0 > x) b.Box({x, y0, 0}, {o.x0, y1, kHeight});
        if (o.z0 > 0) b.Box({o.x0, y0, 0}, {o.x1, y1, o.z0});
        b.Box({o.x0, y0, o.z1}, {o.x1, y1, kHeight});
        x = o.x1;
    }
    if (x1 > x) b.Box({x, y0, 0}, {x1, y1, kHeight});
}

void Furnish(Builder& b, double x0, double y0, double y1) {
    const double ym = 0.5 * (y0 + y1);
    for (int k = 0; k < 2; ++k) {  // two desks with a chair each
        const double dx = x0 + 0.4 + 1.7 * k, dy = y0 + (y1 > y0 ? 1.0 : -1.8);
        const double lo_y = std::min(dy, dy + 0.8), hi_y = std::max(dy, dy + 0.8);
        b.Box({dx, lo_y, 0.72}, {dx + 1.4, hi_y, 0.75});  // top
        for (int leg = 0; leg < 4; ++leg) {
            const double lx = dx + (leg & 1 ? 1.33 : 0.02), ly = lo_y + (leg & 2 ? 0.73 : 0.02);
            b.Box({lx, ly, 0}, {lx + 0.05, ly + 0.05, 0.72});
        }
        const double cx = dx + 0.5, cy = y1 > y0 ? hi_y + 0.2 : lo_y - 0.65;
        b.Box({cx, cy, 0.42}, {cx + 0.45, cy + 0.45, 0.47});  // seat
        b.Box({cx, cy + (y1 > y0 ? 0.4 : 0), 0.47}, {cx + 0.45, cy + (y1 > y0 ? 0.45 : 0.05), 0.9});
        b.Cylinder(cx + 0.225, cy + 0.225, 0.03, 0.05, 0.42, 12);  // column
        b.Cylinder(cx + 0.225, cy + 0.225, 0.28, 0.0, 0.05, 16);   // base
    }
    // A shelf against the far wall: two sides and five boards.
    const double sy = y1 > y0 ? y1 - 0.45 : y1 + 0.05;
    b.Box({x0 + 0.2, sy, 0}, {x0 + 0.23, sy + 0.4, 2.0});
    b.Box({x0 + 1.4, sy, 0}, {x0 + 1.43, sy + 0.4, 2.0});
    for (int k = 0; k < 5; ++k)
        b.Box({x0 + 0.23, sy, 0.1 + 0.45 * k}, {x0 + 1.4, sy + 0.4, 0.13 + 0.45 * k});
    b.Box({x0 + 2.6, sy, 0}, {x0 + 3.6, sy + 0.4, 1.1});  // a cabinet
    b.Cylinder(x0 + 3.0, ym, 0.5, 0.72, 0.75, 32);        // a round table
    b.Cylinder(x0 + 3.0, ym, 0.04, 0.0, 0.72, 12);
}

Builder OfficeStorey() {
    Builder b;
    // Floor and ceiling as 0.6 m tiles (a suspended ceiling; floor tiles).
    const double tile = 0.6;
    for (double x = 0; x < kLength - 1e-9; x += tile) {
        for (double y = 0; y < kDepth - 1e-9; y += tile) {
            const double x1 = std::min(x + tile, kLength), y1 = std::min(y + tile, kDepth);
            b.Quad({x, y, 0}, {x1, y, 0}, {x1, y1, 0}, {x, y1, 0});
            b.Quad({x, y, kHeight}, {x, y1, kHeight}, {x1, y1, kHeight}, {x1, y, kHeight});
        }
        ++b.element;
    }
    const int rooms = int(kLength / kRoomWidth);
    // Exterior walls along x with a window per room; corridor walls with a door per room.
    std::vector<Opening> windows, doors;
    for (int r = 0; r < rooms; ++r) {
        windows.push_back({r * kRoomWidth + 1.0, r * kRoomWidth + 3.0, 0.9, 2.2});
        doors.push_back({r * kRoomWidth + 0.5, r * kRoomWidth + 1.4, 0.0, 2.1});
    }
    WallAlongX(b, 0, kLength, -kWall, 0, windows);
    WallAlongX(b, 0, kLength, kDepth, kDepth + kWall, windows);
    WallAlongX(b, 0, kLength, kCorridorLo - kWall, kCorridorLo, doors);
    WallAlongX(b, 0, kLength, kCorridorHi, kCorridorHi + kWall, doors);
    // End walls and the partitions between rooms.
    b.Box({-kWall, -kWall, 0}, {0, kDepth + kWall, kHeight});
    b.Box({kLength, -kWall, 0}, {kLength + kWall, kDepth + kWall, kHeight});
    for (int r = 1; r < rooms; ++r) {
        const double x = r * kRoomWidth;
        b.Box({x - kWall / 2, 0, 0}, {x + kWall / 2, kCorridorLo - kWall, kHeight});
        b.Box({x - kWall / 2, kCorridorHi + kWall, 0}, {x + kWall / 2, kDepth, kHeight});
    }
    // Round pillars along the corridor, furniture in every room.
    for (int r = 0; r < rooms; ++r) {
        b.Cylinder(r * kRoomWidth + 2.0, kCorridorLo + 0.25, 0.2, 0, kHeight, 48);
        Furnish(b, r * kRoomWidth, 0, kCorridorLo - kWall);
        Furnish(b, r * kRoomWidth, kDepth, kCorridorHi + kWall);
    }
    return b;
}

// Six people (16-sided cylinders, 0.25 m x 1.75 m: 64 triangles each, 384 in all) where the walk
// sees them: two in the corridor, four in the rooms the walk visits. Ids from 1'000'000, apart
// from the storey's: an overlay (SimulatorOptions::overlay) as a capture simulator rebuilds it
// every scan.
constexpr uint32_t kFirstPerson = 1'000'000;
Builder People() {
    Builder b;
    b.element = kFirstPerson;
    for (const auto& [x, y] :
         {std::pair{10.5, 8.6}, {25.5, 9.4}, {6.0, 3.0}, {29.5, 5.5}, {18.0, 15.0}, {42.0, 12.0}}) {
        b.Cylinder(x, y, 0.25, 0.0, 1.75, 16);
    }
    return b;
}

struct Fixture {
    Builder storey = OfficeStorey();
    Builder people = People();
    Scene overlay{people.mesh, people.ids};
    Scene scene{storey.mesh, storey.ids};
    // The same without RTC_SCENE_FLAG_ROBUST, to show what robustness costs.
    Scene fast_scene{storey.mesh, storey.ids, SceneConfig{.robust = false}};
    LidarModel model = LidarModel::DefaultOs1_32(1024, 10);
    // A walk: down the corridor at 0.6 m (on the Go1) and through rooms at 1.2 m (hand-held).
    std::vector<Eigen::Isometry3d> poses;
    Fixture() {
        for (int k = 0; k < 16; ++k) {
            Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
            const bool corridor = k % 2 == 0;
            const int room = (3 * k / 2) % 12;
            T.translation() = corridor
                                  ? Vector3d(1.5 + 2.9 * k, 9.0, 0.6)
                                  : Vector3d(room * kRoomWidth + 2.3, k % 4 == 1 ? 4.5 : 13.5, 1.2);
            T.linear() = Eigen::AngleAxisd(0.4 * k, Vector3d::UnitZ()).toRotationMatrix();
            poses.push_back(T);
        }
    }
};

const Fixture& GetFixture() {
    static const Fixture fixture;
    return fixture;
}

void BM_SimulateScan(benchmark::State& state) {
    const Fixture& f = GetFixture();
    SimulatorOptions options;
    options.max_threads = static_cast<int>(state.range(0));
    options.packet_size = static_cast<int>(state.range(1));
    const Scene& scene = state.range(2) ? f.scene : f.fast_scene;
    if (state.range(3)) options.overlay = &f.overlay;
    const NoiseModel noise;  // the default: 1 cm noise, dropouts, intensity
    ScanImage image;
    size_t k = 0, hits = 0;
    for (auto _ : state) {
        const ScanStats stats =
            SimulateScan(scene, f.model, f.poses[k % f.poses.size()], noise, k, &image, options);
        hits += stats.hits;
        ++k;
        benchmark::DoNotOptimize(image.range_mm.data());
    }
    const auto rays = static_cast<int64_t>(k * f.model.pixels());
    state.SetItemsProcessed(rays);
    state.counters["triangles"] = double(f.scene.triangle_count());
    state.counters["hit_fraction"] = rays > 0 ? double(hits) / double(rays) : 0.0;
    if (state.range(3)) {  // untimed: the share of returns on people over the walk's poses
        size_t on_people = 0, returns = 0;
        for (size_t p = 0; p < f.poses.size(); ++p) {
            returns += SimulateScan(scene, f.model, f.poses[p], noise, p, &image, options).returns;
            for (const uint32_t id : image.element_id) {
                on_people += id != kNoElement && id >= kFirstPerson;
            }
        }
        state.counters["people_fraction"] = returns > 0 ? double(on_people) / double(returns) : 0;
    }
}
BENCHMARK(BM_SimulateScan)
    ->ArgNames({"threads", "packet", "robust", "overlay"})
    ->ArgsProduct({{1, 2}, {1, 4, 8, 16}, {1}, {0, 1}})
    ->Args({1, 16, 0, 0})
    ->Args({2, 16, 0, 0})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// Building the BVH of the storey once (SceneConfig defaults: robust, high-quality build).
void BM_BuildScene(benchmark::State& state) {
    const Fixture& f = GetFixture();
    for (auto _ : state) {
        const Scene scene(f.storey.mesh, f.storey.ids);
        benchmark::DoNotOptimize(scene.triangle_count());
    }
    state.counters["triangles"] = double(f.storey.mesh.triangles.size());
}
BENCHMARK(BM_BuildScene)->Unit(benchmark::kMillisecond)->UseRealTime();

// Building the people's overlay (384 triangles), as a capture simulator does every scan.
void BM_BuildOverlay(benchmark::State& state) {
    const Fixture& f = GetFixture();
    const SceneConfig config{.high_quality_build = state.range(0) != 0};
    for (auto _ : state) {
        const Scene scene(f.people.mesh, f.people.ids, config);
        benchmark::DoNotOptimize(scene.triangle_count());
    }
    state.counters["triangles"] = double(f.people.mesh.triangles.size());
}
BENCHMARK(BM_BuildOverlay)
    ->ArgName("high_quality")
    ->Arg(1)
    ->Arg(0)
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();

}  // namespace
}  // namespace bimslam::simulation

BENCHMARK_MAIN();
