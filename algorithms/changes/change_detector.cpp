// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/changes/change_detector.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <limits>
#include <optional>
#include <string>

#include "algorithms/changes/dbscan.hpp"
#include "algorithms/changes/extension.hpp"
#include "algorithms/changes/model_distance.hpp"
#include "algorithms/changes/point_grid.hpp"
#include "algorithms/common/status.hpp"
#include "algorithms/common/stopwatch.hpp"
#include "algorithms/simulation/scene.hpp"

namespace bimslam::changes {
namespace {
using Clock = std::chrono::steady_clock;

// The normal of the points within `radius` of p that `take` accepts: the eigenvector of the least
// eigenvalue of their covariance where they form a surface (the middle eigenvalue at least 10 %
// of the largest); where they form a line, `toward` (the direction to the sensor that saw p) made
// perpendicular to the line when `line_ok`, else zero; with fewer than 5 points, `toward` when
// `line_ok`, else zero.
template <class Take>
Eigen::Vector3f NormalAt(const PointGrid& grid, const Eigen::Vector3f& p, float radius,
                         const Eigen::Vector3f& toward, bool line_ok, Take&& take) {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
    int n = 0;
    grid.ForEachPointWithin(p, radius, [&](uint32_t j) {
        if (!take(j)) return;
        const Eigen::Vector3d q = (grid.points()[j] - p).cast<double>();
        mean += q;
        second += q * q.transpose();
        ++n;
    });
    const Eigen::Vector3f none = line_ok ? toward : Eigen::Vector3f::Zero();
    if (n < 5) return none;
    mean /= n;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(second / n - mean * mean.transpose());
    const Eigen::Vector3d lambda = eig.eigenvalues();  // ascending
    Eigen::Vector3f normal;
    if (lambda[1] >= 0.1 * lambda[2]) {
        normal = eig.eigenvectors().col(0).cast<float>();
    } else {
        if (!line_ok) return none;
        const Eigen::Vector3f line = eig.eigenvectors().col(2).cast<float>();
        normal = toward - toward.dot(line) * line;
    }
    return normal.allFinite() && normal.norm() > 1e-3f ? Eigen::Vector3f(normal.normalized())
                                                       : none;
}

// Two normals per point for the free-space test. First, of all its neighbours: a static surface
// seen by many keyframes. Where the neighbourhood is a line (one ring across a person), the
// direction to the sensor that saw it, made perpendicular to the line. Second, of its neighbours
// first seen by the same keyframe, where they form a surface, else zero: a person seen by several
// keyframes in a row while walking is smeared along the walk, and the normal of the smear lies in
// the walking direction's plane, along which the other keyframes' beams run.
struct PointNormals {
    std::vector<Eigen::Vector3f> all, same_keyframe;
};
PointNormals EstimateNormals(std::span<const Eigen::Vector3f> points, float radius,
                             std::span<const Eigen::Vector3f> viewpoint,
                             std::span<const uint32_t> keyframe) {
    PointNormals out;
    out.all.resize(points.size());
    out.same_keyframe.resize(points.size());
    const PointGrid grid(points, radius);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, points.size(), 1024), [&](const auto& range) {
        for (size_t i = range.begin(); i < range.end(); ++i) {
            const Eigen::Vector3f toward = (viewpoint[i] - points[i]).normalized();
            out.all[i] =
                NormalAt(grid, points[i], radius, toward, true, [](uint32_t) { return true; });
            out.same_keyframe[i] = NormalAt(grid, points[i], radius, toward, false,
                                            [&](uint32_t j) { return keyframe[j] == keyframe[i]; });
        }
    });
    return out;
}

// The surface an object seen from above only stands on: the highest surface facing up that a ray
// straight down from one of its points meets within `max_drop`, when the map holds no point on
// it under the object's footprint (its smallest plan rectangle, a voxel in from each side): the
// object hid that surface from every keyframe, as a box does; a table's or a shelf's is seen
// between its legs or from the side. The rectangle, not the box: the box of an object turned
// about z holds floor beside it, in view (Duplex_A's armchair turned 15 deg). Nothing (no
// surface, or the surface was seen): NaN.
float UnseenSupport(const simulation::Scene& scene, std::span<const Eigen::Vector3f> map,
                    std::span<const Eigen::Vector3f> object, const PlanRectangle& plan,
                    float max_drop, float voxel, float tolerance) {
    float support = -std::numeric_limits<float>::infinity();
    for (const Eigen::Vector3f& p : object) {
        const auto hit = scene.Intersect(p, -Eigen::Vector3f::UnitZ(), 0.0f, max_drop);
        if (hit && hit->normal.z() > 0.7f) support = std::max(support, p.z() - hit->t);
    }
    if (!std::isfinite(support)) return std::numeric_limits<float>::quiet_NaN();
    const double yaw = plan.yaw_deg * M_PI / 180;
    const Eigen::Vector2d u(std::cos(yaw), std::sin(yaw)), v(-u.y(), u.x());
    const double half_long = 0.5 * plan.long_m - voxel, half_short = 0.5 * plan.short_m - voxel;
    for (const Eigen::Vector3f& q : map) {
        if (std::abs(q.z() - support) > tolerance) continue;
        const Eigen::Vector2d d = q.head<2>().cast<double>() - plan.center;
        if (std::abs(u.dot(d)) < half_long && std::abs(v.dot(d)) < half_short) {
            return std::numeric_limits<float>::quiet_NaN();  // seen under it
        }
    }
    return support;
}

}  // namespace

std::string_view ToString(PointClass c) {
    switch (c) {
        case PointClass::kModel:
            return "model";
        case PointClass::kNewObject:
            return "new_object";
        case PointClass::kTransient:
            return "transient";
        case PointClass::kUnexplained:
            return "unexplained";
        case PointClass::kOutside:
            return "outside";
        case PointClass::kMoved:
            return "moved";
    }
    return "?";
}

void ChangeDetectorConfig::Validate() const {
    map.Validate();
    dbscan.Validate();
    free_space.Validate();
    walls.Validate();
    evidence.Validate();
    elements.Validate();
    moved.Validate();
    refinement.Validate();
    if (!(new_object_threshold_m > 0)) {
        common::ThrowInvalid("new_object_threshold_m must be > 0, not " +
                             std::to_string(new_object_threshold_m));
    }
    if (!(band_threshold_m > 0 && band_threshold_m <= new_object_threshold_m)) {
        common::ThrowInvalid("band_threshold_m must be in (0, new_object_threshold_m], not " +
                             std::to_string(band_threshold_m));
    }
    if (!(crop_margin_m >= 0)) common::ThrowInvalid("crop_margin_m must be >= 0");
    if (!(extension_margin_m >= 0 && extension_clearance_m >= 0)) {
        common::ThrowInvalid("extension_margin_m and extension_clearance_m must be >= 0, not " +
                             std::to_string(extension_margin_m) + " and " +
                             std::to_string(extension_clearance_m));
    }
    if (!(max_unseen_support_drop_m >= 0)) {
        common::ThrowInvalid("max_unseen_support_drop_m must be >= 0, not " +
                             std::to_string(max_unseen_support_drop_m));
    }
    if (!(min_multi_view_fraction >= 0 && min_multi_view_fraction <= 1)) {
        common::ThrowInvalid("min_multi_view_fraction must be in [0, 1], not " +
                             std::to_string(min_multi_view_fraction));
    }
}

void ChangeModel::Validate() const {
    if (triangle_element.size() != mesh.triangles.size()) {
        common::ThrowInvalid("model: " + std::to_string(mesh.triangles.size()) + " triangles but " +
                             std::to_string(triangle_element.size()) + " triangle elements");
    }
    if (!mesh.IndicesValid()) common::ThrowInvalid("model: a triangle index is out of range");
    if (!element_judged.empty() && element_judged.size() != element_count()) {
        common::ThrowInvalid("model: " + std::to_string(element_count()) + " elements but " +
                             std::to_string(element_judged.size()) + " judged flags");
    }
    for (size_t t = 0; t < triangle_element.size(); ++t) {
        if (triangle_element[t] >= element_count()) {
            common::ThrowInvalid("model: triangle " + std::to_string(t) + " has element " +
                                 std::to_string(triangle_element[t]) + " of " +
                                 std::to_string(element_count()));
        }
    }
    for (size_t v = 0; v < mesh.vertices.size(); ++v) {
        if (!mesh.vertices[v].allFinite())
            common::ThrowInvalid("model: vertex " + std::to_string(v) + " is not finite");
    }
}

namespace {

// One run of steps 1-6: what every step reads (the model, the keyframes, the config, the progress
// callback) and fills (the result, counts and timings included), and what later steps take from
// step 2. What one step alone hands the next passes between them in DetectOnPoses.
struct Detection {
    struct Candidates {  // as step 3 sorted them
        std::vector<uint32_t> transient_points, seeds, band;
    };

    Detection(const ChangeModel& m, std::span<const MapKeyframe> k, const ChangeDetectorConfig& c,
              const ChangeProgress& p)
        : model(m), keyframes(k), config(c), progress(p) {}

    void Report(std::string_view stage, double f) const {
        if (progress) progress(stage, f);
    }

    void AlignMap();                           // 1.
    void MeasureDistances();                   // 2.
    std::vector<uint32_t> SelectCandidates();  // 2.
    void AddExtension(const std::vector<uint32_t>& off_footprint,
                      std::vector<uint32_t>& candidates);
    Candidates FindTransients(const std::vector<uint32_t>& candidates);  // 3.
    void FindNewObjects(const Candidates& sorted);                       // 4.
    std::vector<ElementEvidence> CollectEvidence();                      // 5.
    void JudgeElements(std::span<const ElementEvidence> evidence);       // 6.

    // What steps 3 and 4 call.
    void JudgeTransients(const std::vector<uint32_t>& far, std::vector<uint8_t>& transient);
    std::vector<std::vector<uint32_t>> GrowClusters(const std::vector<uint32_t>& seeds,
                                                    const std::vector<uint32_t>& band);
    NewObject MakeObject(std::vector<uint32_t> points) const;
    void MergeParts(std::vector<NewObject>& objects) const;
    void SplitCorners(std::vector<NewObject>& objects) const;
    void JoinHiddenGaps(std::vector<NewObject>& objects);
    const FreeSpaceIndex& FreeSpace();
    void ClusterTransients(const std::vector<uint32_t>& transient_points);

    const ChangeModel& model;
    const std::span<const MapKeyframe> keyframes;
    const ChangeDetectorConfig& config;
    const ChangeProgress& progress;
    const float high = float(config.new_object_threshold_m);
    const float low = float(config.band_threshold_m);
    ChangeResult out;
    std::optional<simulation::Scene> scene;  // of the whole model, from step 2 on
    std::vector<uint32_t> nearest_triangle;  // per map point (kNoElement: none), from step 2
    std::vector<uint8_t> beyond;  // per map point: off the footprint, compared (extension_margin_m)
    std::optional<FreeSpaceIndex> free_space;  // the keyframes' range images, made when first asked
};

// 1. The aligned map.
void Detection::AlignMap() {
    const auto t0 = Clock::now();
    out.map = BuildAlignedMap(keyframes, config.map);
    out.seconds.map_s = common::SecondsSince(t0);
    Report("map", 1.0);
    if (out.map.size() == 0) {
        common::ThrowInvalid("the session's keyframes hold no points between " +
                             std::to_string(config.map.min_range_m) + " and " +
                             std::to_string(config.map.max_range_m) + " m");
    }
}

// 2. Signed distances to the whole model.
void Detection::MeasureDistances() {
    const std::vector<Eigen::Vector3f>& xyz = out.map.xyz;
    const size_t n = xyz.size();
    const auto t0 = Clock::now();
    scene.emplace(model.mesh);
    PointDistances d = ComputeDistances(*scene, xyz, std::numeric_limits<float>::infinity(),
                                        [&](double f) { Report("distances", f); });
    out.signed_distance_m = std::move(d.signed_m);
    out.element.assign(n, kNoElement);
    for (size_t i = 0; i < n; ++i) {
        if (d.triangle[i] != kNoElement) out.element[i] = model.triangle_element[d.triangle[i]];
    }
    nearest_triangle = std::move(d.triangle);
    out.seconds.distance_s = common::SecondsSince(t0);
}

// The end of step 2: the candidates, the points farther than band_threshold_m from the model
// within the compared region and inside the building.
std::vector<uint32_t> Detection::SelectCandidates() {
    const std::vector<Eigen::Vector3f>& xyz = out.map.xyz;
    const size_t n = xyz.size();
    // The compared region: the model's box plus a margin (the outdoors seen through windows and
    // doors is not the building's), and around it in plan the extension's.
    Eigen::AlignedBox3f region;
    for (const auto& v : model.mesh.vertices) region.extend(v);
    region.min().array() -= float(config.crop_margin_m);
    region.max().array() += float(config.crop_margin_m);
    Eigen::AlignedBox3f wide = region;
    wide.min().head<2>().array() -= float(config.extension_margin_m);
    wide.max().head<2>().array() += float(config.extension_margin_m);
    out.point_class.assign(n, PointClass::kModel);
    out.object.assign(n, -1);
    beyond.assign(n, 0);
    std::vector<uint32_t> candidates, off_footprint;
    // Off the model and inside the box, yet outside the building: the ground and what stands
    // around the entrances, which a model does not hold. Such a point has no element below it.
    const float depth = region.sizes().z();
    const auto outside_footprint = [&](const Eigen::Vector3f& p) {
        return config.crop_to_footprint &&
               !scene->Intersect(p, -Eigen::Vector3f::UnitZ(), 0.0f, depth).has_value();
    };
    for (size_t i = 0; i < n; ++i) {
        const float s = std::abs(out.signed_distance_m[i]);
        const bool in_region = region.contains(xyz[i]);
        if (!in_region && !(config.extension_margin_m > 0 && wide.contains(xyz[i]) && s > low)) {
            out.point_class[i] = PointClass::kOutside;
        } else if (s > low) {
            if (!in_region || outside_footprint(xyz[i])) {
                out.point_class[i] = PointClass::kOutside;
                ++out.counts.outside_footprint;
                off_footprint.push_back(uint32_t(i));
                continue;
            }
            if (s > high) out.point_class[i] = PointClass::kUnexplained;
            candidates.push_back(uint32_t(i));
        }
    }
    if (config.extension_margin_m > 0) AddExtension(off_footprint, candidates);
    out.counts.candidates = candidates.size();
    return candidates;
}

// Of the points off the footprint, those above the ground around them join the candidates,
// marked `beyond` (ChangeDetectorConfig::extension_margin_m).
void Detection::AddExtension(const std::vector<uint32_t>& off_footprint,
                             std::vector<uint32_t>& candidates) {
    constexpr float kGroundCellM = 1.0f;  // the ground within 1.5 m: an annex's floor beside it
    const std::vector<uint8_t> above = AboveLocalGround(out.map.xyz, off_footprint, kGroundCellM,
                                                        float(config.extension_clearance_m));
    for (size_t k = 0; k < off_footprint.size(); ++k) {
        if (!above[k]) continue;
        const uint32_t i = off_footprint[k];
        beyond[i] = 1;
        out.point_class[i] = std::abs(out.signed_distance_m[i]) > high ? PointClass::kUnexplained
                                                                       : PointClass::kModel;
        candidates.push_back(i);
        ++out.counts.extension_points;
    }
    std::sort(candidates.begin(), candidates.end());
}

// 3. Transients among the points that would start new objects (a person's lower 10 cm are
// band points: without transient seeds next to them they never become part of an object).
Detection::Candidates Detection::FindTransients(const std::vector<uint32_t>& candidates) {
    const auto t0 = Clock::now();
    std::vector<uint32_t> far;
    for (const uint32_t i : candidates) {
        if (std::abs(out.signed_distance_m[i]) > high) far.push_back(i);
    }
    std::vector<uint8_t> transient(out.map.xyz.size(), 0);
    if (config.detect_transients && !far.empty()) JudgeTransients(far, transient);
    Candidates sorted;
    for (const uint32_t i : candidates) {
        if (transient[i]) {
            sorted.transient_points.push_back(i);
            out.point_class[i] = PointClass::kTransient;
        } else if (std::abs(out.signed_distance_m[i]) > high) {
            sorted.seeds.push_back(i);
        } else {
            sorted.band.push_back(i);
        }
    }
    out.counts.transient_points = sorted.transient_points.size();
    out.counts.seed_points = sorted.seeds.size();
    out.seconds.transient_s = common::SecondsSince(t0);
    return sorted;
}

// Step 3's free-space test of the `far` points (map indices): sets transient[far[k]] for those
// the keyframes looked through, by their votes or their neighbours'.
void Detection::JudgeTransients(const std::vector<uint32_t>& far, std::vector<uint8_t>& transient) {
    const std::vector<Eigen::Vector3f>& xyz = out.map.xyz;
    std::vector<Eigen::Vector3f> cxyz(far.size()), viewpoint(far.size());
    std::vector<uint32_t> seen_by(far.size());
    for (size_t k = 0; k < far.size(); ++k) {
        cxyz[k] = xyz[far[k]];
        seen_by[k] = out.map.first_keyframe[far[k]];
        viewpoint[k] = keyframes[seen_by[k]].T_world_lidar.translation().cast<float>();
    }
    const float radius = std::max(0.1f, 2.0f * float(config.map.voxel_m));
    const PointNormals normals = EstimateNormals(cxyz, radius, viewpoint, seen_by);
    const FreeSpaceIndex& index = FreeSpace();
    std::vector<uint8_t> far_transient(far.size(), 0), judged(far.size(), 0);
    const size_t chunk = std::max<size_t>(1024, far.size() / 20);
    for (size_t first = 0; first < far.size(); first += chunk) {
        const size_t last = std::min(far.size(), first + chunk);
        tbb::parallel_for(tbb::blocked_range<size_t>(first, last, 256), [&](const auto& r) {
            for (size_t k = r.begin(); k < r.end(); ++k) {
                FreeSpaceIndex::Votes v = index.Vote(cxyz[k], normals.all[k]);
                bool is = index.Transient(v);
                bool voted = v.free + v.seen > 0;
                // The second normal where there is one: even 20 deg between the two can turn
                // the beams along a corridor from grazing to crossing.
                const Eigen::Vector3f& second = normals.same_keyframe[k];
                if (!is && second.squaredNorm() > 0) {
                    v = index.Vote(cxyz[k], second);
                    is = index.Transient(v);
                    voted |= v.free + v.seen > 0;
                }
                far_transient[k] = is;
                judged[k] = voted;
            }
        });
        Report("transients", double(last) / double(far.size()));
    }
    out.counts.transient_by_neighbours =
        JudgeByNeighbours(cxyz, judged, far_transient, config.free_space.unjudged_radius_m);
    for (size_t k = 0; k < far.size(); ++k) {
        transient[far[k]] = far_transient[k];
        out.counts.unjudged_points += !judged[k];
    }
}

// 4. New objects: DBSCAN over the seeds, grown into the band.
void Detection::FindNewObjects(const Candidates& sorted) {
    const auto t0 = Clock::now();
    std::vector<std::vector<uint32_t>> members = GrowClusters(sorted.seeds, sorted.band);
    std::vector<std::vector<uint32_t>> object_points;
    for (auto& cluster : members) {
        if (cluster.size() < config.min_object_points) continue;
        if (keyframes.size() >= 2) {
            const auto seen_twice = std::count_if(cluster.begin(), cluster.end(), [&](uint32_t i) {
                return out.map.keyframes[i] >= 2;
            });
            if (double(seen_twice) < config.min_multi_view_fraction * double(cluster.size())) {
                ++out.counts.single_view_clusters;  // its points stay kUnexplained / kModel
                continue;
            }
        }
        object_points.push_back(std::move(cluster));
    }
    std::vector<NewObject> made;
    for (auto& points : object_points) made.push_back(MakeObject(std::move(points)));
    MergeParts(made);
    if (config.walls.split_corners) SplitCorners(made);
    if (config.walls.join_hidden_gaps) JoinHiddenGaps(made);
    free_space.reset();  // its range images are large, and no later step asks them
    for (size_t o = 0; o < made.size(); ++o) {
        NewObject obj = std::move(made[o]);
        const auto off = std::count_if(obj.points.begin(), obj.points.end(),
                                       [&](uint32_t i) { return beyond[i] != 0; });
        obj.outside_footprint = 2 * size_t(off) > obj.points.size();
        for (const uint32_t i : obj.points) {
            out.point_class[i] = PointClass::kNewObject;
            out.object[i] = int32_t(o);
        }
        out.objects.push_back(std::move(obj));
    }
    Report("objects", 0.5);
    ClusterTransients(sorted.transient_points);
    out.seconds.cluster_s = common::SecondsSince(t0);
    Report("objects", 1.0);
}

// Step 4's objects that are parts of a larger one: an object whose box lies, for 0.8 of its
// volume, in a larger object's box (the bottom on the floor, as MakeObject made it) grown by a
// voxel of the map joins it, and the whole is made again from their points.
// The sample hall's cabinet, seen from its front, came out as its face and two slivers of its
// lower corners inside the face's box (2 x 9 and 2 x 13 cm by 0.6 m): three new objects where
// there is one (the history's rule across visits, host_tools/mapping, is the same).
void Detection::MergeParts(std::vector<NewObject>& objects) const {
    constexpr double kPartMinInside = 0.8;
    std::vector<size_t> order(objects.size());  // the largest first; the objects keep theirs
    for (size_t o = 0; o < order.size(); ++o) order[o] = o;
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
        return objects[a].points.size() > objects[b].points.size();
    });
    const double margin = config.map.voxel_m;
    std::vector<bool> merged(objects.size(), false), grew(objects.size(), false);
    for (size_t k = 1; k < order.size(); ++k) {
        const NewObject& part = objects[order[k]];
        const Eigen::AlignedBox3d box(part.box_min, part.box_max);
        for (size_t j = 0; j < k; ++j) {
            NewObject& whole = objects[order[j]];
            if (merged[order[j]]) continue;
            const Eigen::AlignedBox3d grown(whole.box_min.array() - margin,
                                            whole.box_max.array() + margin);
            const Eigen::AlignedBox3d in = box.intersection(grown);
            // A flat or thin part has no volume: its extent along its thin axis is the voxel's.
            const Eigen::Vector3d s = box.sizes().cwiseMax(margin);
            if (in.isEmpty() || in.sizes().cwiseMax(margin).prod() < kPartMinInside * s.prod())
                continue;
            whole.points.insert(whole.points.end(), part.points.begin(), part.points.end());
            whole.box_min = whole.box_min.cwiseMin(part.box_min);
            whole.box_max = whole.box_max.cwiseMax(part.box_max);
            merged[order[k]] = grew[order[j]] = true;
            break;
        }
    }
    size_t kept = 0;
    for (size_t o = 0; o < objects.size(); ++o) {
        if (merged[o]) continue;
        objects[kept++] =
            grew[o] ? MakeObject(std::move(objects[o].points)) : std::move(objects[o]);
    }
    objects.resize(kept);
}

// Step 4's objects that are walls meeting at corners, each wall made an object of its own. The
// visits' annex (host_tools/mapping, visits_benchmark) came out as its west wall and one object
// of its south and east walls, which matched neither.
void Detection::SplitCorners(std::vector<NewObject>& objects) const {
    const size_t n = objects.size();
    for (size_t o = 0; o < n; ++o) {
        std::vector<std::vector<uint32_t>> walls =
            SplitIntoWalls(out.map.xyz, objects[o].points, config.walls);
        if (walls.empty()) continue;
        objects[o] = MakeObject(std::move(walls[0]));
        for (size_t k = 1; k < walls.size(); ++k)
            objects.push_back(MakeObject(std::move(walls[k])));
    }
}

// Step 4's pieces of one wall, seen apart, joined when no keyframe looked through the gap between
// them: the visits' shed, seen through two windows of the hall, its middle hidden by the wall
// between them, came out as two objects. Two things side by side with the floor or a wall seen
// between them stay apart.
void Detection::JoinHiddenGaps(std::vector<NewObject>& objects) {
    std::vector<std::optional<WallPiece>> pieces(objects.size());
    for (size_t o = 0; o < objects.size(); ++o) {
        pieces[o] = AsWallPiece(out.map.xyz, objects[o].points, config.walls);
    }
    std::vector<size_t> group(objects.size());
    for (size_t o = 0; o < group.size(); ++o) group[o] = o;
    const auto root = [&](size_t o) {
        while (group[o] != o) o = group[o];
        return o;
    };
    for (size_t a = 0; a < objects.size(); ++a) {
        for (size_t b = a + 1; b < objects.size() && pieces[a]; ++b) {
            if (!pieces[b] || root(a) == root(b)) continue;
            const std::optional<WallGap> gap = GapBetween(*pieces[a], *pieces[b], config.walls);
            if (!gap) continue;
            size_t looked_through = 0;
            for (const Eigen::Vector3f& p : gap->samples) {
                const FreeSpaceIndex::Votes v = FreeSpace().Vote(p, gap->normal);
                looked_through += v.free > v.seen;
            }
            if (double(looked_through) >
                config.walls.max_looked_through * double(gap->samples.size())) {
                continue;
            }
            group[root(b)] = root(a);
        }
    }
    std::vector<std::vector<uint32_t>> joined(objects.size());
    for (size_t o = 0; o < objects.size(); ++o) {
        std::vector<uint32_t>& to = joined[root(o)];
        to.insert(to.end(), objects[o].points.begin(), objects[o].points.end());
    }
    size_t kept = 0;
    for (size_t o = 0; o < objects.size(); ++o) {
        if (root(o) != o) continue;
        const bool grew = joined[o].size() != objects[o].points.size();
        objects[kept++] = grew ? MakeObject(std::move(joined[o])) : std::move(objects[o]);
    }
    objects.resize(kept);
}

const FreeSpaceIndex& Detection::FreeSpace() {
    if (!free_space) free_space.emplace(keyframes, config.free_space);
    return *free_space;
}

// Step 4's clusters of seeds (DBSCAN), each grown into the band points that touch it, within
// new_object_threshold_m of its seeds' box.
std::vector<std::vector<uint32_t>> Detection::GrowClusters(const std::vector<uint32_t>& seeds,
                                                           const std::vector<uint32_t>& band) {
    const std::vector<Eigen::Vector3f>& xyz = out.map.xyz;
    std::vector<Eigen::Vector3f> seed_xyz(seeds.size());
    for (size_t k = 0; k < seeds.size(); ++k) seed_xyz[k] = xyz[seeds[k]];
    const DbscanResult clusters = Dbscan(seed_xyz, config.dbscan);
    out.counts.clusters = size_t(clusters.clusters);
    std::vector<std::vector<uint32_t>> members(size_t(clusters.clusters));
    for (size_t k = 0; k < seeds.size(); ++k) {
        if (clusters.labels[k] >= 0) members[size_t(clusters.labels[k])].push_back(seeds[k]);
    }
    std::vector<Eigen::Vector3f> band_xyz(band.size());
    for (size_t k = 0; k < band.size(); ++k) band_xyz[k] = xyz[band[k]];
    const float eps = float(config.dbscan.eps_m);
    const PointGrid band_grid(band_xyz, eps);
    std::vector<uint8_t> taken(band.size(), 0);
    for (auto& cluster : members) {
        Eigen::AlignedBox3f limit;
        for (const uint32_t i : cluster) limit.extend(xyz[i]);
        limit.min().array() -= high;
        limit.max().array() += high;
        std::deque<uint32_t> queue(cluster.begin(), cluster.end());
        while (!queue.empty()) {
            const uint32_t i = queue.front();
            queue.pop_front();
            band_grid.ForEachPointWithin(xyz[i], eps, [&](uint32_t k) {
                if (taken[k] || !limit.contains(band_xyz[k])) return;
                taken[k] = 1;
                cluster.push_back(band[k]);
                queue.push_back(band[k]);
            });
        }
    }
    return members;
}

// Step 4's object of the map points `points`: their box, its bottom extended to what the object
// stands on, the voxel solid and its mesh (the points' classes are the caller's).
NewObject Detection::MakeObject(std::vector<uint32_t> points) const {
    const std::vector<Eigen::Vector3f>& xyz = out.map.xyz;
    const float voxel = float(config.map.voxel_m);
    const float floor_reach = high + 2 * voxel;
    NewObject obj;
    obj.points = std::move(points);
    std::sort(obj.points.begin(), obj.points.end());
    std::vector<Eigen::Vector3f> pts(obj.points.size());
    std::vector<float> floor_z(obj.points.size(), std::numeric_limits<float>::quiet_NaN());
    Eigen::AlignedBox3d box;
    for (size_t k = 0; k < obj.points.size(); ++k) {
        pts[k] = xyz[obj.points[k]];
        box.extend(pts[k].cast<double>());
    }
    obj.plan = SmallestPlanRectangle(pts);
    // The floor under the object: a surface facing up within reach below its points.
    const float bottom = float(box.min().z());
    for (size_t k = 0; k < pts.size(); ++k) {
        if (pts[k].z() > bottom + floor_reach) continue;
        const auto hit = scene->Intersect(pts[k], -Eigen::Vector3f::UnitZ(), 0.0f, floor_reach);
        if (hit && hit->normal.z() > 0.7f) floor_z[k] = pts[k].z() - hit->t;
    }
    for (const float z : floor_z) {
        if (std::isfinite(z) && z < box.min().z()) {
            box.min().z() = z;
            obj.on_floor = true;
        }
    }
    if (!obj.on_floor && config.max_unseen_support_drop_m > 0) {
        const float z = UnseenSupport(*scene, xyz, pts, obj.plan,
                                      float(config.max_unseen_support_drop_m), voxel, low);
        if (std::isfinite(z) && z < box.min().z()) {
            box.min().z() = z;
            obj.on_floor = true;
        }
    }
    obj.solid = MakeVoxelSolid(pts, voxel, float(box.min().z()));
    obj.mesh = VoxelSurface(obj.solid);
    obj.box_min = box.min();
    obj.box_max = box.max();
    obj.centroid = obj.solid.centroid();
    obj.volume_m3 = obj.solid.volume_m3();
    return obj;
}

// Transient clusters, reported apart.
void Detection::ClusterTransients(const std::vector<uint32_t>& transient_points) {
    const std::vector<Eigen::Vector3f>& xyz = out.map.xyz;
    std::vector<Eigen::Vector3f> transient_xyz(transient_points.size());
    for (size_t k = 0; k < transient_points.size(); ++k) {
        transient_xyz[k] = xyz[transient_points[k]];
    }
    const DbscanResult tc = Dbscan(transient_xyz, config.dbscan);
    out.transients.resize(size_t(tc.clusters));
    for (size_t k = 0; k < transient_points.size(); ++k) {
        if (tc.labels[k] >= 0)
            out.transients[size_t(tc.labels[k])].points.push_back(transient_points[k]);
    }
    for (TransientCluster& c : out.transients) {
        const Eigen::AlignedBox3d box = ClusterBox(xyz, c.points);
        c.box_min = box.min();
        c.box_max = box.max();
        Eigen::Vector3d sum = Eigen::Vector3d::Zero();
        c.first_keyframe = UINT32_MAX;
        for (const uint32_t i : c.points) {
            sum += xyz[i].cast<double>();
            c.first_keyframe = std::min(c.first_keyframe, out.map.first_keyframe[i]);
            c.last_keyframe = std::max(c.last_keyframe, out.map.first_keyframe[i]);
        }
        c.centroid = sum / double(c.points.size());
    }
}

// 5. The beams' evidence on the opaque elements.
std::vector<ElementEvidence> Detection::CollectEvidence() {
    const auto t0 = Clock::now();
    common::TriangleMesh opaque;
    std::vector<uint32_t> opaque_element;
    opaque.vertices = model.mesh.vertices;  // unused vertices cost Embree nothing
    for (size_t t = 0; t < model.mesh.triangles.size(); ++t) {
        if (!model.element_opaque[model.triangle_element[t]]) continue;
        opaque.triangles.push_back(model.mesh.triangles[t]);
        opaque_element.push_back(model.triangle_element[t]);
    }
    const simulation::Scene opaque_scene(opaque);
    std::vector<ElementEvidence> evidence = CollectElementEvidence(
        opaque_scene, opaque, opaque_element, model.element_count(), keyframes, config.evidence,
        [&](double f) { Report("elements", 0.9 * f); });
    out.seconds.evidence_s = common::SecondsSince(t0);
    return evidence;
}

// 6. Verdicts and deviations, then moved elements.
void Detection::JudgeElements(std::span<const ElementEvidence> evidence) {
    const std::vector<Eigen::Vector3f>& xyz = out.map.xyz;
    const size_t n = xyz.size();
    const auto t0 = Clock::now();
    std::vector<uint8_t> usable(n, 0);
    for (size_t i = 0; i < n; ++i) {
        usable[i] = out.point_class[i] == PointClass::kModel ||
                    out.point_class[i] == PointClass::kUnexplained;
    }
    const std::vector<std::vector<uint32_t>> support = ElementSupport(
        model, out.signed_distance_m, nearest_triangle, usable, config.elements.support_distance_m);
    out.elements = CheckElements(model, out.signed_distance_m, nearest_triangle, support, evidence,
                                 config.elements);
    std::vector<std::vector<uint32_t>> objects_points(out.objects.size());
    for (size_t o = 0; o < out.objects.size(); ++o) objects_points[o] = out.objects[o].points;
    const std::vector<uint32_t> explained = FindMovedElements(
        model, xyz, objects_points, support, out.elements, config.moved, &FreeSpace());
    for (size_t o = 0; o < out.objects.size(); ++o) {
        out.objects[o].moved_element = explained[o];
        if (explained[o] == kNoElement) continue;
        for (const uint32_t i : out.objects[o].points) out.point_class[i] = PointClass::kMoved;
    }
    out.seconds.elements_s = common::SecondsSince(t0);
    Report("elements", 1.0);
}

// Steps 1-6 on the keyframes' poses as given (checked by DetectChanges).
ChangeResult DetectOnPoses(const ChangeModel& model, std::span<const MapKeyframe> keyframes,
                           const ChangeDetectorConfig& config, const ChangeProgress& progress) {
    Detection run(model, keyframes, config, progress);
    run.AlignMap();                                                       // 1.
    run.MeasureDistances();                                               // 2.
    const std::vector<uint32_t> candidates = run.SelectCandidates();      // 2.
    const Detection::Candidates sorted = run.FindTransients(candidates);  // 3.
    run.FindNewObjects(sorted);                                           // 4.
    const std::vector<ElementEvidence> evidence = run.CollectEvidence();  // 5.
    run.JudgeElements(evidence);                                          // 6.
    return std::move(run.out);
}

}  // namespace

ChangeResult DetectChanges(const ChangeModel& model, std::span<const MapKeyframe> keyframes,
                           std::span<const KeyframeEdge> edges, const ChangeDetectorConfig& config,
                           const ChangeProgress& progress) {
    config.Validate();
    model.Validate();
    if (model.mesh.empty()) common::ThrowInvalid("the model has no geometry to compare with");
    if (keyframes.empty()) common::ThrowInvalid("the session has no keyframes");
    if (!config.refinement.enabled) return DetectOnPoses(model, keyframes, config, progress);

    // 0. The keyframe poses and the elements' offsets estimated jointly (pose_refinement.hpp);
    // everything after, deviations included, is measured on the refined poses.
    if (progress) progress("refinement", 0.0);
    PoseRefinement refinement = RefinePoses(model, keyframes, edges, config.refinement);
    if (progress) progress("refinement", 1.0);
    std::vector<MapKeyframe> refined(keyframes.begin(), keyframes.end());
    for (size_t k = 0; k < refined.size(); ++k) {
        refined[k].T_world_lidar = refinement.T_world_lidar[k];
    }
    ChangeResult out = DetectOnPoses(model, refined, config, progress);
    out.seconds.refinement_s = refinement.seconds;
    out.refinement = std::move(refinement);
    return out;
}

ChangeResult DetectChanges(const ChangeModel& model, std::span<const MapKeyframe> keyframes,
                           const ChangeDetectorConfig& config, const ChangeProgress& progress) {
    return DetectChanges(model, keyframes, {}, config, progress);
}

}  // namespace bimslam::changes
