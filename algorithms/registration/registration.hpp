// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Loop registration: an oriented query cloud (a keyframe, or a few merged around it) aligned to a
// surfel map built in the target's frame (the BIM reference, or another session's submap), from
// coarse to fine, with its fitness and a 6x6 information matrix taken from the problem at the
// optimum.
//
// Point-to-plane ICP (Chen & Medioni 1992) solved by Gauss-Newton on SE(3). The unknown is a
// right perturbation delta = [rho; phi] of the current estimate T0 (the query's frame):
// T = T0 Exp(delta). For a point p with surfel (n, o): r = n . (T p) - o, and to first order
// dr/drho = n^T R0, dr/dphi = (p x R0^T n)^T (Barfoot, "State Estimation for Robotics", 7.1.9).
// Outliers (furniture, people: what the model does not hold) are down-weighted by Cauchy IRLS,
// w = 1 / (1 + (r / c)^2), with c shrinking from level to level; correspondences farther than
// the level's max_distance, or whose normals disagree, are not made (Zhang 1994).
//
// Information. At the optimum the Gauss-Newton Hessian H = sum w J^T J over the correspondences is
// the inverse covariance of delta when each residual has variance sigma^2: Sigma = sigma^2 H^-1
// (Censi, "An accurate closed-form estimate of ICP's covariance", ICRA 2007, the term that
// dominates for point-to-plane), with sigma^2 the weighted mean squared residual, floored at
// min_sigma because a perfect fit against a noiseless model would claim infinite certainty. The
// paper turned "ICP fitness" into an adaptive covariance by hand; this is the same idea derived
// from the problem itself. Points of one scan are not independent (a wall's points share its
// plane's error), so `information_scale` < 1 discounts them.
//
// Degeneracy (Zhang, Kaess, Singh, ICRA 2016): the eigenvalues of the unweighted H_geo = sum J^T J
// over the query's points (those a coarse level skips counted too), with rotation scaled by the
// mean range of the points, so both halves are in metres and an eigenvalue counts the points, by
// how squarely they face that direction, that constrain it. Geometry, not the robust weights,
// decides. A direction constrained by fewer than degenerate_min_eigenvalue points' worth (the
// axis of a long corridor, the in-plane motion of a scan that sees only a floor) keeps the
// initial guess and gets zero information; the solve runs in the other directions. An absolute
// count, not a ratio to the largest eigenvalue: a corridor's roll is weak next to its sideways
// translation but measured by thousands of points.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "algorithms/common/se3.hpp"
#include "algorithms/registration/oriented_cloud.hpp"
#include "algorithms/registration/surfel_map.hpp"

namespace bimslam::registration {

struct RegistrationLevel {
    double voxel_size = 0.5;    // m, of this level's surfel map
    double max_distance = 0.5;  // m: farther correspondences are not made
    double cauchy_scale = 0.1;  // m
    int max_iterations = 15;
    // At most this many query points, evenly thinned (every k-th): a coarse level only has to
    // bring the pose within reach of the next.
    size_t max_points = 2000;
    // Converged when an iteration moves the pose less than this (m; the rotation is in metres
    // at the points' mean range).
    double converged = 1e-3;
};

struct RegistrationConfig {
    // Coarse to fine. The first level's reach decides how far off an initial guess may be (about
    // its max_distance plus a voxel); the last decides the accuracy.
    std::vector<RegistrationLevel> levels = {{1.0, 1.2, 0.4, 15, 500, 5e-3},
                                             {0.5, 0.5, 0.15, 15, 1000, 2e-3},
                                             {0.25, 0.2, 0.04, 20, 2000, 2e-4}};
    double min_normal_cos = 0.8;    // the query's and the surfel's normals within 37 degrees
    double inlier_distance = 0.05;  // m: fitness counts points this close at the last level
    int min_correspondences = 50;   // fewer: failed
    double degenerate_min_eigenvalue = 10.0;
    double min_sigma = 0.01;         // m, floor of the residual standard deviation
    double information_scale = 0.1;  // see above

    void Validate() const;  // throws common::Error naming the field
};

// The target: one surfel map per level, built from the same clouds.
class SurfelPyramid {
public:
    explicit SurfelPyramid(const RegistrationConfig& config);
    // Built levels in the order of RegistrationConfig::levels (SurfelMap::Restore: a saved one).
    explicit SurfelPyramid(std::vector<SurfelMap> levels) : maps_(std::move(levels)) {}
    void Add(const OrientedCloud& cloud, const Eigen::Isometry3d& T_map_cloud);
    void Build();
    const SurfelMap& level(size_t i) const { return maps_.at(i); }
    // One level alone: the levels are independent, so a caller may fill them in parallel.
    SurfelMap& mutable_level(size_t i) { return maps_.at(i); }
    size_t levels() const { return maps_.size(); }

private:
    std::vector<SurfelMap> maps_;
};

struct Fitness {
    size_t points = 0;   // query points used at the last level
    size_t inliers = 0;  // with a correspondence within inlier_distance at the end
    double inlier_ratio = 0;
    double inlier_rmse = 0;  // m
};

struct RegistrationResult {
    Eigen::Isometry3d T_target_source = Eigen::Isometry3d::Identity();
    Fitness fitness;
    // Over the right perturbation [rho; phi] of T_target_source; zero along degenerate directions.
    common::Matrix6d information = common::Matrix6d::Zero();
    int degenerate_directions = 0;
    double min_eigen_ratio = 0;  // smallest eigenvalue over the largest, of the scaled H_geo
    int iterations = 0;
    int correspondences = 0;  // at the end
    double sigma = 0;         // m, the residual standard deviation used (before the floor)
    bool converged = false;   // the last level converged
    bool failed = false;      // too few correspondences at some level
};

// Registers `source` (its own frame) to `target` from T_target_source_init, running the levels
// from first_level on (a good initial guess may skip the coarse ones).
RegistrationResult Register(const OrientedCloud& source, const SurfelPyramid& target,
                            const Eigen::Isometry3d& T_target_source_init,
                            const RegistrationConfig& config, size_t first_level = 0);

}  // namespace bimslam::registration
