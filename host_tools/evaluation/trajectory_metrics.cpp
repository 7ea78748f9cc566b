// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/evaluation/trajectory_metrics.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <sstream>
#include <tuple>

#include "algorithms/common/se3.hpp"
#include "algorithms/common/status.hpp"
#include "algorithms/io/session.hpp"

namespace bimslam::evaluation {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kRadToDeg = 180.0 / std::numbers::pi;

[[noreturn]] void Invalid(const std::string& message) {
    throw common::Error(common::StatusCode::kInvalidArgument, message);
}

std::string Number(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

// Path length from pose 0 to pose k along the reference, for every k.
std::vector<double> CumulativeDistance(const std::vector<Eigen::Isometry3d>& poses) {
    std::vector<double> out(poses.size(), 0.0);
    for (size_t k = 1; k < poses.size(); ++k) {
        out[k] = out[k - 1] + (poses[k].translation() - poses[k - 1].translation()).norm();
    }
    return out;
}

// For every start i, the first j > i whose path length from i is at least `length`; j only moves
// forward as i does, so this is linear. Starts without such a j (the tail) are left out.
template <typename Fn>
void ForEachSegment(const std::vector<double>& cum, double length, Fn&& fn) {
    size_t j = 0;
    for (size_t i = 0; i + 1 < cum.size(); ++i) {
        j = std::max(j, i + 1);
        while (j < cum.size() && cum[j] - cum[i] < length) ++j;
        if (j == cum.size()) return;
        fn(i, j);
    }
}

// E = (ref_i^-1 ref_j)^-1 (est_i^-1 est_j): the estimate's motion from i to j seen from the
// reference's (evo's RPE; its inverse is KITTI's pose_error, with the same translation norm).
Eigen::Isometry3d RelativeError(const std::vector<Eigen::Isometry3d>& est,
                                const std::vector<Eigen::Isometry3d>& ref, size_t i, size_t j) {
    return common::Inverse(common::Between(ref[i], ref[j])) * common::Between(est[i], est[j]);
}

}  // namespace

std::vector<MatchedPair> Associate(const std::vector<io::StampedPose>& est,
                                   const std::vector<io::StampedPose>& ref, int64_t max_dt_ns) {
    // Every pair within the window, then the closest first; each pose is used once.
    std::vector<std::tuple<int64_t, size_t, size_t>> candidates;  // |dt|, est, ref
    for (size_t i = 0; i < est.size(); ++i) {
        const int64_t t = est[i].stamp_ns;
        auto it = std::lower_bound(
            ref.begin(), ref.end(), t - max_dt_ns,
            [](const io::StampedPose& p, int64_t stamp) { return p.stamp_ns < stamp; });
        for (; it != ref.end() && it->stamp_ns - t <= max_dt_ns; ++it) {
            candidates.emplace_back(std::abs(it->stamp_ns - t), i, size_t(it - ref.begin()));
        }
    }
    std::sort(candidates.begin(), candidates.end());
    std::vector<bool> est_used(est.size(), false), ref_used(ref.size(), false);
    std::vector<size_t> est_ids, ref_ids;
    for (const auto& [dt, i, j] : candidates) {
        if (est_used[i] || ref_used[j]) continue;
        est_used[i] = ref_used[j] = true;
        est_ids.push_back(i);
        ref_ids.push_back(j);
    }
    // Greedy pairs can cross when the window exceeds half the sampling interval. Pairing the same
    // poses in time order uncrosses them without leaving the window (in 1-D the sorted matching
    // has the smallest largest difference), and keeps both paths running forwards for RPE/drift.
    std::sort(est_ids.begin(), est_ids.end());
    std::sort(ref_ids.begin(), ref_ids.end());
    std::vector<MatchedPair> out(est_ids.size());
    for (size_t k = 0; k < out.size(); ++k) out[k] = {est_ids[k], ref_ids[k]};
    return out;
}

RigidAlignment AlignUmeyama(const std::vector<Eigen::Vector3d>& est,
                            const std::vector<Eigen::Vector3d>& ref) {
    // S. Umeyama, "Least-squares estimation of transformation parameters between two point
    // patterns", IEEE TPAMI 13(4), 1991, eq. (38)-(42) with c = 1 (no scale), as evo's
    // geometry.umeyama_alignment.
    RigidAlignment out;
    if (est.empty() || est.size() != ref.size()) {
        Invalid("alignment needs as many estimated as reference positions, and some");
    }
    const double n = double(est.size());
    Eigen::Vector3d mu_est = Eigen::Vector3d::Zero(), mu_ref = Eigen::Vector3d::Zero();
    for (size_t k = 0; k < est.size(); ++k) {
        mu_est += est[k];
        mu_ref += ref[k];
    }
    mu_est /= n;
    mu_ref /= n;
    Eigen::Matrix3d sigma = Eigen::Matrix3d::Zero();  // eq. (38): covariance of ref and est
    for (size_t k = 0; k < est.size(); ++k) {
        sigma += (ref[k] - mu_ref) * (est[k] - mu_est).transpose();
    }
    sigma /= n;
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(sigma, Eigen::ComputeFullU | Eigen::ComputeFullV);
    // eq. (39)/(43): flip the last axis when U V^T would be a reflection.
    Eigen::Vector3d s = Eigen::Vector3d::Ones();
    if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0.0) s(2) = -1.0;
    const Eigen::Matrix3d R = svd.matrixU() * s.asDiagonal() * svd.matrixV().transpose();
    out.T_ref_est.linear() = R;
    out.T_ref_est.translation() = mu_ref - R * mu_est;  // eq. (41)
    // Rank below 2 (one point or one line) leaves a rotation free: Umeyama's rank condition.
    const Eigen::Vector3d d = svd.singularValues();
    out.degenerate = !(d(1) > 1e-9 * d(0));
    return out;
}

std::string_view ToString(Alignment a) { return a == Alignment::kSe3 ? "se3" : "none"; }

ErrorStats ComputeStats(std::vector<double> values) {
    ErrorStats s;
    s.count = values.size();
    if (values.empty()) {
        s.rmse = s.mean = s.median = s.std = s.min = s.max = kNaN;
        return s;
    }
    std::sort(values.begin(), values.end());
    const double n = double(values.size());
    double sum = 0.0, sum_sq = 0.0;
    for (double v : values) {
        sum += v;
        sum_sq += v * v;
    }
    s.mean = sum / n;
    s.rmse = std::sqrt(sum_sq / n);
    double var = 0.0;
    for (double v : values) var += (v - s.mean) * (v - s.mean);
    s.std = std::sqrt(var / n);  // numpy's default (ddof 0), as evo
    const size_t m = values.size() / 2;
    s.median = values.size() % 2 == 1 ? values[m] : 0.5 * (values[m - 1] + values[m]);
    s.min = values.front();
    s.max = values.back();
    return s;
}

void EvaluationConfig::Validate() const {
    // A day is far beyond any sensible window and keeps stamp +- window clear of overflow.
    if (max_dt_ns < 0 || max_dt_ns > 86'400'000'000'000) {
        Invalid("max_dt: " + Number(1e-6 * double(max_dt_ns)) + " ms is not within 0 to a day");
    }
    if (!(std::isfinite(rpe_delta_m) && rpe_delta_m > 0.0)) {
        Invalid("rpe_delta_m: " + Number(rpe_delta_m) + " is not a positive distance");
    }
    if (!(std::isfinite(drift_segment_m) && drift_segment_m > 0.0)) {
        Invalid("drift_segment_m: " + Number(drift_segment_m) + " is not a positive distance");
    }
}

EvaluationResult Evaluate(const std::vector<io::StampedPose>& est,
                          const std::vector<io::StampedPose>& ref, const EvaluationConfig& config,
                          const std::string& est_name, const std::string& ref_name) {
    config.Validate();
    const std::vector<MatchedPair> pairs = Associate(est, ref, config.max_dt_ns);
    if (pairs.size() < 3) {
        std::string msg = est_name + " (" + std::to_string(est.size()) + " poses) and " + ref_name +
                          " (" + std::to_string(ref.size()) +
                          " poses): " + std::to_string(pairs.size()) + " poses match within " +
                          Number(1e-6 * double(config.max_dt_ns)) + " ms; at least 3 are needed";
        // The usual cause is two clocks (sensor vs host, or a time offset): show both spans.
        if (!est.empty() && !ref.empty()) {
            const auto span = [](const std::vector<io::StampedPose>& p) {
                return Number(1e-9 * double(p.front().stamp_ns)) + " to " +
                       Number(1e-9 * double(p.back().stamp_ns)) + " s";
            };
            msg += " (estimate " + span(est) + ", reference " + span(ref) + ")";
        }
        Invalid(msg);
    }

    EvaluationResult r;
    r.est_poses = est.size();
    r.ref_poses = ref.size();
    r.matched = pairs.size();
    r.align = config.align;
    std::vector<Eigen::Isometry3d> E(pairs.size()), G(pairs.size());  // estimate, ground truth
    std::vector<Eigen::Vector3d> e_pos(pairs.size()), g_pos(pairs.size());
    for (size_t k = 0; k < pairs.size(); ++k) {
        E[k] = est[pairs[k].est].Pose();
        G[k] = ref[pairs[k].ref].Pose();
        e_pos[k] = E[k].translation();
        g_pos[k] = G[k].translation();
    }
    if (config.align == Alignment::kSe3) {
        r.alignment = AlignUmeyama(e_pos, g_pos);
        for (auto& T : E) T = r.alignment.T_ref_est * T;
    }

    // APE (evo_ape -r trans_part / -r angle_deg): per pose, in the reference frame.
    std::vector<double> ape_t(pairs.size()), ape_r(pairs.size());
    for (size_t k = 0; k < pairs.size(); ++k) {
        ape_t[k] = (G[k].translation() - E[k].translation()).norm();
        ape_r[k] = kRadToDeg * common::RotationAngle(common::Between(G[k], E[k]));
    }
    r.ape_trans_m = ComputeStats(std::move(ape_t));
    r.ape_rot_deg = ComputeStats(std::move(ape_r));

    const std::vector<double> cum = CumulativeDistance(G);
    r.distance_m = cum.back();
    r.duration_s = 1e-9 * double(ref[pairs.back().ref].stamp_ns - ref[pairs.front().ref].stamp_ns);

    // RPE over delta metres of reference path (evo_rpe --delta_unit m), from every start.
    r.rpe_delta_m = config.rpe_delta_m;
    std::vector<double> rpe_t, rpe_r;
    ForEachSegment(cum, config.rpe_delta_m, [&](size_t i, size_t j) {
        const Eigen::Isometry3d err = RelativeError(E, G, i, j);
        rpe_t.push_back(err.translation().norm());
        rpe_r.push_back(kRadToDeg * common::RotationAngle(err));
    });
    r.rpe_trans_m = ComputeStats(std::move(rpe_t));
    r.rpe_rot_deg = ComputeStats(std::move(rpe_r));

    // Drift (KITTI, Geiger et al. 2012, one segment length): the relative translation error
    // over a segment as a percentage of the path actually travelled over it (KITTI divides by the
    // nominal length; the actual one does not penalise sparse poses that overshoot it).
    r.drift_segment_m = config.drift_segment_m;
    if (r.distance_m < config.drift_segment_m) {
        r.drift_segment_m = r.distance_m;
        r.drift_segment_shortened = true;
    }
    double drift_sum = 0.0;
    if (r.drift_segment_m > 0.0) {
        ForEachSegment(cum, r.drift_segment_m, [&](size_t i, size_t j) {
            drift_sum += 100.0 * RelativeError(E, G, i, j).translation().norm() / (cum[j] - cum[i]);
            ++r.drift_segments;
        });
    }
    r.drift_percent = r.drift_segments > 0 ? drift_sum / double(r.drift_segments) : kNaN;
    return r;
}

std::vector<io::StampedPose> ReadTrajectory(const std::filesystem::path& poses,
                                            const std::filesystem::path& times,
                                            const std::string& times_option) {
    if (times.empty()) {
        try {
            return io::ReadTum(poses);
        } catch (const common::FileError& e) {
            // A KITTI file read as TUM fails on its first line with 12 numbers: say what it is.
            std::vector<Eigen::Isometry3d> kitti;
            try {
                kitti = io::ReadKitti(poses);
            } catch (const common::FileError&) {
                throw e;
            }
            throw common::FileError(common::StatusCode::kInvalidArgument, poses.string(), 0,
                                    "holds KITTI poses (12 numbers a line, " +
                                        std::to_string(kitti.size()) +
                                        " poses) and KITTI poses carry no time: give " +
                                        times_option + " (one time in seconds a line)");
        }
    }
    const std::vector<Eigen::Isometry3d> kitti = io::ReadKitti(poses);
    const std::vector<int64_t> stamps = io::ReadTimes(times);
    if (stamps.size() != kitti.size()) {
        throw common::FileError(common::StatusCode::kParseError, times.string(), 0,
                                std::to_string(stamps.size()) + " times for the " +
                                    std::to_string(kitti.size()) + " poses of " + poses.string() +
                                    ": expected one time a pose");
    }
    std::vector<io::StampedPose> out;
    out.reserve(kitti.size());
    for (size_t i = 0; i < kitti.size(); ++i) {
        if (i > 0 && stamps[i] < stamps[i - 1]) {
            throw common::FileError(common::StatusCode::kParseError, times.string(), i + 1,
                                    "times must not decrease");
        }
        out.push_back(io::StampedPose::FromIsometry(stamps[i], kitti[i]));
    }
    return out;
}

EvaluationResult EvaluateFiles(const std::filesystem::path& est_path,
                               const std::filesystem::path& ref_path,
                               const EvaluationConfig& config,
                               const std::filesystem::path& est_times,
                               const std::filesystem::path& ref_times) {
    const std::vector<io::StampedPose> est = ReadTrajectory(est_path, est_times, "--est-times");
    const std::vector<io::StampedPose> ref = ReadTrajectory(ref_path, ref_times, "--ref-times");
    return Evaluate(est, ref, config, est_path.string(), ref_path.string());
}

}  // namespace bimslam::evaluation
