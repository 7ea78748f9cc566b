// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/odometry/scan_registration.hpp"

#include <time.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <vector>

#include "algorithms/common/status.hpp"

namespace bimslam::odometry {
using common::Require;

void RegistrationConfig::Validate() const {
    const char* c = "RegistrationConfig";
    Require(max_iterations >= 1 && max_iterations <= 100, c, "max_iterations", max_iterations,
            "must be in [1, 100]");
    Require(max_correspondence_distance > 0 && max_correspondence_distance <= 10, c,
            "max_correspondence_distance", max_correspondence_distance, "must be in (0, 10] m");
    Require(cauchy_scale > 0 && cauchy_scale <= 10, c, "cauchy_scale", cauchy_scale,
            "must be in (0, 10] m");
    Require(cauchy_scale_initial >= cauchy_scale && cauchy_scale_initial <= 10, c,
            "cauchy_scale_initial", cauchy_scale_initial, "must be in [cauchy_scale, 10] m");
    Require(cauchy_anneal > 1 && cauchy_anneal <= 10, c, "cauchy_anneal", cauchy_anneal,
            "must be in (1, 10]");
    Require(evidence_scale > 0 && evidence_scale <= 10, c, "evidence_scale", evidence_scale,
            "must be in (0, 10] m");
    Require(min_correspondences >= 6, c, "min_correspondences", min_correspondences,
            "must be >= 6");
    Require(converged_translation > 0 && converged_rotation > 0, c, "converged_translation",
            converged_translation, "and converged_rotation must be > 0");
    Require(degenerate_ratio >= 0 && degenerate_ratio < 0.5, c, "degenerate_ratio",
            degenerate_ratio, "must be in [0, 0.5)");
    Require(inlier_distance > 0 && inlier_distance <= 10, c, "inlier_distance", inlier_distance,
            "must be in (0, 10] m");
}

Eigen::Isometry3d ApplyPerturbation(const Eigen::Isometry3d& T0, const common::Vector6d& delta) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = T0.linear() * common::ExpSO3(delta.tail<3>());
    T.translation() = T0.translation() + T0.linear() * delta.head<3>();
    return T;
}

namespace {
// The square root of the Cauchy IRLS weight 1 / (1 + r^2 / c^2), given 1 / c^2.
double CauchySqrtWeight(double r, double inv_c2) { return std::sqrt(1.0 / (1.0 + r * r * inv_c2)); }

// The pose and correction of one evaluation (header comment).
struct RowModel {
    Eigen::Matrix3d R0, R, Jr;
    Eigen::Vector3d t, rho_x, phi_x;
    RowModel(const Eigen::Isometry3d& T0, const common::Vector6d& delta,
             const common::Vector6d& xi) {
        R0 = T0.linear();
        R = R0 * common::ExpSO3(delta.tail<3>());
        t = T0.translation() + R0 * delta.head<3>();
        Jr = common::LeftJacobianSO3(-delta.tail<3>());
        rho_x = xi.head<3>();
        phi_x = xi.tail<3>();
    }
    // L = Exp(alpha phi_x) q + alpha rho_x, second order (CorrectPoint).
    Eigen::Vector3d Local(const Eigen::Vector3d& q, double alpha) const {
        const Eigen::Vector3d a = alpha * phi_x;
        const Eigen::Vector3d aq = a.cross(q);
        return q + aq + 0.5 * a.cross(aq) + alpha * rho_x;
    }
    // E^T v for E = Exp(alpha phi_x), second order.
    Eigen::Vector3d LocalRotationTransposed(const Eigen::Vector3d& v, double alpha) const {
        const Eigen::Vector3d a = -alpha * phi_x;
        const Eigen::Vector3d av = a.cross(v);
        return v + av + 0.5 * a.cross(av);
    }
};

// The guess's variance per direction in the scaled coordinates (rotations in metres of mean
// range, x = S x'): where the scan does not measure, this is what the pose keeps.
common::Vector6d ScaledPriorVariance(const common::Vector6d& prior_sigma,
                                     const common::Vector6d& scale) {
    return prior_sigma.cwiseQuotient(scale).cwiseAbs2();
}

// The weighted normal equations H += J^T W J, g += J^T W r of correspondences `corr` at the
// model m, over N parameters: 6 (delta alone) or 12 ([delta; xi], the header's Jacobians). The
// pose alone is what every default path solves; its 6 x 6 outer product is a quarter of the
// 12 x 12 one, whose other three blocks would be zero. (Corr: ScanRegistration's private
// Correspondence, deduced.)
template <int N, class Corr>
void AccumulateNormal(const RowModel& m, std::span<const Corr> corr, Eigen::Matrix<double, N, N>* H,
                      Eigen::Matrix<double, N, 1>* g) {
    static_assert(N == 6 || N == 12);
    const Eigen::Matrix3d R0t = m.R0.transpose(), Jrt = m.Jr.transpose(), Rt = m.R.transpose();
    Eigen::Matrix<double, N, 1> J;
    for (const Corr& c : corr) {
        const Eigen::Vector3d L = m.Local(c.p, c.alpha);
        const Eigen::Vector3d Rn = Rt * c.n;
        J.template segment<3>(0) = R0t * c.n;
        J.template segment<3>(3) = Jrt * L.cross(Rn);
        if constexpr (N == 12) {
            J.template segment<3>(6) = c.alpha * Rn;
            J.template segment<3>(9) = c.alpha * c.p.cross(m.LocalRotationTransposed(Rn, c.alpha));
        }
        const double w = c.sqrt_w * c.sqrt_w;
        const double r = c.n.dot(m.R * L + m.t) - c.d;
        // The whole outer product, fixed-size and vectorised: Eigen's rankUpdate on the lower
        // triangle goes through a general routine (7 % of a scan's profile with the IMU).
        const Eigen::Matrix<double, N, 1> wJ = w * J;
        H->noalias() += wJ * J.transpose();
        *g += r * wJ;
    }
}
}  // namespace

// The normal equations of the weighted residuals at (delta, xi) over [delta; xi] (the header's
// Jacobians): H = J^T W J and g = J^T W r, W the IRLS weights. Without the correction only
// delta's block is filled (xi's rows stay zero).
void ScanRegistration::NormalEquations(const Eigen::Isometry3d& T0, const common::Vector6d& delta,
                                       const common::Vector6d& xi, int n, bool correcting,
                                       Matrix12d* H, Vector12d* g) const {
    const RowModel m(T0, delta, xi);
    const std::span<const Correspondence> corr(corr_.data(), size_t(n));
    H->setZero();
    g->setZero();
    if (correcting) {
        AccumulateNormal<12>(m, corr, H, g);
        return;
    }
    common::Matrix6d H6 = common::Matrix6d::Zero();
    common::Vector6d g6 = common::Vector6d::Zero();
    AccumulateNormal<6>(m, corr, &H6, &g6);
    H->topLeftCorner<6, 6>() = H6;
    g->head<6>() = g6;
}

ScanRegistration::ScanRegistration(const RegistrationConfig& config, size_t max_points)
    : config_(config) {
    config_.Validate();
    corr_.resize(max_points);
    neighbour_key_.resize(max_points);
    neighbour_count_.resize(max_points);
    neighbour_planes_.resize(max_points * kMaxNeighbourPlanes);
}

ScanRegistration::~ScanRegistration() = default;

int ScanRegistration::Associate(const AlignInput& in, const VoxelMap& map,
                                const Eigen::Isometry3d& T, const common::Vector6d& xi,
                                double max_distance, double cauchy_scale) {
    const Eigen::Matrix3f R = T.linear().cast<float>();
    const Eigen::Vector3f t = T.translation().cast<float>();
    const Eigen::Vector3f rho = xi.head<3>().cast<float>(), phi = xi.tail<3>().cast<float>();
    const bool correct = !xi.isZero();
    const float max_d = static_cast<float>(max_distance);
    const double inv_c2 = 1.0 / (cauchy_scale * cauchy_scale);
    int n = 0;
    size_t k = 0;
    for (; k < in.points.size(); ++k) {
        if (size_t(n) >= corr_.size()) break;
        const Eigen::Vector3f& q = in.points[k];
        const float alpha = in.alpha.empty() ? 0.0f : in.alpha[k];
        const Eigen::Vector3f L = correct ? CorrectPoint(q, alpha, rho, phi) : q;
        // FindPlane(p, &r, &t), its neighbourhood looked up again only when p changed voxel.
        const Eigen::Vector3f p = R * L + t;
        float r = 0;
        const VoxelPlane* plane = nullptr;
        if (k < neighbour_key_.size()) {
            const Eigen::Vector3i key = map.KeyOf(p);
            VoxelPlane* planes = &neighbour_planes_[k * kMaxNeighbourPlanes];
            if (k >= neighbours_cached_ || neighbour_key_[k] != key) {
                uint8_t count = 0;
                map.ForNeighbourPlanes(key,
                                       [&](const VoxelPlane& found) { planes[count++] = found; });
                neighbour_key_[k] = key;
                neighbour_count_[k] = count;
            }
            NearestPlane nearest(p, &t);
            for (uint8_t j = 0; j < neighbour_count_[k]; ++j) nearest.Consider(planes[j]);
            plane = nearest.best();
            r = nearest.distance();
        } else {
            plane = map.FindPlane(p, &r, &t);  // beyond the points sized for
        }
        if (!plane || std::abs(r) > max_d) continue;
        Correspondence& c = corr_[size_t(n++)];
        c.p = q.cast<double>();
        c.n = plane->normal.cast<double>();
        c.d = plane->offset;
        c.alpha = alpha;
        c.distance = r;
        c.sqrt_w = CauchySqrtWeight(r, inv_c2);
        c.judged = !plane->line_like;
    }
    neighbours_cached_ = std::max(neighbours_cached_, std::min(k, neighbour_key_.size()));
    if (!in.edge_map) return n;
    for (const Eigen::Vector3f& p : in.edges) {
        if (size_t(n) + 2 > corr_.size()) break;
        float r = 0;
        const VoxelLine* line = in.edge_map->FindLine(R * p + t, &r);
        if (!line || r > max_d) continue;
        // The distance to a line with direction u through c is that to two planes through c,
        // with normals e1, e2 orthogonal to u and to each other.
        const Eigen::Vector3d u = line->direction.cast<double>();
        const Eigen::Vector3d e1 = u.unitOrthogonal(), e2 = u.cross(e1);
        const double sqrt_w = CauchySqrtWeight(r, inv_c2);
        for (const Eigen::Vector3d& e : {e1, e2}) {
            Correspondence& c = corr_[size_t(n++)];
            c.p = p.cast<double>();
            c.n = e;
            c.d = e.dot(line->point.cast<double>());
            c.sqrt_w = sqrt_w;
            c.distance = r;
            c.alpha = 0;
            c.judged = true;
        }
    }
    return n;
}

void ScanRegistration::Reweigh(int n, double cauchy_scale) {
    const double inv_c2 = 1.0 / (cauchy_scale * cauchy_scale);
    for (int i = 0; i < n; ++i) {
        Correspondence& c = corr_[size_t(i)];
        c.sqrt_w = CauchySqrtWeight(c.distance, inv_c2);
    }
}

// One Gauss-Newton step on the weighted problem (the weights fixed at this association, then
// found again: iteratively reweighted least squares, as KISS-ICP takes one step per association).
// The correction's prior r = k .* xi adds k^2 to its diagonal. The damping is that of the first
// Levenberg-Marquardt iteration the Ceres solve this replaces took (diag(H) / 1e4, Ceres'
// initial trust region radius): a no-op on a well-posed scan, a bound along a direction the scan
// does not see until the degeneracy test below handles it. Parameters held (the rotation under
// fix_rotation, the correction when not estimated) get an identity row: their step is zero.
void ScanRegistration::Step(const Eigen::Isometry3d& T0, int n, bool correcting, bool fix_rotation,
                            const common::Vector6d& prior_k, common::Vector6d* delta,
                            common::Vector6d* xi) const {
    Matrix12d H;
    Vector12d g;
    NormalEquations(T0, *delta, *xi, n, correcting, &H, &g);
    if (correcting) {
        H.diagonal().tail<6>() += prior_k.cwiseAbs2();
        g.tail<6>() += prior_k.cwiseAbs2().cwiseProduct(*xi);
    }
    for (int k = 0; k < 12; ++k) {
        const bool held = (k >= 6 && !correcting) || (k >= 3 && k < 6 && fix_rotation);
        if (held) {
            H.row(k).setZero();
            H.col(k).setZero();
            H(k, k) = 1;
            g(k) = 0;
            continue;
        }
        H(k, k) += std::clamp(H(k, k), 1e-6, 1e32) * 1e-4;
    }
    const Vector12d dx = H.ldlt().solve(-g);
    if (!dx.allFinite()) return;  // no correspondence moves the pose: keep it
    *delta += dx.head<6>();
    *xi += dx.tail<6>();
}

std::chrono::steady_clock::time_point BudgetNow(bool cpu_time) {
    if (!cpu_time) return std::chrono::steady_clock::now();
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return std::chrono::steady_clock::time_point(std::chrono::seconds(t.tv_sec) +
                                                 std::chrono::nanoseconds(t.tv_nsec));
}

const RegistrationResult& ScanRegistration::Align(std::span<const Eigen::Vector3f> points,
                                                  const VoxelMap& map, const Eigen::Isometry3d& T0,
                                                  const common::Vector6d& prior_sigma,
                                                  Clock::time_point deadline,
                                                  std::span<const Eigen::Vector3f> edges,
                                                  const VoxelMap* edge_map) {
    AlignInput in;
    in.points = points;
    in.T0 = T0;
    in.prior_sigma = prior_sigma;
    in.edges = edges;
    in.edge_map = edge_map;
    return Align(in, map, deadline);
}

void ScanRegistration::HoldAxis(const AlignInput& in, common::Vector6d* scaled,
                                common::Matrix6d* cov) {
    const Eigen::Vector3d& u = in.axis;
    if (!(u.squaredNorm() > 0.5) || result_.axis_share >= in.hold_axis_below) return;
    // Translation is unscaled (scale's head is 1). The guess's variance along u.
    scaled->head<3>() -= u * u.dot(scaled->head<3>());
    cov->topLeftCorner<3, 3>() +=
        u.cwiseAbs2().dot(in.prior_sigma.head<3>().cwiseAbs2()) * u * u.transpose();
    result_.axis_held = true;
    ++result_.degenerate_directions;
}

int ScanRegistration::Iterate(const AlignInput& in, const VoxelMap& map, Clock::time_point deadline,
                              const Solve& solve, common::Vector6d* delta, common::Vector6d* xi,
                              double* last_kernel) {
    const Eigen::Isometry3d& T0 = in.T0;
    int n = 0;
    if (map.version() != neighbours_version_) {  // another map, or this one changed
        neighbours_cached_ = 0;
        neighbours_version_ = map.version();
    }
    // A wide threshold (a poor prediction) starts the kernel wider too; predictions that have
    // been good (the IMU's) start it narrower, which saves outer iterations.
    double kernel = std::max(config_.cauchy_scale_initial, solve.max_distance / 6);
    if (in.prediction_error > 0) {
        kernel = std::max(config_.cauchy_scale, std::min(kernel, in.prediction_error));
    }
    for (int it = 0; it < config_.max_iterations;
         ++it, kernel = std::max(config_.cauchy_scale, kernel / config_.cauchy_anneal)) {
        if (BudgetNow(config_.cpu_time_budget) >= deadline) {
            result_.over_budget = true;
            break;
        }
        const Eigen::Isometry3d T = ApplyPerturbation(T0, *delta);
        const int found = Associate(in, map, T, *xi, solve.max_distance, kernel);
        *last_kernel = kernel;
        if (found < config_.min_correspondences) {
            if (it == 0) {
                result_.failed = true;
                result_.correspondences = found;
                return -1;
            }
            break;  // keep the last solution, whose correspondences were enough
        }
        n = found;
        const common::Vector6d xi_before = *xi;
        Step(T0, n, solve.correcting, in.fix_rotation, solve.prior_k, delta, xi);
        ++result_.iterations;
        const Eigen::Isometry3d step = common::Between(T, ApplyPerturbation(T0, *delta));
        // The correction's step, as the displacement it makes at the end of the sweep 10 m out.
        const common::Vector6d dxi = *xi - xi_before;
        const double xi_step = dxi.head<3>().norm() + 10.0 * dxi.tail<3>().norm();
        if (kernel <= config_.cauchy_scale &&
            step.translation().norm() < config_.converged_translation &&
            common::RotationAngle(step) < config_.converged_rotation &&
            xi_step < 10.0 * config_.converged_translation) {
            result_.converged = true;
            break;
        }
    }
    return n;
}

ScanRegistration::Residuals ScanRegistration::Measure(const AlignInput& in,
                                                      const common::Vector6d& delta,
                                                      const common::Vector6d& xi, int n) const {
    const RowModel m(in.T0, delta, xi);
    Residuals out;
    for (int i = 0; i < n; ++i) out.mean_range += corr_[size_t(i)].p.norm();
    out.mean_range = n > 0 ? std::max(1.0, out.mean_range / n) : 1.0;
    const Eigen::Matrix3d R0t = m.R0.transpose();
    for (int i = 0; i < n; ++i) {
        const Correspondence& c = corr_[size_t(i)];
        const double w = c.sqrt_w * c.sqrt_w;
        const double r = c.n.dot(m.R * m.Local(c.p, c.alpha) + m.t) - c.d;
        // The axis's evidence: a surface facing it (its normal within 60 deg), hit by the ray at
        // more than grazing incidence (cos > 0.1). A voxel holding one or two rings' points at a
        // corner fits a "plane" across the walls, and the rays run along it: in a 2.4 m shaft
        // such voxels at the map's upper and lower edge put 1-2 % of the weights on the height.
        const Eigen::Vector3d n0 = R0t * c.n;   // the normal in T0's lidar frame
        const double facing = in.axis.dot(n0);  // cos of the normal to the axis
        if (std::abs(facing) >= 0.5 && std::abs(n0.dot(c.p)) > 0.1 * c.p.norm()) {
            out.axis_sum += w * facing * facing;
        }
        out.weight_sum += w;
        out.weighted_sq += w * r * r;
        if (!c.judged) {
            ++out.unjudged;
            continue;
        }
        out.inliers += std::abs(r) <= config_.inlier_distance ? 1 : 0;
    }
    return out;
}

ScanRegistration::Information ScanRegistration::InformationAt(const Eigen::Isometry3d& T0,
                                                              const common::Vector6d& delta,
                                                              const common::Vector6d& xi, int n,
                                                              const Solve& solve,
                                                              double mean_range) const {
    Matrix12d H;
    Vector12d g;
    NormalEquations(T0, delta, xi, n, solve.correcting, &H, &g);
    Vector12d scale12 = Vector12d::Ones();  // J' = J S: rotations per metre of mean range
    scale12.segment<3>(3).setConstant(1 / mean_range);
    scale12.segment<3>(9).setConstant(1 / mean_range);
    H = scale12.asDiagonal() * H * scale12.asDiagonal();
    Information info;
    info.scale << 1, 1, 1, 1 / mean_range, 1 / mean_range, 1 / mean_range;  // x = S x'
    // The correction's block: its prior (in scaled units), or pinned when not estimated.
    common::Matrix6d Hxx = H.block<6, 6>(6, 6);
    info.Hdx = H.block<6, 6>(0, 6);
    if (solve.correcting) {
        Hxx += solve.prior_k.cwiseProduct(info.scale).cwiseAbs2().asDiagonal();
    } else {
        Hxx = common::Matrix6d::Identity();
    }
    info.Hxx_ldlt.compute(Hxx);
    // The information about delta with the correction marginalised out (Schur complement).
    info.S = solve.correcting
                 ? common::Matrix6d(H.block<6, 6>(0, 0) -
                                    info.Hdx * info.Hxx_ldlt.solve(info.Hdx.transpose()))
                 : common::Matrix6d(H.block<6, 6>(0, 0));
    return info;
}

common::Matrix6d ScanRegistration::KeepMeasured(const AlignInput& in, const Information& info,
                                                const Residuals& res, common::Vector6d* scaled) {
    Eigen::SelfAdjointEigenSolver<common::Matrix6d> eig(info.S);
    const common::Vector6d lambda = eig.eigenvalues();
    const common::Matrix6d V = eig.eigenvectors();
    const double s2 = std::max(res.weighted_sq / std::max(1.0, res.weight_sum - 6), 0.005 * 0.005);
    const common::Vector6d prior_var = ScaledPriorVariance(in.prior_sigma, info.scale);
    common::Matrix6d cov = common::Matrix6d::Zero();
    result_.min_eigen_ratio = res.weight_sum > 0 ? lambda(0) / res.weight_sum : 0;
    result_.axis_share = res.weight_sum > 0 ? res.axis_sum / res.weight_sum : 0;
    for (int k = 0; k < 6; ++k) {
        const common::Vector6d v = V.col(k);
        if (res.weight_sum > 0 && lambda(k) / res.weight_sum >= config_.degenerate_ratio) {
            cov += (s2 / lambda(k)) * v * v.transpose();
            continue;
        }
        // A weak direction. Mostly translation (a corridor's axis, a tunnel): the scan's
        // information along it comes from noise and discretisation, so it keeps the initial
        // guess (Zhang et al.). Mostly rotation: indoors every rotation is seen by some surface
        // at range, so the scan's estimate (variance s2 / lambda) and the guess's (variance
        // v^T P v, P the prior's diagonal) are fused by their information; the guess wins only
        // where it knows more. Keeping a constant-velocity guess outright there put the Go1
        // trot's wobble into the pose (README.md, "LiDAR only").
        const double prior_var_v = std::max(v.cwiseAbs2().dot(prior_var), 1e-12);
        if (v.head<3>().squaredNorm() >= 0.5) {
            ++result_.degenerate_directions;
            *scaled -= v * v.dot(*scaled);  // this direction keeps the initial guess
            cov += prior_var_v * v * v.transpose();
            continue;
        }
        const double data_info = std::max(lambda(k), 0.0) / s2;
        const double prior_info = 1.0 / prior_var_v;
        const double keep = data_info / (data_info + prior_info);  // the scan's share
        if (keep < 0.5) ++result_.degenerate_directions;
        *scaled -= (1.0 - keep) * v * v.dot(*scaled);
        cov += 1.0 / (data_info + prior_info) * v * v.transpose();
    }
    HoldAxis(in, scaled, &cov);
    return cov;
}

const RegistrationResult& ScanRegistration::Align(const AlignInput& in, const VoxelMap& map,
                                                  Clock::time_point deadline) {
    const Eigen::Isometry3d& T0 = in.T0;
    result_ = RegistrationResult{};
    result_.T_map_lidar = T0;
    result_.points = static_cast<int>(in.points.size());
    Solve solve;
    solve.correcting =
        config_.motion_correction && (in.correction_sigma.array() > 0).all() && !in.alpha.empty();
    solve.max_distance = in.max_correspondence_distance > 0 ? in.max_correspondence_distance
                                                            : config_.max_correspondence_distance;
    // The prior weighs like a correspondence at the final Cauchy scale per sigma of correction.
    if (solve.correcting) solve.prior_k = in.correction_sigma.cwiseInverse() * config_.cauchy_scale;

    // 1. Gauss-Newton from T0.
    common::Vector6d delta = common::Vector6d::Zero(), xi = common::Vector6d::Zero();
    double last_kernel = 0;
    const int n = Iterate(in, map, deadline, solve, &delta, &xi, &last_kernel);
    if (n < 0) return result_;

    // 2. The normal equations at the solution, with rotation scaled to metres (header comment):
    // H over [delta, xi], the correction's prior added to its block; the directions the scan did
    // not measure keep the guess. Weighed at the evidence's scale (RegistrationConfig).
    Reweigh(n, std::max(config_.evidence_scale, last_kernel));
    const Residuals res = Measure(in, delta, xi, n);
    const Information info = InformationAt(T0, delta, xi, n, solve, res.mean_range);
    const common::Vector6d scaled_before = delta.cwiseQuotient(info.scale);
    common::Vector6d scaled = scaled_before;
    common::Matrix6d cov = KeepMeasured(in, info, res, &scaled);
    if (solve.correcting && result_.degenerate_directions > 0) {
        // The correction's optimum given the delta kept: xi' += -Hxx^-1 Hxd (delta' - delta).
        const common::Vector6d scaled_xi =
            xi.cwiseQuotient(info.scale) -
            info.Hxx_ldlt.solve(info.Hdx.transpose() * (scaled - scaled_before));
        xi = scaled_xi.cwiseProduct(info.scale);
    }
    delta = scaled.cwiseProduct(info.scale);
    if (in.fix_rotation) {
        // A weak direction mixing rotation in must not bring it back; its variance is T0's.
        delta.tail<3>().setZero();
        cov.block<3, 3>(3, 0).setZero();
        cov.block<3, 3>(0, 3).setZero();
        cov.block<3, 3>(3, 3) =
            ScaledPriorVariance(in.prior_sigma, info.scale).tail<3>().asDiagonal();
    }
    result_.T_map_lidar = ApplyPerturbation(T0, delta);
    result_.correction = xi;
    result_.covariance = info.scale.asDiagonal() * cov * info.scale.asDiagonal();
    result_.correspondences = n;
    result_.inliers = res.inliers;
    result_.unjudged = res.unjudged;
    result_.rms = res.weight_sum > 0 ? std::sqrt(res.weighted_sq / res.weight_sum) : 0;
    return result_;
}

}  // namespace bimslam::odometry
