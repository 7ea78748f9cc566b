// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/anchor/pieces.hpp"

#include <algorithm>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "algorithms/common/status.hpp"
#include "algorithms/io/file_util.hpp"
#include "host_tools/anchor/anchor_session.hpp"

namespace bimslam::anchor {
namespace fs = std::filesystem;
using common::FileError;
using common::StatusCode;

std::string OdometryStretch::Describe() const {
    std::string why;
    for (const std::string& r : reasons) why += (why.empty() ? "" : ", ") + r;
    char buf[96];
    std::snprintf(buf, sizeof buf, "scans %zu-%zu (%.1f-%.1f s", first_scan, last_scan, first_s,
                  last_s);
    return buf + (why.empty() ? std::string() : ": " + why) + ")";
}

OdometryVerdict ReadOdometryVerdict(const fs::path& dir) {
    const fs::path file = dir / kOdometryVerdictFile;
    OdometryVerdict v;
    if (!fs::exists(file)) return v;
    const auto bad = [&](const std::string& why) {
        return FileError(StatusCode::kDataLoss, file.string(), 0, why);
    };
    try {
        const nlohmann::json j = nlohmann::json::parse(io::ReadFileToString(file));
        v.verdict = j.at("verdict").get<std::string>();
        if (v.verdict != "trusted" && v.verdict != "untrusted") {
            throw bad("verdict '" + v.verdict + "': expected trusted or untrusted");
        }
        const auto stretch = [&](const nlohmann::json& s, const char* kind) {
            OdometryStretch o;
            o.first_scan = s.at("first_scan").get<size_t>();
            o.last_scan = s.at("last_scan").get<size_t>();
            o.first_s = s.at("first_s").get<double>();
            o.last_s = s.at("last_s").get<double>();
            o.first_ns = s.at("first_stamp_ns").get<int64_t>();
            o.last_ns = s.at("last_stamp_ns").get<int64_t>();
            o.failed = s.value("failed", size_t(0));
            for (const nlohmann::json& r : s.value("reasons", nlohmann::json::array()))
                o.reasons.push_back(r.get<std::string>());
            if (o.last_ns < o.first_ns || o.last_scan < o.first_scan) {
                throw bad(std::string(kind) + " stretch " + o.Describe() +
                          " ends before it starts");
            }
            return o;
        };
        for (const nlohmann::json& s : j.at("failed_stretches"))
            v.stretches.push_back(stretch(s, "failed"));
        // Written since stop 63; an older file has none.
        for (const nlohmann::json& s :
             j.value("height_ambiguous_stretches", nlohmann::json::array()))
            v.height_ambiguous.push_back(stretch(s, "height ambiguous"));
        for (const nlohmann::json& s : j.value("height_unseen_stretches", nlohmann::json::array()))
            v.height_unseen.push_back(stretch(s, "height unseen"));
    } catch (const FileError&) {
        throw;
    } catch (const std::exception& e) {
        throw bad(std::string("not an odometry verdict: ") + e.what());
    }
    if ((v.verdict == "untrusted") == v.stretches.empty()) {
        throw bad("verdict " + v.verdict + " with " + std::to_string(v.stretches.size()) +
                  " failed stretches");
    }
    return v;
}

bool StretchBetween(const std::vector<OdometryStretch>& stretches, int64_t a_ns, int64_t b_ns) {
    for (const OdometryStretch& s : stretches) {
        if (s.first_ns <= b_ns && s.last_ns >= a_ns) return true;
    }
    return false;
}

std::vector<bool> HeightUnsureEdges(const std::vector<io::SessionEdge>& edges,
                                    const std::vector<io::SessionKeyframe>& keyframes,
                                    const OdometryVerdict& v) {
    std::vector<bool> out;
    if (v.height_unseen.empty() && v.height_ambiguous.empty()) return out;  // none unsure
    out.reserve(edges.size());
    for (const io::SessionEdge& e : edges) {
        const int64_t a = keyframes.at(std::min(e.from, e.to)).stamp_ns;
        const int64_t b = keyframes.at(std::max(e.from, e.to)).stamp_ns;
        out.push_back(StretchBetween(v.height_unseen, a, b) ||
                      StretchBetween(v.height_ambiguous, a, b));
    }
    return out;
}

SessionSplit SplitAtStretches(const std::vector<int64_t>& keyframe_ns,
                              const std::vector<OdometryStretch>& stretches) {
    SessionSplit out;
    bool open = false;  // a piece is being extended
    for (size_t k = 0; k < keyframe_ns.size(); ++k) {
        const int64_t t = keyframe_ns[k];
        if (StretchBetween(stretches, t, t)) {
            out.inside.push_back(k);
            open = false;
            continue;
        }
        if (open && !StretchBetween(stretches, keyframe_ns[k - 1], t)) {
            out.pieces.back().last = k;
        } else {
            out.pieces.push_back({k, k});
            open = true;
        }
    }
    return out;
}

AnchorSession MakePiece(const AnchorSession& s, const KeyframeSpan& span) {
    AnchorSession p;
    p.name = s.name + "[" + std::to_string(span.first) + "-" + std::to_string(span.last) + "]";
    p.dir = s.dir;
    p.foreign = s.foreign;
    p.notes = s.notes;
    p.session.manifest = s.session.manifest;
    p.session.complete = s.session.complete;
    const auto sub = [&](const auto& v) {
        using V = std::decay_t<decltype(v)>;
        return v.empty() ? V{} : V(v.begin() + long(span.first), v.begin() + long(span.last) + 1);
    };
    p.session.keyframes = sub(s.session.keyframes);
    p.poses = sub(s.poses);
    p.descriptors = sub(s.descriptors);
    p.clouds = sub(s.clouds);
    for (size_t k = span.first; k <= span.last; ++k)
        p.path_m.push_back(s.path_m[k] - s.path_m[span.first]);
    for (io::SessionEdge e : s.session.edges) {
        if (e.from < span.first || e.from > span.last || e.to < span.first || e.to > span.last)
            continue;
        e.from -= uint32_t(span.first);
        e.to -= uint32_t(span.first);
        p.session.edges.push_back(e);
    }
    const int64_t t0 = s.session.keyframes[span.first].stamp_ns;
    const int64_t t1 = s.session.keyframes[span.last].stamp_ns;
    for (const io::StampedPose& x : s.session.trajectory) {
        if (x.stamp_ns >= t0 && x.stamp_ns <= t1) p.session.trajectory.push_back(x);
    }
    p.session.manifest.counts.keyframes = span.size();
    p.session.manifest.counts.scans = p.session.trajectory.size();
    return p;
}

}  // namespace bimslam::anchor
