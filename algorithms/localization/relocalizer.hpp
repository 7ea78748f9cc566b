// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Relocalisation in the building's model while the rig walks (issue 35, item 2): the offline
// anchoring's Step 2 (host_tools/anchor/README.md, "The method") turned into one keyframe at a
// time against a rig map package (rig_map.hpp). No thread and no I/O: the rig's localiser thread
// and `bimslam localize` feed it.
//
// Per keyframe (its deskewed cloud, its Scan Context descriptor, its odometry pose):
//   - searching, candidate, ambiguous, lost: place recognition as offline: the ring-key
//     candidates, the best `sc_candidates` within `max_sc_distance` registered to the package's
//     surfel pyramid from the candidate's pose turned by the descriptors' yaw, and verified by
//     the same fitness and full rank. Each verified loop implies T_bim_odom. Loops of the last
//     `window_keyframes` keyframes are the hypotheses' material: the cliques of mutually
//     consistent loops (the offline test: one loop's keyframe placed through the other's
//     T_bim_odom and the odometry lies where its registration put it, within bounds that grow
//     with the distance walked between them), a clique whose keyframes see through the model's
//     surfaces (median over its loops) more than `max_seen_through`, beyond what removed
//     elements explain (registration/removed_surfaces.hpp), dropped as contradicted
//     (the search goes on until three cliques stand), a rival outweighed by free space as
//     offline. Each hypothesis standing after the previous keyframe also registers this one from
//     where it puts it (guided loops: offline's proximity rounds, live), so a hypothesis grows
//     where Scan Context finds no candidate.
//       - no clique whose loops come from min_clique keyframes: candidate (with the largest
//         clique's loops) or searching. Keyframes, not loops: one keyframe's two candidates at
//         neighbouring reference keyframes register to one place and would count twice;
//       - a rival clique of at least rival_min_ratio of the best's keyframes: ambiguous, with both;
//       - else localised, T_bim_odom from the clique's newest loop.
//   - localised: the keyframe registered from where T_bim_odom puts it (from the middle level),
//     accepted when verified and within track bounds of that prediction: T_bim_odom follows it.
//     The bounds also refuse a slide into a wall's second basin 0.31 m off, which made offline's
//     proximity rounds start at the finest level. `lost_after` keyframes in a row without an
//     accepted registration: lost (the search starts again); `contradictions` verified but far
//     from the prediction, with no registration in between that measured the contradicted
//     direction and agreed (MeasuredAlong): the hypothesis is dropped and the search starts again
//     (searching).
#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <optional>
#include <random>
#include <string_view>
#include <vector>

#include "algorithms/common/point_cloud.hpp"
#include "algorithms/io/trajectory.hpp"
#include "algorithms/localization/loop_rules.hpp"
#include "algorithms/localization/rig_map.hpp"
#include "algorithms/localization/walked_space.hpp"
#include "algorithms/registration/free_space.hpp"
#include "algorithms/registration/oriented_cloud.hpp"
#include "algorithms/registration/registration.hpp"
#include "algorithms/scancontext/candidate_index.hpp"

namespace bimslam::localization {

// The defaults are the offline anchoring's (host_tools/anchor/anchor_config.hpp), whose README
// gives the reasons; what only the live search has says its own.
// The loops' rules are LoopRules, the offline anchoring's own (loop_rules.hpp); the rest is the
// live search's and the tracking's.
struct RelocalizerConfig : LoopRules {
    // Here distinct keyframes; offline 3 loops, since it follows a clique with proximity rounds
    // that must then find 5 loops, where a live clique of 4 keyframes decides at once.
    int min_clique = 4;
    // Live only. The loops of the last 120 keyframes (about 120 m of walk at the rig's 1 m
    // keyframes) make the hypotheses: the clique search stays small, and a wrong loop from long
    // ago cannot hold a hypothesis up.
    size_t window_keyframes = 120;
    // Tracking: a registration from the predicted pose moves T_bim_odom by at most what the
    // odometry can have drifted since the last fix (drift_per_m and drift_deg_per_m over the
    // distance the odometry moved since), plus track_step_m and track_step_deg for the
    // registrations' own spread, and never by more than track_max_m and track_max_deg (offline's
    // proximity bounds). The drift's bound, not only the proximity's: on Duplex_A a wall's two
    // basins 31 cm apart were both within 0.5 m of each prediction, and T_bim_odom flipped
    // between them from keyframe to keyframe (live error 0 or 31 cm by turns). In height, as
    // much again as the odometry climbed since the fix: on a flight the stairwell hides floor
    // and ceiling and its height drifts faster than drift_per_m (issue 31). With the distance's
    // bound alone, the held-out Office_A's Go1 climb had its right registrations refused as its
    // height drifted 50 cm, three in a row dropped the hypothesis, and the rig searched for 175 s
    // upstairs (live RMSE 4.5 -> 19 cm). The climb's bound is no constant fitted to that walk:
    // an odometry is not off in height by more than it climbed.
    double track_step_m = 0.1;
    double track_step_deg = 1.0;
    double track_max_m = 0.5;
    double track_max_deg = 5.0;
    // A height the odometry saw again while uncertain (odometry::kHeightAmbiguous: its
    // accelerometers' filter over half a stair's lowest riser, 7.5 cm) may be off by whole
    // risers from there on, more than track_max_m. Until a tracked registration measures the
    // height to this sigma (the odometry's own height_ambiguous_sigma), the height's bound is
    // what the odometry climbed since the height was last measured so, uncapped: an odometry is
    // not off in height by more than it climbed. On the held-out Office_A's Go1 climb the height
    // ended 1 m low at such a scan; the registrations that saw the floor upstairs said so and
    // were refused by the 0.5 m cap, and the live pose stood 1 m low for 60 s (localization
    // README, "A height the odometry flagged").
    double height_measured_sigma = 0.075;
    // Where the rig starts, when the operator knows (the rig's localization.near, `bimslam
    // localize --near`): a clique that puts the first keyframe farther than its radius, grown by
    // drift_per_m over the walk from there to the clique's newest loop, is set aside, never a
    // rival (offline's off_hint). In a building of identical parts (Duplex_A's two dwellings, a
    // mirror-symmetric hall) the rig is otherwise ambiguous for as long as it walks.
    std::optional<StartHint> start;
    int lost_after = 15;     // keyframes without an accepted registration (about 15 m)
    int contradictions = 3;  // verified registrations far from the prediction, uncleared
    // Tests of robustness only (issue 35: "30 % of the candidate loops injected wrong"): while
    // searching, each keyframe adds with this probability a loop to a random reference keyframe,
    // registered from there and kept whatever its fitness (as offline's inject_false_loops).
    double inject_false_loops = 0.0;
    uint64_t seed = 1;
};

// A tracked keyframe's pose: the prediction moved by the registration only as far as the
// registration measured. In information form (a Kalman update of the right perturbation of
// T_bim_lidar, the perturbation the registration's information is over): delta = (P^-1 + I)^-1
// I nu, with nu the registration's step from the prediction, I its information (zero along a
// degenerate direction, registration.hpp) and P the prediction's covariance, the tracking's
// bounds taken as its standard deviations (sigma_m across, sigma_up in height, in the model's
// axes). Where the registration is well constrained I >> P^-1 and delta is its step; along what
// it did not constrain the prediction stays. Taking the registration whole, twelve keyframes of
// a hand-held FZK-Haus walk turning on the spot, their height degenerate (information 4-455
// against 7000-10000 before and after), moved T_bim_odom up to 11 cm in height, and the live
// poses with it, for 3 s (localization README, "Tracking what was measured").
Eigen::Isometry3d FuseWithPrediction(const Eigen::Isometry3d& predicted,
                                     const registration::RegistrationResult& r, double sigma_m,
                                     double sigma_up, double sigma_deg);

// Whether a tracked registration measured the direction `along` (unit, the model's axes) at least
// as well as the prediction knows it (the same bounds as sigmas as FuseWithPrediction): only such
// a registration, agreeing with the prediction, clears the contradictions counted against it. A
// zero `along` (the contradictions were in rotation, or none): any agreeing registration clears.
// On the held-out Office_A's Go1 climb the odometry's height ended 1 m low; upstairs every
// registration that saw the floor said so (1 m up, information 22 000 along the vertical), and
// between them one whose height was degenerate (information under 5) agreed with the wrong
// height, cleared the count, and the hypothesis stood 1 m off for the rest of the walk
// (localization README, "A contradiction is cleared by what measured it").
bool MeasuredAlong(const registration::RegistrationResult& r, const Eigen::Isometry3d& predicted,
                   const Eigen::Vector3d& along, double sigma_m, double sigma_up);

// A scan's live pose in the model: its odometry pose composed with the relocaliser's T_bim_odom
// of the last keyframe at or before it. One function, so that `bimslam localize` and the rig's
// session write the same trajectory_bim_live.tum.
io::StampedPose LivePose(const Eigen::Isometry3d& T_bim_odom, const io::StampedPose& odom);

// The covariance of a live T_bim_base (bim_pose_t.pose_covariance): the fixing registration's
// information (Censi's sigma^2 H^-1, algorithms/registration/registration.hpp) carried from the
// fix's lidar frame to the base by the adjoint (T Exp(d) T_rel = T T_rel Exp(Ad(T_rel^-1) d)),
// plus the odometry's drift since the fix (RelocalizerConfig::drift_per_m and drift_deg_per_m
// over `odometry_m`, the distance the odometry moved since). Over the right perturbation
// [rho; phi] of T_bim_base (the base's axes, as odometry_t's), m^2 and rad^2. A direction the
// registration could not constrain (zero information: degenerate) gets kUnconstrainedVariance.
inline constexpr double kUnconstrainedVariance = 1e4;
common::Matrix6d LiveCovariance(const common::Matrix6d& fix_information,
                                const Eigen::Isometry3d& T_lidar_fix_base, double odometry_m,
                                const RelocalizerConfig& config);

enum class RelocalizerState : uint8_t { kSearching, kCandidate, kLocalised, kAmbiguous, kLost };
std::string_view ToString(RelocalizerState state);

struct RelocalizerStep {
    RelocalizerState state = RelocalizerState::kSearching;
    size_t keyframe = 0;                        // how many keyframes came before this one
    size_t consistent_loops = 0;                // the best clique's loops (searching: 0)
    std::vector<Eigen::Isometry3d> hypotheses;  // T_bim_odom of each clique kept, best first
    Eigen::Isometry3d T_bim_odom = Eigen::Isometry3d::Identity();   // localised: the tracked one
    Eigen::Isometry3d T_bim_lidar = Eigen::Isometry3d::Identity();  // localised: this keyframe
    // Localised: the registration that last fixed T_bim_odom (a loop of the deciding clique, or
    // a tracked keyframe): its information over the right perturbation of T_bim_lidar there, and
    // that keyframe's odometry pose. LiveCovariance carries it to any later scan.
    common::Matrix6d fix_information = common::Matrix6d::Zero();
    Eigen::Isometry3d T_odom_lidar_fix = Eigen::Isometry3d::Identity();
    int32_t storey = -1;       // localised: index into the package's storeys
    size_t registrations = 0;  // run for this keyframe
    size_t injected = 0;       // false loops added (RelocalizerConfig::inject_false_loops)
    bool accepted = false;     // localised: this keyframe's registration was accepted
};

class Relocalizer {
public:
    // Keeps a reference to `map`, which must outlive it. Throws common::Error on a package
    // without keyframes or surfel levels other than the registration's.
    Relocalizer(const RigMap& map, const RelocalizerConfig& config = {});

    // What the constructor checks of a package, without building anything (the rig refuses a
    // package at start with it): keyframes, the surfel levels the registration runs, descriptors
    // of a configuration the Scan Context index takes. Throws common::Error naming the problem.
    static void Check(const RigMap& map, const RelocalizerConfig& config = {});

    // One keyframe: its deskewed cloud (lidar frame), its descriptor (the package's kind and
    // shape), its odometry pose, how far the rig has walked (m, from the start), and whether
    // the odometry flagged its height ambiguous (odometry::kHeightAmbiguous) at a scan since the
    // previous keyframe, this one's included (RelocalizerConfig::height_measured_sigma).
    const RelocalizerStep& AddKeyframe(const common::PointCloud& cloud,
                                       const scancontext::Descriptor& descriptor,
                                       const Eigen::Isometry3d& T_odom_lidar, double path_m,
                                       bool height_ambiguous = false);

    const RelocalizerStep& last() const { return step_; }
    RelocalizerState state() const { return step_.state; }

private:
    struct Loop {
        size_t keyframe = 0;
        Eigen::Isometry3d T_bim_lidar;  // registered
        Eigen::Isometry3d T_odom_lidar;
        double path_m = 0;
        double seen_through = 0;
        registration::FreeSpaceResult free_space;  // the rays and crossings behind seen_through
        common::Matrix6d information = common::Matrix6d::Zero();
        Eigen::Isometry3d T_bim_odom() const { return T_bim_lidar * T_odom_lidar.inverse(); }
    };
    struct Clique {
        std::vector<size_t> loops;  // into loops_
        size_t keyframes = 0;       // distinct keyframes among them
        double seen_through = 0;    // median
        double unexplained = 0;     // median, but for what removed elements explain
    };

    bool Verified(const registration::RegistrationResult& r, bool full_rank) const;
    // The clique puts the first keyframe within RelocalizerConfig::start (true without one).
    bool OnHint(const Clique& c) const;
    // The clique's newest loop: its T_bim_odom is the clique's (the odometry has drifted least
    // since).
    const Loop& Newest(const Clique& c) const;
    void AddLoop(const registration::OrientedCloud& cloud,
                 const registration::RegistrationResult& r, const Eigen::Isometry3d& T_odom_lidar,
                 double path_m);
    void Search(const registration::OrientedCloud& cloud, const scancontext::Descriptor& d,
                const Eigen::Isometry3d& T_odom_lidar, double path_m);
    std::vector<Clique> Cliques() const;
    bool Consistent(const Loop& a, const Loop& b) const;
    void Decide(const std::vector<Clique>& cliques);
    void Track(const registration::OrientedCloud& cloud, const Eigen::Isometry3d& T_odom_lidar);
    void StartSearch(RelocalizerState state);
    // `found` within max_m of `predicted` horizontally, max_up vertically (the model's z) and
    // max_deg.
    bool Near(const Eigen::Isometry3d& predicted, const Eigen::Isometry3d& found, double max_m,
              double max_up, double max_deg) const;

    const RigMap& map_;
    RelocalizerConfig config_;
    registration::SurfelPyramid pyramid_;
    scancontext::CandidateIndex index_;
    std::vector<Loop> loops_;
    std::vector<Eigen::Isometry3d> guides_;  // the hypotheses standing after the last keyframe
    // The package's keyframes (LoopRules::HeightsPrefer), and the odometry positions of the
    // last window_keyframes keyframes, which each clique places.
    WalkedSpace walked_;
    std::deque<Eigen::Vector3d> window_odom_;
    RelocalizerStep step_;
    size_t keyframes_ = 0;
    // The first keyframe's odometry position and walk (RelocalizerConfig::start).
    Eigen::Vector3d start_odom_ = Eigen::Vector3d::Zero();
    double start_path_m_ = 0;
    int misses_ = 0, contradicted_ = 0;
    // The last contradiction's translation from the prediction (unit, the model's axes), or zero
    // when it was off in rotation only (MeasuredAlong).
    Eigen::Vector3d contradicted_along_ = Eigen::Vector3d::Zero();
    // Where (the odometry's frame) the height was last measured to height_measured_sigma, and
    // whether the odometry flagged its height ambiguous since (RelocalizerConfig).
    Eigen::Vector3d height_fix_odom_ = Eigen::Vector3d::Zero();
    bool height_ambiguous_ = false;
    std::mt19937_64 rng_;
};

}  // namespace bimslam::localization
