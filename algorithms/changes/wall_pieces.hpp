// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Step 4's new objects that are walls the model lacks (an annex, a shed, new partitions), seen as
// DBSCAN cuts them and not as they were built (issue 33, README.md "Walls the model lacks"):
//   - walls that meet at corners are one cluster: SplitIntoWalls gives each wall its points;
//   - one wall seen through two windows, its middle hidden by the model's wall between them, is
//     two clusters: GapBetween gives the part of their shared plane between them, which the
//     caller asks the keyframes' range images about (free_space.hpp). A gap no beam went through
//     joins the pieces; one the beams looked through is a gap between two things.
// Walls stand upright, so both rules work in plan: a wall is a line in (x, y) and its heights.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace bimslam::changes {

struct WallPiecesConfig {
    bool split_corners = true;
    bool join_hidden_gaps = true;
    // A point within this of a vertical plane lies on it: half the thickest wall's 0.3 m. A wall
    // walked around (the visits' annex) is two faces that far apart, and both are the wall.
    double plane_tolerance_m = 0.15;
    // An object is walls when this share of its points lie on its one or two planes.
    double min_on_planes = 0.9;
    // A corner is split when both walls are at least this long and high: a wardrobe or a shelf
    // seen from two sides (at most ~1 m deep) stays one object.
    double min_wall_length_m = 1.5;
    double min_wall_height_m = 1.5;
    double min_corner_deg = 60;
    // Two pieces are of one wall when their planes are within max_parallel_deg and
    // plane_tolerance_m of each other, their heights overlap for min_height_overlap of the lower
    // one's, and at most max_gap_m lies between them...
    double max_parallel_deg = 5;
    double min_height_overlap = 0.5;
    double max_gap_m = 3.0;
    // ... of which the keyframes looked through at most this share of the samples.
    double max_looked_through = 0.1;
    double gap_step_m = 0.1;  // samples along the gap; twice this apart in height
    void Validate() const;
};

// A vertical plane: the line through `point` along `direction` (unit) in plan.
struct VerticalPlane {
    Eigen::Vector2f point = Eigen::Vector2f::Zero(), direction = Eigen::Vector2f::UnitX();
    Eigen::Vector2f Normal() const { return {-direction.y(), direction.x()}; }
    float Distance(const Eigen::Vector3f& p) const {
        return std::abs(Normal().dot(p.head<2>() - point));
    }
    float Along(const Eigen::Vector3f& p) const { return direction.dot(p.head<2>() - point); }
};

// The vertical plane that holds most of xyz[points] within `tolerance_m` (RANSAC over pairs of
// points, a fixed seed, then least squares on its points), and which points lie on it. Needs two
// points at least 0.1 m apart in plan.
struct PlaneFit {
    VerticalPlane plane;
    std::vector<uint32_t> on, off;
};
std::optional<PlaneFit> FitVerticalPlane(std::span<const Eigen::Vector3f> xyz,
                                         std::span<const uint32_t> points, float tolerance_m);

// The points of two to four walls that meet at corners (an L, a U, a room seen from outside),
// each wall's apart (every point to the nearest plane), or nothing when xyz[points] are not such
// walls: the walls are peeled off one plane at a time, each at least min_wall_length_m long and
// min_wall_height_m high, until min_on_planes of the points lie on them; two of them at least
// min_corner_deg apart.
std::vector<std::vector<uint32_t>> SplitIntoWalls(std::span<const Eigen::Vector3f> xyz,
                                                  std::span<const uint32_t> points,
                                                  const WallPiecesConfig& config);

// An object that is one wall: its plane, the ends of its points on the plane (in plan) and their
// heights. Nothing when fewer than min_on_planes of its points lie on one plane.
struct WallPiece {
    VerticalPlane plane;
    std::array<Eigen::Vector2f, 2> ends;
    float z_min = 0, z_max = 0;
};
std::optional<WallPiece> AsWallPiece(std::span<const Eigen::Vector3f> xyz,
                                     std::span<const uint32_t> points,
                                     const WallPiecesConfig& config);

// The gap between two pieces of one wall, as samples on their plane with its normal, or nothing
// when a and b are not pieces of one wall. No samples: the pieces overlap along the wall.
struct WallGap {
    std::vector<Eigen::Vector3f> samples;
    Eigen::Vector3f normal = Eigen::Vector3f::Zero();
};
std::optional<WallGap> GapBetween(const WallPiece& a, const WallPiece& b,
                                  const WallPiecesConfig& config);

}  // namespace bimslam::changes
