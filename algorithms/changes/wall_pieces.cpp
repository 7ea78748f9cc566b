// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/changes/wall_pieces.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <string>

#include "algorithms/common/status.hpp"

namespace bimslam::changes {
namespace {

float CosOfDegrees(double deg) { return float(std::cos(deg * std::numbers::pi / 180.0)); }

size_t CountOn(const VerticalPlane& plane, std::span<const Eigen::Vector3f> xyz,
               std::span<const uint32_t> points, float tolerance_m) {
    return size_t(std::count_if(points.begin(), points.end(),
                                [&](uint32_t i) { return plane.Distance(xyz[i]) <= tolerance_m; }));
}

// The least-squares line in plan of the points on `plane`: their mean and principal direction.
VerticalPlane Refit(const VerticalPlane& plane, std::span<const Eigen::Vector3f> xyz,
                    std::span<const uint32_t> points, float tolerance_m) {
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    size_t n = 0;
    for (const uint32_t i : points) {
        if (plane.Distance(xyz[i]) > tolerance_m) continue;
        mean += xyz[i].head<2>().cast<double>();
        ++n;
    }
    if (n < 2) return plane;
    mean /= double(n);
    Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
    for (const uint32_t i : points) {
        if (plane.Distance(xyz[i]) > tolerance_m) continue;
        const Eigen::Vector2d d = xyz[i].head<2>().cast<double>() - mean;
        cov += d * d.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov);
    return {mean.cast<float>(), eig.eigenvectors().col(1).normalized().cast<float>()};
}

// The extent of xyz[points] along `plane` and in height, of those on it.
struct Extent {
    float along_min = 0, along_max = 0, z_min = 0, z_max = 0;
    float Length() const { return along_max - along_min; }
    float Height() const { return z_max - z_min; }
};
Extent ExtentOn(const VerticalPlane& plane, std::span<const Eigen::Vector3f> xyz,
                std::span<const uint32_t> points, float tolerance_m) {
    Extent e{std::numeric_limits<float>::max(), std::numeric_limits<float>::lowest(),
             std::numeric_limits<float>::max(), std::numeric_limits<float>::lowest()};
    for (const uint32_t i : points) {
        if (plane.Distance(xyz[i]) > tolerance_m) continue;
        const float s = plane.Along(xyz[i]);
        e.along_min = std::min(e.along_min, s);
        e.along_max = std::max(e.along_max, s);
        e.z_min = std::min(e.z_min, xyz[i].z());
        e.z_max = std::max(e.z_max, xyz[i].z());
    }
    return e;
}

}  // namespace

void WallPiecesConfig::Validate() const {
    const auto positive = [](double v, const char* name) {
        if (!(v > 0))
            common::ThrowInvalid(std::string(name) + " must be > 0, not " + std::to_string(v));
    };
    positive(plane_tolerance_m, "walls.plane_tolerance_m");
    positive(gap_step_m, "walls.gap_step_m");
    if (!(min_wall_length_m >= 0 && min_wall_height_m >= 0 && max_gap_m >= 0)) {
        common::ThrowInvalid(
            "walls: min_wall_length_m, min_wall_height_m and max_gap_m must be "
            ">= 0");
    }
    if (!(min_on_planes > 0 && min_on_planes <= 1 && min_height_overlap >= 0 &&
          min_height_overlap <= 1 && max_looked_through >= 0 && max_looked_through <= 1)) {
        common::ThrowInvalid(
            "walls: min_on_planes, min_height_overlap and max_looked_through "
            "must be shares in [0, 1]");
    }
    if (!(min_corner_deg >= 0 && min_corner_deg <= 90 && max_parallel_deg >= 0 &&
          max_parallel_deg <= 90)) {
        common::ThrowInvalid("walls: min_corner_deg and max_parallel_deg must be in [0, 90]");
    }
}

std::optional<PlaneFit> FitVerticalPlane(std::span<const Eigen::Vector3f> xyz,
                                         std::span<const uint32_t> points, float tolerance_m) {
    constexpr int kTrials = 200;
    constexpr float kMinPairDistance = 0.1f;
    if (points.size() < 2) return std::nullopt;
    std::mt19937 rng(20261205);  // a fixed seed: the same map gives the same objects
    std::uniform_int_distribution<size_t> pick(0, points.size() - 1);
    std::optional<VerticalPlane> best;
    size_t best_on = 0;
    for (int t = 0; t < kTrials; ++t) {
        const Eigen::Vector2f a = xyz[points[pick(rng)]].head<2>();
        const Eigen::Vector2f d = xyz[points[pick(rng)]].head<2>() - a;
        if (d.norm() < kMinPairDistance) continue;
        const VerticalPlane candidate{a, d.normalized()};
        const size_t on = CountOn(candidate, xyz, points, tolerance_m);
        if (on > best_on) best = candidate, best_on = on;
    }
    if (!best) return std::nullopt;
    PlaneFit fit;
    fit.plane = Refit(*best, xyz, points, tolerance_m);
    for (const uint32_t i : points) {
        (fit.plane.Distance(xyz[i]) <= tolerance_m ? fit.on : fit.off).push_back(i);
    }
    return fit;
}

std::vector<std::vector<uint32_t>> SplitIntoWalls(std::span<const Eigen::Vector3f> xyz,
                                                  std::span<const uint32_t> points,
                                                  const WallPiecesConfig& config) {
    constexpr int kMaxWalls = 4;  // a room's
    const float tol = float(config.plane_tolerance_m);
    const double n = double(points.size());
    // Walls peeled off one by one, the one holding most of the rest first.
    std::vector<VerticalPlane> walls;
    std::vector<uint32_t> rest(points.begin(), points.end());
    for (int k = 0; k<kMaxWalls&& double(rest.size())>(1 - config.min_on_planes) * n; ++k) {
        std::optional<PlaneFit> fit = FitVerticalPlane(xyz, rest, tol);
        if (!fit) break;
        // Its extent over all the points: the corner it shares with a wall peeled before is its
        // too (FZK-Haus's shed: its south wall, 1.64 m, measured 1.47 m without the corner).
        const Extent e = ExtentOn(fit->plane, xyz, points, tol);
        if (e.Length() < float(config.min_wall_length_m) ||
            e.Height() < float(config.min_wall_height_m)) {
            break;
        }
        walls.push_back(fit->plane);
        rest = std::move(fit->off);
    }
    if (walls.size() < 2 || double(rest.size()) > (1 - config.min_on_planes) * n) return {};
    bool corner = false;
    for (size_t a = 0; a < walls.size(); ++a) {
        for (size_t b = a + 1; b < walls.size(); ++b) {
            corner |= std::abs(walls[a].direction.dot(walls[b].direction)) <=
                      CosOfDegrees(config.min_corner_deg);
        }
    }
    if (!corner) return {};  // parallel faces: a wall seen from both sides, or a thick one
    std::vector<std::vector<uint32_t>> parts(walls.size());
    for (const uint32_t i : points) {
        size_t nearest = 0;
        for (size_t k = 1; k < walls.size(); ++k) {
            if (walls[k].Distance(xyz[i]) < walls[nearest].Distance(xyz[i])) nearest = k;
        }
        parts[nearest].push_back(i);
    }
    return parts;
}

std::optional<WallPiece> AsWallPiece(std::span<const Eigen::Vector3f> xyz,
                                     std::span<const uint32_t> points,
                                     const WallPiecesConfig& config) {
    const float tol = float(config.plane_tolerance_m);
    const std::optional<PlaneFit> fit = FitVerticalPlane(xyz, points, tol);
    if (!fit || double(fit->on.size()) < config.min_on_planes * double(points.size())) {
        return std::nullopt;
    }
    const Extent e = ExtentOn(fit->plane, xyz, fit->on, tol);
    WallPiece piece;
    piece.plane = fit->plane;
    piece.ends = {fit->plane.point + e.along_min * fit->plane.direction,
                  fit->plane.point + e.along_max * fit->plane.direction};
    piece.z_min = e.z_min;
    piece.z_max = e.z_max;
    return piece;
}

std::optional<WallGap> GapBetween(const WallPiece& a, const WallPiece& b,
                                  const WallPiecesConfig& config) {
    const float tol = float(config.plane_tolerance_m);
    if (std::abs(a.plane.direction.dot(b.plane.direction)) <
        CosOfDegrees(config.max_parallel_deg)) {
        return std::nullopt;
    }
    const Eigen::Vector2f normal = a.plane.Normal();
    const auto offset = [&](const Eigen::Vector2f& q) { return normal.dot(q - a.plane.point); };
    const auto off_plane = [&](const WallPiece& piece, const Eigen::Vector2f& q) {
        return std::abs(piece.plane.Normal().dot(q - piece.plane.point)) > tol;
    };
    if (off_plane(a, b.ends[0]) || off_plane(a, b.ends[1]) || off_plane(b, a.ends[0]) ||
        off_plane(b, a.ends[1])) {
        return std::nullopt;
    }
    const float z_lo = std::max(a.z_min, b.z_min), z_hi = std::min(a.z_max, b.z_max);
    const float lower = std::min(a.z_max - a.z_min, b.z_max - b.z_min);
    if (z_hi - z_lo < float(config.min_height_overlap) * lower) return std::nullopt;
    // Along a's plane: each piece's interval, and what lies between them.
    const auto along = [&](const Eigen::Vector2f& q) {
        return a.plane.direction.dot(q - a.plane.point);
    };
    const float a0 = along(a.ends[0]), a1 = along(a.ends[1]);
    const float b0 = std::min(along(b.ends[0]), along(b.ends[1]));
    const float b1 = std::max(along(b.ends[0]), along(b.ends[1]));
    const float from = b0 > a1 ? a1 : b1, to = b0 > a1 ? b0 : a0;
    if (to - from > float(config.max_gap_m)) return std::nullopt;
    // The samples lie halfway between the two planes.
    const float shift = 0.25f * (offset(b.ends[0]) + offset(b.ends[1]));  // half b's offset
    WallGap gap;
    gap.normal = Eigen::Vector3f(normal.x(), normal.y(), 0.0f);
    const float step = float(config.gap_step_m);
    for (float s = from + 0.5f * step; s < to; s += step) {
        const Eigen::Vector2f q = a.plane.point + s * a.plane.direction + shift * normal;
        for (float z = z_lo + step; z < z_hi; z += 2 * step)
            gap.samples.emplace_back(q.x(), q.y(), z);
    }
    return gap;
}

}  // namespace bimslam::changes
