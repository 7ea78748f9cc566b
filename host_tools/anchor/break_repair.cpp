// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// A trusted odometry that the joint solution breaks: RepairBreaks (break_repair.hpp) and
// AnchoringProblem::RepairOdometryBreaks, which applies it to every anchored query.
//
// Why: the final graph's odometry edges carry a Cauchy loss (an odometry that lost track for a
// moment must not outvote the loops around it), so a coherent group of wrong loops (keyframes
// that registered at a wrong height beside a table, or slid into a second registration basin)
// can bend an odometry that passed every check (host_tools/anchor/README.md, "A trusted
// odometry broken"). The breaks split the session into pieces the solution places against the
// odometry; one piece's loops are right. Trying each piece as that one and keeping the solution
// that explains the most loops is a consensus over a handful of hypotheses, as RANSAC's.
#include "host_tools/anchor/break_repair.hpp"

#include <algorithm>
#include <cstdio>
#include <numeric>
#include <set>
#include <string>
#include <tuple>

#include "host_tools/anchor/anchoring_problem.hpp"

namespace bimslam::anchor {
namespace {

// Keyframe -> piece: the components of the odometry edges that are not broken.
std::vector<size_t> Pieces(size_t n, const std::vector<io::SessionEdge>& edges,
                           const std::vector<SessionResult::OdometryBreak>& breaks, size_t* count) {
    std::vector<size_t> parent(n);
    std::iota(parent.begin(), parent.end(), size_t(0));
    const auto root = [&](size_t k) {
        while (parent[k] != k) k = parent[k] = parent[parent[k]];
        return k;
    };
    std::set<std::pair<size_t, size_t>> broken;
    for (const SessionResult::OdometryBreak& b : breaks) broken.insert({b.from, b.to});
    for (const io::SessionEdge& e : edges) {
        if (!broken.count({e.from, e.to})) parent[root(e.from)] = root(e.to);
    }
    std::vector<size_t> piece(n), id(n, SIZE_MAX);
    *count = 0;
    for (size_t k = 0; k < n; ++k) {
        size_t& i = id[root(k)];
        if (i == SIZE_MAX) i = (*count)++;
        piece[k] = i;
    }
    return piece;
}

// Whether loop l holds a keyframe of session q outside piece p.
bool OutsidePiece(const LoopRecord& l, size_t q, const std::vector<size_t>& piece, size_t p) {
    return (l.query_session == q && piece[l.query_index] != p) ||
           (l.target_session == q && piece[l.target_index] != p);
}

// Piece p taken as the right one (RepairBreaks).
BreakRepair TryPiece(const std::vector<AnchorSession>& sessions, const std::vector<State>& state,
                     const std::vector<LoopRecord>& loops, size_t q,
                     const std::vector<size_t>& piece, size_t p, const AnchorConfig& config,
                     StageTimes* times) {
    BreakRepair r;
    r.state = state;
    std::vector<LoopRecord> inside;
    for (const LoopRecord& l : loops) {
        if (!OutsidePiece(l, q, piece, p)) inside.push_back(l);
    }
    OptimizeStates(sessions, &r.state, inside, config, times);
    const posegraph::PoseGraph g = BuildGraph(sessions, r.state, loops, config);
    for (size_t k = 0; k < loops.size(); ++k) {
        const LoopRecord& l = loops[k];
        const bool of_q = l.query_session == q || l.target_session == q;
        const bool fits = g.LoopChi2(k) <= config.max_loop_chi2;
        r.explained += of_q && fits;
        (!of_q || fits ? r.kept : r.dropped).push_back(l);
    }
    OptimizeStates(sessions, &r.state, r.kept, config, times);
    r.left = OdometryBreaks(sessions[q], r.state[q].poses, config);
    return r;
}

using LoopKey = std::tuple<size_t, size_t, size_t, size_t, LoopSource>;
LoopKey KeyOf(const LoopRecord& l) {
    return {l.query_session, l.query_index, l.target_session, l.target_index, l.source};
}

}  // namespace

std::optional<BreakRepair> RepairBreaks(const std::vector<AnchorSession>& sessions,
                                        const std::vector<State>& state,
                                        const std::vector<LoopRecord>& loops, size_t q,
                                        const AnchorConfig& config, StageTimes* times) {
    const std::vector<SessionResult::OdometryBreak> found =
        OdometryBreaks(sessions[q], state[q].poses, config);
    if (found.empty()) return std::nullopt;
    size_t count = 0;
    const std::vector<size_t> piece =
        Pieces(sessions[q].poses.size(), sessions[q].session.edges, found, &count);
    if (count < 2) return std::nullopt;
    std::optional<BreakRepair> best;
    for (size_t p = 0; p < count; ++p) {
        BreakRepair r = TryPiece(sessions, state, loops, q, piece, p, config, times);
        if (!best || r.explained > best->explained ||
            (r.explained == best->explained && r.left.size() < best->left.size())) {
            best = std::move(r);
        }
    }
    if (best->dropped.empty() || best->left.size() >= found.size()) return std::nullopt;
    best->found = found;
    return best;
}

bool AnchoringProblem::RepairOdometryBreaks(std::vector<LoopRecord>* loops) {
    bool any = false;
    for (size_t q : Anchored()) {
        if (!sessions_[q].odometry.stretches.empty()) continue;  // not trusted: pieces.hpp
        std::optional<BreakRepair> r = RepairBreaks(sessions_, state_, *loops, q, config_, times());
        if (!r) continue;
        state_ = std::move(r->state);
        *loops = std::move(r->kept);
        Repaired(q, r->found, r->dropped);
        any = true;
    }
    return any;
}

// Session q's result and the loops' records after its repair: the dropped loops are no longer
// accepted, and say why.
void AnchoringProblem::Repaired(size_t q, const std::vector<SessionResult::OdometryBreak>& breaks,
                                const std::vector<LoopRecord>& dropped) {
    SessionResult& r = outcomes_[q - 1].result;
    r.breaks_repaired = breaks;
    r.loops_dropped_at_breaks = dropped.size();
    double worst = 0;
    for (const SessionResult::OdometryBreak& b : breaks) worst = std::max(worst, b.offset_m);
    char why[240];
    std::snprintf(why, sizeof why,
                  "dropped: with it the solution broke the trusted odometry at %zu edge(s), up "
                  "to %.2f m, and without it explained more loops",
                  breaks.size(), worst);
    std::set<LoopKey> gone;
    for (const LoopRecord& l : dropped) gone.insert(KeyOf(l));
    for (QueryOutcome& o : outcomes_) {
        for (LoopRecord& l : o.records) {
            if (!l.accepted || !gone.count(KeyOf(l))) continue;
            l.accepted = false;
            l.reason = why;
            SessionResult& owner = outcomes_[l.query_session - 1].result;
            if (owner.accepted_loops > 0) --owner.accepted_loops;
        }
    }
    std::set<size_t> covered;  // q's keyframes still with an accepted loop
    for (const LoopRecord& l : outcomes_[q - 1].records) {
        if (l.accepted && l.query_session == q) covered.insert(l.query_index);
    }
    r.covered = covered.size();
    std::snprintf(why, sizeof why,
                  "; %zu loop(s) dropped that broke the trusted odometry at %zu edge(s), up to "
                  "%.2f m (anchor.json odometry_breaks_repaired)",
                  dropped.size(), breaks.size(), worst);
    r.reason += why;
}

}  // namespace bimslam::anchor
