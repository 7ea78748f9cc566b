#include "host_tools/anchor/anchoring.hpp"

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <optional>
#include <set>

#include "algorithms/common/status.hpp"
#include "algorithms/common/stopwatch.hpp"
#include "algorithms/registration/free_space.hpp"
#include "host_tools/anchor/anchor_pieces.hpp"
#include "host_tools/anchor/graph_state.hpp"
#include "host_tools/anchor/hypothesis.hpp"
#include "host_tools/anchor/place_recognition.hpp"
#include "host_tools/anchor/target.hpp"

namespace bimslam::anchor {
namespace {
using Clock = std::chrono::steady_clock;
using posegraph::PoseGraph;

// The loop whose registration fits best.
const LoopRecord& BestLoop(const std::vector<LoopRecord>& loops) {
    return *std::max_element(loops.begin(), loops.end(), [](const auto& a, const auto& b) {
        return a.registration.fitness.inlier_ratio < b.registration.fitness.inlier_ratio;
    });
}

// The mean distance between the query's keyframes placed by two anchors.
double MeanDistance(const std::vector<Eigen::Isometry3d>& poses, const Eigen::Isometry3d& a,
                    const Eigen::Isometry3d& b) {
    double sum = 0;
    for (const auto& x : poses) sum += ((a * x).translation() - (b * x).translation()).norm();
    return poses.empty() ? 0 : sum / double(poses.size());
}

struct QueryOutcome {
    SessionResult result;
    std::vector<LoopRecord> records;  // every candidate, with its verdict
    std::vector<LoopRecord> accepted;
    State state;
};

// Steps 1-4 for one query session against a target.
QueryOutcome AnchorQuery(const std::vector<AnchorSession>& sessions,
                         const std::vector<State>& state, size_t q, const Target& target,
                         const AnchorConfig& config, StageTimes* times, const Progress& progress) {
    QueryOutcome out;
    const AnchorSession& query = sessions[q];
    SessionResult& res = out.result;
    res.name = query.name;
    res.keyframes = query.keyframes();
    if (progress) progress("place recognition: " + query.name, 0, query.keyframes());
    out.records = FindPlaceLoops(sessions, q, target, config, times);
    InjectFalseLoops(sessions, q, target, config, &out.records, times);
    res.candidates = out.records.size();
    std::vector<size_t> verified;
    for (size_t k = 0; k < out.records.size(); ++k) {
        if (out.records[k].verified) verified.push_back(k);
    }
    res.verified = verified.size();
    if (progress)
        progress("place recognition: " + query.name, query.keyframes(), query.keyframes());

    // Hypotheses: cliques of consistent loops (PCM), or all verified loops together (GNC, none).
    const auto t0 = Clock::now();
    std::vector<std::vector<size_t>> cliques;
    if (config.outliers == OutlierMethod::kPcm) {
        cliques = ConsistentHypotheses(out.records, verified, sessions, config);
    } else if (int(verified.size()) >= config.min_clique) {
        cliques.push_back(verified);
    }
    times->consistency_s += common::SecondsSince(t0);
    for (auto& r : out.records) {
        if (r.verified) r.reason = "not in a consistent set of loops";
    }

    std::vector<Evaluation> evals;
    for (size_t h = 0; h < cliques.size(); ++h) {
        std::vector<LoopRecord> seeds;
        for (size_t k : cliques[h]) {
            out.records[k].hypothesis = int(h);
            out.records[k].reason = "hypothesis " + std::to_string(h) + " (rejected)";
            seeds.push_back(out.records[k]);
        }
        const Eigen::Isometry3d anchor = ImpliedAnchor(BestLoop(seeds), sessions);
        if (config.outliers == OutlierMethod::kGnc) {
            std::vector<State> st = state;
            st[q] = {anchor, query.poses, false};
            const auto tg = Clock::now();
            const std::vector<double> w = GncWeights(sessions, &st, seeds, config, times);
            times->consistency_s += common::SecondsSince(tg);
            std::vector<LoopRecord> kept;
            for (size_t k = 0; k < seeds.size(); ++k) {
                LoopRecord& r = out.records[cliques[h][k]];
                if (w[k] >= 0.5) {
                    kept.push_back(seeds[k]);
                } else {
                    r.hypothesis = -1;
                    r.reason = "rejected by GNC: weight " + std::to_string(w[k]).substr(0, 4);
                }
            }
            if (int(kept.size()) < config.min_clique) continue;
            evals.push_back(
                FollowHypothesis(sessions, state, q, target, kept, st[q].anchor, config, times));
        } else {
            evals.push_back(
                FollowHypothesis(sessions, state, q, target, seeds, anchor, config, times));
        }
        evals.back().clique = int(h);
        evals.back().hypothesis.clique_index = int(h);
        if (progress) progress("hypotheses: " + query.name, h + 1, cliques.size());
    }
    // Free space marks and ranks the hypotheses; the verdict follows from the best two.
    std::vector<Hypothesis> hypotheses;
    for (const Evaluation& e : evals) hypotheses.push_back(e.hypothesis);
    const std::vector<size_t> order = RankHypotheses(hypotheses, config);
    std::vector<Evaluation> ranked;
    for (size_t i : order) {
        ranked.push_back(std::move(evals[i]));
        ranked.back().hypothesis = hypotheses[i];
        res.hypotheses.push_back(hypotheses[i]);
    }
    evals = std::move(ranked);

    res.verdict = DecideVerdict(res.hypotheses, query.poses, config, &res.reason);
    if (evals.empty()) {
        res.reason = "no set of at least " + std::to_string(config.min_clique) +
                     " mutually consistent loops among " + std::to_string(verified.size()) +
                     " verified of " + std::to_string(out.records.size()) + " candidates";
    }
    if (res.verdict != Verdict::kAnchored) return out;
    const size_t n = query.keyframes();
    const Evaluation& best = evals[0];
    res.verdict = Verdict::kAnchored;
    res.anchor = best.hypothesis.anchor;
    res.world_poses = best.query.World();
    res.accepted_loops = best.accepted.size();
    res.covered = best.hypothesis.covered;
    const auto percent = [](double r) { return std::to_string(100 * r).substr(0, 4) + " %"; };
    res.reason = std::to_string(best.hypothesis.loops) + " loops on " +
                 std::to_string(best.hypothesis.covered) + " of " + std::to_string(n) +
                 " keyframes, mean inlier ratio " +
                 std::to_string(best.hypothesis.mean_inlier_ratio).substr(0, 4) + ", " +
                 percent(best.hypothesis.seen_through) + " of rays through the model; ";
    if (evals.size() == 1) {
        res.reason += "no rival hypothesis";
    } else {
        const Hypothesis& next = evals[1].hypothesis;
        res.reason +=
            "the next hypothesis explains " + std::to_string(next.covered) +
            (next.contradicted ? " and is contradicted (" + percent(next.seen_through) + ")"
             : next.outweighed ? " and is outweighed by free space (" + percent(next.seen_through) +
                                     " of rays through the model)"
                               : std::string());
    }
    out.state = best.query;
    out.accepted = best.accepted;
    // Records: accepted place-recognition loops and every proximity loop of the chosen one.
    std::set<std::pair<size_t, size_t>> accepted_pr;
    for (const LoopRecord& l : best.accepted) {
        if (l.source != LoopSource::kProximity) accepted_pr.insert({l.query_index, l.target_index});
    }
    for (LoopRecord& r : out.records) {
        if (accepted_pr.count({r.query_index, r.target_index}) && r.verified) {
            r.accepted = true;
            r.reason = "accepted";
        } else if (r.verified && r.hypothesis == best.clique) {
            r.reason = "consistent; superseded by a proximity loop of the same keyframe";
        }
    }
    for (LoopRecord l : best.accepted) {
        if (l.source != LoopSource::kProximity) continue;
        l.accepted = true;
        l.reason = "accepted";
        out.records.push_back(l);
    }
    for (const LoopRecord& l : best.rejected) out.records.push_back(l);
    return out;
}

}  // namespace

std::vector<size_t> RankHypotheses(std::vector<Hypothesis>& hypotheses,
                                   const AnchorConfig& config) {
    for (Hypothesis& h : hypotheses) h.contradicted = h.seen_through > config.max_seen_through;
    for (Hypothesis& b : hypotheses) {
        for (const Hypothesis& a : hypotheses) {
            if (&a == &b || a.contradicted || b.contradicted) continue;
            if (double(a.covered) >= config.ambiguity_ratio * double(b.covered) &&
                FreeSpacePrefers(a, b, config)) {
                b.outweighed = true;
            }
        }
    }
    const auto rank = [&](size_t i) {
        const Hypothesis& h = hypotheses[i];
        return std::make_tuple(!h.contradicted, !h.outweighed, h.covered, h.loops);
    };
    std::vector<size_t> order(hypotheses.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return rank(a) > rank(b); });
    return order;
}

Verdict DecideVerdict(const std::vector<Hypothesis>& ranked,
                      const std::vector<Eigen::Isometry3d>& poses, const AnchorConfig& config,
                      std::string* reason) {
    const size_t n = poses.size();
    if (ranked.empty()) {
        *reason = "no hypothesis";
        return Verdict::kFailed;
    }
    const Hypothesis& best = ranked[0];
    if (best.contradicted) {
        *reason = "every hypothesis (" + std::to_string(ranked.size()) +
                  ") is contradicted by free space: the best one's keyframes see through the "
                  "model's surfaces with " +
                  std::to_string(100 * best.seen_through).substr(0, 4) +
                  " % of their rays (at most " +
                  std::to_string(100 * config.max_seen_through).substr(0, 4) + " %)";
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
    if (ranked.size() > 1 && !ranked[1].contradicted && !ranked[1].outweighed) {
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
    return a.seen_through * config.outweigh_ratio <= b.seen_through &&
           b.seen_through - a.seen_through >= config.outweigh_gap;
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

namespace {

// Steps 1-6 (anchoring.hpp) for sessions that are each anchored whole.
AnchorResult AnchorWhole(const std::vector<AnchorSession>& sessions, const AnchorConfig& config,
                         const Progress& progress) {
    std::unique_ptr<tbb::global_control> limit;
    if (config.threads > 0) {
        limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                      size_t(config.threads));
    }
    const auto t_start = Clock::now();
    AnchorResult result;
    StageTimes& times = result.times;
    std::vector<State> state(sessions.size());
    for (size_t s = 0; s < sessions.size(); ++s) {
        state[s] = {Eigen::Isometry3d::Identity(), sessions[s].poses, true};
    }

    // 1-4: each query against the reference.
    auto t0 = Clock::now();
    if (progress) progress("reference map", 0, 1);
    const Target reference(sessions, {{0, state[0].World()}}, config);
    times.map_s += common::SecondsSince(t0);
    std::vector<QueryOutcome> outcomes;
    for (size_t q = 1; q < sessions.size(); ++q) {
        outcomes.push_back(AnchorQuery(sessions, state, q, reference, config, &times, progress));
    }
    auto anchored = [&] {
        std::vector<size_t> a;
        for (size_t q = 1; q < sessions.size(); ++q) {
            if (outcomes[q - 1].result.verdict == Verdict::kAnchored) a.push_back(q);
        }
        return a;
    };
    for (size_t q : anchored()) state[q] = outcomes[q - 1].state;

    // 5: a session that failed alone, against the reference and the anchored sessions.
    const std::vector<size_t> alone = anchored();
    if (!alone.empty() && alone.size() + 1 < sessions.size()) {
        t0 = Clock::now();
        std::vector<std::pair<size_t, std::vector<Eigen::Isometry3d>>> members{
            {0, state[0].World()}};
        for (size_t q : alone) members.push_back({q, state[q].World()});
        const Target all(sessions, members, config);
        times.map_s += common::SecondsSince(t0);
        for (size_t q = 1; q < sessions.size(); ++q) {
            if (outcomes[q - 1].result.verdict == Verdict::kAnchored) continue;
            QueryOutcome retry = AnchorQuery(sessions, state, q, all, config, &times, progress);
            if (retry.result.verdict == Verdict::kAnchored) {
                retry.result.via_other_sessions = true;
                outcomes[q - 1] = std::move(retry);
                state[q] = outcomes[q - 1].state;
            }
        }
    }

    // 5: loops between anchored query sessions, by proximity, then all together.
    std::vector<LoopRecord> joint;
    const std::vector<size_t> now = anchored();
    for (size_t q : now) {
        for (const LoopRecord& l : outcomes[q - 1].accepted) joint.push_back(l);
    }
    if (now.size() >= 2) {
        for (size_t q : now) {
            t0 = Clock::now();
            std::vector<std::pair<size_t, std::vector<Eigen::Isometry3d>>> others;
            for (size_t o : now) {
                if (o != q) others.push_back({o, state[o].World()});
            }
            const Target target(sessions, others, config);
            times.map_s += common::SecondsSince(t0);
            // Each pair of sessions once: from the later session to the earlier.
            const std::vector<LoopRecord> loops = ProximityLoops(
                sessions, target, state[q].World(), q, {},
                [q](const TargetKeyframe& tk) { return tk.session < q; }, config, &times);
            for (LoopRecord r : loops) {
                if (r.verified) {
                    r.accepted = true;
                    r.reason = "accepted";
                    joint.push_back(r);
                }
                outcomes[q - 1].records.push_back(r);
            }
        }
    }
    for (size_t q : now) state[q].fixed = false;
    if (!now.empty())
        OptimizeStates(sessions, &state, joint, config, &times, {}, nullptr, &result.graph);
    for (size_t q = 1; q < sessions.size(); ++q) {
        QueryOutcome& o = outcomes[q - 1];
        if (o.result.verdict == Verdict::kAnchored) {
            o.result.anchor = state[q].anchor;
            o.result.world_poses = state[q].World();
        }
        result.sessions.push_back(o.result);
        for (LoopRecord& r : o.records) result.loops.push_back(std::move(r));
    }
    times.total_s = common::SecondsSince(t_start);
    return result;
}

}  // namespace

AnchorResult Anchor(const std::vector<AnchorSession>& sessions, const AnchorConfig& config,
                    const Progress& progress) {
    config.Validate();
    if (sessions.size() < 2) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            "Anchor: a reference and at least one query session");
    }
    bool split = false;
    for (size_t q = 1; q < sessions.size(); ++q)
        split = split || !sessions[q].odometry.stretches.empty();
    if (!split) {
        AnchorResult r = AnchorWhole(sessions, config, progress);
        for (SessionResult& s : r.sessions)
            s.placed.assign(s.keyframes, s.verdict == Verdict::kAnchored);
        return r;
    }
    const SplitQueries parts = SplitAtUntrustedOdometry(sessions);
    return MergePieces(sessions, parts, AnchorWhole(parts.sessions, config, progress));
}

}  // namespace bimslam::anchor
