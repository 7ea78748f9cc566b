// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// bimslam evaluate: the accuracy of an estimated trajectory against a reference, both TUM files
// (host_tools/evaluation/trajectory_metrics.hpp; the metrics follow evo).
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "host_tools/cli/command.hpp"
#include "host_tools/evaluation/trajectory_metrics.hpp"

namespace bimslam::cli {
namespace {

struct EvaluateArgs {
    std::string est;
    std::string ref;
    std::string est_times, ref_times;  // KITTI poses' times files
    std::string align = "se3";
    double max_dt_ms = 10.0;
    double rpe_delta_m = 1.0;
    double drift_segment_m = 10.0;
    bool json = false;
};

// Centimetres for the table; "n/a" where there was nothing to measure (NaN).
std::string Cm(double m) {
    if (std::isnan(m)) return "n/a";
    std::ostringstream s;
    s << std::fixed << std::setprecision(2) << 100.0 * m << " cm";
    return s.str();
}

std::string FixedOrNa(double v, int digits, const std::string& unit) {
    if (std::isnan(v)) return "n/a";
    std::ostringstream s;
    s << std::fixed << std::setprecision(digits) << v << unit;
    return s.str();
}

std::string Number(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

// A row label padded to the table's first column (12 characters, at least one space).
std::string Label(std::string label) {
    label.resize(std::max<size_t>(label.size() + 1, 12), ' ');
    return label;
}

void PrintJson(const EvaluateArgs& a, const evaluation::EvaluationResult& r) {
    // NaN (no RPE pair, no drift segment) is written as null.
    const auto or_null = [](const std::string& s) {
        return s.empty() ? nlohmann::json(nullptr) : nlohmann::json(s);
    };
    const nlohmann::json j = {{"est", a.est},
                              {"ref", a.ref},
                              {"est_times", or_null(a.est_times)},
                              {"ref_times", or_null(a.ref_times)},
                              {"est_poses", r.est_poses},
                              {"ref_poses", r.ref_poses},
                              {"matched", r.matched},
                              {"max_dt_ms", a.max_dt_ms},
                              {"align", evaluation::ToString(r.align)},
                              {"alignment_degenerate", r.alignment.degenerate},
                              {"ape_trans_rmse_m", r.ape_trans_m.rmse},
                              {"ape_trans_mean_m", r.ape_trans_m.mean},
                              {"ape_trans_median_m", r.ape_trans_m.median},
                              {"ape_trans_std_m", r.ape_trans_m.std},
                              {"ape_trans_min_m", r.ape_trans_m.min},
                              {"ape_trans_max_m", r.ape_trans_m.max},
                              {"ape_rot_rmse_deg", r.ape_rot_deg.rmse},
                              {"ape_rot_max_deg", r.ape_rot_deg.max},
                              {"rpe_delta_m", r.rpe_delta_m},
                              {"rpe_pairs", r.rpe_trans_m.count},
                              {"rpe_trans_rmse_m", r.rpe_trans_m.rmse},
                              {"rpe_trans_mean_m", r.rpe_trans_m.mean},
                              {"rpe_trans_max_m", r.rpe_trans_m.max},
                              {"rpe_rot_rmse_deg", r.rpe_rot_deg.rmse},
                              {"drift_percent", r.drift_percent},
                              {"drift_segment_m", r.drift_segment_m},
                              {"drift_segment_shortened", r.drift_segment_shortened},
                              {"drift_segments", r.drift_segments},
                              {"distance_m", r.distance_m},
                              {"duration_s", r.duration_s}};
    std::cout << j.dump(2) << "\n";
}

void PrintTable(const EvaluateArgs& a, const evaluation::EvaluationResult& r) {
    const auto& t = r.ape_trans_m;
    std::cout << "matched     " << r.matched << " poses of est " << r.est_poses << " / ref "
              << r.ref_poses << " (within " << a.max_dt_ms << " ms), align "
              << evaluation::ToString(r.align) << "\n"
              << "APE trans   rmse " << Cm(t.rmse) << ", mean " << Cm(t.mean) << ", median "
              << Cm(t.median) << ", max " << Cm(t.max) << "\n"
              << "APE rot     rmse " << FixedOrNa(r.ape_rot_deg.rmse, 3, " deg") << ", max "
              << FixedOrNa(r.ape_rot_deg.max, 3, " deg") << "\n"
              << Label("RPE " + Number(r.rpe_delta_m) + " m") << "trans rmse "
              << Cm(r.rpe_trans_m.rmse) << ", mean " << Cm(r.rpe_trans_m.mean) << ", max "
              << Cm(r.rpe_trans_m.max) << "; rot rmse " << FixedOrNa(r.rpe_rot_deg.rmse, 3, " deg")
              << " (" << r.rpe_trans_m.count << " pairs)\n"
              << "drift       " << FixedOrNa(r.drift_percent, 2, " %") << " over "
              << FixedOrNa(r.drift_segment_m, 1, " m") << " segments (" << r.drift_segments << ")"
              << (r.drift_segment_shortened
                      ? ": the path is shorter than " + FixedOrNa(a.drift_segment_m, 1, " m") +
                            ", so the whole path is one segment"
                      : "")
              << "\n"
              << "distance    " << FixedOrNa(r.distance_m, 2, " m") << " in "
              << FixedOrNa(r.duration_s, 2, " s") << " (reference, matched poses)\n";
    if (r.alignment.degenerate) {
        std::cout << "note        the matched positions lie on a line (or a point): the se3 "
                     "alignment's rotation about it is arbitrary, so APE rotation means little; "
                     "try --align none\n";
    }
}

int Evaluate(const EvaluateArgs& a) {
    evaluation::EvaluationConfig config;
    config.align = a.align == "none" ? evaluation::Alignment::kNone : evaluation::Alignment::kSe3;
    config.max_dt_ns = std::llround(a.max_dt_ms * 1e6);
    config.rpe_delta_m = a.rpe_delta_m;
    config.drift_segment_m = a.drift_segment_m;
    const evaluation::EvaluationResult r =
        evaluation::EvaluateFiles(a.est, a.ref, config, a.est_times, a.ref_times);
    if (a.json) {
        PrintJson(a, r);
    } else {
        PrintTable(a, r);
    }
    return kExitOk;
}

}  // namespace

void AddEvaluateCommand(CLI::App& app, int& exit_code) {
    auto a = std::make_shared<EvaluateArgs>();
    CLI::App* cmd = app.add_subcommand(
        "evaluate",
        "trajectory accuracy of an estimate against a reference (TUM files, or KITTI poses with "
        "a times file), as evo (github.com/MichaelGrupp/evo) computes it. Exit 2 on a malformed "
        "file or fewer than 3 poses matched in time");
    cmd->add_option("--est", a->est,
                    "estimated trajectory: TUM (t x y z qx qy qz qw), or KITTI (12 numbers a "
                    "line, row-major 3x4) with --est-times")
        ->required();
    cmd->add_option("--ref", a->ref,
                    "reference trajectory, e.g. ground_truth.tum: TUM, or KITTI with --ref-times")
        ->required();
    cmd->add_option("--est-times", a->est_times,
                    "times of --est's KITTI poses: one time (seconds) a line, line i for pose i, "
                    "as KITTI's times.txt");
    cmd->add_option("--ref-times", a->ref_times, "times of --ref's KITTI poses, as --est-times");
    cmd->add_option("--align", a->align,
                    "se3: rigid least-squares alignment of est onto ref first (Umeyama 1991, "
                    "evo's --align); none: compare as given")
        ->check(CLI::IsMember({"none", "se3"}))
        ->capture_default_str();
    cmd->add_option("--max-dt-ms", a->max_dt_ms,
                    "largest time difference of an est/ref pose pair (evo's --t_max_diff)")
        ->check(CLI::Range(0.0, 3.6e6))
        ->capture_default_str();
    cmd->add_option("--rpe-delta-m", a->rpe_delta_m, "RPE pair spacing along the reference path")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    cmd->add_option("--drift-segment-m", a->drift_segment_m,
                    "drift segment length (the whole path when shorter)")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    cmd->add_flag("--json", a->json, "print one JSON object instead of the table");
    cmd->footer(
        "Metrics (host_tools/evaluation/README.md has the formulas):\n"
        "  APE trans  ||t_ref - t_est|| per matched pose after alignment: rmse, mean, median, max "
        "(evo_ape -r trans_part)\n"
        "  APE rot    angle of R_ref^T R_est per matched pose, degrees: rmse, max (evo_ape -r "
        "angle_deg)\n"
        "  RPE        error of the relative motion over --rpe-delta-m of reference path, from "
        "every pose: ||t(E)|| and angle(E), E = (ref_i^-1 ref_j)^-1 (est_i^-1 est_j) (evo_rpe "
        "--delta_unit m)\n"
        "  drift      relative translation error over --drift-segment-m of path, in % of the "
        "path travelled, mean over every start (KITTI odometry, Geiger et al. 2012)\n"
        "  distance   path length and duration of the matched reference poses\n"
        "KITTI poses are given times (evo_ape kitti pairs two KITTI files by line instead) and\n"
        "are then associated in time like TUM poses, e.g. a KITTI sequence's ground truth:\n"
        "  bimslam evaluate --est est.tum --ref poses/00.txt --ref-times sequences/00/times.txt\n");
    cmd->callback([a, &exit_code] { exit_code = Run([&] { return Evaluate(*a); }); });
}

}  // namespace bimslam::cli
