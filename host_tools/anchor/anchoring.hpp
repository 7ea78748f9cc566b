// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Multi-session anchoring (the BIM-SLAM paper's Step 2): query sessions moved into the frame of
// a fixed reference session (the BIM's, "bim") without any initial pose.
//
//  1. Place recognition: every query keyframe against every reference keyframe by Scan Context
//     (ring-key candidates, then the column-shift distance, whose shift is the yaw); the best
//     candidates are registered to the reference's surfel map from the reference keyframe's pose
//     turned by that yaw. A registration with enough inliers, well constrained, is a verified
//     loop; each implies where the query's frame lies in the world (its anchor).
//  2. Wrong loops: a symmetric building gives loops that register well and are wrong. Pairwise
//     consistency maximisation (Mangelson et al. 2018) keeps the largest set of loops that agree
//     with each other through the query's odometry; the next largest sets that disagree with it
//     are rival hypotheses.
//  3. Each hypothesis: the pose graph (algorithms/posegraph: fixed reference, the query's anchor
//     node and odometry edges, the loops with a Cauchy loss) from the anchor its best loop
//     implies; then rounds of proximity registration from the estimate (every query keyframe
//     near a reference keyframe), optimising again, until the accepted loops stop changing.
//  4. Verdict: the hypothesis whose loops explain the most keyframes; "ambiguous" when a rival at
//     a distinct anchor explains nearly as many (both reported), "failed" when none holds.
//  5. A session whose odometry failed somewhere (its odometry_verdict.json) is split at the
//     failed stretches into pieces, each anchored as a session of its own (pieces.hpp); its
//     verdict is at best "anchored-in-parts".
//  6. Several query sessions: each is anchored to the reference first; then every session's
//     keyframes near another session's are registered to that session's map (loops between
//     query sessions, lifelong mapping); a session that failed alone is tried again against the
//     reference together with the anchored sessions; and all are optimised together.
//  7. Earlier visits (AnchorSession::earlier: sessions an earlier anchoring placed in the world
//     frame): targets with the reference from step 1 on, so place recognition and proximity
//     loops land on what they saw and the model lacks; held fixed while each query is anchored,
//     then free in the joint optimisation, each keyframe held by a prior at its earlier pose
//     (AnchorConfig::earlier_sigma_*): one graph, the reference fixed.
#pragma once

#include <Eigen/Geometry>
#include <functional>
#include <string>
#include <vector>

#include "algorithms/posegraph/pose_graph.hpp"
#include "algorithms/registration/free_space.hpp"
#include "algorithms/registration/registration.hpp"
#include "algorithms/registration/removed_surfaces.hpp"
#include "host_tools/anchor/anchor_config.hpp"
#include "host_tools/anchor/anchor_session.hpp"

namespace bimslam::anchor {

// kAnchoredInParts: the session's odometry failed in places (pieces.hpp); the pieces on either
// side were anchored on their own, at least one of them, and the keyframes inside the failed
// stretches were not placed. Never "anchored": the whole session was not.
enum class Verdict { kAnchored, kAnchoredInParts, kAmbiguous, kFailed };
std::string_view ToString(Verdict v);
// How bad a verdict is for the overall one: anchored < anchored-in-parts < ambiguous < failed.
int Severity(Verdict v);

enum class LoopSource { kScanContext, kProximity, kInjected };
std::string_view ToString(LoopSource s);

// One loop candidate: session indices are into AnchorInput's order (0 = the reference).
struct LoopRecord {
    size_t query_session = 0, query_index = 0;
    size_t target_session = 0, target_index = 0;
    LoopSource source = LoopSource::kScanContext;
    double sc_distance = -1;  // Scan Context distance (place recognition only)
    double sc_yaw = 0;        // rad, the yaw registration started from
    registration::RegistrationResult registration;  // T_target_source: the query's world pose
    // The target keyframe's world pose when registered, and c = T_target_query: the query
    // keyframe's pose in the target keyframe's frame (the loop factor's measurement).
    Eigen::Isometry3d T_world_target = Eigen::Isometry3d::Identity();
    Eigen::Isometry3d T_target_query = Eigen::Isometry3d::Identity();
    bool verified = false;  // the registration passed
    bool accepted = false;  // in the final graph
    int hypothesis = -1;    // the clique it belongs to, if any
    // Share of the query keyframe's rays seen through the target at the final estimate
    // (registration::CheckFreeSpace); -1 when not checked.
    double seen_through = -1;
    registration::FreeSpaceResult free_space;  // the same check's rays and crossings
    std::string reason;                        // why rejected, or "accepted"
};

struct Hypothesis {
    Eigen::Isometry3d anchor = Eigen::Isometry3d::Identity();  // T_world_local
    int clique_index = -1;  // the clique it grew from (LoopRecord::hypothesis)
    size_t clique = 0;      // mutually consistent place-recognition loops in it
    size_t loops = 0;       // accepted after the proximity rounds
    size_t covered = 0;     // query keyframes with an accepted loop
    double mean_inlier_ratio = 0;
    // The median over the query's keyframes near the target of the share of their rays that pass
    // through a target surface before reaching their point (registration::CheckFreeSpace):
    // evidence against the placement.
    double seen_through = 0;
    // The surfaces that removed elements explain (registration::FindRemovedSurfaces), and the
    // median share of rays seen through the others: what contradicts the placement.
    std::vector<registration::RemovedSurface> removed_surfaces;
    double seen_through_unexplained = 0;
    double Unexplained() const {
        return removed_surfaces.empty() ? seen_through : seen_through_unexplained;
    }
    // Over AnchorConfig::max_seen_through: Unexplained() when the walk's start was given (a
    // placement the user vouches for), else seen_through (RankHypotheses).
    bool contradicted = false;
    // Query keyframes it puts over or under every walk of the target (localization::WalkedSpace):
    // target keyframes near, none at its height. The target's walks cover every storey they
    // reached, so a placement that floats a flight's worth of the walk above the top storey (or
    // sinks it below the lowest) is not the building's.
    size_t floating = 0;
    // Another uncontradicted hypothesis explains nearly as many keyframes and free space prefers
    // it decisively (FreeSpacePrefers), or the walk's heights do (HeightsPrefer): not a rival.
    bool outweighed = false;
    bool outweighed_by_heights = false;  // by HeightsPrefer (the reason says which)
    // It puts the query's first keyframe farther than its StartHint allows: set aside, not a
    // rival.
    bool off_hint = false;
    int rounds = 0;
};

struct PieceResult;

struct SessionResult {
    std::string name;
    Verdict verdict = Verdict::kFailed;
    std::string reason;  // what the verdict rests on, in words
    Eigen::Isometry3d anchor = Eigen::Isometry3d::Identity();  // T_world_local, when anchored
    std::vector<Eigen::Isometry3d> world_poses;                // T_world_lidar per keyframe
    std::vector<Hypothesis> hypotheses;                        // best first
    size_t keyframes = 0;
    size_t candidates = 0;  // place-recognition candidates registered
    size_t verified = 0;
    size_t accepted_loops = 0;
    size_t covered = 0;
    bool via_other_sessions = false;  // anchored only with the help of other query sessions
    // Per keyframe: world_poses[k] is an anchored pose. All true when anchored; for
    // anchored-in-parts, the keyframes of the anchored pieces.
    std::vector<bool> placed;
    // A session whose odometry has failed stretches: the stretches, and the pieces it was split
    // into, each with its own result (empty otherwise).
    std::vector<OdometryStretch> untrusted;
    std::vector<PieceResult> pieces;
    std::vector<size_t> inside;  // keyframes inside a failed stretch, in no piece
    // An anchored session whose odometry is trusted (no failed stretch) but whose solution
    // breaks it: the odometry edges whose anchored relative pose is off the measured one by more
    // than AnchorConfig::odometry_break_m or _deg. The graph's robust odometry loss lets a
    // coherent group of wrong loops (a registration at a wrong height: the sample hall's meeting
    // table) bend a trusted odometry; the reason says so, the verdict is not changed (issue 33's
    // notes: a second building's walk anchored to 13.6 cm RMSE, 12 keyframes 0.75 m low).
    struct OdometryBreak {
        size_t from = 0, to = 0;
        double offset_m = 0, rotation_deg = 0;
    };
    std::vector<OdometryBreak> odometry_breaks;
    // The breaks the first joint solution had, when dropping the loops of the keyframes on their
    // wrong side mended them (break_repair.cpp), and how many loops that dropped.
    std::vector<OdometryBreak> breaks_repaired;
    size_t loops_dropped_at_breaks = 0;
};

// One piece of a split session: its keyframes (the session's indices) and its result as a session
// of its own (world_poses, hypotheses and indices are the piece's).
struct PieceResult {
    KeyframeSpan span;
    SessionResult result;
};

struct StageTimes {
    double descriptors_s = 0;   // loading, oriented clouds and descriptors (the caller's)
    double map_s = 0;           // the reference's surfel maps
    double candidates_s = 0;    // Scan Context search
    double registration_s = 0;  // every registration, wall time
    double consistency_s = 0;   // PCM (or GNC weights)
    double optimisation_s = 0;  // Ceres
    double total_s = 0;
    size_t registrations = 0;
};

// An earlier visit's session after the joint optimisation (step 7): the loops the queries
// closed to it and how far the new visits moved its keyframes from their priors.
struct EarlierResult {
    std::string name;
    size_t keyframes = 0;
    size_t accepted_loops = 0;
    double max_move_m = 0;
};

struct AnchorResult {
    std::vector<SessionResult> sessions;  // one per query, in input order
    std::vector<EarlierResult> earlier;   // one per earlier session, in input order
    std::vector<LoopRecord> loops;        // every candidate
    posegraph::PoseGraph graph;           // the final graph, accepted loops only
    StageTimes times;
};

// Progress: (stage name, done, total).
using Progress = std::function<void(const std::string&, size_t, size_t)>;

// Whether the free-space evidence prefers hypothesis a to b (LoopRules::FreeSpacePrefers, the
// relocaliser's rule too): a's keyframes see through the model decisively less often, or a
// stands as the model is where b stands only because removed elements explain what it sees
// through (b has removed_surfaces). FZK-Haus's attic is the same turned 180 degrees
// but for the stair's railings: its twin placement sees through them, two patches of 1.2 and 1.5
// m2 that a removed element would explain, and would otherwise be a rival of the right one.
bool FreeSpacePrefers(const Hypothesis& a, const Hypothesis& b, const AnchorConfig& config);

// Whether the walk's heights prefer hypothesis a to b over a walk of `keyframes`
// (LoopRules::HeightsPrefer, with at least min_loops floating): the session's own continuity
// through the stairs tells similar storeys apart.
bool HeightsPrefer(const Hypothesis& a, const Hypothesis& b, size_t keyframes,
                   const AnchorConfig& config);

// Marks each hypothesis contradicted (its keyframes see through the model more than
// max_seen_through), off the hint (`start` given, and it puts the first of the query's keyframes
// at `poses`, T_local_lidar, farther than start->radius_m from it) or outweighed (another
// uncontradicted one on the hint explains at least ambiguity_ratio of its keyframes and
// FreeSpacePrefers it). Returns their indices best first: uncontradicted, then on the hint, then
// not outweighed, then by keyframes covered, then by loops.
std::vector<size_t> RankHypotheses(std::vector<Hypothesis>& hypotheses,
                                   const std::vector<Eigen::Isometry3d>& poses,
                                   const AnchorConfig& config,
                                   const std::optional<StartHint>& start = std::nullopt);

// The verdict on a query whose keyframes are at `poses` (T_local_lidar) from its hypotheses
// ranked best first (RankHypotheses): failed when there is none, when the best is contradicted
// or off the hint, or when it explains fewer than max(min_loops, min_coverage of the keyframes)
// keyframes or has fewer than min_loops loops; ambiguous when the next (neither contradicted, off
// the hint nor outweighed) explains at least ambiguity_ratio as many keyframes at an anchor
// that places them more than distinct_m away on average or turns them more than distinct_deg;
// anchored otherwise. *reason says why when it is not anchored.
Verdict DecideVerdict(const std::vector<Hypothesis>& ranked,
                      const std::vector<Eigen::Isometry3d>& poses, const AnchorConfig& config,
                      std::string* reason, const std::optional<StartHint>& start = std::nullopt);

// The verdict on a session split at its odometry's failed stretches, from its pieces' verdicts:
// anchored-in-parts when one piece or more is anchored (never anchored: the keyframes inside the
// stretches are not placed, and no odometry ties the pieces together); else ambiguous when one
// is; else failed (also for no piece at all).
Verdict CombinePieces(const std::vector<Verdict>& pieces);

// sessions[0] is the reference (held fixed, its frame is the world's); the rest are queries, then
// the earlier visits' sessions (AnchorSession::earlier), if any, after every query. Every session
// must have been loaded with clouds. Throws common::Error for a bad config or order.
// A query whose odometry is untrusted (AnchorSession::odometry) is anchored in pieces
// (pieces.hpp): result.sessions still has one entry per query, with its pieces; the loops' indices
// are the query's own keyframes; result.graph holds each piece as a session of its own.
AnchorResult Anchor(const std::vector<AnchorSession>& sessions, const AnchorConfig& config,
                    const Progress& progress = {});

}  // namespace bimslam::anchor
