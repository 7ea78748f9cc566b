#include "algorithms/odometry/scan_registration.hpp"

#include <ceres/ceres.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "algorithms/common/status.hpp"

namespace bimslam::odometry {
using common::Require;

void RegistrationConfig::Validate() const {
    const char* c = "RegistrationConfig";
    Require(max_iterations >= 1 && max_iterations <= 100, c, "max_iterations", max_iterations,
            "must be in [1, 100]");
    Require(max_solver_iterations >= 1 && max_solver_iterations <= 100, c, "max_solver_iterations",
            max_solver_iterations, "must be in [1, 100]");
    Require(max_correspondence_distance > 0 && max_correspondence_distance <= 10, c,
            "max_correspondence_distance", max_correspondence_distance, "must be in (0, 10] m");
    Require(cauchy_scale > 0 && cauchy_scale <= 10, c, "cauchy_scale", cauchy_scale,
            "must be in (0, 10] m");
    Require(cauchy_scale_initial >= cauchy_scale && cauchy_scale_initial <= 10, c,
            "cauchy_scale_initial", cauchy_scale_initial, "must be in [cauchy_scale, 10] m");
    Require(min_correspondences >= 6, c, "min_correspondences", min_correspondences,
            "must be >= 6");
    Require(converged_translation > 0 && converged_rotation > 0, c, "converged_translation",
            converged_translation, "and converged_rotation must be > 0");
    Require(degenerate_ratio >= 0 && degenerate_ratio < 0.5, c, "degenerate_ratio",
            degenerate_ratio, "must be in [0, 0.5)");
}

Eigen::Isometry3d ApplyPerturbation(const Eigen::Isometry3d& T0, const common::Vector6d& delta) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = T0.linear() * common::ExpSO3(delta.tail<3>());
    T.translation() = T0.translation() + T0.linear() * delta.head<3>();
    return T;
}

namespace {
// One residual and its Jacobian row (header comment); J may be null.
struct RowModel {
    Eigen::Matrix3d R0, R, Jr;
    Eigen::Vector3d t;
    RowModel(const Eigen::Isometry3d& T0, const double* delta) {
        const Eigen::Map<const common::Vector6d> x(delta);
        R0 = T0.linear();
        R = R0 * common::ExpSO3(x.tail<3>());
        t = T0.translation() + R0 * x.head<3>();
        Jr = common::LeftJacobianSO3(-x.tail<3>());
    }
};
}  // namespace

// The whole scan as one residual block of n residuals (the IRLS weights are inside), so that
// Ceres's overhead is per scan, not per point.
class ScanRegistration::Cost final : public ceres::CostFunction {
public:
    Cost(const std::vector<Correspondence>* corr, const Eigen::Isometry3d& T0)
        : corr_(corr), T0_(T0) {
        mutable_parameter_block_sizes()->push_back(6);
    }
    void SetCount(int n) { set_num_residuals(n); }

    bool Evaluate(double const* const* parameters, double* residuals,
                  double** jacobians) const override {
        const RowModel m(T0_, parameters[0]);
        const int n = num_residuals();
        for (int i = 0; i < n; ++i) {
            const Correspondence& c = (*corr_)[size_t(i)];
            residuals[i] = c.sqrt_w * (c.n.dot(m.R * c.p + m.t) - c.d);
            if (jacobians && jacobians[0]) {
                double* J = jacobians[0] + 6 * i;
                const Eigen::Vector3d jt = c.sqrt_w * (m.R0.transpose() * c.n);
                const Eigen::Vector3d jr =
                    c.sqrt_w * (m.Jr.transpose() * c.p.cross(m.R.transpose() * c.n));
                J[0] = jt.x(), J[1] = jt.y(), J[2] = jt.z();
                J[3] = jr.x(), J[4] = jr.y(), J[5] = jr.z();
            }
        }
        return true;
    }

private:
    const std::vector<Correspondence>* corr_;
    Eigen::Isometry3d T0_;
};

ScanRegistration::ScanRegistration(const RegistrationConfig& config, size_t max_points)
    : config_(config) {
    config_.Validate();
    corr_.resize(max_points);
}

ScanRegistration::~ScanRegistration() = default;

int ScanRegistration::Associate(std::span<const Eigen::Vector3f> points, const VoxelMap& map,
                                std::span<const Eigen::Vector3f> edges, const VoxelMap* edge_map,
                                const Eigen::Isometry3d& T, double cauchy_scale) {
    const Eigen::Matrix3f R = T.linear().cast<float>();
    const Eigen::Vector3f t = T.translation().cast<float>();
    const float max_d = static_cast<float>(config_.max_correspondence_distance);
    const double inv_c2 = 1.0 / (cauchy_scale * cauchy_scale);
    int n = 0;
    for (const Eigen::Vector3f& p : points) {
        if (size_t(n) >= corr_.size()) break;
        float r = 0;
        const VoxelPlane* plane = map.FindPlane(R * p + t, &r);
        if (!plane || std::abs(r) > max_d) continue;
        Correspondence& c = corr_[size_t(n++)];
        c.p = p.cast<double>();
        c.n = plane->normal.cast<double>();
        c.d = plane->offset;
        c.sqrt_w = std::sqrt(1.0 / (1.0 + double(r) * r * inv_c2));  // Cauchy IRLS weight
    }
    if (!edge_map) return n;
    for (const Eigen::Vector3f& p : edges) {
        if (size_t(n) + 2 > corr_.size()) break;
        float r = 0;
        const VoxelLine* line = edge_map->FindLine(R * p + t, &r);
        if (!line || r > max_d) continue;
        // The distance to a line with direction u through c is that to two planes through c,
        // with normals e1, e2 orthogonal to u and to each other.
        const Eigen::Vector3d u = line->direction.cast<double>();
        const Eigen::Vector3d e1 = u.unitOrthogonal(), e2 = u.cross(e1);
        const double sqrt_w = std::sqrt(1.0 / (1.0 + double(r) * r * inv_c2));
        for (const Eigen::Vector3d& e : {e1, e2}) {
            Correspondence& c = corr_[size_t(n++)];
            c.p = p.cast<double>();
            c.n = e;
            c.d = e.dot(line->point.cast<double>());
            c.sqrt_w = sqrt_w;
        }
    }
    return n;
}

const RegistrationResult& ScanRegistration::Align(std::span<const Eigen::Vector3f> points,
                                                  const VoxelMap& map, const Eigen::Isometry3d& T0,
                                                  const common::Vector6d& prior_sigma,
                                                  Clock::time_point deadline,
                                                  std::span<const Eigen::Vector3f> edges,
                                                  const VoxelMap* edge_map) {
    result_ = RegistrationResult{};
    result_.T_map_lidar = T0;
    common::Vector6d delta = common::Vector6d::Zero();
    Cost cost(&corr_, T0);
    ceres::Problem::Options problem_options;
    problem_options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Solver::Options options;
    options.linear_solver_type = ceres::DENSE_QR;
    options.max_num_iterations = config_.max_solver_iterations;
    options.num_threads = 1;
    options.logging_type = ceres::SILENT;
    options.minimizer_progress_to_stdout = false;

    int n = 0;
    double kernel = config_.cauchy_scale_initial;
    for (int it = 0; it < config_.max_iterations;
         ++it, kernel = std::max(config_.cauchy_scale, kernel / 2)) {
        const double remaining = std::chrono::duration<double>(deadline - Clock::now()).count();
        if (remaining <= 0) {
            result_.over_budget = true;
            break;
        }
        const Eigen::Isometry3d T = ApplyPerturbation(T0, delta);
        const int found = Associate(points, map, edges, edge_map, T, kernel);
        if (found < config_.min_correspondences) {
            if (it == 0) {
                result_.failed = true;
                result_.correspondences = found;
                return result_;
            }
            break;  // keep the last solution, whose correspondences were enough
        }
        n = found;
        cost.SetCount(n);
        ceres::Problem problem(problem_options);
        problem.AddResidualBlock(&cost, nullptr, delta.data());
        options.max_solver_time_in_seconds = remaining;
        ceres::Solver::Summary summary;
        ceres::Solve(options, &problem, &summary);
        ++result_.iterations;
        const Eigen::Isometry3d step = common::Between(T, ApplyPerturbation(T0, delta));
        if (kernel <= config_.cauchy_scale &&
            step.translation().norm() < config_.converged_translation &&
            common::RotationAngle(step) < config_.converged_rotation) {
            result_.converged = true;
            break;
        }
    }

    // The normal equations at the solution, with rotation scaled to metres (header comment).
    const RowModel m(T0, delta.data());
    double mean_range = 0, weight_sum = 0, weighted_sq = 0;
    for (int i = 0; i < n; ++i) mean_range += corr_[size_t(i)].p.norm();
    mean_range = n > 0 ? std::max(1.0, mean_range / n) : 1.0;
    common::Matrix6d H = common::Matrix6d::Zero();
    for (int i = 0; i < n; ++i) {
        const Correspondence& c = corr_[size_t(i)];
        common::Vector6d J;
        J.head<3>() = m.R0.transpose() * c.n;
        J.tail<3>() = m.Jr.transpose() * c.p.cross(m.R.transpose() * c.n) / mean_range;
        const double w = c.sqrt_w * c.sqrt_w;
        const double r = c.n.dot(m.R * c.p + m.t) - c.d;
        H += w * J * J.transpose();
        weight_sum += w;
        weighted_sq += w * r * r;
    }
    common::Vector6d scale;
    scale << 1, 1, 1, 1 / mean_range, 1 / mean_range, 1 / mean_range;  // delta = S delta'
    Eigen::SelfAdjointEigenSolver<common::Matrix6d> eig(H);
    const common::Vector6d lambda = eig.eigenvalues();
    const common::Matrix6d V = eig.eigenvectors();
    common::Vector6d scaled = delta.cwiseQuotient(scale);
    const double s2 = std::max(weighted_sq / std::max(1.0, weight_sum - 6), 0.005 * 0.005);
    const common::Vector6d prior_var = prior_sigma.cwiseQuotient(scale).cwiseAbs2();
    common::Matrix6d cov = common::Matrix6d::Zero();
    result_.min_eigen_ratio = weight_sum > 0 ? lambda(0) / weight_sum : 0;
    for (int k = 0; k < 6; ++k) {
        const common::Vector6d v = V.col(k);
        if (weight_sum > 0 && lambda(k) / weight_sum >= config_.degenerate_ratio) {
            cov += (s2 / lambda(k)) * v * v.transpose();
            continue;
        }
        ++result_.degenerate_directions;
        scaled -= v * v.dot(scaled);  // this direction keeps the initial guess
        cov += v.cwiseAbs2().dot(prior_var) * v * v.transpose();
    }
    delta = scaled.cwiseProduct(scale);
    result_.T_map_lidar = ApplyPerturbation(T0, delta);
    result_.covariance = scale.asDiagonal() * cov * scale.asDiagonal();
    result_.correspondences = n;
    result_.rms = weight_sum > 0 ? std::sqrt(weighted_sq / weight_sum) : 0;
    return result_;
}

}  // namespace bimslam::odometry
