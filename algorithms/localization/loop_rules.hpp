// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The rules a loop to the model is held to, one set for the offline anchoring
// (host_tools/anchor, AnchorConfig) and the rig's relocaliser (relocalizer.hpp, RelocalizerConfig):
// both configurations derive from LoopRules, so the live relocaliser finds, verifies and checks
// its loops as the offline anchoring does (issue 35) and a default changed in one is changed in
// the other. What only one of them needs (proximity rounds, tracking, the clique size) stays in
// its own configuration. The reasons for the values are the offline measurements
// (host_tools/anchor/README.md).
#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <vector>

#include "algorithms/registration/free_space.hpp"
#include "algorithms/registration/oriented_cloud.hpp"
#include "algorithms/registration/registration.hpp"
#include "algorithms/registration/removed_surfaces.hpp"

namespace bimslam::localization {

// Where a walk starts, when the user knows (model x y, m; `--near X Y [R]`, the rig's
// localization.near): a hypothesis that puts the session's first keyframe farther than radius_m
// from it is set aside, never a rival (offline Hypothesis::off_hint; live, the relocaliser's
// clique, the radius grown by drift_per_m over the walk to its loops). For buildings of identical
// parts: Duplex_A's two dwellings are one turned 180 degrees, and a walk in one fits the other as
// well (host_tools/anchor/README.md, "Identical parts"); without it, such a walk is ambiguous.
struct StartHint {
    Eigen::Vector2d xy = Eigen::Vector2d::Zero();
    double radius_m = 3.0;
    void Validate() const;  // throws common::Error naming the radius
    // [x, y, radius_m]: its form in anchor.json, project.json and the map's stamps.
    std::vector<double> List() const { return {xy.x(), xy.y(), radius_m}; }
    // From `--near X Y [R]` (R 3 m when absent) or a List(), validated; throws common::Error
    // for any other count.
    static StartHint FromList(const std::vector<double>& x_y_radius);
};

struct LoopRules {
    // Out of line: GCC 12 inlined the registration's levels into every configuration made and
    // warned of them as "maybe uninitialized" (a false positive) in two places.
    LoopRules();

    // Place recognition: each keyframe's nearest ring keys, then the best few of them by Scan
    // Context distance are registered.
    int ring_key_candidates = 10;  // [SC] uses 10
    int sc_candidates = 2;         // registered per query keyframe (2: symmetric places)
    double max_sc_distance = 0.6;  // candidates beyond are not worth a registration

    // Registration and what a loop must show to count as verified. The information of a loop
    // is the registration's Hessian over its residual variance, times information_scale: the
    // points of one scan do not err independently (a wall's points share its plane's error), so
    // they carry the information of far fewer points. 0.006 (about one point in 150) makes the
    // loops' errors against ground truth match their stated sigma (median |e|/sigma 0.67 as for
    // a normal distribution) on the sample building's Go1 and handheld captures
    // (host_tools/anchor/README.md, "Calibration"); 0.1, Censi's closed form with a 1 cm floor,
    // claimed 3-5x too little error.
    registration::OrientedCloudConfig cloud;
    registration::RegistrationConfig registration;  // information_scale 0.006 (the constructor)
    double min_inlier_ratio = 0.5;  // of the query's planar points within 5 cm of the model
    double max_inlier_rmse = 0.03;  // m

    // Pairwise consistency of two loops of one session (PCM): the pose of one keyframe predicted
    // through the other loop and the odometry between them must agree within consistency_* plus
    // drift_* times the distance travelled between the two keyframes (Agree). 0.15 m: verified
    // loops were within 2 cm of the truth or 0.30 m and more off (2987 loops of 42 walks); at
    // 0.3 m a loop in a wall's second basin 0.31 m away joined its right neighbour's clique
    // (Duplex_A, host_tools/anchor/README.md "Two registration basins").
    double consistency_m = 0.15;
    double consistency_deg = 2.0;
    double drift_per_m = 0.03;  // 3 %: three times this project's odometry without IMU
    double drift_deg_per_m = 0.15;
    double rival_min_ratio = 0.25;  // a rival clique this big (relative) is examined too

    // Negative evidence (registration::CheckFreeSpace), on the surfel map of this registration
    // level: a hypothesis whose keyframes see through the target's surfaces (the median share of
    // their rays) more than max_seen_through is contradicted, however well it registers. 5 %:
    // right placements measured 0.6-1.7 % (1.7 % in a changed building with removed columns),
    // the sample building's ground floor placed on its first floor 5.6-7.6 %.
    registration::FreeSpaceConfig free_space;
    size_t free_space_level = 1;
    double max_seen_through = 0.05;
    // What a removed element explains is no contradiction (registration/removed_surfaces.hpp) of
    // a placement the walk's start hint vouches for (StartHint): max_seen_through then judges the
    // share of rays seen through other surfaces. Duplex_A's third visit, its partition between
    // entry and living room demolished, saw through it with 13-20 % of its rays at the right
    // placement and was refused. Without a hint the rays count whole: the sample office's ground
    // floor placed on its first floor saw through the first floor's one extra partition (7.6 %,
    // 0.6 % but for it), as the right storey would with that partition demolished.
    registration::RemovedSurfaceConfig removed_surfaces;
    // Between hypotheses that explain the loops about equally well, free space decides when one's
    // keyframes see through the model decisively less often than the other's: at most
    // 1/outweigh_ratio as often and by at least outweigh_gap less. The other is "outweighed" and
    // no longer a rival. A handheld walk's ground floor placed on the sample building's first
    // floor saw through 4.4 % of its rays, under max_seen_through, where the right placement saw
    // 0.66 %: with identical coverage (63 keyframes each) it was reported ambiguous. Right
    // placements measured 0.6-1.7 %, so two of them differ by less than the gap; a
    // mirror-symmetric building's two placements see alike and stay ambiguous.
    double outweigh_ratio = 3.0;
    double outweigh_gap = 0.02;
    // The walk's heights decide too (HeightsPrefer, walked_space.hpp): a placement that puts
    // floating_share of the walk's keyframes a storey off every walk of the model (reference
    // keyframes within floating_radius_m horizontally, none within floating_height_m: not the
    // storey above or below, as offline's proximity loops) is outweighed by one that puts at most
    // 1/outweigh_ratio as many there. A tenth: a flight and a landing of a short walk. The sample
    // office's walk up its stair and back placed a storey up explained 99 of its 121 keyframes
    // (over the 80 % ambiguity ratio) and floated the other 22 above the roof, where free space
    // sees nothing: it preferred the right placement by 1.9 points, under outweigh_gap. A walk on
    // one of two similar storeys floats nothing on either and stays for free space to decide.
    double floating_share = 0.1;
    double floating_radius_m = 3.0;
    double floating_height_m = 1.5;

    // Throws common::Error (kInvalidArgument) naming `owner` (the derived configuration), the
    // field, its value and the rule.
    void ValidateLoopRules(const char* owner) const;

    // Whether free space prefers placement a to b (a hypothesis offline, a clique live), from the
    // shares of their rays seen through the model: decisively (at most 1/outweigh_ratio as often
    // and by at least outweigh_gap less), or because a stands as the model is (within
    // max_seen_through) where b stands only by what removed elements explain (`b_explained`).
    bool FreeSpacePrefers(double a_seen_through, double b_seen_through, bool b_explained) const;

    // Whether the walk's heights prefer placement a to b over a walk of `keyframes`, from how
    // many of them each floats: b at least floating_share of them and `min_count`, a at most
    // 1/outweigh_ratio as many as b.
    bool HeightsPrefer(size_t a_floating, size_t b_floating, size_t keyframes,
                       size_t min_count) const;

    // Two loops agree when E, the disagreement of the poses they imply for one keyframe, is
    // within the consistency bounds grown by the drift over `path_m`, the odometry's path between
    // their keyframes.
    bool Agree(const Eigen::Isometry3d& E, double path_m) const;
};

}  // namespace bimslam::localization
