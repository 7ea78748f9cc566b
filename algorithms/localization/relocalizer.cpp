// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/localization/relocalizer.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <string>

#include "algorithms/common/se3.hpp"
#include "algorithms/common/status.hpp"
#include "algorithms/posegraph/max_clique.hpp"
#include "algorithms/registration/removed_surfaces.hpp"
#include "algorithms/scancontext/config.hpp"

namespace bimslam::localization {
namespace {

constexpr int kMaxHypotheses = 3;  // as offline: the best and at most two rivals
// Cliques searched per keyframe, those seen through the model included; these hold no
// hypothesis's place. A person walking in from outside gathers larger wrong cliques (on the
// storey above or off the building, 20-56 % of rays through the model) than the one right loop,
// which took no place among three, guided no registration, and the rig searched for 40 s inside
// (the office, hand-held, seeds 1 and 2; now 16 and 13 s). At most 15 cliques were found in a
// keyframe over the localisation benchmark's walks: the bound keeps the search's time bounded,
// not the result.
constexpr int kMaxCliques = 32;

double Median(std::vector<double> v) {
    if (v.empty()) return 0;
    std::nth_element(v.begin(), v.begin() + long(v.size() / 2), v.end());
    return v[v.size() / 2];
}

}  // namespace

Eigen::Isometry3d FuseWithPrediction(const Eigen::Isometry3d& predicted,
                                     const registration::RegistrationResult& r, double sigma_m,
                                     double sigma_up, double sigma_deg) {
    const common::Vector6d nu = common::LogSE3(predicted.inverse() * r.T_target_source);
    const Eigen::Matrix3d R = predicted.linear();  // the model's axes to the lidar's
    const Eigen::Vector3d var(sigma_m * sigma_m, sigma_m * sigma_m, sigma_up * sigma_up);
    common::Matrix6d P_inv = common::Matrix6d::Zero();
    P_inv.topLeftCorner<3, 3>() = R.transpose() * var.cwiseInverse().asDiagonal() * R;
    const double sigma_rad = sigma_deg * M_PI / 180;
    P_inv.bottomRightCorner<3, 3>() = Eigen::Matrix3d::Identity() / (sigma_rad * sigma_rad);
    const common::Vector6d delta = (P_inv + r.information).ldlt().solve(r.information * nu);
    return predicted * common::ExpSE3(delta);
}

bool MeasuredAlong(const registration::RegistrationResult& r, const Eigen::Isometry3d& predicted,
                   const Eigen::Vector3d& along, double sigma_m, double sigma_up) {
    if (along.isZero()) return true;
    const Eigen::Vector3d a = predicted.linear().transpose() * along;  // the lidar's axes
    const double measured = a.dot(r.information.topLeftCorner<3, 3>() * a);
    const double known = along.head<2>().squaredNorm() / (sigma_m * sigma_m) +
                         along.z() * along.z() / (sigma_up * sigma_up);
    return measured >= known;
}

io::StampedPose LivePose(const Eigen::Isometry3d& T_bim_odom, const io::StampedPose& odom) {
    return io::StampedPose::FromIsometry(odom.stamp_ns, T_bim_odom * odom.Pose());
}

common::Matrix6d LiveCovariance(const common::Matrix6d& fix_information,
                                const Eigen::Isometry3d& T_lidar_fix_base, double odometry_m,
                                const RelocalizerConfig& config) {
    // The inverse on the information's eigenvectors: a zero eigenvalue (a degenerate direction,
    // registration.hpp) is no knowledge, not certainty.
    const Eigen::SelfAdjointEigenSolver<common::Matrix6d> eig(
        0.5 * (fix_information + fix_information.transpose()));
    const double largest = std::max(eig.eigenvalues().maxCoeff(), 0.0);
    common::Vector6d variance;
    for (int i = 0; i < 6; ++i) {
        const double l = eig.eigenvalues()[i];
        variance[i] = l > 1e-12 * largest && l > 0 ? std::min(1 / l, kUnconstrainedVariance)
                                                   : kUnconstrainedVariance;
    }
    const common::Matrix6d at_fix =
        eig.eigenvectors() * variance.asDiagonal() * eig.eigenvectors().transpose();
    const common::Matrix6d Ad = common::Adjoint(T_lidar_fix_base.inverse());
    common::Matrix6d body = Ad * at_fix * Ad.transpose();
    const double d = std::max(odometry_m, 0.0);
    const double drift_t = config.drift_per_m * d,
                 drift_r = config.drift_deg_per_m * M_PI / 180 * d;
    body.diagonal().head<3>().array() += drift_t * drift_t;
    body.diagonal().tail<3>().array() += drift_r * drift_r;
    return body;
}

std::string_view ToString(RelocalizerState state) {
    switch (state) {
        case RelocalizerState::kSearching:
            return "searching";
        case RelocalizerState::kCandidate:
            return "candidate";
        case RelocalizerState::kLocalised:
            return "localised";
        case RelocalizerState::kAmbiguous:
            return "ambiguous";
        case RelocalizerState::kLost:
            return "lost";
    }
    return "?";
}

Relocalizer::Relocalizer(const RigMap& map, const RelocalizerConfig& config)
    : map_(map),
      config_(config),
      pyramid_(map.Pyramid()),
      index_(map.DescriptorConfig()),
      rng_(config.seed) {
    Check(map, config_);
    for (const scancontext::Descriptor& d : map.descriptors) {
        const common::Status s = index_.Add(d);
        if (!s.ok()) throw common::Error(common::StatusCode::kInvalidArgument, s.message());
    }
    index_.Build();
    std::vector<Eigen::Vector3d> walked;
    for (const Eigen::Isometry3d& k : map.keyframes) walked.push_back(k.translation());
    walked_ = WalkedSpace(walked, config_.floating_radius_m, config_.floating_height_m);
}

void Relocalizer::Check(const RigMap& map, const RelocalizerConfig& config) {
    config.ValidateLoopRules("RelocalizerConfig");
    if (config.start) config.start->Validate();
    map.DescriptorConfig().Validate();
    if (map.keyframes.empty()) {
        throw common::Error(common::StatusCode::kInvalidArgument, "Relocalizer: no keyframes");
    }
    if (map.levels.size() != config.registration.levels.size()) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            "Relocalizer: the package has " + std::to_string(map.levels.size()) +
                                " surfel levels, the registration " +
                                std::to_string(config.registration.levels.size()));
    }
}

const RelocalizerStep& Relocalizer::AddKeyframe(const common::PointCloud& cloud,
                                                const scancontext::Descriptor& descriptor,
                                                const Eigen::Isometry3d& T_odom_lidar,
                                                double path_m, bool height_ambiguous) {
    const RelocalizerStep last = std::move(step_);
    step_ = RelocalizerStep{};
    step_.state = last.state;
    step_.T_bim_odom = last.T_bim_odom;
    step_.fix_information = last.fix_information;
    step_.T_odom_lidar_fix = last.T_odom_lidar_fix;
    const RelocalizerState was = last.state;
    if (keyframes_ == 0) {
        start_odom_ = T_odom_lidar.translation();
        start_path_m_ = path_m;
    }
    step_.keyframe = keyframes_++;
    window_odom_.push_back(T_odom_lidar.translation());
    if (window_odom_.size() > config_.window_keyframes) window_odom_.pop_front();
    const registration::OrientedCloud oc = registration::MakeOrientedCloud(cloud, config_.cloud);
    height_ambiguous_ = height_ambiguous_ || height_ambiguous;
    if (was == RelocalizerState::kLocalised) {
        Track(oc, T_odom_lidar);
    } else {
        Search(oc, descriptor, T_odom_lidar, path_m);
    }
    if (step_.state == RelocalizerState::kLocalised) {
        step_.T_bim_lidar = step_.T_bim_odom * T_odom_lidar;
        step_.storey = StoreyAt(map_.storeys, step_.T_bim_lidar.translation().z());
    }
    return step_;
}

bool Relocalizer::Verified(const registration::RegistrationResult& r, bool full_rank) const {
    return !r.failed && r.fitness.inlier_ratio >= config_.min_inlier_ratio &&
           r.fitness.inlier_rmse <= config_.max_inlier_rmse &&
           (!full_rank || r.degenerate_directions == 0);
}

// Place recognition for this keyframe, then the hypotheses over the window's loops.
void Relocalizer::Search(const registration::OrientedCloud& cloud, const scancontext::Descriptor& d,
                         const Eigen::Isometry3d& T_odom_lidar, double path_m) {
    const auto match = index_.Query(d, config_.ring_key_candidates);
    if (match) {
        std::vector<scancontext::Candidate> c = match->candidates;
        std::sort(c.begin(), c.end(), [](const auto& a, const auto& b) {
            return a.scan_context.distance < b.scan_context.distance;
        });
        for (const scancontext::Candidate& cand : c) {
            if (int(step_.registrations) >= config_.sc_candidates) break;
            if (cand.scan_context.distance > config_.max_sc_distance) break;
            const Eigen::Isometry3d init =
                map_.keyframes[cand.index] * common::YawPose(cand.scan_context.yaw);
            const registration::RegistrationResult r =
                registration::Register(cloud, pyramid_, init, config_.registration);
            ++step_.registrations;
            if (Verified(r, true)) AddLoop(cloud, r, T_odom_lidar, path_m);
        }
    }
    if (config_.inject_false_loops > 0 &&
        std::uniform_real_distribution<double>(0, 1)(rng_) < config_.inject_false_loops) {
        const size_t t = std::uniform_int_distribution<size_t>(0, map_.keyframes.size() - 1)(rng_);
        const double yaw = std::uniform_real_distribution<double>(-M_PI, M_PI)(rng_);
        const registration::RegistrationResult r = registration::Register(
            cloud, pyramid_, map_.keyframes[t] * common::YawPose(yaw), config_.registration);
        ++step_.registrations;
        if (!r.failed) {  // accepted whatever its fitness: the worst case
            AddLoop(cloud, r, T_odom_lidar, path_m);
            ++step_.injected;
        }
    }
    // Each standing hypothesis guides a registration from where it puts this keyframe (from the
    // middle level, 0.5 m reach: a clique's anchor may be decimetres off, where offline's
    // proximity rounds start from the graph's estimate at the finest), so that a hypothesis
    // gathers loops where Scan Context finds no candidate (a flight of stairs, a room the
    // reference saw from elsewhere). Full rank and the tracking bounds, as a loop must be to
    // count.
    for (const Eigen::Isometry3d& T_bim_odom : guides_) {
        const Eigen::Isometry3d predicted = T_bim_odom * T_odom_lidar;
        const registration::RegistrationResult r =
            registration::Register(cloud, pyramid_, predicted, config_.registration, 1);
        ++step_.registrations;
        if (Verified(r, true) && Near(predicted, r.T_target_source, config_.track_max_m,
                                      config_.track_max_m, config_.track_max_deg)) {
            AddLoop(cloud, r, T_odom_lidar, path_m);
        }
    }
    // The window: only the loops of the last window_keyframes keyframes.
    std::erase_if(
        loops_, [&](const Loop& l) { return l.keyframe + config_.window_keyframes < keyframes_; });
    Decide(Cliques());
}

// A loop at the registered pose, with the share of the keyframe's rays that pass through the
// model's surfaces there (free-space evidence, judged per clique in Decide).
void Relocalizer::AddLoop(const registration::OrientedCloud& cloud,
                          const registration::RegistrationResult& r,
                          const Eigen::Isometry3d& T_odom_lidar, double path_m) {
    registration::FreeSpaceResult free_space = registration::CheckFreeSpace(
        cloud, pyramid_.level(config_.free_space_level), r.T_target_source, config_.free_space);
    const double seen = free_space.ratio();
    loops_.push_back({step_.keyframe, r.T_target_source, T_odom_lidar, path_m, seen,
                      std::move(free_space), r.information});
}

// The offline test (host_tools/anchor/place_recognition.cpp, Consistent): b's keyframe placed
// through a's T_bim_odom and the odometry lies where b's registration put it.
bool Relocalizer::Consistent(const Loop& a, const Loop& b) const {
    const Eigen::Isometry3d E = (a.T_bim_odom() * b.T_odom_lidar).inverse() * b.T_bim_lidar;
    return config_.Agree(E, std::abs(a.path_m - b.path_m));
}

// The largest clique of mutually consistent loops, then the largest among the loops that disagree
// with those found (offline's ConsistentHypotheses), each with its median seen-through share,
// until kMaxHypotheses of them are not seen through the model (or kMaxCliques in all).
std::vector<Relocalizer::Clique> Relocalizer::Cliques() const {
    const size_t n = loops_.size();
    posegraph::Graph g(n);
    for (size_t a = 0; a < n; ++a) {
        for (size_t b = a + 1; b < n; ++b) {
            if (Consistent(loops_[a], loops_[b]) && Consistent(loops_[b], loops_[a])) {
                g.Connect(a, b);
            }
        }
    }
    std::vector<Clique> out;
    std::vector<char> used(n, 0);
    int standing = 0;
    while (standing < kMaxHypotheses && int(out.size()) < kMaxCliques) {
        std::vector<size_t> allowed;
        for (size_t v = 0; v < n; ++v) {
            if (!used[v]) allowed.push_back(v);
        }
        if (allowed.empty()) break;
        const posegraph::CliqueResult c = posegraph::MaximumClique(g, allowed);
        if (c.vertices.empty()) break;
        for (size_t v = 0; v < n; ++v) {  // a loop agreeing with half of it is its own
            size_t agree = 0;
            for (size_t m : c.vertices) agree += (m == v || g.Connected(v, m));
            if (2 * agree >= c.vertices.size()) used[v] = 1;
        }
        Clique k;
        k.loops = c.vertices;
        std::vector<double> seen;
        std::vector<size_t> keyframes;
        std::vector<const registration::FreeSpaceResult*> views;
        for (size_t m : c.vertices) {
            seen.push_back(loops_[m].seen_through);
            keyframes.push_back(loops_[m].keyframe);
            views.push_back(&loops_[m].free_space);
        }
        std::sort(keyframes.begin(), keyframes.end());
        k.keyframes = size_t(std::unique(keyframes.begin(), keyframes.end()) - keyframes.begin());
        k.seen_through = Median(seen);
        // What a removed element explains is no contradiction (offline's rule, LoopRules).
        // With a start hint only (RelocalizerConfig::start; offline's RankHypotheses).
        k.unexplained =
            config_.start
                ? registration::MedianUnexplained(
                      views, registration::FindRemovedSurfaces(views, config_.removed_surfaces),
                      config_.removed_surfaces)
                : k.seen_through;
        standing += k.unexplained <= config_.max_seen_through;
        out.push_back(std::move(k));
    }
    return out;
}

const Relocalizer::Loop& Relocalizer::Newest(const Clique& c) const {
    return loops_[*std::max_element(c.loops.begin(), c.loops.end())];
}

bool Relocalizer::OnHint(const Clique& c) const {
    if (!config_.start) return true;
    const Loop& newest = Newest(c);
    const Eigen::Vector2d at = (newest.T_bim_odom() * start_odom_).head<2>();
    const double radius = config_.start->radius_m +
                          config_.drift_per_m * std::max(0.0, newest.path_m - start_path_m_);
    return (at - config_.start->xy).norm() <= radius;
}

void Relocalizer::Decide(const std::vector<Clique>& cliques) {
    step_.consistent_loops = cliques.empty() ? 0 : cliques.front().loops.size();
    std::vector<const Clique*> kept;  // not seen through the model
    std::vector<size_t> floating(cliques.size());
    const std::vector<Eigen::Vector3d> window(window_odom_.begin(), window_odom_.end());
    for (size_t i = 0; i < cliques.size(); ++i) {
        const Clique& c = cliques[i];
        if (c.unexplained > config_.max_seen_through || !OnHint(c)) continue;
        kept.push_back(&c);
        floating[i] = walked_.Floating(window, Newest(c).T_bim_odom());
    }
    const auto floats = [&](const Clique* c) { return floating[size_t(c - cliques.data())]; };
    // A clique whose keyframes see through the model decisively more often than another's is
    // outweighed, and one that stands only because removed elements explain what it sees
    // through by one that needs none (offline's rule, LoopRules::FreeSpacePrefers); and one that
    // puts a tenth of the window's keyframes a storey off the model's walks by one that does not
    // (LoopRules::HeightsPrefer, walked_space.hpp): a walk up the stairs placed a storey up.
    const auto outweighs = [&](const Clique* a, const Clique* b) {
        return config_.FreeSpacePrefers(a->seen_through, b->seen_through,
                                        b->unexplained < b->seen_through) ||
               config_.HeightsPrefer(floats(a), floats(b), window.size(),
                                     size_t(config_.min_clique));
    };
    std::vector<const Clique*> rivals;
    for (const Clique* c : kept) {
        bool out = false;
        for (const Clique* o : kept) out = out || (o != c && outweighs(o, c));
        if (!out) rivals.push_back(c);
    }
    std::sort(rivals.begin(), rivals.end(),
              [](const Clique* a, const Clique* b) { return a->keyframes > b->keyframes; });
    for (const Clique* c : rivals) step_.hypotheses.push_back(Newest(*c).T_bim_odom());
    guides_ = step_.hypotheses;
    const auto big = [&](const Clique* c) { return int(c->keyframes) >= config_.min_clique; };
    if (rivals.empty() || !big(rivals[0])) {
        if (step_.state != RelocalizerState::kLost || !rivals.empty()) {
            step_.state =
                rivals.empty() ? RelocalizerState::kSearching : RelocalizerState::kCandidate;
        }
        return;
    }
    // Live, a rival is any clique that disagrees, however small: offline sees the whole walk,
    // here the other place may have been seen less often so far (a mirror-symmetric building's
    // other half). While one has rival_min_ratio of the best's keyframes, nothing is decided:
    // ambiguous when it has min_clique keyframes too, else still a candidate.
    if (rivals.size() > 1 &&
        double(rivals[1]->keyframes) >= config_.rival_min_ratio * double(rivals[0]->keyframes)) {
        step_.state = big(rivals[1]) ? RelocalizerState::kAmbiguous : RelocalizerState::kCandidate;
        return;
    }
    // Localised: T_bim_odom of the clique's newest loop (the odometry has drifted least since).
    const Loop& newest = Newest(*rivals[0]);
    step_.state = RelocalizerState::kLocalised;
    step_.T_bim_odom = step_.hypotheses.front();
    step_.fix_information = newest.information;
    step_.T_odom_lidar_fix = newest.T_odom_lidar;
    // A loop is verified at full rank: it measured the height too.
    height_fix_odom_ = newest.T_odom_lidar.translation();
    height_ambiguous_ = false;
    loops_.clear();
    guides_.clear();
    misses_ = contradicted_ = 0;
    contradicted_along_.setZero();
}

void Relocalizer::Track(const registration::OrientedCloud& cloud,
                        const Eigen::Isometry3d& T_odom_lidar) {
    const Eigen::Isometry3d predicted = step_.T_bim_odom * T_odom_lidar;
    // From the middle level: the prediction is within its reach. A height the odometry flagged
    // may be off by more: from the coarse level then, whose reach (1.2 m) spans several risers.
    const registration::RegistrationResult r = registration::Register(
        cloud, pyramid_, predicted, config_.registration, height_ambiguous_ ? 0 : 1);
    step_.registrations = 1;
    step_.consistent_loops = 1;
    if (Verified(r, false)) {
        // What the odometry can have drifted since the last fix (RelocalizerConfig, Tracking):
        // with the distance it moved, and in height by as much as it climbed besides.
        const Eigen::Vector3d moved =
            step_.T_bim_odom.linear() *
            (T_odom_lidar.translation() - step_.T_odom_lidar_fix.translation());
        const double max_m = std::min(config_.track_max_m,
                                      config_.track_step_m + config_.drift_per_m * moved.norm());
        double max_up = std::min(config_.track_max_m, max_m + std::abs(moved.z()));
        const bool measured_height = MeasuredAlong(r, predicted, Eigen::Vector3d::UnitZ(), max_m,
                                                   config_.height_measured_sigma);
        if (height_ambiguous_ && measured_height) {
            // Whole risers off (RelocalizerConfig::height_measured_sigma): up to the climb since
            // the height was last measured, from a registration that measured it.
            const double climbed =
                (step_.T_bim_odom.linear() * (T_odom_lidar.translation() - height_fix_odom_)).z();
            max_up = std::max(max_up, max_m + std::abs(climbed));
        }
        const double max_deg = std::min(
            config_.track_max_deg, config_.track_step_deg + config_.drift_deg_per_m * moved.norm());
        const Eigen::Isometry3d found = FuseWithPrediction(predicted, r, max_m, max_up, max_deg);
        if (Near(predicted, found, max_m, max_up, max_deg)) {
            step_.T_bim_odom = found * T_odom_lidar.inverse();
            step_.fix_information = r.information;
            step_.T_odom_lidar_fix = T_odom_lidar;
            step_.accepted = true;
            misses_ = 0;
            if (MeasuredAlong(r, predicted, contradicted_along_, max_m, max_up)) contradicted_ = 0;
            if (measured_height) {
                height_fix_odom_ = T_odom_lidar.translation();
                height_ambiguous_ = false;
            }
            return;
        }
        ++contradicted_;
        const Eigen::Vector3d off = r.T_target_source.translation() - predicted.translation();
        const bool moved_off = off.head<2>().norm() > max_m || std::abs(off.z()) > max_up;
        contradicted_along_ = moved_off ? off.normalized() : Eigen::Vector3d::Zero();
    }
    // A registration that failed its check measured nothing: it clears no contradiction.
    ++misses_;
    if (contradicted_ >= config_.contradictions) {
        StartSearch(RelocalizerState::kSearching);
    } else if (misses_ >= config_.lost_after) {
        StartSearch(RelocalizerState::kLost);
    }
}

void Relocalizer::StartSearch(RelocalizerState state) {
    step_.state = state;
    step_.T_bim_odom = Eigen::Isometry3d::Identity();
    loops_.clear();
    guides_.clear();
    misses_ = contradicted_ = 0;
    contradicted_along_.setZero();
}

bool Relocalizer::Near(const Eigen::Isometry3d& predicted, const Eigen::Isometry3d& found,
                       double max_m, double max_up, double max_deg) const {
    const Eigen::Vector3d d = found.translation() - predicted.translation();  // the model's axes
    return d.head<2>().norm() <= max_m && std::abs(d.z()) <= max_up &&
           common::RotationAngle(predicted.inverse() * found) <= max_deg * M_PI / 180;
}

}  // namespace bimslam::localization
