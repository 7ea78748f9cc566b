// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// A joint estimate of the anchored keyframe poses and of every element's as-built offset, against
// the model, before the changes are measured (change_detector.hpp runs it first).
//
// Why. Anchoring registers each keyframe to the reference session, i.e. to the model as designed.
// Where walls were built off (the changed-building scenario draws every wall's offset from
// N(0, 2 cm), `as_built.wall_offset_sigma_m`), each keyframe is pulled to the compromise of the
// few walls it sees, and the deviation measured afterwards is the wall's offset minus that pull
// (README.md, "Measured": 3-9 of 13 walls within 1 cm when anchored, 13 of 13 on the true poses).
// Registering each keyframe alone to the walls that look "stable" does not work either: when every
// wall is off by N(0, 2 cm) there is no such set (branch `refine`, not merged).
//
// The estimate. Unknowns: every keyframe pose T_k (quaternion + translation) and one offset
// t_e in R^3 per element of the model (the element translated as a whole; a wall's support only
// constrains t_e along its normal, a column's across its two axes, the rest is held by the prior).
// Factors, all in one Ceres problem:
//   (a) the session's own relative-pose edges (odometry, intra-session loops) with their
//       information, the pose graph's residual (algorithms/posegraph/relative_pose_cost.hpp), with
//       a Cauchy loss: an odometry edge that lost track (a nearly empty scan) must be able to give;
//   (b) point to plane: a subsample of each keyframe's points, p, against the nearest model
//       triangle facing the keyframe's sensor (normal n, nearest point c; a thin wall's far face
//       is nearer than its near face to a point seen from a pose 8 cm off, and no beam hit it)
//       at the current estimate, the plane moved by its element's offset:
//       r = n . (T_k p - c - t_e) / sigma_point, Cauchy. Points farther than the gate from every
//       element are changes, not support, and are left out;
//   (c) a zero-mean prior per element seen, t_e / sigma_element: the as-built spread (2 cm: the
//       changed-building scenario's, and the site tolerance the element check judges deviations
//       by, README.md "Thresholds"); for a surveyed element (the datum), (t_e - survey) / 3 mm.
// The correspondences are found again a few times with a shrinking gate (ICP's outer loop).
//
// Gauge. The model fixes the frame: the offsets' priors say that, on average, the building stands
// where the model says. An element seen by one keyframe only cannot tell its offset from that
// keyframe's pose, the prior holds it. What the data cannot tell apart is a shift of the whole
// session from the same shift of every element seen along that direction: it is resolved by the
// priors, i.e. to the weighted mean of the true offsets (about sigma_element / sqrt(elements seen
// along that direction); README.md, "Pose refinement"). A datum removes that error: elements
// surveyed as built (a total station's ~2 mm, as Scan-vs-BIM work registers on control), whose
// offsets are held to the surveyed ones by a tight prior; one element across each direction fixes
// the shift along it. A keyframe whose points the model does not explain at its anchored pose is
// moved by its edges only, and kept where it is without any.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <span>
#include <vector>

#include "algorithms/changes/aligned_map.hpp"
#include "algorithms/changes/change_model.hpp"
#include "algorithms/common/se3.hpp"

namespace bimslam::changes {

// A relative-pose edge of the session's own graph (io::SessionEdge, without io): the measured
// T_from_to with its information over [x y z rx ry rz].
struct KeyframeEdge {
    uint32_t from = 0, to = 0;
    Eigen::Isometry3d T_from_to = Eigen::Isometry3d::Identity();
    common::Matrix6d information = common::Matrix6d::Identity();
};

// An element surveyed as built: its offset from the model (model frame, metres).
struct SurveyedElement {
    uint32_t element = 0;
    Eigen::Vector3d offset = Eigen::Vector3d::Zero();
};

struct PoseRefinementConfig {
    bool enabled = true;
    // Prior of an element's as-built offset, per axis (see above).
    double element_sigma_m = 0.02;
    // The datum (see "Gauge" above): surveyed elements, their offsets held to the survey's within
    // datum_sigma_m (a total station's setting-out accuracy, a few millimetres) instead of the
    // zero-mean prior. Empty: the gauge is the offsets' mean.
    std::vector<SurveyedElement> datum;
    double datum_sigma_m = 0.003;
    // A point's distance to its plane: OS1 range noise, 1 cm. The points of a keyframe are not
    // independent (their common error is the pose's), which is what the edges and priors bound.
    double point_sigma_m = 0.01;
    double point_loss_sigmas = 3.0;  // Cauchy scale of (b), in point sigmas
    double edge_loss_sigmas = 3.0;   // Cauchy scale of (a), in sigmas (as posegraph's odometry)
    // The edges' information is multiplied by this: the odometry's g2o states errors 1.2-5 times
    // too small (host_tools/anchor/README.md, "Calibration"; anchoring uses the same 0.1).
    double edge_information_scale = 0.1;
    // Points of each keyframe used, evenly spread over its scan (a stride), between these ranges
    // (those of the aligned map).
    size_t points_per_keyframe = 400;
    double min_range_m = 0.5, max_range_m = 25.0;
    // The outer loop: correspondences within each gate in turn. The first covers the anchoring's
    // outliers (13-17 cm in the benchmark); the last is the new-object threshold (10 cm: farther
    // points are changes).
    std::vector<double> gates_m = {0.20, 0.15, 0.10, 0.10};
    // The edges' Cauchy scale is multiplied by these in the rounds (the last repeats): wide
    // first, nearly quadratic, so that a keyframe placed far off is pulled by its edges into
    // reach of the gate, then narrow, so that an edge that lost track can give (graduated
    // non-convexity, as posegraph's annealing).
    std::vector<double> edge_loss_annealing = {16.0, 4.0, 1.0};
    // A keyframe is registered to the model (its points become factors) when, at its anchored
    // pose, at least this many of its points and this fraction of them are within the first
    // gate; otherwise only its edges move it (a nearly empty scan, a garbled one, a view of
    // things not in the model), and without edges it keeps its pose.
    size_t min_points = 30;
    double min_explained_fraction = 0.3;
    int max_iterations = 25;  // per round
    int threads = 2;
    void Validate() const;
};

struct PoseRefinement {
    std::vector<Eigen::Isometry3d> T_world_lidar;  // per keyframe, refined
    std::vector<double> correction_m;              // per keyframe: translation moved
    std::vector<double> correction_deg;            // per keyframe: rotation moved
    std::vector<Eigen::Vector3d> element_offset;   // per element: t_e (not seen: 0, or its survey)
    std::vector<uint32_t> element_points;          // per element: correspondences, last round
    size_t correspondences = 0;                    // last round
    size_t edges = 0;
    size_t unexplained = 0;  // keyframes not registered to the model (moved by edges only)
    size_t held = 0;         // of those, kept as they were (no edge)
    size_t datum_seen = 0;   // surveyed elements with correspondences (they held the frame)
    int iterations = 0;
    double seconds = 0;
    // Summary of correction_m: keyframes moved by more than 1 cm, mean and max.
    size_t moved_1cm = 0;
    double mean_correction_m = 0, max_correction_m = 0, max_correction_deg = 0;
};

// Throws common::Error (kInvalidArgument) for an invalid config, an edge naming a keyframe that
// does not exist or a surveyed element the model does not have.
PoseRefinement RefinePoses(const ChangeModel& model, std::span<const MapKeyframe> keyframes,
                           std::span<const KeyframeEdge> edges, const PoseRefinementConfig& config);

}  // namespace bimslam::changes
