// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// bimslam anchor: query sessions moved into the BIM reference session's frame, with no initial
// pose (host_tools/anchor: place recognition, registration, consistency, pose graph).
#include <cmath>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "algorithms/common/status.hpp"
#include "host_tools/anchor/anchor_output.hpp"
#include "host_tools/anchor/anchoring.hpp"
#include "host_tools/cli/command.hpp"
#include "host_tools/cli/progress.hpp"

namespace bimslam::cli {
namespace {
namespace fs = std::filesystem;

struct AnchorArgs {
    std::string reference;
    std::vector<std::string> queries;
    std::vector<std::string> earlier;  // --prior-session
    std::string out;
    std::string outliers = "pcm";
    double inject_false_loops = 0;
    double model_tolerance_m = anchor::AnchorConfig{}.model_tolerance_m;
    std::vector<double> near;  // x y [radius]
    int threads = 0;
    uint64_t seed = 1;
    bool overwrite = false;
    bool json = false;
};

void PrintAnchor(const std::string& label, const anchor::SessionResult& s) {
    const Eigen::Vector3d t = s.anchor.translation();
    std::cout << "  " << label << ": t = (" << t.x() << ", " << t.y() << ", " << t.z()
              << ") m, yaw "
              << std::atan2(s.anchor.linear()(1, 0), s.anchor.linear()(0, 0)) * 180 / M_PI << " deg"
              << (s.via_other_sessions ? " (through other sessions)" : "") << "\n";
}

int AnchorMain(const AnchorArgs& a) {
    anchor::AnchorConfig config;
    if (!anchor::ParseOutlierMethod(a.outliers, &config.outliers)) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            "--outliers " + a.outliers + ": expected pcm, gnc or none");
    }
    config.inject_false_loops = a.inject_false_loops;
    // The rotation part: the angle the tolerance subtends over 6 m, a room's size.
    config.model_tolerance_m = a.model_tolerance_m;
    config.model_tolerance_deg = std::atan2(a.model_tolerance_m, 6.0) * 180.0 / M_PI;
    config.threads = a.threads;
    config.seed = a.seed;
    std::optional<anchor::StartHint> start;
    if (!a.near.empty()) start = anchor::StartHint::FromList(a.near);
    config.Validate();
    if (fs::exists(a.out) && !fs::is_empty(a.out) && !a.overwrite) {
        throw common::FileError(common::StatusCode::kAlreadyExists, a.out, 0,
                                "exists and is not empty (--overwrite replaces it)");
    }
    ProgressBar bar(!a.json && ProgressBar::Terminal());
    anchor::LoadOptions lo;
    lo.cloud = config.cloud;
    lo.descriptor = config.descriptor;
    lo.threads = a.threads;
    std::vector<anchor::AnchorSession> sessions;
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<std::string> dirs{a.reference};
    dirs.insert(dirs.end(), a.queries.begin(), a.queries.end());
    for (size_t k = 0; k < dirs.size(); ++k) {
        bar.Update("reading " + fs::path(dirs[k]).filename().string(),
                   double(k) / double(dirs.size()));
        sessions.push_back(anchor::LoadAnchorSession(dirs[k], lo));
        if (k > 0) sessions.back().start = start;  // the queries'
    }
    for (const std::string& dir : a.earlier) {
        bar.Update("reading " + fs::path(dir).filename().string(), 1.0);
        sessions.push_back(anchor::LoadEarlierSession(dir, lo));
    }
    // Two queries of one name would write to one folder: name them apart.
    for (size_t k = 1; k < sessions.size(); ++k) {
        for (size_t o = 1; o < k; ++o) {
            if (sessions[o].name == sessions[k].name) sessions[k].name += "_" + std::to_string(k);
        }
    }
    const double load_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    anchor::AnchorResult r =
        anchor::Anchor(sessions, config, [&](const std::string& s, size_t d, size_t n) {
            bar.Update(s, n ? double(d) / double(n) : 0.0);
        });
    r.times.descriptors_s = load_s;
    bar.Update("writing " + a.out, 0.0);
    const std::vector<fs::path> written =
        anchor::WriteAnchorOutput(a.out, sessions, r, config, a.overwrite);
    bar.Clear();
    const size_t first_earlier = sessions.size() - r.earlier.size();

    bool all = true;
    for (const auto& s : r.sessions) all = all && s.verdict == anchor::Verdict::kAnchored;
    if (a.json) {
        std::cout << anchor::AnchorSummaryJson(sessions, r, config);
        return all ? kExitOk : kExitFailure;
    }
    std::cout << std::fixed << std::setprecision(1);
    std::cout << "reference  " << a.reference << ": " << sessions[0].keyframes() << " keyframes\n";
    for (size_t q = 0; q < r.sessions.size(); ++q) {
        const anchor::SessionResult& s = r.sessions[q];
        for (const std::string& n : sessions[q + 1].notes)
            std::cout << "note       " << s.name << ": " << n << "\n";
        std::cout << "query      " << s.name << ": " << s.keyframes << " keyframes, "
                  << s.candidates << " Scan Context candidates registered, " << s.verified
                  << " verified\n";
        std::cout << "  " << anchor::ToString(s.verdict) << ": " << s.reason << "\n";
        if (s.verdict == anchor::Verdict::kAnchored) PrintAnchor("T_bim_" + s.name, s);
        for (const anchor::PieceResult& p : s.pieces) {
            const std::string span =
                std::to_string(p.span.first) + "-" + std::to_string(p.span.last);
            std::cout << "  piece " << span << ": " << anchor::ToString(p.result.verdict) << ": "
                      << p.result.reason << "\n";
            if (p.result.verdict == anchor::Verdict::kAnchored)
                PrintAnchor("  T_bim_" + s.name + "[" + span + "]", p.result);
        }
        if (!s.inside.empty()) {
            std::cout << "  not placed: " << s.inside.size()
                      << " keyframes inside the odometry's failed stretches (";
            for (size_t k = 0; k < s.inside.size() && k < 20; ++k)
                std::cout << (k ? " " : "") << s.inside[k];
            std::cout << (s.inside.size() > 20 ? " ...)\n" : ")\n");
        }
        for (size_t h = 0; h < s.hypotheses.size() && s.verdict == anchor::Verdict::kAmbiguous;
             ++h) {
            const Eigen::Vector3d t = s.hypotheses[h].anchor.translation();
            std::cout << "  hypothesis " << h << ": " << s.hypotheses[h].covered
                      << " keyframes, t = (" << t.x() << ", " << t.y() << ", " << t.z() << ")\n";
        }
    }
    for (size_t e = 0; e < r.earlier.size(); ++e) {
        const anchor::EarlierResult& x = r.earlier[e];
        std::cout << "earlier    " << x.name << " (" << sessions[first_earlier + e].dir.string()
                  << "): " << x.keyframes << " keyframes, " << x.accepted_loops
                  << " loops to it accepted, moved at most " << std::setprecision(1)
                  << 100 * x.max_move_m << " cm from its prior\n";
    }
    const anchor::StageTimes& t = r.times;
    std::cout << std::setprecision(2) << "time       " << t.descriptors_s << " s reading (clouds, "
              << "descriptors), " << t.map_s << " s maps, " << t.candidates_s << " s candidates, "
              << t.registration_s << " s registration (" << t.registrations << "), "
              << t.consistency_s << " s consistency, " << t.optimisation_s << " s optimisation\n";
    std::cout << "wrote      " << a.out << "/: anchor.json, loops.json, posegraph.g2o";
    for (const fs::path& p : written) std::cout << ", " << p.filename().string() << "/";
    std::cout << "\n";
    return all ? kExitOk : kExitFailure;
}

}  // namespace

void AddAnchorCommand(CLI::App& app, int& exit_code) {
    auto args = std::make_shared<AnchorArgs>();
    CLI::App* cmd = app.add_subcommand(
        "anchor",
        "Move query sessions into the BIM reference's frame: no initial pose, robust to wrong "
        "loops (Step 2)");
    cmd->add_option("--reference", args->reference,
                    "The BIM reference session (bimslam bim2session)")
        ->required();
    cmd->add_option("--query", args->queries,
                    "A query session (repeatable): bimslam odometry's, or SC-A-LOAM/LT-mapper's "
                    "layout (Scans/, poses, times)")
        ->required();
    cmd->add_option("--prior-session", args->earlier,
                    "An earlier visit's anchored session in BIM coordinates (repeatable: a folder "
                    "OUT/<name>/ that bimslam anchor or bimslam map wrote): a target with the "
                    "reference, so loops to what it saw anchor walks through what the model lacks; "
                    "held at its poses by a prior (2 cm, 0.2 deg) in the joint solution, not "
                    "rewritten");
    cmd->add_option("-o,--output", args->out, "Output folder")->required();
    cmd->add_option("--outliers", args->outliers,
                    "How wrong loops are rejected: pcm (pairwise consistency), gnc (graduated "
                    "non-convexity) or none (the Cauchy loss only)")
        ->capture_default_str();
    cmd->add_option("--model-tolerance", args->model_tolerance_m,
                    "How far (m) the building may stand from its model (construction "
                    "tolerance): added to every loop's uncertainty so walls built off do not bend "
                    "the trajectory; 0 trusts the model exactly")
        ->check(CLI::Range(0.0, 1.0))
        ->capture_default_str();
    cmd->add_option("--near", args->near,
                    "X Y [R]: where the walks start, in model metres, when you know it (within R, "
                    "default 3 m): hypotheses that put a query's first keyframe farther away are "
                    "set aside. For buildings of identical parts (two dwellings one turned 180 "
                    "degrees), where a walk in one fits the other as well and is otherwise "
                    "ambiguous. A placement the hint vouches for may also see through one or two "
                    "walls of the model that were taken away since (anchor.json's "
                    "removed_surfaces); without it those rays contradict the placement")
        ->expected(2, 3);
    cmd->add_option("--inject-false-loops", args->inject_false_loops,
                    "Benchmarks: replace this share of the verified loops by wrong pairs")
        ->check(CLI::Range(0.0, 0.95));
    cmd->add_option("--seed", args->seed, "Seed of --inject-false-loops")->capture_default_str();
    cmd->add_option("--threads", args->threads, "Threads (0: all cores)")->capture_default_str();
    cmd->add_flag("--overwrite", args->overwrite, "Replace an existing output folder");
    cmd->add_flag("--json", args->json, "Print anchor.json instead of the summary");
    cmd->footer(
        "Writes OUT/anchor.json (the verdict per query: anchored, anchored-in-parts, ambiguous or "
        "failed, with the numbers behind it), OUT/loops.json (every loop candidate, accepted or "
        "rejected and why), OUT/posegraph.g2o (multi-session graph), and per anchored query "
        "OUT/<name>/: the session with world frame 'bim' and trajectory_bim.tum (every scan). "
        "A query whose odometry failed somewhere (the odometry_verdict.json that bimslam odometry "
        "writes into the session says untrusted, with its failed stretches) is split at those "
        "stretches into pieces anchored on their own; keyframes inside a stretch are not placed, "
        "and the best it gets is anchored-in-parts, each piece with its verdict (OUT/<name>/ "
        "then holds the anchored pieces' keyframes only). Exit 0 when every query is anchored, "
        "1 when one is anchored-in-parts, ambiguous or failed, 2 for bad or damaged input "
        "(host_tools/anchor/README.md).");
    cmd->callback([args, &exit_code] { exit_code = Run([&] { return AnchorMain(*args); }); });
}

}  // namespace bimslam::cli
