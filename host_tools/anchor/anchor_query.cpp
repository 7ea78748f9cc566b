// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Steps 1-4 of anchoring.hpp for one query session against a target (AnchoringProblem::
// AnchorQuery): place recognition, the hypotheses, each followed, ranked, and the verdict.
#include <algorithm>
#include <chrono>
#include <iomanip>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <tuple>

#include "algorithms/common/stopwatch.hpp"
#include "host_tools/anchor/anchoring_problem.hpp"
#include "host_tools/anchor/place_recognition.hpp"

namespace bimslam::anchor {
namespace {
using Clock = std::chrono::steady_clock;

// The loop whose registration fits best.
const LoopRecord& BestLoop(const std::vector<LoopRecord>& loops) {
    return *std::max_element(loops.begin(), loops.end(), [](const auto& a, const auto& b) {
        return a.registration.fitness.inlier_ratio < b.registration.fitness.inlier_ratio;
    });
}

std::string Percent(double r) { return std::to_string(100 * r).substr(0, 4) + " %"; }

// The surfaces removed elements explain, in words, when the placement needed them (seen through
// more than max_seen_through): where a report reader would look for a demolished wall (its
// elements are reported missing by the changes).
std::string RemovedSurfaces(const Hypothesis& h, double max_seen_through) {
    if (h.removed_surfaces.empty() || h.seen_through <= max_seen_through) return "";
    std::ostringstream os;
    os << std::fixed << std::setprecision(1) << ", " << Percent(h.seen_through_unexplained)
       << " but for " << h.removed_surfaces.size() << " surface(s) seen through as if removed";
    for (const registration::RemovedSurface& r : h.removed_surfaces) {
        os << " (at " << r.center.x() << ", " << r.center.y() << ", " << r.center.z() << ", "
           << r.area_m2 << " m2, from " << r.views << " keyframes)";
    }
    return os.str();
}

// What an anchored verdict rests on: the best hypothesis's loops and free space, and why the
// next one (ranked[1], if any) is not a rival.
std::string AnchoredReason(const std::vector<Evaluation>& ranked, size_t keyframes,
                           double max_seen_through) {
    const Hypothesis& best = ranked[0].hypothesis;
    std::string reason = std::to_string(best.loops) + " loops on " + std::to_string(best.covered) +
                         " of " + std::to_string(keyframes) + " keyframes, mean inlier ratio " +
                         std::to_string(best.mean_inlier_ratio).substr(0, 4) + ", " +
                         Percent(best.seen_through) + " of rays through the model" +
                         RemovedSurfaces(best, max_seen_through) + "; ";
    if (ranked.size() == 1) return reason + "no rival hypothesis";
    const Hypothesis& next = ranked[1].hypothesis;
    return reason + "the next hypothesis explains " + std::to_string(next.covered) +
           (next.contradicted ? " and is contradicted (" + Percent(next.seen_through) + ")"
            : next.off_hint   ? " and puts the walk's start off the hint (--near)"
            : next.outweighed_by_heights
                ? " and is outweighed by the walk's heights (it puts " +
                      std::to_string(next.floating) + " keyframes a storey off every walk)"
            : next.outweighed ? " and is outweighed by free space (" + Percent(next.seen_through) +
                                    " of rays through the model)"
                              : std::string());
}

}  // namespace

QueryOutcome AnchoringProblem::AnchorQuery(size_t q, const Target& target) {
    QueryOutcome out;
    const std::vector<size_t> verified = PlaceRecognition(q, target, &out);
    const std::vector<std::vector<size_t>> cliques = Cliques(verified, &out);
    std::vector<Evaluation> evals;
    for (size_t h = 0; h < cliques.size(); ++h) {
        std::optional<Evaluation> e = FollowClique(q, target, cliques[h], int(h), &out.records);
        if (!e) continue;
        evals.push_back(std::move(*e));
        evals.back().clique = int(h);
        evals.back().hypothesis.clique_index = int(h);
        if (progress_) progress_("hypotheses: " + sessions_[q].name, h + 1, cliques.size());
    }
    // Free space marks and ranks the hypotheses; the verdict follows from the best two.
    evals = Rank(q, std::move(evals), &out.result);
    Decide(q, evals, &out);
    if (out.result.verdict == Verdict::kAnchored) Accept(evals, sessions_[q].keyframes(), &out);
    return out;
}

// Step 1: the candidates, registered and verified (and the injected false ones); returns the
// indices of the verified ones.
std::vector<size_t> AnchoringProblem::PlaceRecognition(size_t q, const Target& target,
                                                       QueryOutcome* out) {
    const AnchorSession& query = sessions_[q];
    SessionResult& res = out->result;
    res.name = query.name;
    res.keyframes = query.keyframes();
    if (progress_) progress_("place recognition: " + query.name, 0, query.keyframes());
    out->records = FindPlaceLoops(q, target);
    InjectFalseLoops(q, target, &out->records);
    res.candidates = out->records.size();
    std::vector<size_t> verified;
    for (size_t k = 0; k < out->records.size(); ++k) {
        if (out->records[k].verified) verified.push_back(k);
    }
    res.verified = verified.size();
    if (progress_)
        progress_("place recognition: " + query.name, query.keyframes(), query.keyframes());
    return verified;
}

// Step 2: the hypotheses, cliques of consistent loops (PCM), or all verified loops together
// (GNC, none).
std::vector<std::vector<size_t>> AnchoringProblem::Cliques(const std::vector<size_t>& verified,
                                                           QueryOutcome* out) {
    std::vector<LoopRecord>& records = out->records;
    const auto t0 = Clock::now();
    std::vector<std::vector<size_t>> cliques, seen_through;
    if (config_.outliers == OutlierMethod::kPcm) {
        cliques = ConsistentHypotheses(records, verified, sessions_, config_, &seen_through);
    } else if (int(verified.size()) >= config_.min_clique) {
        cliques.push_back(verified);
    }
    times()->consistency_s += common::SecondsSince(t0);
    for (auto& r : records) {
        if (r.verified) r.reason = "not in a consistent set of loops";
    }
    for (const std::vector<size_t>& c : seen_through) {
        for (size_t k : c) {
            records[k].reason = "in a consistent set of " + std::to_string(c.size()) +
                                " loops that sees through the model (passed over)";
        }
    }
    out->cliques_seen_through = seen_through.size();
    return cliques;
}

// Step 3 for clique h: its loops (those GNC keeps, with GNC) followed from the anchor its best
// loop implies; none when GNC keeps fewer than min_clique.
std::optional<Evaluation> AnchoringProblem::FollowClique(size_t q, const Target& target,
                                                         const std::vector<size_t>& clique, int h,
                                                         std::vector<LoopRecord>* records) {
    std::vector<LoopRecord> seeds;
    for (size_t k : clique) {
        (*records)[k].hypothesis = h;
        (*records)[k].reason = "hypothesis " + std::to_string(h) + " (rejected)";
        seeds.push_back((*records)[k]);
    }
    const Eigen::Isometry3d anchor = ImpliedAnchor(BestLoop(seeds), sessions_);
    if (config_.outliers != OutlierMethod::kGnc) return FollowHypothesis(q, target, seeds, anchor);
    std::vector<State> st = state_;
    st[q] = {anchor, sessions_[q].poses, false};
    const auto tg = Clock::now();
    const std::vector<double> w = GncWeights(sessions_, &st, seeds, config_, times());
    times()->consistency_s += common::SecondsSince(tg);
    std::vector<LoopRecord> kept;
    for (size_t k = 0; k < seeds.size(); ++k) {
        LoopRecord& r = (*records)[clique[k]];
        if (w[k] >= 0.5) {
            kept.push_back(seeds[k]);
        } else {
            r.hypothesis = -1;
            r.reason = "rejected by GNC: weight " + std::to_string(w[k]).substr(0, 4);
        }
    }
    if (int(kept.size()) < config_.min_clique) return std::nullopt;
    return FollowHypothesis(q, target, kept, st[q].anchor);
}

// Step 4: free space marks the hypotheses and ranks them (RankHypotheses); the result lists them
// best first.
std::vector<Evaluation> AnchoringProblem::Rank(size_t q, std::vector<Evaluation> evals,
                                               SessionResult* res) const {
    std::vector<Hypothesis> hypotheses;
    for (const Evaluation& e : evals) hypotheses.push_back(e.hypothesis);
    const std::vector<size_t> order =
        RankHypotheses(hypotheses, sessions_[q].poses, config_, sessions_[q].start);
    std::vector<Evaluation> ranked;
    for (size_t i : order) {
        ranked.push_back(std::move(evals[i]));
        ranked.back().hypothesis = hypotheses[i];
        res->hypotheses.push_back(hypotheses[i]);
    }
    return ranked;
}

// Step 4: the verdict (DecideVerdict) and, unless anchored, why.
void AnchoringProblem::Decide(size_t q, const std::vector<Evaluation>& ranked,
                              QueryOutcome* out) const {
    SessionResult& res = out->result;
    res.verdict =
        DecideVerdict(res.hypotheses, sessions_[q].poses, config_, &res.reason, sessions_[q].start);
    if (ranked.empty()) {
        res.reason = "no set of at least " + std::to_string(config_.min_clique) +
                     " mutually consistent loops among " + std::to_string(res.verified) +
                     " verified of " + std::to_string(res.candidates) + " candidates";
        if (out->cliques_seen_through > 0) {
            res.reason += " that the model does not contradict (" +
                          std::to_string(out->cliques_seen_through) +
                          " passed over: their loops see through its surfaces)";
        }
    }
}

// An anchored query: its pose and loops from the best hypothesis; the records say which loops
// were accepted, and gain the chosen hypothesis's proximity loops and its rejected ones.
void AnchoringProblem::Accept(const std::vector<Evaluation>& ranked, size_t keyframes,
                              QueryOutcome* out) const {
    const Evaluation& best = ranked[0];
    SessionResult& res = out->result;
    res.anchor = best.hypothesis.anchor;
    res.world_poses = best.query.World();
    res.accepted_loops = best.accepted.size();
    res.covered = best.hypothesis.covered;
    res.reason = AnchoredReason(ranked, keyframes, config_.max_seen_through);
    out->state = best.query;
    out->accepted = best.accepted;
    std::set<std::pair<size_t, size_t>> accepted_pr;
    std::set<size_t> proximity_keyframes;  // keyframes whose accepted loop is a proximity loop
    for (const LoopRecord& l : best.accepted) {
        if (l.source != LoopSource::kProximity)
            accepted_pr.insert({l.query_index, l.target_index});
        else
            proximity_keyframes.insert(l.query_index);
    }
    // A place-recognition loop the final solution dropped (chi-square) is said so on its own
    // record, not listed a second time beside a record that calls it superseded.
    using Key = std::tuple<size_t, size_t, LoopSource>;
    std::map<Key, const LoopRecord*> dropped;
    for (const LoopRecord& l : best.rejected) {
        if (l.source != LoopSource::kProximity)
            dropped[{l.query_index, l.target_index, l.source}] = &l;
    }
    std::set<Key> said;  // dropped loops said on their own record
    // PCM's hypothesis is a consistent set; GNC's and none's hold every verified loop.
    const std::string in_set =
        config_.outliers == OutlierMethod::kPcm ? "consistent" : "in the hypothesis";
    for (LoopRecord& r : out->records) {
        if (!r.verified) continue;
        const Key key{r.query_index, r.target_index, r.source};
        if (accepted_pr.count({r.query_index, r.target_index})) {
            r.accepted = true;
            r.reason = "accepted";
        } else if (const auto d = dropped.find(key); d != dropped.end()) {
            r.reason = d->second->reason;
            said.insert(key);
        } else if (r.hypothesis == best.clique) {
            r.reason = in_set + (proximity_keyframes.count(r.query_index)
                                     ? "; superseded by a proximity loop of the same keyframe"
                                     : "; not in the final solution");
        }
    }
    for (LoopRecord l : best.accepted) {
        if (l.source != LoopSource::kProximity) continue;
        l.accepted = true;
        l.reason = "accepted";
        out->records.push_back(l);
    }
    for (const LoopRecord& l : best.rejected) {
        if (!said.count({l.query_index, l.target_index, l.source})) out->records.push_back(l);
    }
}

}  // namespace bimslam::anchor
