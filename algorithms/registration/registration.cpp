// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/registration/registration.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>

#include "algorithms/common/status.hpp"

namespace bimslam::registration {
using common::Matrix6d;
using common::Require;
using common::Vector6d;

void RegistrationConfig::Validate() const {
    const char* c = "RegistrationConfig";
    Require(!levels.empty(), c, "levels", 0, "needs at least one level");
    for (const RegistrationLevel& l : levels) {
        Require(l.voxel_size > 0.01, c, "levels[].voxel_size", l.voxel_size, "must be over 0.01 m");
        Require(l.max_distance > 0, c, "levels[].max_distance", l.max_distance, "must be positive");
        Require(l.cauchy_scale > 0, c, "levels[].cauchy_scale", l.cauchy_scale, "must be positive");
        Require(l.max_iterations >= 1, c, "levels[].max_iterations", l.max_iterations,
                "must be at least 1");
        Require(l.max_points >= 6, c, "levels[].max_points", double(l.max_points),
                "must be at least 6");
        Require(l.converged > 0, c, "levels[].converged", l.converged, "must be positive");
    }
    Require(min_normal_cos >= -1 && min_normal_cos < 1, c, "min_normal_cos", min_normal_cos,
            "must be in [-1, 1)");
    Require(inlier_distance > 0, c, "inlier_distance", inlier_distance, "must be positive");
    Require(min_correspondences >= 6, c, "min_correspondences", min_correspondences,
            "must be at least 6");
    Require(degenerate_min_eigenvalue >= 0, c, "degenerate_min_eigenvalue",
            degenerate_min_eigenvalue, "must not be negative");
    Require(min_sigma > 0, c, "min_sigma", min_sigma, "must be positive");
    Require(information_scale > 0, c, "information_scale", information_scale, "must be positive");
}

SurfelPyramid::SurfelPyramid(const RegistrationConfig& config) {
    config.Validate();
    for (const RegistrationLevel& l : config.levels) {
        // Coarse voxels span more of a slightly uneven surface (a floor's slope, a wall's
        // tolerance): the flatness test grows with them, never below 3 cm.
        SurfelMapConfig m;
        m.voxel_size = l.voxel_size;
        m.max_thickness = std::max(0.03, 0.05 * l.voxel_size);
        maps_.emplace_back(m);
    }
}

void SurfelPyramid::Add(const OrientedCloud& cloud, const Eigen::Isometry3d& T_map_cloud) {
    for (SurfelMap& m : maps_) m.Add(cloud, T_map_cloud);
}

void SurfelPyramid::Build() {
    for (SurfelMap& m : maps_) m.Build();
}

namespace {

struct Normal {
    Matrix6d H = Matrix6d::Zero();      // weighted: the solve and the information
    Matrix6d H_geo = Matrix6d::Zero();  // unweighted, per point of the full cloud: degeneracy
    Vector6d g = Vector6d::Zero();
    double weighted_sq = 0, weight = 0;
    int correspondences = 0;
    size_t used = 0;  // query points tried
    size_t inliers = 0;
    double inlier_sq = 0;
};

// One pass over the points at T: the weighted normal equations of the level.
Normal Accumulate(const OrientedCloud& source, const SurfelMap& map, const Eigen::Isometry3d& T,
                  const RegistrationLevel& level, const RegistrationConfig& config) {
    Normal ne;
    const Eigen::Matrix3f R = T.linear().cast<float>();
    const Eigen::Vector3f t = T.translation().cast<float>();
    const Eigen::Matrix3d Rd = T.linear();
    const float max_d = static_cast<float>(level.max_distance);
    const float min_cos = static_cast<float>(config.min_normal_cos);
    const double c2 = level.cauchy_scale * level.cauchy_scale;
    const size_t stride =
        std::max<size_t>(1, (source.size() + level.max_points - 1) / level.max_points);
    for (size_t k = 0; k < source.size(); k += stride) {
        ++ne.used;
        const Eigen::Vector3f q = R * source.points[k] + t;
        float r = 0;
        const Surfel* s = map.Find(q, R * source.normals[k], min_cos, &r);
        if (!s || std::abs(r) > max_d) continue;
        const Eigen::Vector3d n = s->normal.cast<double>();
        const Eigen::Vector3d p = source.points[k].cast<double>();
        const Eigen::Vector3d Rtn = Rd.transpose() * n;
        Vector6d J;
        J << Rtn, p.cross(Rtn);  // n^T R0 = (R0^T n)^T
        const double w = 1.0 / (1.0 + double(r) * r / c2);
        ne.H.noalias() += w * J * J.transpose();
        ne.H_geo.noalias() += double(stride) * J * J.transpose();
        ne.g.noalias() += w * double(r) * J;
        ne.weighted_sq += w * double(r) * r;
        ne.weight += w;
        ++ne.correspondences;
        if (std::abs(r) <= config.inlier_distance) {
            ++ne.inliers;
            ne.inlier_sq += double(r) * r;
        }
    }
    return ne;
}

double MeanRange(const OrientedCloud& cloud) {
    double sum = 0;
    for (const auto& p : cloud.points) sum += p.norm();
    return cloud.empty() ? 1.0 : std::max(1.0, sum / double(cloud.size()));
}

}  // namespace

// The directions (eigenvectors of the scaled geometric Hessian) that enough points constrain,
// as columns: the subspace the solve and the information live in (see the header).
Eigen::Matrix<double, 6, Eigen::Dynamic> Constrained(const Matrix6d& H_geo_scaled, double min_eigen,
                                                     int* degenerate, double* min_ratio) {
    const Eigen::SelfAdjointEigenSolver<Matrix6d> eig(H_geo_scaled);
    const Vector6d lambda = eig.eigenvalues().cwiseMax(0.0);
    if (min_ratio) *min_ratio = lambda.minCoeff() / std::max(lambda.maxCoeff(), 1e-12);
    Eigen::Matrix<double, 6, Eigen::Dynamic> U(6, 0);
    int d = 0;
    for (int i = 0; i < 6; ++i) {
        if (lambda(i) < min_eigen) {
            ++d;
            continue;
        }
        U.conservativeResize(6, U.cols() + 1);
        U.col(U.cols() - 1) = eig.eigenvectors().col(i);
    }
    if (degenerate) *degenerate = d;
    return U;
}

RegistrationResult Register(const OrientedCloud& source, const SurfelPyramid& target,
                            const Eigen::Isometry3d& T_init, const RegistrationConfig& config,
                            size_t first_level) {
    RegistrationResult out;
    out.T_target_source = T_init;
    if (target.levels() != config.levels.size()) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            "Register: the target was built for another number of levels");
    }
    // Rotation scaled by the mean range, so that both halves of delta are in metres.
    Vector6d scale;
    const double L = MeanRange(source);
    scale << 1, 1, 1, L, L, L;
    const Vector6d Sinv = scale.cwiseInverse();
    Eigen::Isometry3d T = T_init;
    Normal ne;
    for (size_t li = first_level; li < config.levels.size(); ++li) {
        const RegistrationLevel& level = config.levels[li];
        const SurfelMap& map = target.level(li);
        out.converged = false;
        for (int it = 0; it < level.max_iterations; ++it) {
            ne = Accumulate(source, map, T, level, config);
            ++out.iterations;
            if (ne.correspondences < config.min_correspondences) {
                out.failed = true;
                out.correspondences = ne.correspondences;
                return out;
            }
            // Solve in scaled coordinates, x = S delta (H_s = S^-1 H S^-1), within the
            // constrained subspace U: x = U (U^T H_s U)^-1 U^T (-g_s); along the rest, the guess.
            const Matrix6d Hs = Sinv.asDiagonal() * ne.H * Sinv.asDiagonal();
            const Vector6d gs = Sinv.asDiagonal() * ne.g;
            const auto U = Constrained(Sinv.asDiagonal() * ne.H_geo * Sinv.asDiagonal(),
                                       config.degenerate_min_eigenvalue, nullptr, nullptr);
            if (U.cols() == 0) break;
            const Eigen::MatrixXd A = U.transpose() * Hs * U;
            const Vector6d xs = -U * A.ldlt().solve(U.transpose() * gs);
            const Vector6d delta = Sinv.asDiagonal() * xs;
            T = T * common::ExpSE3(delta);
            if (xs.norm() < level.converged) {
                out.converged = true;
                break;
            }
        }
    }
    // Fitness and information at the final estimate.
    ne =
        Accumulate(source, target.level(config.levels.size() - 1), T, config.levels.back(), config);
    out.T_target_source = T;
    out.correspondences = ne.correspondences;
    out.fitness.inliers = ne.inliers;
    out.fitness.points = ne.used;
    out.fitness.inlier_ratio = ne.used ? double(ne.inliers) / double(ne.used) : 0;
    out.fitness.inlier_rmse = ne.inliers ? std::sqrt(ne.inlier_sq / double(ne.inliers)) : 0;
    if (ne.correspondences < config.min_correspondences) {
        out.failed = true;
        return out;
    }
    out.sigma = std::sqrt(ne.weighted_sq / std::max(ne.weight, 1e-12));
    const double sigma = std::max(out.sigma, config.min_sigma);
    // The information: the weighted Hessian on the constrained subspace, zero elsewhere.
    const auto U = Constrained(Sinv.asDiagonal() * ne.H_geo * Sinv.asDiagonal(),
                               config.degenerate_min_eigenvalue, &out.degenerate_directions,
                               &out.min_eigen_ratio);
    const Matrix6d P = U * U.transpose();
    const Matrix6d Is = P * (Sinv.asDiagonal() * ne.H * Sinv.asDiagonal()) * P;
    out.information =
        config.information_scale / (sigma * sigma) * scale.asDiagonal() * Is * scale.asDiagonal();
    return out;
}

}  // namespace bimslam::registration
