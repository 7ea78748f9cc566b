// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Trajectory accuracy: an estimated trajectory against a reference (ground truth), both TUM files.
// The metrics follow evo (Grupp, github.com/MichaelGrupp/evo: evo_ape, evo_rpe) so that figures can
// be checked against it; drift follows the KITTI odometry benchmark (Geiger et al., CVPR 2012).
// host_tools/evaluation/README.md gives the formulas and where they differ from evo.
#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "algorithms/io/trajectory.hpp"

namespace bimslam::evaluation {

// evo's default --t_max_diff (0.01 s).
inline constexpr int64_t kDefaultMaxDtNs = 10'000'000;

// An estimated pose and the reference pose it is compared with (indices into the inputs).
struct MatchedPair {
    size_t est = 0;
    size_t ref = 0;
    bool operator==(const MatchedPair&) const = default;
};

// Pairs each estimated pose with the reference pose nearest in time, if within max_dt_ns. A
// reference pose is used at most once: pairs are taken greedily, smallest time difference first
// (ties: earlier estimate first), as TUM's associate.py does. Both inputs must be sorted by time
// (io::ReadTum guarantees it). The result is sorted by estimate index.
std::vector<MatchedPair> Associate(const std::vector<io::StampedPose>& est,
                                   const std::vector<io::StampedPose>& ref,
                                   int64_t max_dt_ns = kDefaultMaxDtNs);

// The least-squares rigid transform (no scale) taking `est` positions onto `ref` positions
// (Umeyama 1991; evo's align with correct_scale=false).
struct RigidAlignment {
    Eigen::Isometry3d T_ref_est = Eigen::Isometry3d::Identity();
    // The positions are all equal or on one line: the rotation about that line is arbitrary, so
    // rotation errors after alignment mean nothing (evo has the same blind spot).
    bool degenerate = false;
};
RigidAlignment AlignUmeyama(const std::vector<Eigen::Vector3d>& est,
                            const std::vector<Eigen::Vector3d>& ref);

enum class Alignment { kNone, kSe3 };
std::string_view ToString(Alignment a);

// Summary of a set of errors, as evo reports them (std is the population standard deviation).
// With no values every figure is NaN and count is 0.
struct ErrorStats {
    size_t count = 0;
    double rmse = 0.0, mean = 0.0, median = 0.0, std = 0.0, min = 0.0, max = 0.0;
};
ErrorStats ComputeStats(std::vector<double> values);

struct EvaluationConfig {
    Alignment align = Alignment::kSe3;
    int64_t max_dt_ns = kDefaultMaxDtNs;
    double rpe_delta_m = 1.0;       // RPE pair spacing along the reference path
    double drift_segment_m = 10.0;  // KITTI-style segment length for drift
    // Throws common::Error (kInvalidArgument) naming the field and value.
    void Validate() const;
};

struct EvaluationResult {
    size_t est_poses = 0, ref_poses = 0, matched = 0;
    Alignment align = Alignment::kSe3;
    RigidAlignment alignment;  // identity for Alignment::kNone
    ErrorStats ape_trans_m;    // ||t_ref - t_est_aligned|| per matched pose
    ErrorStats ape_rot_deg;    // angle of R_ref^T R_est_aligned per matched pose
    double rpe_delta_m = 0.0;
    ErrorStats rpe_trans_m;        // ||t(E)|| per pair, E = (ref_i^-1 ref_j)^-1 (est_i^-1 est_j)
    ErrorStats rpe_rot_deg;        // angle of E per pair
    double drift_segment_m = 0.0;  // the segment length used
    // The reference path is shorter than the requested segment, so the whole path was used.
    bool drift_segment_shortened = false;
    size_t drift_segments = 0;
    double drift_percent = 0.0;  // mean over segments; NaN when there is none
    double distance_m = 0.0;     // path length of the matched reference poses
    double duration_s = 0.0;     // time from the first to the last matched reference pose
};

// Associates, aligns and computes every metric. Fewer than 3 matched poses throw common::Error
// (kInvalidArgument) whose message names `est_name`, `ref_name`, the pose counts and the window.
EvaluationResult Evaluate(const std::vector<io::StampedPose>& est,
                          const std::vector<io::StampedPose>& ref, const EvaluationConfig& config,
                          const std::string& est_name = "estimate",
                          const std::string& ref_name = "reference");

// A trajectory file: TUM (`times` empty), or KITTI poses (12 numbers a line, row-major 3x4) with
// a times file (one time in seconds a line, as KITTI's sequences/NN/times.txt), line i of one
// with line i of the other. evo's `evo_ape kitti` has no times and pairs two KITTI files by line
// index; with times, KITTI poses go through the same time association as TUM (evo's `tum`
// reading), so an estimate and a reference of different rates or starts still pair correctly.
// Throws common::FileError naming the file and line; a KITTI file given without times says so
// and names `times_option`.
std::vector<io::StampedPose> ReadTrajectory(const std::filesystem::path& poses,
                                            const std::filesystem::path& times,
                                            const std::string& times_option = "a times file");

// Reads both trajectories (ReadTrajectory) and evaluates.
EvaluationResult EvaluateFiles(const std::filesystem::path& est_path,
                               const std::filesystem::path& ref_path,
                               const EvaluationConfig& config,
                               const std::filesystem::path& est_times = {},
                               const std::filesystem::path& ref_times = {});

}  // namespace bimslam::evaluation
