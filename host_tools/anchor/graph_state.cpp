// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/anchor/graph_state.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace bimslam::anchor {
namespace {
using Clock = std::chrono::steady_clock;
}  // namespace
using posegraph::PoseGraph;

std::vector<Eigen::Isometry3d> State::World() const {
    std::vector<Eigen::Isometry3d> w;
    for (const auto& x : poses) w.push_back(anchor * x);
    return w;
}

PoseGraph BuildGraph(const std::vector<AnchorSession>& sessions, const std::vector<State>& state,
                     const std::vector<LoopRecord>& loops, const AnchorConfig& config) {
    PoseGraph g;
    for (size_t s = 0; s < sessions.size(); ++s) {
        g.AddSession(state[s].poses, state[s].anchor, state[s].fixed);
        if (state[s].fixed) continue;
        if (state[s].held) {
            const double rad = config.earlier_sigma_deg * M_PI / 180;
            common::Matrix6d info = common::Matrix6d::Zero();
            info.diagonal() << 1 / std::pow(config.earlier_sigma_m, 2),
                1 / std::pow(config.earlier_sigma_m, 2), 1 / std::pow(config.earlier_sigma_m, 2),
                1 / (rad * rad), 1 / (rad * rad), 1 / (rad * rad);
            for (size_t k = 0; k < sessions[s].poses.size(); ++k)
                g.AddPrior({s, k, sessions[s].poses[k], info});
        }
        for (const io::SessionEdge& e : sessions[s].session.edges) {
            g.AddOdometry(
                {s, e.from, e.to, e.T_from_to, config.odometry_information_scale * e.information});
        }
    }
    for (const LoopRecord& l : loops) {
        const auto information =
            l.target_session == 0
                ? WithModelTolerance(l.registration.information, config.model_tolerance_m,
                                     config.model_tolerance_deg)
                : l.registration.information;
        g.AddLoop({l.target_session, l.target_index, l.query_session, l.query_index,
                   l.T_target_query, information});
    }
    return g;
}

Eigen::Matrix<double, 6, 6> WithModelTolerance(const Eigen::Matrix<double, 6, 6>& information,
                                               double sigma_m, double sigma_deg) {
    using Matrix6d = Eigen::Matrix<double, 6, 6>;
    const double sigma_rad = sigma_deg * M_PI / 180.0;
    Eigen::Matrix<double, 6, 1> variance;
    variance << sigma_m * sigma_m, sigma_m * sigma_m, sigma_m * sigma_m, sigma_rad * sigma_rad,
        sigma_rad * sigma_rad, sigma_rad * sigma_rad;
    const Matrix6d lhs = Matrix6d::Identity() + information * variance.asDiagonal();
    const Matrix6d out = lhs.partialPivLu().solve(information);
    return 0.5 * (out + out.transpose());  // symmetric up to rounding
}

double OptimizeStates(const std::vector<AnchorSession>& sessions, std::vector<State>* state,
                      const std::vector<LoopRecord>& loops, const AnchorConfig& config,
                      StageTimes* times, const std::vector<double>& weights,
                      const posegraph::PoseGraphConfig* graph_config, PoseGraph* out) {
    const auto t0 = Clock::now();
    PoseGraph g = BuildGraph(sessions, *state, loops, config);
    g.Optimize(graph_config ? *graph_config : config.graph, weights);
    double moved = 0;
    for (size_t s = 0; s < sessions.size(); ++s) {
        State& st = (*state)[s];
        if (st.fixed) continue;
        for (size_t k = 0; k < st.poses.size(); ++k) {
            moved = std::max(
                moved,
                (g.WorldPose(s, k).translation() - (st.anchor * st.poses[k]).translation()).norm());
        }
        st.anchor = g.anchor(s);
        for (size_t k = 0; k < st.poses.size(); ++k) st.poses[k] = g.pose(s, k);
    }
    times->optimisation_s += std::chrono::duration<double>(Clock::now() - t0).count();
    if (out) *out = std::move(g);
    return moved;
}

double GncTlsWeight(double r2, double c2, double mu) {
    if (r2 >= (mu + 1) / mu * c2) return 0;
    if (r2 <= mu / (mu + 1) * c2) return 1;
    return std::sqrt(c2 * mu * (mu + 1) / r2) - mu;
}

double GncInitialMu(double max_r2, double c2) { return c2 / (2 * max_r2 - c2); }

std::vector<double> GncWeights(const std::vector<AnchorSession>& sessions,
                               std::vector<State>* state, const std::vector<LoopRecord>& loops,
                               const AnchorConfig& config, StageTimes* times) {
    posegraph::PoseGraphConfig plain = config.graph;
    plain.robust_loops = false;
    std::vector<double> w(loops.size(), 1.0);
    const double c2 = config.max_loop_chi2;
    PoseGraph g;
    OptimizeStates(sessions, state, loops, config, times, w, &plain, &g);
    double max_r2 = 0;
    for (size_t k = 0; k < loops.size(); ++k) max_r2 = std::max(max_r2, g.LoopChi2(k));
    if (max_r2 <= c2) return w;
    double mu = GncInitialMu(max_r2, c2);
    for (int it = 0; it < 100 && mu < 1e4; ++it) {
        bool binary = true;
        for (size_t k = 0; k < loops.size(); ++k) {
            w[k] = GncTlsWeight(g.LoopChi2(k), c2, mu);
            if (w[k] != 0 && w[k] != 1) binary = false;
        }
        OptimizeStates(sessions, state, loops, config, times, w, &plain, &g);
        if (binary && it > 0) break;
        mu *= 1.4;
    }
    return w;
}

std::vector<SessionResult::OdometryBreak> OdometryBreaks(
    const std::vector<io::SessionEdge>& edges, const std::vector<Eigen::Isometry3d>& poses,
    double max_m, double max_deg, const std::vector<bool>& height_unsure) {
    std::vector<SessionResult::OdometryBreak> breaks;
    for (size_t i = 0; i < edges.size(); ++i) {
        const io::SessionEdge& e = edges[i];
        const Eigen::Isometry3d d = e.T_from_to.inverse() * (poses[e.from].inverse() * poses[e.to]);
        double m = d.translation().norm();
        if (i < height_unsure.size() && height_unsure[i]) {
            // d's translation is in the frame of `to` as the odometry measured it from `from`.
            const Eigen::Matrix3d R_local = poses[e.from].linear() * e.T_from_to.linear();
            m = (R_local * d.translation()).head<2>().norm();
        }
        const double deg = common::RotationAngle(d) * 180 / M_PI;
        if (m > max_m || deg > max_deg) breaks.push_back({e.from, e.to, m, deg});
    }
    return breaks;
}

std::vector<SessionResult::OdometryBreak> OdometryBreaks(
    const AnchorSession& s, const std::vector<Eigen::Isometry3d>& poses,
    const AnchorConfig& config) {
    return OdometryBreaks(s.session.edges, poses, config.odometry_break_m,
                          config.odometry_break_deg,
                          HeightUnsureEdges(s.session.edges, s.session.keyframes, s.odometry));
}

}  // namespace bimslam::anchor
