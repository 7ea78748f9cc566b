// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/anchor/anchor_pieces.hpp"

namespace bimslam::anchor {
namespace {

std::string SpanText(const KeyframeSpan& s) {
    return s.first == s.last
               ? "keyframe " + std::to_string(s.first)
               : "keyframes " + std::to_string(s.first) + "-" + std::to_string(s.last);
}

// What a split session's verdict rests on: the stretches, then each piece's verdict.
std::string PiecesReason(const SessionResult& r) {
    size_t failed = 0, placed = 0;
    for (const OdometryStretch& s : r.untrusted) failed += s.failed;
    for (const bool p : r.placed) placed += p ? 1 : 0;
    std::string text = "the odometry is untrusted: " + std::to_string(failed) +
                       " failed scans in " + std::to_string(r.untrusted.size()) + " stretches (";
    for (size_t k = 0; k < r.untrusted.size(); ++k)
        text += (k ? "; " : "") + r.untrusted[k].Describe();
    text += "), so the session was anchored in " + std::to_string(r.pieces.size()) +
            " pieces split there: ";
    for (size_t k = 0; k < r.pieces.size(); ++k) {
        const SessionResult& p = r.pieces[k].result;
        text +=
            (k ? ", " : "") + SpanText(r.pieces[k].span) + " " + std::string(ToString(p.verdict));
        if (p.verdict != Verdict::kAnchored) text += " (" + p.reason + ")";
    }
    if (r.pieces.empty()) text += "none (every keyframe lies inside a stretch)";
    text += "; " + std::to_string(r.inside.size()) +
            " keyframes inside the stretches are not placed; " + std::to_string(placed) + " of " +
            std::to_string(r.keyframes) + " keyframes anchored";
    return text;
}

}  // namespace

SplitQueries SplitAtUntrustedOdometry(const std::vector<AnchorSession>& sessions) {
    SplitQueries out;
    out.splits.resize(sessions.size());
    for (size_t s = 0; s < sessions.size(); ++s) {
        const AnchorSession& in = sessions[s];
        const KeyframeSpan all{0, in.keyframes() == 0 ? 0 : in.keyframes() - 1};
        if (s == 0 || in.earlier || in.odometry.stretches.empty()) {
            out.sessions.push_back(in);
            out.origin.push_back({s, all});
            continue;
        }
        std::vector<int64_t> stamps;
        for (const io::SessionKeyframe& k : in.session.keyframes) stamps.push_back(k.stamp_ns);
        out.splits[s] = SplitAtStretches(stamps, in.odometry.stretches);
        for (const KeyframeSpan& span : out.splits[s].pieces) {
            out.sessions.push_back(MakePiece(in, span));
            out.origin.push_back({s, span});
            // The walk's start hint holds for every piece, widened by the way from the start to
            // its first keyframe (the odometry's, through the failed stretches before it): a
            // Duplex_A walk whose first scan failed had a piece of one keyframe, then one of 39
            // left ambiguous.
            if (in.start) {
                out.sessions.back().start = in.start;
                out.sessions.back().start->radius_m += in.path_m[span.first];
            }
        }
    }
    return out;
}

AnchorResult MergePieces(const std::vector<AnchorSession>& sessions, const SplitQueries& parts,
                         AnchorResult anchored) {
    AnchorResult out;
    out.graph = std::move(anchored.graph);
    out.times = anchored.times;
    std::vector<std::vector<size_t>> of(sessions.size());  // input session -> its parts
    for (size_t e = 1; e < parts.sessions.size(); ++e) of[parts.origin[e].session].push_back(e);
    out.earlier = std::move(anchored.earlier);
    for (size_t q = 1; q < sessions.size() && !sessions[q].earlier; ++q) {
        const AnchorSession& in = sessions[q];
        if (in.odometry.stretches.empty()) {
            SessionResult r = std::move(anchored.sessions[of[q].at(0) - 1]);
            r.placed.assign(r.keyframes, r.verdict == Verdict::kAnchored);
            out.sessions.push_back(std::move(r));
            continue;
        }
        SessionResult r;
        r.name = in.name;
        r.keyframes = in.keyframes();
        r.untrusted = in.odometry.stretches;
        r.inside = parts.splits[q].inside;
        r.world_poses.assign(r.keyframes, Eigen::Isometry3d::Identity());
        r.placed.assign(r.keyframes, false);
        std::vector<Verdict> verdicts;
        for (const size_t e : of[q]) {
            const KeyframeSpan span = parts.origin[e].span;
            SessionResult p = std::move(anchored.sessions[e - 1]);
            p.placed.assign(p.keyframes, p.verdict == Verdict::kAnchored);
            verdicts.push_back(p.verdict);
            r.candidates += p.candidates;
            r.verified += p.verified;
            if (p.verdict == Verdict::kAnchored) {
                r.accepted_loops += p.accepted_loops;
                r.covered += p.covered;
                r.via_other_sessions = r.via_other_sessions || p.via_other_sessions;
                for (size_t k = 0; k < span.size(); ++k) {
                    r.world_poses[span.first + k] = p.world_poses[k];
                    r.placed[span.first + k] = true;
                }
            }
            r.pieces.push_back({span, std::move(p)});
        }
        r.verdict = CombinePieces(verdicts);
        r.reason = PiecesReason(r);
        out.sessions.push_back(std::move(r));
    }
    // Loops as the input sessions number their keyframes (pieces' loops to each other included).
    for (LoopRecord& l : anchored.loops) {
        const PieceOrigin& from = parts.origin[l.query_session];
        const PieceOrigin& to = parts.origin[l.target_session];
        l.query_session = from.session;
        l.query_index += from.span.first;
        l.target_session = to.session;
        l.target_index += to.span.first;
        out.loops.push_back(std::move(l));
    }
    return out;
}

}  // namespace bimslam::anchor
