// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The parameters of multi-session anchoring (anchoring.hpp), with the reasons for their defaults.
#pragma once

#include <cstdint>
#include <string_view>

#include "algorithms/localization/loop_rules.hpp"
#include "algorithms/posegraph/pose_graph.hpp"
#include "algorithms/scancontext/config.hpp"

namespace bimslam::anchor {

// How wrong loops are kept out (README.md, "Wrong loops", gives the measurements).
enum class OutlierMethod {
    kPcm,   // pairwise consistency maximisation: the largest set of mutually consistent loops
    kGnc,   // graduated non-convexity with a truncated least squares cost (Yang et al. 2020)
    kNone,  // only the Cauchy loss of the pose graph
};
std::string_view ToString(OutlierMethod m);
bool ParseOutlierMethod(std::string_view name, OutlierMethod* out);

// The loops' rules (place recognition, verification, consistency, free space) are
// localization::LoopRules, shared with the rig's relocaliser; the rest is the offline anchoring's.
struct AnchorConfig : localization::LoopRules {
    scancontext::ScanContextConfig descriptor = scancontext::ScanContextConfig::Indoor();

    // The query's odometry edges keep their covariances from the session's g2o, scaled by this:
    // the rig's odometry states its per-scan registration covariance, which the same calibration
    // measured to be about 3x too small in sigma (median |e|/sigma 2.0).
    double odometry_information_scale = 0.1;
    // The model is not the building: walls stand within construction tolerances of where they
    // are drawn, and a loop registered to the model inherits the deviation of the walls it saw,
    // the same for every loop that saw them. This much covariance can be added to each loop to
    // the reference (Sigma_loop = H^-1 + Sigma_model), so that walls built off bend the
    // trajectory less. Off by default: measured, 2 cm helped a little where walls were built
    // off (APE 2.02 -> 1.91 cm) and hurt where the odometry made an excursion the weakened
    // loops no longer corrected (a clean handheld walk: 1.00 -> 1.78 cm, max 5.1 -> 9.5 cm)
    // (README.md, "The model's tolerance"). Loops between query sessions never get it.
    double model_tolerance_m = 0.0;
    double model_tolerance_deg = 0.0;
    // Place-recognition loops must be well constrained in every direction: one that is not (a
    // corridor) kept its initial guess along its weak axis, and that guess was only "here".
    bool require_full_rank = true;

    // Fewer mutually consistent loops are no hypothesis. 3: a Go1 walk from outside had 3 right
    // loops among 35 verified (README.md, "Walks from outside"); a hypothesis still needs
    // min_loops after its proximity rounds to be anchored.
    int min_clique = 3;
    int max_hypotheses = 3;
    // Cliques searched in all, those passed over as seen through the model included: a bound
    // on the search's time (the relocaliser's kMaxCliques).
    int max_cliques = 32;
    OutlierMethod outliers = OutlierMethod::kPcm;

    // Proximity: once placed, every query keyframe near a reference keyframe is registered again
    // from its estimated pose; accepted when it stays within the gate of that estimate.
    double proximity_radius_m = 3.0;  // horizontal
    double proximity_height_m = 1.5;  // vertical: not the storey above or below
    double proximity_gate_m = 0.5;
    double proximity_gate_deg = 5.0;
    // The estimate is good to centimetres: the finest level only (0.2 m reach). From the middle
    // level (0.5 m reach) registrations started within 2 mm of the truth slid 0.31 m into a second
    // basin (README.md, "Two registration basins").
    size_t proximity_first_level = 2;
    int max_rounds = 6;  // 0: place-recognition loops only (to measure the outlier methods alone)
    double converged_m = 0.01;  // rounds end when no keyframe moves more than this ...
    // ... and the accepted set is the same. After the last round, a loop whose whitened residual
    // exceeds this chi-square (6 dof, 0.999) is dropped as inconsistent with the solution.
    double max_loop_chi2 = 22.5;

    // Earlier visits' anchored sessions (AnchorSession::earlier) are held where their own
    // anchoring put them by a prior on each keyframe's world pose, this sigma per axis. The
    // anchoring states no covariance of its own; these are its measured errors against ground
    // truth (README.md, "Measured": keyframes 0.6-3.3 cm RMSE, rotation 0.09-0.20 deg over 44
    // anchored walks), so a new visit can move an earlier one about that much and no further.
    double earlier_sigma_m = 0.02;
    double earlier_sigma_deg = 0.2;
    // `bimslam map` gives a new visit the earlier visits' keyframes as targets, newest visit
    // first, and leaves out an older visit's keyframe within this distance of a newer visit's:
    // the newer one saw that place since (its surfaces as they are now), and a 360-degree scan
    // and a yaw-invariant descriptor need no second one there. So the targets grow with the
    // building walked, not with the number of visits (issue 33: the tenth visit's anchoring took
    // 2.7x the first's with all nine visits' keyframes). Keyframes of one visit never thin each
    // other: with one earlier visit, all of it is a target.
    double earlier_spacing_m = 1.0;

    // An anchored solution that moves two keyframes joined by a trusted odometry edge this much
    // (or turns them this much) apart from the measured edge breaks the odometry
    // (SessionResult::odometry_breaks): 10-20 times what the graph bends a sound edge by.
    double odometry_break_m = 0.2;
    double odometry_break_deg = 5.0;
    // Such breaks are mended by dropping the loops on their wrong side (break_repair.hpp). Off:
    // reported only (benchmarks compare the two).
    bool repair_odometry_breaks = true;

    // Verdict.
    int min_loops = 5;             // loops of the best hypothesis for "anchored"
    double min_coverage = 0.1;     // share of the query's keyframes with a loop
    double ambiguity_ratio = 0.8;  // a rival explaining this share of the best's loops ...
    double distinct_m = 1.0;       // ... at an anchor at least this far off ...
    double distinct_deg = 5.0;     // ... or turned this much: "ambiguous"

    // For the robustness benchmark: this share of the verified place-recognition loops is
    // replaced by wrong pairs (a query keyframe registered at a random other reference keyframe)
    // that are accepted as verified whatever their fitness.
    double inject_false_loops = 0.0;
    uint64_t seed = 1;

    posegraph::PoseGraphConfig graph;
    int threads = 0;  // 0: all cores

    void Validate() const;  // throws common::Error naming the field
};

}  // namespace bimslam::anchor
