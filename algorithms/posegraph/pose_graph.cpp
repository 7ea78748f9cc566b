// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/posegraph/pose_graph.hpp"

#include <ceres/ceres.h>

#include <Eigen/Eigenvalues>
#include <chrono>
#include <cmath>
#include <memory>

#include "algorithms/common/status.hpp"
#include "algorithms/posegraph/relative_pose_cost.hpp"
#include "algorithms/posegraph/solver_options.hpp"

namespace bimslam::posegraph {
using common::Matrix6d;
using common::Require;
using common::Vector6d;

void PoseGraphConfig::Validate() const {
    const char* c = "PoseGraphConfig";
    Require(loop_loss_scale > 0, c, "loop_loss_scale", loop_loss_scale, "must be positive");
    Require(!annealing.empty() && annealing.back() == 1.0, c, "annealing",
            annealing.empty() ? 0.0 : annealing.back(), "must end with 1");
    Require(odometry_loss_scale >= 0, c, "odometry_loss_scale", odometry_loss_scale,
            "must not be negative (0: no robust loss)");
    Require(max_iterations >= 1, c, "max_iterations", max_iterations, "must be at least 1");
    Require(threads >= 1, c, "threads", threads, "must be at least 1");
}

namespace {

// Between keyframes of two sessions, each placed by its anchor (eq. 2 of the paper).
struct AnchoredCost {
    Eigen::Quaterniond qz;
    Eigen::Vector3d tz;
    Matrix6d S;
    template <typename T>
    bool operator()(const T* qda, const T* tda, const T* qa, const T* ta, const T* qdb,
                    const T* tdb, const T* qb, const T* tb, T* r) const {
        const Quat<T> Qda(qda), Qdb(qdb);
        const Quat<T> QA = Qda * Quat<T>(qa);
        const Vec3<T> TA = Qda * Vec3<T>(ta) + Vec3<T>(tda);
        const Quat<T> QB = Qdb * Quat<T>(qb);
        const Vec3<T> TB = Qdb * Vec3<T>(tb) + Vec3<T>(tdb);
        Relative(qz, tz, QA, TA, QB, TB, r);
        Whiten(S, r);
        return true;
    }
};

// A keyframe's world pose Delta x against where a prior puts it: [t; 2 vec(q)] of
// z^-1 Delta x (Relative from the identity), a right perturbation of the world pose.
struct PriorCost {
    Eigen::Quaterniond qz;
    Eigen::Vector3d tz;
    Matrix6d S;
    template <typename T>
    bool operator()(const T* qd, const T* td, const T* qx, const T* tx, T* r) const {
        const Quat<T> Qd(qd);
        const Quat<T> Q = Qd * Quat<T>(qx);
        const Vec3<T> t = Qd * Vec3<T>(tx) + Vec3<T>(td);
        Relative(qz, tz, Quat<T>::Identity(), Vec3<T>(Vec3<T>::Zero()), Q, t, r);
        Whiten(S, r);
        return true;
    }
};

using Block = PoseBlock;

}  // namespace

Matrix6d SqrtInformation(const Matrix6d& information) {
    const Eigen::SelfAdjointEigenSolver<Matrix6d> eig(0.5 *
                                                      (information + information.transpose()));
    const Vector6d root = eig.eigenvalues().cwiseMax(0.0).cwiseSqrt();
    return root.asDiagonal() * eig.eigenvectors().transpose();
}

Vector6d RelativePoseResidual(const Eigen::Isometry3d& z, const Eigen::Isometry3d& T_a,
                              const Eigen::Isometry3d& T_b) {
    Vector6d r;
    const Eigen::Quaterniond qa = common::Rotation(T_a), qb = common::Rotation(T_b);
    const Eigen::Vector3d ta = T_a.translation(), tb = T_b.translation();
    Relative(common::Rotation(z), Eigen::Vector3d(z.translation()), qa, ta, qb, tb, r.data());
    return r;
}

size_t PoseGraph::AddSession(std::vector<Eigen::Isometry3d> poses, const Eigen::Isometry3d& anchor,
                             bool fixed) {
    sessions_.push_back({std::move(poses), anchor, fixed});
    return sessions_.size() - 1;
}

void PoseGraph::AddOdometry(const OdometryFactor& f) {
    if (f.session >= sessions_.size() || f.from >= keyframes(f.session) ||
        f.to >= keyframes(f.session) || f.from == f.to) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            "PoseGraph: odometry factor joins missing keyframes");
    }
    odometry_.push_back(f);
}

size_t PoseGraph::AddLoop(const LoopFactor& f) {
    if (f.session_a >= sessions_.size() || f.session_b >= sessions_.size() ||
        f.index_a >= keyframes(f.session_a) || f.index_b >= keyframes(f.session_b) ||
        (f.session_a == f.session_b && f.index_a == f.index_b)) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            "PoseGraph: loop factor joins missing keyframes");
    }
    loops_.push_back(f);
    return loops_.size() - 1;
}

void PoseGraph::AddPrior(const PriorFactor& f) {
    if (f.session >= sessions_.size() || f.index >= keyframes(f.session)) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            "PoseGraph: prior factor on a missing keyframe");
    }
    priors_.push_back(f);
}

void PoseGraph::SetAnchor(size_t s, const Eigen::Isometry3d& T) { sessions_.at(s).anchor = T; }

void PoseGraph::SetPoses(size_t s, std::vector<Eigen::Isometry3d> poses) {
    if (poses.size() != keyframes(s)) {
        throw common::Error(common::StatusCode::kInvalidArgument, "PoseGraph: wrong pose count");
    }
    sessions_.at(s).poses = std::move(poses);
}

Vector6d PoseGraph::LoopResidual(size_t i) const {
    const LoopFactor& f = loops_.at(i);
    return SqrtInformation(f.information) * RelativePoseResidual(f.T_a_b,
                                                                 WorldPose(f.session_a, f.index_a),
                                                                 WorldPose(f.session_b, f.index_b));
}

OptimizeSummary PoseGraph::Optimize(const PoseGraphConfig& config,
                                    const std::vector<double>& loop_weights) {
    config.Validate();
    if (!loop_weights.empty() && loop_weights.size() != loops_.size()) {
        throw common::Error(common::StatusCode::kInvalidArgument, "PoseGraph: one weight per loop");
    }
    const auto start = std::chrono::steady_clock::now();
    std::vector<Block> anchors(sessions_.size());
    std::vector<std::vector<Block>> poses(sessions_.size());
    for (size_t s = 0; s < sessions_.size(); ++s) {
        anchors[s].Set(sessions_[s].anchor);
        poses[s].resize(sessions_[s].poses.size());
        for (size_t k = 0; k < poses[s].size(); ++k) poses[s][k].Set(sessions_[s].poses[k]);
    }
    ceres::Problem problem;
    // Every robust loss is wrapped so that its scale can be annealed between solves.
    std::vector<std::pair<ceres::LossFunctionWrapper*, double>> losses;
    auto robust = [&](double scale) -> ceres::LossFunction* {
        if (!(scale > 0)) return nullptr;
        auto* w =
            new ceres::LossFunctionWrapper(new ceres::CauchyLoss(scale), ceres::TAKE_OWNERSHIP);
        losses.push_back({w, scale});
        return w;
    };
    for (const OdometryFactor& f : odometry_) {
        Block& a = poses[f.session][f.from];
        Block& b = poses[f.session][f.to];
        auto* cost = new ceres::AutoDiffCostFunction<BetweenCost, 6, 4, 3, 4, 3>(
            new BetweenCost{common::Rotation(f.T_from_to), f.T_from_to.translation(),
                            SqrtInformation(f.information)});
        problem.AddResidualBlock(cost, robust(config.odometry_loss_scale), a.q, a.t, b.q, b.t);
    }
    for (size_t i = 0; i < loops_.size(); ++i) {
        const double w = loop_weights.empty() ? 1.0 : loop_weights[i];
        if (!(w > 0)) continue;
        const LoopFactor& f = loops_[i];
        const Matrix6d S = std::sqrt(w) * SqrtInformation(f.information);
        const Eigen::Quaterniond qz = common::Rotation(f.T_a_b);
        const Eigen::Vector3d tz = f.T_a_b.translation();
        ceres::LossFunction* loss = config.robust_loops ? robust(config.loop_loss_scale) : nullptr;
        Block& a = poses[f.session_a][f.index_a];
        Block& b = poses[f.session_b][f.index_b];
        if (f.session_a == f.session_b) {
            auto* cost = new ceres::AutoDiffCostFunction<BetweenCost, 6, 4, 3, 4, 3>(
                new BetweenCost{qz, tz, S});
            problem.AddResidualBlock(cost, loss, a.q, a.t, b.q, b.t);
        } else {
            Block& da = anchors[f.session_a];
            Block& db = anchors[f.session_b];
            auto* cost = new ceres::AutoDiffCostFunction<AnchoredCost, 6, 4, 3, 4, 3, 4, 3, 4, 3>(
                new AnchoredCost{qz, tz, S});
            problem.AddResidualBlock(cost, loss, da.q, da.t, a.q, a.t, db.q, db.t, b.q, b.t);
        }
    }
    for (const PriorFactor& f : priors_) {
        Block& d = anchors[f.session];
        Block& x = poses[f.session][f.index];
        auto* cost = new ceres::AutoDiffCostFunction<PriorCost, 6, 4, 3, 4, 3>(
            new PriorCost{common::Rotation(f.T_world_lidar), f.T_world_lidar.translation(),
                          SqrtInformation(f.information)});
        problem.AddResidualBlock(cost, nullptr, d.q, d.t, x.q, x.t);
    }
    // Blocks enter the problem with their residuals; a block in none (an anchor without loops)
    // stays out and keeps its value. Then the manifolds, the fixed sessions and the gauge.
    auto prepare = [&](Block& b, bool constant) {
        if (!problem.HasParameterBlock(b.q)) return;
        problem.SetManifold(b.q, new ceres::EigenQuaternionManifold);
        if (constant) {
            problem.SetParameterBlockConstant(b.q);
            problem.SetParameterBlockConstant(b.t);
        }
    };
    for (size_t s = 0; s < sessions_.size(); ++s) {
        const bool fixed = sessions_[s].fixed;
        prepare(anchors[s], fixed);
        for (size_t k = 0; k < poses[s].size(); ++k) prepare(poses[s][k], fixed || k == 0);
    }
    OptimizeSummary out;
    if (problem.NumResidualBlocks() == 0) {
        out.converged = true;
        return out;
    }
    const ceres::Solver::Options options =
        posegraph::SparseSolverOptions(config.max_iterations, config.threads);
    ceres::Solver::Summary summary;
    for (size_t stage = 0; stage < config.annealing.size(); ++stage) {
        for (auto& [wrapper, scale] : losses) {
            wrapper->Reset(new ceres::CauchyLoss(scale * config.annealing[stage]),
                           ceres::TAKE_OWNERSHIP);
        }
        ceres::Solver::Summary s;
        ceres::Solve(options, &problem, &s);
        if (stage == 0) summary = s;
        summary.termination_type = s.termination_type;
        summary.final_cost = s.final_cost;
        summary.message = s.message;
        out.iterations += static_cast<int>(s.iterations.size());
    }

    for (size_t s = 0; s < sessions_.size(); ++s) {
        if (sessions_[s].fixed) continue;
        sessions_[s].anchor = anchors[s].Get();
        for (size_t k = 0; k < poses[s].size(); ++k) sessions_[s].poses[k] = poses[s][k].Get();
    }
    out.converged = summary.termination_type == ceres::CONVERGENCE;
    out.initial_cost = summary.initial_cost;
    out.final_cost = summary.final_cost;
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!out.converged) out.message = summary.message;
    return out;
}

}  // namespace bimslam::posegraph
