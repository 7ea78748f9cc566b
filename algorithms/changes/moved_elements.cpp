// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/changes/moved_elements.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <string>

#include "algorithms/changes/dbscan.hpp"
#include "algorithms/common/status.hpp"
#include "algorithms/simulation/scene.hpp"

namespace bimslam::changes {
namespace {

Eigen::Matrix3d Yaw(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).matrix(); }

// G(p) = R(theta) (p - c) + c + t maps observed points onto the element as the model has it.
struct Inverse {
    double theta = 0;
    Eigen::Vector3d t = Eigen::Vector3d::Zero();
};

}  // namespace

common::TriangleMesh ElementMesh(const ChangeModel& model, uint32_t element,
                                 Eigen::AlignedBox3d* box) {
    common::TriangleMesh mesh;
    for (size_t t = 0; t < model.mesh.triangles.size(); ++t) {
        if (model.triangle_element[t] != element) continue;
        std::array<uint32_t, 3> tri;
        for (int k = 0; k < 3; ++k) {
            tri[k] = uint32_t(mesh.vertices.size());
            mesh.vertices.push_back(model.mesh.vertices[model.mesh.triangles[t][k]]);
            if (box) box->extend(mesh.vertices.back().cast<double>());
        }
        mesh.triangles.push_back(tri);
    }
    return mesh;
}

double InlierFraction(const ChangeModel& model, uint32_t element, const MotionFit& motion,
                      std::span<const Eigen::Vector3f> points, double inlier_m) {
    Eigen::AlignedBox3d box;
    const common::TriangleMesh mesh = ElementMesh(model, element, &box);
    if (mesh.empty() || points.empty()) return 0;
    const simulation::Scene scene(mesh);
    const Eigen::Vector3d c = box.center();
    // M^-1(p) = R(-yaw) (p - c - t) + c.
    const Eigen::Matrix3d R = Yaw(-motion.yaw_rad);
    size_t inliers = 0;
    for (const auto& p : points) {
        const Eigen::Vector3d q = R * (p.cast<double>() - c - motion.translation) + c;
        inliers += scene.ClosestPoint(q.cast<float>(), float(inlier_m)).has_value();
    }
    return double(inliers) / double(points.size());
}

ExtentCoverage InlierCoverage(const Eigen::AlignedBox3d& element_box, const MotionFit& motion,
                              std::span<const Eigen::Vector3f> points) {
    ExtentCoverage out;
    const Eigen::Vector3d c = element_box.center();
    const Eigen::Matrix3d R = Yaw(-motion.yaw_rad);
    Eigen::AlignedBox3d back;
    for (size_t i = 0; i < points.size() && i < motion.inlier.size(); ++i) {
        if (!motion.inlier[i]) continue;
        back.extend(R * (points[i].cast<double>() - c - motion.translation) + c);  // M^-1(p)
    }
    if (back.isEmpty()) return out;
    const Eigen::Vector3d size = element_box.sizes();
    const Eigen::Vector3d seen = back.intersection(element_box).sizes().cwiseMax(0.0);
    if (size.z() > 0) out.height = seen.z() / size.z();
    const int long_axis = size.x() >= size.y() ? 0 : 1;
    if (size[long_axis] > 0) out.length = seen[long_axis] / size[long_axis];
    return out;
}

void MovedSurfaceSamples(const ChangeModel& model, uint32_t element,
                         const Eigen::AlignedBox3d& element_box, const MotionFit& motion,
                         double spacing, double inset, std::vector<Eigen::Vector3f>* points,
                         std::vector<Eigen::Vector3f>* normals) {
    const Eigen::Vector3d c = element_box.center();
    const Eigen::Matrix3d R = Yaw(motion.yaw_rad);
    const auto moved = [&](const Eigen::Vector3f& x) {  // M(x) = R(yaw) (x - c) + c + t
        return Eigen::Vector3f((R * (x.cast<double>() - c) + c + motion.translation).cast<float>());
    };
    for (size_t t = 0; t < model.mesh.triangles.size(); ++t) {
        if (model.triangle_element[t] != element) continue;
        const auto& tri = model.mesh.triangles[t];
        const std::array<Eigen::Vector3f, 3> v = {moved(model.mesh.vertices[tri[0]]),
                                                  moved(model.mesh.vertices[tri[1]]),
                                                  moved(model.mesh.vertices[tri[2]])};
        const Eigen::Vector3f ab = v[1] - v[0], ac = v[2] - v[0];
        const Eigen::Vector3f n = ab.cross(ac);
        if (!(n.norm() > 1e-9f)) continue;
        const Eigen::Vector3f unit = n.normalized();
        // Distance from p to the triangle's edge (a, b), in its plane.
        const auto to_edge = [&](const Eigen::Vector3f& p, int a, int b) {
            const Eigen::Vector3f e = (v[b] - v[a]).normalized();
            const Eigen::Vector3f d = p - v[a];
            return (d - e * e.dot(d)).norm();
        };
        const int nb = std::max(1, int(std::ceil(ab.norm() / spacing)));
        const int nc = std::max(1, int(std::ceil(ac.norm() / spacing)));
        for (int i = 0; i <= nb; ++i) {
            for (int j = 0; j <= nc; ++j) {
                const float u = float(i) / float(nb), w = float(j) / float(nc);
                if (u + w > 1.0f) break;
                const Eigen::Vector3f p = v[0] + u * ab + w * ac;
                if (std::min({to_edge(p, 0, 1), to_edge(p, 1, 2), to_edge(p, 2, 0)}) < inset) {
                    continue;
                }
                points->push_back(p);
                normals->push_back(unit);
            }
        }
    }
}

LookedThrough MovedSurfaceLookedThrough(const ChangeModel& model, uint32_t element,
                                        const Eigen::AlignedBox3d& element_box,
                                        const MotionFit& motion, const FreeSpaceIndex& free_space,
                                        const MovedConfig& config) {
    std::vector<Eigen::Vector3f> points, normals;
    MovedSurfaceSamples(model, element, element_box, motion, config.sample_spacing_m,
                        config.sample_inset_m, &points, &normals);
    LookedThrough out;
    size_t through = 0;
    for (size_t k = 0; k < points.size(); ++k) {
        const FreeSpaceIndex::Votes v = free_space.Vote(points[k], normals[k]);
        if (v.free == 0 && v.seen == 0) continue;
        ++out.judged;
        through += v.free > v.seen;
    }
    out.share = out.judged ? double(through) / double(out.judged) : 0.0;
    return out;
}

void MovedConfig::Validate() const {
    if (!(pair_radius_m >= 0)) common::ThrowInvalid("moved.pair_radius_m must be >= 0");
    if (!(max_seen_fraction >= 0 && max_seen_fraction <= 1)) {
        common::ThrowInvalid("moved.max_seen_fraction must be in [0, 1]");
    }
    if (!(inlier_m > 0)) common::ThrowInvalid("moved.inlier_m must be > 0");
    if (!(min_inlier_fraction > 0 && min_inlier_fraction <= 1)) {
        common::ThrowInvalid("moved.min_inlier_fraction must be in (0, 1]");
    }
    if (!(min_object_fraction > 0 && min_object_fraction <= 1)) {
        common::ThrowInvalid("moved.min_object_fraction must be in (0, 1]");
    }
    common::Require(min_extent_fraction >= 0 && min_extent_fraction <= 1, "moved",
                    "min_extent_fraction", min_extent_fraction, "must be in [0, 1]");
    common::Require(sample_spacing_m > 0, "moved", "sample_spacing_m", sample_spacing_m,
                    "must be positive");
    common::Require(sample_inset_m >= 0, "moved", "sample_inset_m", sample_inset_m,
                    "must not be negative");
    common::Require(max_looked_through >= 0 && max_looked_through <= 1, "moved",
                    "max_looked_through", max_looked_through, "must be in [0, 1]");
}

MotionFit FitElementMotion(const ChangeModel& model, uint32_t element,
                           std::span<const Eigen::Vector3f> points, const MovedConfig& config) {
    Eigen::AlignedBox3d box;
    const common::TriangleMesh mesh = ElementMesh(model, element, &box);
    MotionFit best;
    // No point within inlier_m of any start's fit: still one flag per point given, all 0 (the
    // caller reads them for the object's share).
    best.inlier.assign(points.size(), 0);
    if (mesh.empty() || points.empty()) return best;
    const simulation::Scene scene(mesh);
    const Eigen::Vector3d c = box.center();
    Eigen::AlignedBox3d seen;
    for (const auto& p : points) seen.extend(p.cast<double>());
    Eigen::Vector3d m = seen.center();
    m.z() = c.z();
    const double inlier = config.inlier_m;
    const double search = std::max(0.5, 4 * inlier);
    const double cauchy2 = 4 * inlier * inlier;

    const auto score = [&](const Inverse& g, MotionFit* fit) {
        const Eigen::Matrix3d R = Yaw(g.theta);
        size_t inliers = 0;
        fit->inlier.assign(points.size(), 0);
        for (size_t i = 0; i < points.size(); ++i) {
            const Eigen::Vector3d q = R * (points[i].cast<double>() - c) + c + g.t;
            const auto hit = scene.ClosestPoint(q.cast<float>(), float(inlier));
            if (hit) fit->inlier[i] = 1, ++inliers;
        }
        fit->inlier_fraction = double(inliers) / double(points.size());
    };

    for (const double yaw_deg : {0.0, 15.0, -15.0, 35.0, -35.0, 90.0, -90.0, 180.0}) {
        for (const bool centred : {false, true}) {
            Inverse g;
            g.theta = yaw_deg * M_PI / 180.0;
            if (centred) g.t = -Yaw(g.theta) * (m - c);
            if (!centred && yaw_deg != 0.0) continue;
            for (int iteration = 0; iteration < 30; ++iteration) {
                const Eigen::Matrix3d R = Yaw(g.theta);
                Eigen::Matrix4d H = Eigen::Matrix4d::Zero();
                Eigen::Vector4d b = Eigen::Vector4d::Zero();
                for (const auto& p : points) {
                    const Eigen::Vector3d q = R * (p.cast<double>() - c) + c + g.t;
                    const auto hit = scene.ClosestPoint(q.cast<float>(), float(search));
                    if (!hit) continue;
                    const Eigen::Vector3d n = hit->normal.cast<double>();
                    const double res = n.dot(q - hit->point.cast<double>());
                    const double w = 1.0 / (1.0 + res * res / cauchy2);
                    Eigen::Vector4d J;
                    J.head<3>() = n;
                    J[3] = n.dot(Eigen::Vector3d::UnitZ().cross(q - c));
                    H += w * J * J.transpose();
                    b += w * J * res;
                }
                H.diagonal().array() += 1e-6;
                const Eigen::Vector4d delta = -H.ldlt().solve(b);
                if (!delta.allFinite()) break;
                g.t = Yaw(delta[3]) * g.t + delta.head<3>();
                g.theta += delta[3];
                if (delta.head<3>().norm() < 1e-5 && std::abs(delta[3]) < 1e-6) break;
            }
            MotionFit fit;
            score(g, &fit);
            if (fit.inlier_fraction > best.inlier_fraction) {
                // M = G^-1: M(x) = R(-theta) (x - c - t) + c.
                fit.yaw_rad = std::remainder(-g.theta, 2 * M_PI);
                fit.translation = -(Yaw(-g.theta) * g.t);
                best = std::move(fit);
            }
        }
    }
    return best;
}

namespace {

// One search for moved elements, its inputs held together (FindMovedElements's steps).
class MovedSearch {
public:
    MovedSearch(const ChangeModel& model, std::span<const Eigen::Vector3f> map_xyz,
                const std::vector<std::vector<uint32_t>>& objects,
                const std::vector<std::vector<uint32_t>>& element_support,
                const MovedConfig& config, const FreeSpaceIndex* free_space)
        : model_(model),
          xyz_(map_xyz),
          objects_(objects),
          support_(element_support),
          config_(config),
          free_space_(free_space),
          element_box_(model.element_count()),
          object_box_(objects.size()) {
        for (size_t t = 0; t < model.mesh.triangles.size(); ++t) {
            for (const uint32_t v : model.mesh.triangles[t]) {
                element_box_[model.triangle_element[t]].extend(
                    model.mesh.vertices[v].cast<double>());
            }
        }
        for (size_t o = 0; o < objects.size(); ++o) object_box_[o] = ClusterBox(xyz_, objects[o]);
    }

    bool Near(size_t e, size_t o) const {
        return object_box_[o].exteriorDistance(element_box_[e]) <= config_.pair_radius_m;
    }

    // Element e moved onto object o (with e's remaining support): the fit, when it passes every
    // test of MovedConfig and puts more than `beat` of the object's points on e; *inliers gets
    // that count.
    std::optional<MotionFit> FitOnto(size_t e, size_t o, size_t beat, size_t* inliers) {
        points_.clear();
        for (const uint32_t i : objects_[o]) points_.push_back(xyz_[i]);
        for (const uint32_t i : support_[e]) points_.push_back(xyz_[i]);
        MotionFit fit = FitElementMotion(model_, uint32_t(e), points_, config_);
        size_t object_inliers = 0;
        for (size_t k = 0; k < objects_[o].size(); ++k) object_inliers += fit.inlier[k];
        const double object_fraction = double(object_inliers) / double(objects_[o].size());
        if (fit.inlier_fraction < config_.min_inlier_fraction ||
            object_fraction < config_.min_object_fraction || object_inliers <= beat) {
            return std::nullopt;
        }
        const ExtentCoverage cover = InlierCoverage(element_box_[e], fit, points_);
        if (cover.height < config_.min_extent_fraction ||
            cover.length < config_.min_extent_fraction) {
            return std::nullopt;
        }
        if (free_space_) {
            const LookedThrough through = MovedSurfaceLookedThrough(
                model_, uint32_t(e), element_box_[e], fit, *free_space_, config_);
            if (through.judged >= config_.min_judged_samples &&
                through.share > config_.max_looked_through) {
                return std::nullopt;
            }
        }
        *inliers = object_inliers;
        return fit;
    }

    // A moved element may have come apart into several clusters (a desk's two ends): the others
    // nearby that the moved element explains are it too.
    void ClaimParts(size_t e, const MotionFit& motion, std::vector<uint32_t>& explained) {
        for (size_t o = 0; o < objects_.size(); ++o) {
            if (explained[o] != kNoElement || !Near(e, o)) continue;
            points_.clear();
            for (const uint32_t i : objects_[o]) points_.push_back(xyz_[i]);
            if (InlierFraction(model_, uint32_t(e), motion, points_, config_.inlier_m) >=
                config_.min_object_fraction) {
                explained[o] = uint32_t(e);
            }
        }
    }

private:
    const ChangeModel& model_;
    std::span<const Eigen::Vector3f> xyz_;
    const std::vector<std::vector<uint32_t>>& objects_;
    const std::vector<std::vector<uint32_t>>& support_;
    const MovedConfig& config_;
    const FreeSpaceIndex* free_space_;
    std::vector<Eigen::AlignedBox3d> element_box_, object_box_;
    std::vector<Eigen::Vector3f> points_;
};

}  // namespace

std::vector<uint32_t> FindMovedElements(const ChangeModel& model,
                                        std::span<const Eigen::Vector3f> map_xyz,
                                        const std::vector<std::vector<uint32_t>>& objects,
                                        const std::vector<std::vector<uint32_t>>& element_support,
                                        std::vector<ElementReport>& reports,
                                        const MovedConfig& config,
                                        const FreeSpaceIndex* free_space) {
    config.Validate();
    std::vector<uint32_t> explained(objects.size(), kNoElement);
    if (!config.enabled) return explained;
    MovedSearch search(model, map_xyz, objects, element_support, config, free_space);
    for (size_t e = 0; e < reports.size(); ++e) {
        const ElementEvidence& ev = reports[e].evidence;
        const bool partly_missing =
            reports[e].verdict != Verdict::kNotObserved && model.element_opaque[e] &&
            ev.seen_area_m2 < config.max_seen_fraction * ev.expected_area_m2;
        if (reports[e].verdict != Verdict::kMissing && !partly_missing) continue;
        int best_object = -1;
        MotionFit best;
        size_t best_inliers = 0;
        for (size_t o = 0; o < objects.size(); ++o) {
            if (explained[o] != kNoElement || !search.Near(e, o)) continue;
            size_t inliers = 0;
            std::optional<MotionFit> fit = search.FitOnto(e, o, best_inliers, &inliers);
            if (!fit) continue;
            best_inliers = inliers;
            best_object = int(o);
            best = std::move(*fit);
        }
        if (best_object < 0) continue;
        explained[size_t(best_object)] = uint32_t(e);
        search.ClaimParts(e, best, explained);
        ElementReport& r = reports[e];
        r.moved = true;
        r.verdict = Verdict::kDeviating;
        r.offset = best.translation;
        r.constrained_axes = 3;
        r.moved_yaw_deg = best.yaw_rad * 180.0 / M_PI;
        r.moved_inlier_fraction = best.inlier_fraction;
        r.moved_object = best_object;
    }
    return explained;
}

}  // namespace bimslam::changes
