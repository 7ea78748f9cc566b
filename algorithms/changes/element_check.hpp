// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The verdict on each element of the model, and its as-built deviation (Scan-vs-BIM).
//
// Support: the map points whose nearest element it is, within support_distance_m of it, that are
// neither transient nor outside the compared region. Their signed distances give the numbers a
// Scan-vs-BIM tool reports (mean, the largest in magnitude, RMS), and a consistent offset: the
// translation t that best explains them, r_i ~ n_i . t (r_i the signed distance of point i, n_i the
// outward normal of its nearest triangle), by iteratively reweighted least squares with Cauchy
// weights (scale offset_cauchy_m): A = sum w n n^T, b = sum w n r, t = A^+ b over the directions
// the support constrains (eigenvalues of A >= max(min_constraint, 5 % of the largest)). A wall
// seen from both sides has normals +n and -n, and both faces agree on t along n; along the wall
// nothing constrains t and it stays 0 there.
//
// Verdicts (opaque elements; element_evidence.hpp gives the areas):
//   not_observed   expected area < min_judged_area_m2: too little of it was in view to judge;
//   missing        seen area < missing_seen_fraction x expected area: the beams went through it;
//   deviating      |t| >= deviation_tolerance_m with at least min_support_points;
//   confirmed      otherwise.
// Elements beams pass (doors taken as open, glass) are not judged: not_observed, with their
// support numbers all the same (a door's points may be its frame's or the wall's reveal).
//
// Tolerance verdicts (issue 34, `--tolerance`, elements.csv `tolerance_verdict`): a QA engineer's
// acceptance of each element against a tolerance T of their own, apart from the detector's
// deviation_tolerance_m (which decides what is reported as a deviating change and stays as it
// is): within when the measured deviation |t| <= T, beyond when it is larger or the
// element is missing or moved (turned in place too), not_observed when the element is not_observed
// or its deviation was not measured (fewer than min_support_points support points, or no direction
// constrained).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "algorithms/changes/change_model.hpp"
#include "algorithms/changes/element_evidence.hpp"

namespace bimslam::changes {

enum class Verdict : uint8_t { kConfirmed, kMissing, kDeviating, kNotObserved };
// "confirmed", "missing", "deviating", "not_observed".
std::string_view ToString(Verdict v);

enum class ToleranceVerdict : uint8_t { kWithin, kBeyond, kNotObserved };
// "within", "beyond", "not_observed".
std::string_view ToString(ToleranceVerdict v);

struct ElementCheckConfig {
    double support_distance_m = 0.10;
    double deviation_tolerance_m = 0.02;  // a deviating change: reported, BCF, IFC, history
    double tolerance_m = 0.01;            // the QA tolerance of ToleranceVerdict (`--tolerance`)
    size_t min_support_points = 30;
    double min_judged_area_m2 = 0.25;
    double missing_seen_fraction = 0.25;
    double offset_cauchy_m = 0.02;
    double min_constraint = 10.0;  // weighted points along a direction to constrain it
    void Validate() const;
};

struct ElementReport {
    Verdict verdict = Verdict::kNotObserved;
    ElementEvidence evidence;
    size_t support_points = 0;
    double mean_signed_m = 0;  // mean signed distance of the support
    double max_signed_m = 0;   // the support's signed distance of largest magnitude
    double rms_m = 0;          // of the signed distances
    Eigen::Vector3d offset = Eigen::Vector3d::Zero();  // consistent offset t (metres)
    int constrained_axes = 0;   // 0 ... 3: how many directions of t the support fixes
    double residual_rms_m = 0;  // of r_i - n_i . t
    // Set by the moved-element search (moved_elements.hpp): the rigid motion that puts the
    // element where the session saw it; offset is then its translation.
    bool moved = false;
    double moved_yaw_deg = 0;
    double moved_inlier_fraction = 0;
    int moved_object = -1;  // the new-object cluster it explains
};

// An element's verdict against config.tolerance_m (see above).
ToleranceVerdict JudgeTolerance(const ElementReport& report, const ElementCheckConfig& config);

// The support of every element: the indices of the map points whose nearest triangle (of
// model.mesh; kNoElement for none) belongs to it, within `distance` of it, and `usable` (not
// transient, not part of a new object, inside the compared region).
std::vector<std::vector<uint32_t>> ElementSupport(const ChangeModel& model,
                                                  std::span<const float> signed_m,
                                                  std::span<const uint32_t> triangle,
                                                  std::span<const uint8_t> usable, double distance);

// Per map point its signed distance and nearest triangle; per element its support and evidence.
std::vector<ElementReport> CheckElements(const ChangeModel& model, std::span<const float> signed_m,
                                         std::span<const uint32_t> triangle,
                                         const std::vector<std::vector<uint32_t>>& support,
                                         std::span<const ElementEvidence> evidence,
                                         const ElementCheckConfig& config);

// The unit normal of each triangle of a mesh (counter-clockwise side; zero for degenerate ones).
std::vector<Eigen::Vector3f> FaceNormals(const common::TriangleMesh& mesh);

// The consistent offset of a set of points with signed distances r and normals n (see above).
struct OffsetFit {
    Eigen::Vector3d offset = Eigen::Vector3d::Zero();
    int constrained_axes = 0;
    double residual_rms_m = 0;
};
OffsetFit FitOffset(std::span<const float> r, std::span<const Eigen::Vector3f> n, double cauchy_m,
                    double min_constraint);

}  // namespace bimslam::changes
