// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/changes/pose_refinement.hpp"

#include <ceres/ceres.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <string>

#include "algorithms/common/status.hpp"
#include "algorithms/posegraph/pose_graph.hpp"
#include "algorithms/posegraph/relative_pose_cost.hpp"
#include "algorithms/posegraph/solver_options.hpp"
#include "algorithms/simulation/scene.hpp"

namespace bimslam::changes {
namespace {
using posegraph::PoseBlock;
using posegraph::Quat;
using posegraph::Vec3;

// (b): a keyframe point against its element's plane, the plane moved by the element's offset.
struct PointPlaneCost {
    Eigen::Vector3d p;  // lidar frame
    Eigen::Vector3d n;  // the triangle's unit normal, model frame
    Eigen::Vector3d c;  // the triangle's nearest point, model frame
    double inv_sigma;
    template <typename T>
    bool operator()(const T* q, const T* t, const T* offset, T* r) const {
        const Vec3<T> w = Quat<T>(q) * p.cast<T>() + Vec3<T>(t);
        r[0] = inv_sigma * n.cast<T>().dot(w - c.cast<T>() - Vec3<T>(offset));
        return true;
    }
};

// (c): the element's offset against zero, or against its surveyed offset (the datum).
struct OffsetPriorCost {
    Eigen::Vector3d prior;
    double inv_sigma;
    template <typename T>
    bool operator()(const T* offset, T* r) const {
        for (int i = 0; i < 3; ++i) r[i] = inv_sigma * (offset[i] - T(prior[i]));
        return true;
    }
};

struct Correspondence {
    Eigen::Vector3d p, n, c;
    uint32_t keyframe, element;
};

// The points of each keyframe used: in range, every stride-th so that at most `count` remain.
std::vector<std::vector<Eigen::Vector3d>> Subsample(std::span<const MapKeyframe> keyframes,
                                                    const PoseRefinementConfig& config) {
    std::vector<std::vector<Eigen::Vector3d>> out(keyframes.size());
    const double lo2 = config.min_range_m * config.min_range_m;
    const double hi2 = config.max_range_m * config.max_range_m;
    for (size_t k = 0; k < keyframes.size(); ++k) {
        if (keyframes[k].cloud == nullptr) continue;
        std::vector<Eigen::Vector3d> in_range;
        for (const Eigen::Vector3f& p : keyframes[k].cloud->xyz) {
            const double r2 = p.cast<double>().squaredNorm();
            if (std::isfinite(r2) && r2 >= lo2 && r2 <= hi2) in_range.push_back(p.cast<double>());
        }
        const size_t stride = std::max<size_t>(
            1, (in_range.size() + config.points_per_keyframe - 1) / config.points_per_keyframe);
        for (size_t i = stride / 2; i < in_range.size(); i += stride) {
            out[k].push_back(in_range[i]);
        }
    }
    return out;
}

}  // namespace

void PoseRefinementConfig::Validate() const {
    const char* c = "PoseRefinementConfig";
    using common::Require;
    Require(element_sigma_m > 0, c, "element_sigma_m", element_sigma_m, "must be positive");
    Require(point_sigma_m > 0, c, "point_sigma_m", point_sigma_m, "must be positive");
    Require(point_loss_sigmas > 0, c, "point_loss_sigmas", point_loss_sigmas, "must be positive");
    Require(edge_loss_sigmas >= 0, c, "edge_loss_sigmas", edge_loss_sigmas,
            "must not be negative (0: no robust loss)");
    Require(edge_information_scale > 0, c, "edge_information_scale", edge_information_scale,
            "must be positive");
    Require(min_explained_fraction >= 0 && min_explained_fraction <= 1, c, "min_explained_fraction",
            min_explained_fraction, "must be in [0, 1]");
    Require(points_per_keyframe >= 1, c, "points_per_keyframe", double(points_per_keyframe),
            "must be at least 1");
    Require(min_range_m >= 0 && max_range_m > min_range_m, c, "max_range_m", max_range_m,
            "must be above min_range_m >= 0");
    Require(!gates_m.empty(), c, "gates_m", 0.0, "needs at least one gate");
    for (const double g : gates_m) Require(g > 0, c, "gates_m", g, "every gate must be positive");
    Require(!edge_loss_annealing.empty() && edge_loss_annealing.back() == 1.0, c,
            "edge_loss_annealing", edge_loss_annealing.empty() ? 0.0 : edge_loss_annealing.back(),
            "must end with 1");
    Require(max_iterations >= 1, c, "max_iterations", max_iterations, "must be at least 1");
    Require(threads >= 1, c, "threads", threads, "must be at least 1");
    Require(datum_sigma_m > 0, c, "datum_sigma_m", datum_sigma_m, "must be positive");
    for (const SurveyedElement& d : datum) {
        Require(d.offset.allFinite() && d.offset.norm() < 1.0, c, "datum offset", d.offset.norm(),
                "must be finite and under 1 m (a survey of an element built off, not moved)");
    }
}

namespace {

void CheckEdges(std::span<const KeyframeEdge> edges, size_t n) {
    for (const KeyframeEdge& e : edges) {
        if (e.from >= n || e.to >= n || e.from == e.to) {
            throw common::Error(common::StatusCode::kInvalidArgument,
                                "pose refinement: the edge " + std::to_string(e.from) + " -> " +
                                    std::to_string(e.to) + " joins keyframes that do not exist (" +
                                    std::to_string(n) + " keyframes)");
        }
    }
}

// The refinement held in one object (as Ceres' pose_graph_3d holds its problem): the poses and
// the elements' offsets it moves, their priors, the correspondences of the current round.
class Refinement {
public:
    Refinement(const ChangeModel& model, std::span<const MapKeyframe> keyframes,
               std::span<const KeyframeEdge> edges, const PoseRefinementConfig& config)
        : model_(model),
          keyframes_(keyframes),
          edges_(edges),
          config_(config),
          n_(keyframes.size()),
          poses_(n_),
          found_(n_),
          registered_(n_, 0),
          has_edge_(n_, 0) {
        SetPriors();
        offsets_ = prior_;
        for (size_t k = 0; k < n_; ++k) poses_[k].Set(keyframes[k].T_world_lidar);
        for (const KeyframeEdge& e : edges) has_edge_[e.from] = has_edge_[e.to] = 1;
        out_.edges = edges.size();
        points_ = Subsample(keyframes, config);
    }

    // One round per gate; false when nothing was left to solve.
    bool Round(size_t round, const simulation::Scene& scene) {
        const double gate = config_.gates_m[round];
        const double annealing =
            config_.edge_loss_annealing[std::min(round, config_.edge_loss_annealing.size() - 1)];
        Associate(scene, gate);
        if (round == 0) DecideRegistered();
        ceres::Problem problem;
        // One loss for every point's block: the problem owns it (and deletes it once) as soon as
        // a block uses it; until then the unique_ptr does.
        auto point_loss = std::make_unique<ceres::CauchyLoss>(config_.point_loss_sigmas);
        std::vector<uint8_t> in_problem(n_, 0);
        const std::vector<uint32_t> per_element = AddPoints(problem, point_loss.get(), in_problem);
        if (out_.correspondences > 0) (void)point_loss.release();  // now the problem's
        AddEdges(problem, annealing, in_problem);
        AddOffsetPriors(problem, per_element);
        for (size_t k = 0; k < n_; ++k) {
            if (in_problem[k]) problem.SetManifold(poses_[k].q, new ceres::EigenQuaternionManifold);
        }
        out_.element_points = per_element;
        if (problem.NumResidualBlocks() == 0) return false;
        const ceres::Solver::Options options =
            posegraph::SparseSolverOptions(config_.max_iterations, config_.threads);
        ceres::Solver::Summary summary;
        ceres::Solve(options, &problem, &summary);
        out_.iterations += int(summary.iterations.size());
        return true;
    }

    // The poses, their corrections and the offsets found.
    PoseRefinement Result() {
        out_.T_world_lidar.resize(n_);
        out_.correction_m.resize(n_);
        out_.correction_deg.resize(n_);
        for (size_t k = 0; k < n_; ++k) {
            const Eigen::Isometry3d& before = keyframes_[k].T_world_lidar;
            out_.T_world_lidar[k] = poses_[k].Get();
            out_.correction_m[k] =
                (out_.T_world_lidar[k].translation() - before.translation()).norm();
            out_.correction_deg[k] =
                Eigen::AngleAxisd(before.rotation().transpose() * out_.T_world_lidar[k].rotation())
                    .angle() *
                180.0 / M_PI;
            out_.moved_1cm += out_.correction_m[k] > 0.01;
            out_.mean_correction_m += out_.correction_m[k] / double(n_);
            out_.max_correction_m = std::max(out_.max_correction_m, out_.correction_m[k]);
            out_.max_correction_deg = std::max(out_.max_correction_deg, out_.correction_deg[k]);
        }
        for (const SurveyedElement& d : config_.datum) {
            out_.datum_seen += out_.element_points[d.element] > 0;
        }
        out_.element_offset = std::move(offsets_);
        return std::move(out_);
    }

private:
    // Per element: its prior's mean and 1 / sigma (the datum's where surveyed).
    void SetPriors() {
        prior_.assign(model_.element_count(), Eigen::Vector3d::Zero());
        prior_inv_sigma_.assign(model_.element_count(), 1.0 / config_.element_sigma_m);
        for (const SurveyedElement& d : config_.datum) {
            if (d.element >= model_.element_count()) {
                throw common::Error(common::StatusCode::kInvalidArgument,
                                    "pose refinement: the surveyed element " +
                                        std::to_string(d.element) + " does not exist (" +
                                        std::to_string(model_.element_count()) + " elements)");
            }
            prior_[d.element] = d.offset;
            prior_inv_sigma_[d.element] = 1.0 / config_.datum_sigma_m;
        }
    }

    // Correspondences at the current poses, against the model as designed (the offsets are
    // centimetres; the nearest triangle does not change with them).
    void Associate(const simulation::Scene& scene, double gate) {
        tbb::parallel_for(size_t(0), n_, [&](size_t k) {
            found_[k].clear();
            const Eigen::Isometry3d T = poses_[k].Get();
            const Eigen::Vector3f sensor = T.translation().cast<float>();
            for (const Eigen::Vector3d& p : points_[k]) {
                // Only surfaces facing the sensor: the far face of a wall 10-15 cm thick is
                // nearer than its near face to a point seen from a pose 8 cm off (scene.hpp).
                const auto c = scene.ClosestFacing((T * p).cast<float>(), sensor, float(gate));
                if (!c) continue;
                found_[k].push_back({p, c->normal.cast<double>(), c->point.cast<double>(),
                                     uint32_t(k), model_.triangle_element[c->triangle]});
            }
        });
    }

    // Decided once, at the anchored poses: a keyframe whose points the model does not explain (a
    // scan the odometry garbled, a view of things not in the model) would otherwise slide into
    // whatever its few near points fit (seen: 42 cm, Go1 seed 7).
    void DecideRegistered() {
        for (size_t k = 0; k < n_; ++k) {
            registered_[k] = found_[k].size() >= config_.min_points &&
                             double(found_[k].size()) >=
                                 config_.min_explained_fraction * double(points_[k].size());
            out_.unexplained += !registered_[k];
            out_.held += !registered_[k] && !has_edge_[k];
        }
    }

    // (b) for the registered keyframes' correspondences; the points per element.
    std::vector<uint32_t> AddPoints(ceres::Problem& problem, ceres::LossFunction* loss,
                                    std::vector<uint8_t>& in_problem) {
        std::vector<uint32_t> per_element(model_.element_count(), 0);
        out_.correspondences = 0;
        for (size_t k = 0; k < n_; ++k) {
            if (!registered_[k]) continue;
            for (const Correspondence& c : found_[k]) {
                auto* cost = new ceres::AutoDiffCostFunction<PointPlaneCost, 1, 4, 3, 3>(
                    new PointPlaneCost{c.p, c.n, c.c, 1.0 / config_.point_sigma_m});
                problem.AddResidualBlock(cost, loss, poses_[k].q, poses_[k].t,
                                         offsets_[c.element].data());
                ++per_element[c.element];
            }
            out_.correspondences += found_[k].size();
            in_problem[k] = 1;
        }
        return per_element;
    }

    // (a) the odometry's edges, their robust loss annealed over the rounds.
    void AddEdges(ceres::Problem& problem, double annealing, std::vector<uint8_t>& in_problem) {
        for (const KeyframeEdge& e : edges_) {
            auto* cost = new ceres::AutoDiffCostFunction<posegraph::BetweenCost, 6, 4, 3, 4, 3>(
                new posegraph::BetweenCost{
                    common::Rotation(e.T_from_to), e.T_from_to.translation(),
                    posegraph::SqrtInformation(config_.edge_information_scale * e.information)});
            ceres::LossFunction* loss =
                config_.edge_loss_sigmas > 0
                    ? new ceres::CauchyLoss(annealing * config_.edge_loss_sigmas)
                    : nullptr;
            problem.AddResidualBlock(cost, loss, poses_[e.from].q, poses_[e.from].t, poses_[e.to].q,
                                     poses_[e.to].t);
            in_problem[e.from] = in_problem[e.to] = 1;
        }
    }

    // (c) for every element a point landed on.
    void AddOffsetPriors(ceres::Problem& problem, const std::vector<uint32_t>& per_element) {
        for (size_t e = 0; e < offsets_.size(); ++e) {
            if (per_element[e] == 0) continue;
            problem.AddResidualBlock(new ceres::AutoDiffCostFunction<OffsetPriorCost, 3, 3>(
                                         new OffsetPriorCost{prior_[e], prior_inv_sigma_[e]}),
                                     nullptr, offsets_[e].data());
        }
    }

    const ChangeModel& model_;
    std::span<const MapKeyframe> keyframes_;
    std::span<const KeyframeEdge> edges_;
    const PoseRefinementConfig& config_;
    size_t n_;
    std::vector<PoseBlock> poses_;
    std::vector<Eigen::Vector3d> prior_, offsets_;
    std::vector<double> prior_inv_sigma_;
    std::vector<std::vector<Eigen::Vector3d>> points_;
    std::vector<std::vector<Correspondence>> found_;
    std::vector<uint8_t> registered_;  // its points are factors (decided in the first round)
    std::vector<uint8_t> has_edge_;
    PoseRefinement out_;
};

}  // namespace

PoseRefinement RefinePoses(const ChangeModel& model, std::span<const MapKeyframe> keyframes,
                           std::span<const KeyframeEdge> edges,
                           const PoseRefinementConfig& config) {
    const auto start = std::chrono::steady_clock::now();
    config.Validate();
    CheckEdges(edges, keyframes.size());
    Refinement refinement(model, keyframes, edges, config);
    const simulation::Scene scene(model.mesh);
    for (size_t round = 0; round < config.gates_m.size(); ++round) {
        if (!refinement.Round(round, scene)) break;
    }
    PoseRefinement out = refinement.Result();
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return out;
}

}  // namespace bimslam::changes
