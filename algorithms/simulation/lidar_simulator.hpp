// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// LiDAR scans simulated by ray casting against a Scene, in the sensor's own staggered H x W
// layout (row u = beam, column v = measurement id), so that a simulated range image decodes with
// the driver's XYZ table (drivers/ouster XyzLut) to the ray-cast points.
//
// Per pixel the ray leaves LidarModel::Origin(u, v) along LidarModel::Direction(u, v), both
// mapped into the world by T_world_sensor (one pose per scan, or one per column for a moving
// sensor: the rolling shutter), and the range is the hit distance along the ray, hits closer than
// the beam's emission point (LidarModel::BeamOriginDistance) being ignored.
//
// Measurement model (NoiseModel), applied to each hit at true range r and incidence angle a (the
// angle between the ray and the surface normal):
//   - no return when r > max_range_m (the ray is cast no farther) or r < min_range_m;
//   - dropout: no return with probability
//         p = clamp(dropout_base + dropout_incidence_gain * (1 - cos a)^dropout_incidence_exponent
//                   + dropout_range_gain * (r / max_range_m)^dropout_range_exponent, 0, 1)
//     (grazing surfaces and distant ones return less often);
//   - range noise: r' = r + N(0, range_sigma_m^2); no return when r' < min_range_m;
//   - quantisation: range_mm = range_resolution_mm * round(r' * 1000 / range_resolution_mm),
//     range 0 meaning no return.
// Intensity proxy (a Lambertian target of diffuse reflectance `albedo`, no noise):
//   reflectivity = round(100 * albedo * cos a)                     (uint8, 0 ... 100: Ouster's
//                  calibrated reflectivity, range-compensated, 100 for a white Lambertian target)
//   signal = min(65535, round(signal_at_1m * albedo * cos a / max(r, 1 m)^2))
//                  (uint16 photon-count-like: inverse-square, saturating below 1 m)
// Pixels without a return have range 0, signal 0, reflectivity 0 and element id kNoElement.
//
// Materials (Scene's Material, per triangle of the static scene; README.md has the physics):
//   - glass: the beam meets the pane at incidence a. With probability
//         p = glass_return_probability * cos(a)^glass_return_exponent
//     (a PixelRandom draw) the pane returns (its range, its id: Fresnel reflection comes back to
//     the receiver only near normal incidence); otherwise the beam passes on undeflected and what
//     lies behind the pane returns;
//   - mirror: the beam reflects, d' = d - 2 (d.n) n, and goes on from the hit point. The sensor
//     times the whole path and reports it along the beam it sent, so the point appears behind
//     the mirror, at the mirror image of the surface the beam finally hit (a ghost), with that
//     surface's element id. At most max_mirror_bounces reflections (then no return).
//   The measurement model above then applies to the path's end at the path's whole length, with
//   the incidence of its last leg. How a user tells a ghost: its point does not lie on the
//   surface of its element (it is mirrored across the mirror's plane); ScanStats counts them.
//   Only the static scene's materials act (overlay and rig triangles are diffuse); later legs
//   are cast against the static scene and the overlay, never the rig. A scene without special
//   materials takes the plain path: its images are unchanged, byte for byte.
//
// Overlay (SimulatorOptions::overlay): a second, small Scene (e.g. people walking, rebuilt per
// scan) cast with the same rays as the static scene, so the big static BVH is never rebuilt for
// moving objects. Each ray is cast first against the static scene, then against the overlay for
// t up to the static hit's distance (max_range_m when there is none), and the nearer hit is the
// pixel's (the overlay's at an equal distance): its distance, normal (incidence angle) and id.
// The measurement model then applies to that hit exactly as for a single scene, with the same
// per-pixel randomness: an image with an overlay equals the image of one scene holding both
// meshes (with the same ids). An empty overlay is skipped.
//
// Rig (SimulatorOptions::rig): a third scene, fixed in the sensor frame, cast after the others
// with the same rays expressed in the sensor frame, up to the nearest hit so far. From a static
// pose T, an image with a rig scene equals the image of one scene holding the rig's mesh mapped by
// T (the same ids).
//
// Threads and determinism: columns are cast in parallel (TBB, blocks of columns; Embree packets
// of SimulatorOptions::packet_size rays within a block). All randomness of pixel (u, v) comes
// from a counter-based hash of (seed, u * W + v), never from a shared generator, so the images
// are identical for any number of threads, any block size and any packet size. Use a different
// seed per scan (e.g. seed ^ frame index) for independent noise between scans.
#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <span>
#include <vector>

#include "algorithms/simulation/lidar_model.hpp"
#include "algorithms/simulation/scene.hpp"

namespace bimslam::simulation {

// Element id of a pixel without a return.
inline constexpr uint32_t kNoElement = std::numeric_limits<uint32_t>::max();

struct NoiseModel {
    double range_sigma_m = 0.01;  // Gaussian range noise, 1 sigma (OS1: ~1 cm at 1-20 m)
    double min_range_m = 0.3;     // closer hits: no return
    double max_range_m = 100.0;   // farther hits: no return
    int range_resolution_mm = 1;  // quantisation step: 1 mm (8 mm for the RNG15 profiles)
    // Dropout probability, see the file comment.
    double dropout_base = 0.001;
    double dropout_incidence_gain = 0.5;
    double dropout_incidence_exponent = 4.0;
    double dropout_range_gain = 0.05;
    double dropout_range_exponent = 2.0;
    // Intensity proxy, see the file comment.
    double albedo = 0.5;           // diffuse reflectance of every surface, [0, 1]
    double signal_at_1m = 4000.0;  // signal of a white target at 1 m, normal incidence
    // Materials, see the file comment. Glass returns p0 cos(a)^k: p0 = 0.5 and k = 30 give
    // p >= 0.25 within 12 degrees of normal incidence, 0.11 at 20, < 0.007 beyond 30 (real Ouster
    // scans of glazing show returns mostly near normal incidence, README.md).
    double glass_return_probability = 0.5;  // p0, in [0, 1]
    double glass_return_exponent = 30.0;    // k, >= 0
    int max_mirror_bounces = 2;             // more reflections: no return

    // No noise and no dropouts (the range limits, quantisation and intensity stay).
    static NoiseModel Noiseless();
    // Throws common::Error (kInvalidArgument) naming the field and the value.
    void Validate() const;
};

// One scan, staggered, row-major: pixel (u, v) at index u * w + v (the layout drivers/ouster's
// LidarFrame and XyzLut use).
struct ScanImage {
    int h = 0;                          // beams
    int w = 0;                          // columns
    std::vector<uint32_t> range_mm;     // 0 = no return
    std::vector<uint16_t> signal;       // intensity proxy
    std::vector<uint8_t> reflectivity;  // intensity proxy, 0 ... 100
    std::vector<uint32_t> element_id;   // Scene::TriangleId of the triangle hit (of the overlay's
                                        // scene for an overlay hit), or kNoElement

    size_t Index(int u, int v) const { return static_cast<size_t>(u) * w + v; }
    // Sizes the planes (keeping their capacity: no allocation for the same size again).
    void Resize(int beams, int columns);
};

struct ScanStats {
    size_t rays = 0;           // H * W
    size_t hits = 0;           // rays that hit geometry within max_range_m
    size_t returns = 0;        // pixels with a range
    size_t dropouts = 0;       // hits removed by the dropout model
    size_t too_close = 0;      // hits removed by min_range_m (before or after noise)
    size_t glass_returns = 0;  // returns from a glass pane
    size_t ghosts = 0;         // returns whose path reflected off a mirror
};

struct SimulatorOptions {
    // Rays per Embree query: 1 (rtcIntersect1), 4, 8 or 16 (rtcIntersect4/8/16 packets of
    // consecutive beams of a column). 16 was measured fastest (README.md, "Measured rates").
    int packet_size = 16;
    int columns_per_task = 8;  // TBB block size, in columns
    int max_threads = 0;       // 0: as many as TBB allows; else a task arena of that many
    // A second scene cast with the same rays (e.g. moving people, rebuilt per scan); a pixel's
    // hit is the nearer of the two. element_id of an overlay hit is the overlay scene's
    // TriangleId (callers give overlay triangles ids distinct from the static scene's). Casting
    // the overlay only up to the static hit keeps its cost small; nullptr or an empty scene: no
    // overlay. Not owned; must outlive the SimulateScan call.
    const Scene* overlay = nullptr;
    // A scene fixed in the sensor frame: the rig's own body in view (the Go1's trunk, the person
    // carrying the sensor, the car's roof). Cast with each ray before T_world_sensor maps it into
    // the world, so it moves with the sensor exactly, the rolling shutter included; a pixel's hit
    // is the nearest of all scenes. A rig hit's element_id is the rig scene's TriangleId. Not
    // owned; nullptr or an empty scene: none.
    const Scene* rig = nullptr;
    void Validate() const;
};

// A scan from one pose (a static sensor). T_world_sensor maps sensor-frame points into the
// scene's frame. Throws common::Error (kInvalidArgument) for an invalid model, noise model,
// options or a non-rigid pose; `out` is resized to model.beams() x model.columns.
ScanStats SimulateScan(const Scene& scene, const LidarModel& model,
                       const Eigen::Isometry3d& T_world_sensor, const NoiseModel& noise,
                       uint64_t seed, ScanImage* out, const SimulatorOptions& options = {});

// Rolling shutter: column v is cast from T_world_sensor_per_column[v] (the sensor's pose at the
// column's timestamp, LidarModel::ColumnTimeOffsetNs(v) after the scan start). The span must
// hold model.columns poses.
ScanStats SimulateScan(const Scene& scene, const LidarModel& model,
                       std::span<const Eigen::Isometry3d> T_world_sensor_per_column,
                       const NoiseModel& noise, uint64_t seed, ScanImage* out,
                       const SimulatorOptions& options = {});
// The same with the pose of column v from a callable, evaluated once per column, in order, on the
// calling thread (it need not be thread-safe).
ScanStats SimulateScan(const Scene& scene, const LidarModel& model,
                       const std::function<Eigen::Isometry3d(int column)>& T_world_sensor_at,
                       const NoiseModel& noise, uint64_t seed, ScanImage* out,
                       const SimulatorOptions& options = {});

}  // namespace bimslam::simulation
