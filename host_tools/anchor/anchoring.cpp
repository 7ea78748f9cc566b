// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/anchor/anchoring.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "algorithms/common/status.hpp"
#include "host_tools/anchor/anchor_pieces.hpp"
#include "host_tools/anchor/anchoring_problem.hpp"

namespace bimslam::anchor {
namespace {

// The mean distance between the query's keyframes placed by two anchors.
double MeanDistance(const std::vector<Eigen::Isometry3d>& poses, const Eigen::Isometry3d& a,
                    const Eigen::Isometry3d& b) {
    double sum = 0;
    for (const auto& x : poses) sum += ((a * x).translation() - (b * x).translation()).norm();
    return poses.empty() ? 0 : sum / double(poses.size());
}

std::string Metres(double m) {
    std::ostringstream os;
    os << std::fixed << std::setprecision(1) << m << " m";
    return os.str();
}

std::string Point(const Eigen::Vector2d& p) {
    std::ostringstream os;
    os << std::fixed << std::setprecision(2) << "(" << p.x() << ", " << p.y() << ")";
    return os.str();
}

}  // namespace

std::vector<size_t> RankHypotheses(std::vector<Hypothesis>& hypotheses,
                                   const std::vector<Eigen::Isometry3d>& poses,
                                   const AnchorConfig& config,
                                   const std::optional<StartHint>& start) {
    for (Hypothesis& h : hypotheses) {
        h.off_hint = start && !poses.empty() &&
                     ((h.anchor * poses.front()).translation().head<2>() - start->xy).norm() >
                         start->radius_m;
        // What removed elements explain counts for a placement the user's start hint vouches
        // for only: without one, a storey placed on another that has one more partition looks
        // the same as the right storey with a partition demolished.
        h.contradicted = (start ? h.Unexplained() : h.seen_through) > config.max_seen_through;
    }
    for (Hypothesis& b : hypotheses) {
        for (const Hypothesis& a : hypotheses) {
            if (&a == &b || a.contradicted || b.contradicted || a.off_hint) continue;
            if (double(a.covered) < config.ambiguity_ratio * double(b.covered)) continue;
            if (FreeSpacePrefers(a, b, config)) {
                b.outweighed = true;
            } else if (HeightsPrefer(a, b, poses.size(), config)) {
                b.outweighed = b.outweighed_by_heights = true;
            }
        }
    }
    const auto rank = [&](size_t i) {
        const Hypothesis& h = hypotheses[i];
        return std::make_tuple(!h.contradicted, !h.off_hint, !h.outweighed, h.covered, h.loops);
    };
    std::vector<size_t> order(hypotheses.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return rank(a) > rank(b); });
    return order;
}

Verdict DecideVerdict(const std::vector<Hypothesis>& ranked,
                      const std::vector<Eigen::Isometry3d>& poses, const AnchorConfig& config,
                      std::string* reason, const std::optional<StartHint>& start) {
    const size_t n = poses.size();
    if (ranked.empty()) {
        *reason = "no hypothesis";
        return Verdict::kFailed;
    }
    const Hypothesis& best = ranked[0];
    if (best.contradicted) {
        *reason =
            "every hypothesis (" + std::to_string(ranked.size()) +
            ") is contradicted by free space: the best one's keyframes see through the "
            "model's surfaces with " +
            std::to_string(100 * (start ? best.Unexplained() : best.seen_through)).substr(0, 4) +
            " % of their rays (at most " +
            std::to_string(100 * config.max_seen_through).substr(0, 4) + " %)";
        if (!start && !best.removed_surfaces.empty() &&
            best.seen_through_unexplained <= config.max_seen_through) {
            *reason += "; " + std::to_string(best.removed_surfaces.size()) +
                       " surface(s) of the model, if removed, would explain all but " +
                       std::to_string(100 * best.seen_through_unexplained).substr(0, 4) +
                       " %: if the building changed there since the model, say where the walk "
                       "starts (--near) to accept the placement";
        }
        return Verdict::kFailed;
    }
    if (best.off_hint && start) {
        const Eigen::Vector2d at = (best.anchor * poses.front()).translation().head<2>();
        *reason = "no hypothesis of " + std::to_string(ranked.size()) +
                  " puts the walk's start within " + Metres(start->radius_m) + " of " +
                  Point(start->xy) + " (--near); the best puts it at " + Point(at);
        return Verdict::kFailed;
    }
    const double min_cover = std::max(double(config.min_loops), config.min_coverage * double(n));
    if (double(best.covered) < min_cover || int(best.loops) < config.min_loops) {
        *reason = "the best hypothesis explains " + std::to_string(best.covered) + " of " +
                  std::to_string(n) + " keyframes with " + std::to_string(best.loops) +
                  " loops, fewer than " + std::to_string(int(std::ceil(min_cover))) +
                  " keyframes or " + std::to_string(config.min_loops) + " loops";
        return Verdict::kFailed;
    }
    if (ranked.size() > 1 && !ranked[1].contradicted && !ranked[1].off_hint &&
        !ranked[1].outweighed) {
        const Hypothesis& rival = ranked[1];
        const double dist = MeanDistance(poses, best.anchor, rival.anchor);
        const double turn =
            common::RotationAngle(best.anchor.inverse() * rival.anchor) * 180 / M_PI;
        const bool distinct = dist > config.distinct_m || turn > config.distinct_deg;
        if (distinct && double(rival.covered) >= config.ambiguity_ratio * double(best.covered)) {
            *reason = "two hypotheses explain the loops about equally well: " +
                      std::to_string(best.covered) + " and " + std::to_string(rival.covered) +
                      " keyframes, " + std::to_string(dist).substr(0, 5) + " m and " +
                      std::to_string(turn).substr(0, 5) + " deg apart";
            return Verdict::kAmbiguous;
        }
    }
    return Verdict::kAnchored;
}

Verdict CombinePieces(const std::vector<Verdict>& pieces) {
    Verdict v = Verdict::kFailed;
    for (const Verdict p : pieces) {
        if (p == Verdict::kAnchored) return Verdict::kAnchoredInParts;
        if (p == Verdict::kAmbiguous) v = Verdict::kAmbiguous;
    }
    return v;
}

int Severity(Verdict v) {
    switch (v) {
        case Verdict::kAnchored:
            return 0;
        case Verdict::kAnchoredInParts:
            return 1;
        case Verdict::kAmbiguous:
            return 2;
        case Verdict::kFailed:
            return 3;
    }
    return 3;
}

bool FreeSpacePrefers(const Hypothesis& a, const Hypothesis& b, const AnchorConfig& config) {
    return config.FreeSpacePrefers(a.seen_through, b.seen_through, !b.removed_surfaces.empty());
}

bool HeightsPrefer(const Hypothesis& a, const Hypothesis& b, size_t keyframes,
                   const AnchorConfig& config) {
    return config.HeightsPrefer(a.floating, b.floating, keyframes, size_t(config.min_loops));
}

std::string_view ToString(Verdict v) {
    switch (v) {
        case Verdict::kAnchored:
            return "anchored";
        case Verdict::kAnchoredInParts:
            return "anchored-in-parts";
        case Verdict::kAmbiguous:
            return "ambiguous";
        case Verdict::kFailed:
            return "failed";
    }
    return "?";
}

std::string_view ToString(LoopSource s) {
    switch (s) {
        case LoopSource::kScanContext:
            return "scancontext";
        case LoopSource::kProximity:
            return "proximity";
        case LoopSource::kInjected:
            return "injected";
    }
    return "?";
}

AnchorResult Anchor(const std::vector<AnchorSession>& sessions, const AnchorConfig& config,
                    const Progress& progress) {
    config.Validate();
    if (sessions.size() < 2 || sessions[1].earlier) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            "Anchor: a reference and at least one query session");
    }
    for (size_t s = 1; s + 1 < sessions.size(); ++s) {
        if (sessions[s].earlier && !sessions[s + 1].earlier) {
            throw common::Error(common::StatusCode::kInvalidArgument,
                                "Anchor: earlier visits' sessions come after every query");
        }
    }
    bool split = false;
    for (size_t q = 1; q < sessions.size(); ++q)
        split = split || !sessions[q].odometry.stretches.empty();
    if (!split) {
        AnchorResult r = AnchoringProblem(sessions, config, progress).Solve();
        for (SessionResult& s : r.sessions)
            s.placed.assign(s.keyframes, s.verdict == Verdict::kAnchored);
        return r;
    }
    const SplitQueries parts = SplitAtUntrustedOdometry(sessions);
    return MergePieces(sessions, parts, AnchoringProblem(parts.sessions, config, progress).Solve());
}

}  // namespace bimslam::anchor
