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
#include "algorithms/registration/free_space.hpp"
#include "host_tools/anchor/place_recognition.hpp"
#include "host_tools/anchor/target.hpp"

namespace bimslam::anchor {
namespace {
using Clock = std::chrono::steady_clock;
using posegraph::PoseGraph;

double Since(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}

// Where each session is: its anchor and keyframe poses, and whether it may move.
struct State {
    Eigen::Isometry3d anchor = Eigen::Isometry3d::Identity();
    std::vector<Eigen::Isometry3d> poses;
    bool fixed = true;
    std::vector<Eigen::Isometry3d> World() const {
        std::vector<Eigen::Isometry3d> w;
        for (const auto& x : poses) w.push_back(anchor * x);
        return w;
    }
};

PoseGraph BuildGraph(const std::vector<AnchorSession>& sessions, const std::vector<State>& state,
                     const std::vector<LoopRecord>& loops, double odometry_scale) {
    PoseGraph g;
    for (size_t s = 0; s < sessions.size(); ++s) {
        g.AddSession(state[s].poses, state[s].anchor, state[s].fixed);
        if (state[s].fixed) continue;
        for (const io::SessionEdge& e : sessions[s].session.edges) {
            g.AddOdometry({s, e.from, e.to, e.T_from_to, odometry_scale * e.information});
        }
    }
    for (const LoopRecord& l : loops) {
        g.AddLoop({l.target_session, l.target_index, l.query_session, l.query_index,
                   l.T_target_query, l.registration.information});
    }
    return g;
}

// Optimises and reads the free sessions back; returns the largest keyframe move (m).
double Optimize(const std::vector<AnchorSession>& sessions, std::vector<State>* state,
                const std::vector<LoopRecord>& loops, const AnchorConfig& config, StageTimes* times,
                const std::vector<double>& weights = {},
                const posegraph::PoseGraphConfig* graph_config = nullptr,
                PoseGraph* out = nullptr) {
    const auto t0 = Clock::now();
    PoseGraph g = BuildGraph(sessions, *state, loops, config.odometry_information_scale);
    g.Optimize(graph_config ? *graph_config : config.graph, weights);
    double moved = 0;
    for (size_t s = 0; s < sessions.size(); ++s) {
        State& st = (*state)[s];
        if (st.fixed) continue;
        for (size_t k = 0; k < st.poses.size(); ++k) {
            moved = std::max(
                moved,
                (g.WorldPose(s, k).translation() - (st.anchor * st.poses[k]).translation()).norm());
        }
        st.anchor = g.anchor(s);
        for (size_t k = 0; k < st.poses.size(); ++k) st.poses[k] = g.pose(s, k);
    }
    times->optimisation_s += Since(t0);
    if (out) *out = std::move(g);
    return moved;
}

// Whether two poses differ by more than (m, deg).
bool Apart(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double m, double deg) {
    const Eigen::Isometry3d d = a.inverse() * b;
    return d.translation().norm() > m || common::RotationAngle(d) > deg * M_PI / 180;
}

// The result of following one hypothesis through the proximity rounds.
struct Evaluation {
    Hypothesis hypothesis;
    int clique = -1;  // the clique (place-recognition hypothesis) it started from
    State query;
    std::vector<LoopRecord> accepted;
    std::vector<LoopRecord> rejected;  // the last round's rejected proximity candidates
};

// GNC with a truncated least squares cost (Yang, Antonante, Tzoumas, Carlone, "Graduated
// Non-Convexity for Robust Spatial Perception", RA-L 2020, Prop. 4): the loops' weights go from
// the convex surrogate (all in) to TLS (0 or 1) as mu grows; returns the final weights.
std::vector<double> GncWeights(const std::vector<AnchorSession>& sessions,
                               std::vector<State>* state, const std::vector<LoopRecord>& loops,
                               const AnchorConfig& config, StageTimes* times) {
    posegraph::PoseGraphConfig plain = config.graph;
    plain.robust_loops = false;
    std::vector<double> w(loops.size(), 1.0);
    const double c2 = config.max_loop_chi2;
    PoseGraph g;
    Optimize(sessions, state, loops, config, times, w, &plain, &g);
    double max_r2 = 0;
    for (size_t k = 0; k < loops.size(); ++k) max_r2 = std::max(max_r2, g.LoopChi2(k));
    if (max_r2 <= c2) return w;
    double mu = c2 / (2 * max_r2 - c2);
    for (int it = 0; it < 100 && mu < 1e4; ++it) {
        bool binary = true;
        for (size_t k = 0; k < loops.size(); ++k) {
            const double r2 = g.LoopChi2(k);
            if (r2 >= (mu + 1) / mu * c2) {
                w[k] = 0;
            } else if (r2 <= mu / (mu + 1) * c2) {
                w[k] = 1;
            } else {
                w[k] = std::sqrt(c2 * mu * (mu + 1) / r2) - mu;
                binary = false;
            }
        }
        Optimize(sessions, state, loops, config, times, w, &plain, &g);
        if (binary && it > 0) break;
        mu *= 1.4;
    }
    return w;
}

// Follows a hypothesis: the graph from its loops, then proximity rounds until the accepted loops
// stop changing; the query's state starts at its odometry, placed by `anchor`.
Evaluation Evaluate(const std::vector<AnchorSession>& sessions, std::vector<State> state, size_t q,
                    const Target& target, std::vector<LoopRecord> seed_loops,
                    const Eigen::Isometry3d& anchor, const AnchorConfig& config,
                    StageTimes* times) {
    const AnchorSession& query = sessions[q];
    const size_t n = query.keyframes();
    state[q] = {anchor, query.poses, false};
    Optimize(sessions, &state, seed_loops, config, times);

    // The place-recognition loop of each keyframe, used where proximity finds none.
    std::vector<std::optional<LoopRecord>> seed(n), near(n);
    for (const LoopRecord& l : seed_loops) {
        if (!seed[l.query_index] || l.registration.fitness.inlier_ratio >
                                        seed[l.query_index]->registration.fitness.inlier_ratio) {
            seed[l.query_index] = l;
        }
    }
    std::vector<Eigen::Isometry3d> registered_at(n);
    std::set<size_t> previous;
    std::vector<LoopRecord> loops = seed_loops;
    Evaluation ev;
    for (int round = 1; round <= config.max_rounds; ++round) {
        ev.hypothesis.rounds = round;
        std::vector<LoopRecord> jobs;
        std::vector<Eigen::Isometry3d> init;
        for (size_t j = 0; j < n; ++j) {
            const Eigen::Isometry3d T = state[q].anchor * state[q].poses[j];
            const size_t t = target.Nearest(T.translation(), config.proximity_radius_m,
                                            config.proximity_height_m);
            if (t == Target::kNone) {
                near[j].reset();
                continue;
            }
            // A keyframe that has not moved since its last registration keeps its result.
            if (near[j] && !Apart(T, registered_at[j], 0.02, 0.2)) continue;
            const TargetKeyframe& tk = target.keyframes()[t];
            LoopRecord r;
            r.query_session = q;
            r.query_index = j;
            r.target_session = tk.session;
            r.target_index = tk.index;
            r.T_world_target = tk.T_world_lidar;
            r.source = LoopSource::kProximity;
            jobs.push_back(r);
            init.push_back(T);
            registered_at[j] = T;
        }
        RegisterLoops(sessions, target, config, init, config.proximity_first_level, true, &jobs,
                      times);
        for (size_t k = 0; k < jobs.size(); ++k) {
            LoopRecord& r = jobs[k];
            if (r.verified && Apart(r.registration.T_target_source, init[k],
                                    config.proximity_gate_m, config.proximity_gate_deg)) {
                r.verified = false;
                const Eigen::Isometry3d d = init[k].inverse() * r.registration.T_target_source;
                r.reason = "moved " + std::to_string(d.translation().norm()).substr(0, 4) +
                           " m / " +
                           std::to_string(common::RotationAngle(d) * 180 / M_PI).substr(0, 4) +
                           " deg from the estimate (gate " +
                           std::to_string(config.proximity_gate_m).substr(0, 4) + " m)";
            }
            near[r.query_index] = r;
        }
        loops.clear();
        std::set<size_t> covered;
        for (size_t j = 0; j < n; ++j) {
            if (near[j] && near[j]->verified) {
                loops.push_back(*near[j]);
            } else if (seed[j]) {
                loops.push_back(*seed[j]);
            } else {
                continue;
            }
            covered.insert(j);
        }
        const double moved = Optimize(sessions, &state, loops, config, times);
        if (covered == previous && moved < config.converged_m) break;
        previous = covered;
    }
    // Loops the solution cannot explain are dropped, and the rest optimised once more.
    PoseGraph g = BuildGraph(sessions, state, loops, config.odometry_information_scale);
    std::vector<LoopRecord> kept;
    for (size_t k = 0; k < loops.size(); ++k) {
        const double chi2 = g.LoopChi2(k);
        if (chi2 > config.max_loop_chi2) {
            LoopRecord r = loops[k];
            r.reason = "inconsistent with the solution: chi2 " + std::to_string(chi2).substr(0, 6);
            ev.rejected.push_back(r);
        } else {
            kept.push_back(loops[k]);
        }
    }
    if (kept.size() != loops.size()) Optimize(sessions, &state, kept, config, times);
    for (size_t j = 0; j < n; ++j) {
        if (near[j] && !near[j]->verified) ev.rejected.push_back(*near[j]);
    }
    // Negative evidence: the query's rays through the target's surfaces, where it is near.
    std::vector<registration::FreeSpaceResult> fs(n);
    const registration::SurfelMap& fs_map = target.map().level(config.free_space_level);
    tbb::parallel_for(size_t(0), n, [&](size_t j) {
        const Eigen::Isometry3d T = state[q].anchor * state[q].poses[j];
        if (target.Nearest(T.translation(), config.proximity_radius_m, config.proximity_height_m) ==
            Target::kNone) {
            return;
        }
        fs[j] = registration::CheckFreeSpace(query.clouds[j], fs_map, T, config.free_space);
    });
    std::vector<double> ratios;
    for (const auto& f : fs) {
        if (f.rays > 0) ratios.push_back(f.ratio());
    }
    if (!ratios.empty()) {
        std::nth_element(ratios.begin(), ratios.begin() + ratios.size() / 2, ratios.end());
        ev.hypothesis.seen_through = ratios[ratios.size() / 2];
    }
    for (LoopRecord& l : kept) l.seen_through = fs[l.query_index].ratio();
    double inliers = 0;
    for (const LoopRecord& l : kept) inliers += l.registration.fitness.inlier_ratio;
    ev.hypothesis.anchor = state[q].anchor;
    ev.hypothesis.clique = seed_loops.size();
    ev.hypothesis.loops = kept.size();
    std::set<size_t> covered;
    for (const LoopRecord& l : kept) covered.insert(l.query_index);
    ev.hypothesis.covered = covered.size();
    ev.hypothesis.mean_inlier_ratio = kept.empty() ? 0 : inliers / double(kept.size());
    ev.query = state[q];
    ev.accepted = std::move(kept);
    return ev;
}

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
    times->consistency_s += Since(t0);
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
            times->consistency_s += Since(tg);
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
                Evaluate(sessions, state, q, target, kept, st[q].anchor, config, times));
        } else {
            evals.push_back(Evaluate(sessions, state, q, target, seeds, anchor, config, times));
        }
        evals.back().clique = int(h);
        evals.back().hypothesis.clique_index = int(h);
        if (progress) progress("hypotheses: " + query.name, h + 1, cliques.size());
    }
    // Hypotheses that free space contradicts rank last; then by the keyframes they explain.
    for (Evaluation& e : evals) {
        e.hypothesis.contradicted = e.hypothesis.seen_through > config.max_seen_through;
    }
    std::sort(evals.begin(), evals.end(), [](const Evaluation& a, const Evaluation& b) {
        return std::make_tuple(!a.hypothesis.contradicted, a.hypothesis.covered,
                               a.hypothesis.loops) > std::make_tuple(!b.hypothesis.contradicted,
                                                                     b.hypothesis.covered,
                                                                     b.hypothesis.loops);
    });
    for (const Evaluation& e : evals) res.hypotheses.push_back(e.hypothesis);

    // Verdict.
    const size_t n = query.keyframes();
    if (!evals.empty() && evals[0].hypothesis.contradicted) {
        res.verdict = Verdict::kFailed;
        res.reason = "every hypothesis (" + std::to_string(evals.size()) +
                     ") is contradicted by free space: the best one's keyframes see through the "
                     "model's surfaces with " +
                     std::to_string(100 * evals[0].hypothesis.seen_through).substr(0, 4) +
                     " % of their rays (at most " +
                     std::to_string(100 * config.max_seen_through).substr(0, 4) + " %)";
        return out;
    }
    const double min_cover = std::max(double(config.min_loops), config.min_coverage * double(n));
    if (evals.empty() || double(evals[0].hypothesis.covered) < min_cover ||
        int(evals[0].hypothesis.loops) < config.min_loops) {
        res.verdict = Verdict::kFailed;
        res.reason =
            evals.empty()
                ? "no set of at least " + std::to_string(config.min_clique) +
                      " mutually consistent loops among " + std::to_string(verified.size()) +
                      " verified of " + std::to_string(out.records.size()) + " candidates"
                : "the best hypothesis explains " + std::to_string(evals[0].hypothesis.covered) +
                      " of " + std::to_string(n) + " keyframes, fewer than " +
                      std::to_string(int(std::ceil(min_cover)));
        return out;
    }
    const Evaluation& best = evals[0];
    if (evals.size() > 1 && !evals[1].hypothesis.contradicted) {
        const Evaluation& rival = evals[1];
        const double dist =
            MeanDistance(query.poses, best.hypothesis.anchor, rival.hypothesis.anchor);
        const double turn =
            common::RotationAngle(best.hypothesis.anchor.inverse() * rival.hypothesis.anchor) *
            180 / M_PI;
        const bool distinct = dist > config.distinct_m || turn > config.distinct_deg;
        if (distinct && double(rival.hypothesis.covered) >=
                            config.ambiguity_ratio * double(best.hypothesis.covered)) {
            res.verdict = Verdict::kAmbiguous;
            res.reason = "two hypotheses explain the loops about equally well: " +
                         std::to_string(best.hypothesis.covered) + " and " +
                         std::to_string(rival.hypothesis.covered) + " keyframes, " +
                         std::to_string(dist).substr(0, 5) + " m and " +
                         std::to_string(turn).substr(0, 5) + " deg apart";
            return out;
        }
    }
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

std::string_view ToString(Verdict v) {
    switch (v) {
        case Verdict::kAnchored:
            return "anchored";
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
    if (sessions.size() < 2) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            "Anchor: a reference and at least one query session");
    }
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
    times.map_s += Since(t0);
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
        times.map_s += Since(t0);
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
            times.map_s += Since(t0);
            std::vector<LoopRecord> jobs;
            std::vector<Eigen::Isometry3d> init;
            for (size_t j = 0; j < sessions[q].keyframes(); ++j) {
                const Eigen::Isometry3d T = state[q].anchor * state[q].poses[j];
                const size_t t = target.Nearest(T.translation(), config.proximity_radius_m,
                                                config.proximity_height_m);
                if (t == Target::kNone) continue;
                const TargetKeyframe& tk = target.keyframes()[t];
                // Each pair of sessions once: from the later session to the earlier.
                if (tk.session > q) continue;
                LoopRecord r;
                r.query_session = q;
                r.query_index = j;
                r.target_session = tk.session;
                r.target_index = tk.index;
                r.T_world_target = tk.T_world_lidar;
                r.source = LoopSource::kProximity;
                jobs.push_back(r);
                init.push_back(T);
            }
            RegisterLoops(sessions, target, config, init, config.proximity_first_level, true, &jobs,
                          &times);
            for (size_t k = 0; k < jobs.size(); ++k) {
                LoopRecord& r = jobs[k];
                if (r.verified && Apart(r.registration.T_target_source, init[k],
                                        config.proximity_gate_m, config.proximity_gate_deg)) {
                    r.verified = false;
                    r.reason = "outside the gate of the estimate";
                }
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
    if (!now.empty()) Optimize(sessions, &state, joint, config, &times, {}, nullptr, &result.graph);
    for (size_t q = 1; q < sessions.size(); ++q) {
        QueryOutcome& o = outcomes[q - 1];
        if (o.result.verdict == Verdict::kAnchored) {
            o.result.anchor = state[q].anchor;
            o.result.world_poses = state[q].World();
        }
        result.sessions.push_back(o.result);
        for (LoopRecord& r : o.records) result.loops.push_back(std::move(r));
    }
    times.total_s = Since(t_start);
    return result;
}

}  // namespace bimslam::anchor
