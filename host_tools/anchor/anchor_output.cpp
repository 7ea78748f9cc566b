// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/anchor/anchor_output.hpp"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "algorithms/common/se3.hpp"
#include "algorithms/common/status.hpp"
#include "algorithms/io/file_util.hpp"
#include "algorithms/io/pcd.hpp"
#include "algorithms/io/session.hpp"
#include "algorithms/io/trajectory.hpp"
#include "algorithms/posegraph/pose_graph.hpp"
#include "algorithms/scancontext/session_descriptor.hpp"

namespace bimslam::anchor {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

json PoseJson(const Eigen::Isometry3d& T) {
    const Eigen::Quaterniond q = common::Rotation(T);
    const Eigen::Vector3d t = T.translation();
    return {{"translation", {t.x(), t.y(), t.z()}},
            {"quaternion_xyzw", {q.x(), q.y(), q.z(), q.w()}},
            {"yaw_deg", common::Heading(T.linear()) * 180 / M_PI}};
}

// Odometry breaks (SessionResult::OdometryBreak) as anchor.json lists them.
json BreaksJson(const std::vector<SessionResult::OdometryBreak>& breaks) {
    json out = json::array();
    for (const SessionResult::OdometryBreak& b : breaks)
        out.push_back({{"from", b.from},
                       {"to", b.to},
                       {"offset_m", b.offset_m},
                       {"rotation_deg", b.rotation_deg}});
    return out;
}

// A session's (or a piece's) verdict and the numbers behind it.
json ResultJson(const SessionResult& s) {
    json hyps = json::array();
    for (const Hypothesis& h : s.hypotheses) {
        json removed = json::array();
        for (const registration::RemovedSurface& r : h.removed_surfaces) {
            removed.push_back({{"center", {r.center.x(), r.center.y(), r.center.z()}},
                               {"normal_axis", std::string(1, "xyz"[r.axis])},
                               {"area_m2", r.area_m2},
                               {"crossings", r.crossings},
                               {"keyframes", r.views},
                               {"rays_ending_on_model", r.on_map}});
        }
        hyps.push_back({{"T_world_local", PoseJson(h.anchor)},
                        {"clique_index", h.clique_index},
                        {"clique", h.clique},
                        {"loops", h.loops},
                        {"covered_keyframes", h.covered},
                        {"mean_inlier_ratio", h.mean_inlier_ratio},
                        {"seen_through", h.seen_through},
                        {"removed_surfaces", removed},
                        {"seen_through_unexplained", h.Unexplained()},
                        {"contradicted", h.contradicted},
                        {"floating_keyframes", h.floating},
                        {"outweighed", h.outweighed},
                        {"outweighed_by_heights", h.outweighed_by_heights},
                        {"off_hint", h.off_hint},
                        {"rounds", h.rounds}});
    }
    json e = {{"name", s.name},
              {"verdict", ToString(s.verdict)},
              {"reason", s.reason},
              {"keyframes", s.keyframes},
              {"candidates", s.candidates},
              {"verified", s.verified},
              {"accepted_loops", s.accepted_loops},
              {"covered_keyframes", s.covered},
              {"via_other_sessions", s.via_other_sessions},
              {"hypotheses", hyps}};
    if (s.verdict == Verdict::kAnchored) e["T_world_local"] = PoseJson(s.anchor);
    // Only when there are some: other outputs stay as they were.
    if (!s.odometry_breaks.empty()) e["odometry_breaks"] = BreaksJson(s.odometry_breaks);
    if (!s.breaks_repaired.empty()) {
        e["odometry_breaks_repaired"] = BreaksJson(s.breaks_repaired);
        e["loops_dropped_at_breaks"] = s.loops_dropped_at_breaks;
    }
    return e;
}

}  // namespace

std::string AnchorSummaryJson(const std::vector<AnchorSession>& sessions,
                              const AnchorResult& result, const AnchorConfig& config) {
    json j;
    const AnchorSession& ref = sessions[0];
    j["reference"] = {{"dir", ref.dir.string()},
                      {"keyframes", ref.keyframes()},
                      {"world_frame", ref.session.manifest.world_frame}};
    if (ref.session.manifest.model) {
        j["reference"]["model"] = {{"file", ref.session.manifest.model->file},
                                   {"sha256", ref.session.manifest.model->sha256}};
    }
    Verdict overall = Verdict::kAnchored;
    json out = json::array();
    for (size_t q = 0; q < result.sessions.size(); ++q) {
        const SessionResult& s = result.sessions[q];
        const AnchorSession& in = sessions[q + 1];
        json e = ResultJson(s);
        e["dir"] = in.dir.string();
        e["notes"] = in.notes;
        e["odometry_verdict"] = in.odometry.verdict.empty() ? "not judged" : in.odometry.verdict;
        if (in.start) e["near"] = in.start->List();
        if (!s.untrusted.empty()) {
            json stretches = json::array();
            for (const OdometryStretch& o : s.untrusted) {
                stretches.push_back({{"first_scan", o.first_scan},
                                     {"last_scan", o.last_scan},
                                     {"first_s", o.first_s},
                                     {"last_s", o.last_s},
                                     {"failed", o.failed},
                                     {"reasons", o.reasons},
                                     {"text", o.Describe()}});
            }
            json pieces = json::array();
            for (const PieceResult& p : s.pieces) {
                json x = ResultJson(p.result);
                x.erase("name");
                x["first_keyframe"] = p.span.first;
                x["last_keyframe"] = p.span.last;
                pieces.push_back(x);
            }
            size_t placed = 0;
            for (const bool b : s.placed) placed += b ? 1 : 0;
            e["failed_stretches"] = stretches;
            e["pieces"] = pieces;
            e["keyframes_inside_stretches"] = s.inside;
            e["placed_keyframes"] = placed;
        }
        if (Severity(s.verdict) > Severity(overall)) overall = s.verdict;
        out.push_back(e);
    }
    j["sessions"] = out;
    j["verdict"] = ToString(overall);
    if (!result.earlier.empty()) {  // only then: the output of a run without them is as before
        json earlier = json::array();
        const size_t first = sessions.size() - result.earlier.size();
        for (size_t e = 0; e < result.earlier.size(); ++e) {
            const EarlierResult& r = result.earlier[e];
            earlier.push_back({{"name", r.name},
                               {"dir", sessions[first + e].dir.string()},
                               {"keyframes", r.keyframes},
                               {"accepted_loops", r.accepted_loops},
                               {"max_move_m", r.max_move_m}});
        }
        j["earlier_sessions"] = earlier;
    }
    const StageTimes& t = result.times;
    j["times_s"] = {{"maps", t.map_s},
                    {"candidates", t.candidates_s},
                    {"registration", t.registration_s},
                    {"consistency", t.consistency_s},
                    {"optimisation", t.optimisation_s},
                    {"total", t.total_s},
                    {"registrations", t.registrations}};
    j["config"] = {{"outliers", ToString(config.outliers)},
                   {"sc_candidates", config.sc_candidates},
                   {"max_sc_distance", config.max_sc_distance},
                   {"min_inlier_ratio", config.min_inlier_ratio},
                   {"proximity_radius_m", config.proximity_radius_m},
                   {"inject_false_loops", config.inject_false_loops},
                   {"model_tolerance_m", config.model_tolerance_m},
                   {"model_tolerance_deg", config.model_tolerance_deg}};
    if (!result.earlier.empty()) {
        j["config"]["earlier_sigma_m"] = config.earlier_sigma_m;
        j["config"]["earlier_sigma_deg"] = config.earlier_sigma_deg;
    }
    return j.dump(2) + "\n";
}

std::string LoopsJson(const std::vector<AnchorSession>& sessions, const AnchorResult& result) {
    json a = json::array();
    for (const LoopRecord& l : result.loops) {
        const Eigen::Isometry3d& c = l.T_target_query;
        const Eigen::Quaterniond q = common::Rotation(c);
        const registration::RegistrationResult& r = l.registration;
        a.push_back({{"query", sessions[l.query_session].name},
                     {"query_index", l.query_index},
                     {"target", sessions[l.target_session].name},
                     {"target_index", sessions[l.target_session].KeyframeId(l.target_index)},
                     {"source", ToString(l.source)},
                     {"sc_distance", l.sc_distance},
                     {"sc_yaw_deg", l.sc_yaw * 180 / M_PI},
                     {"inlier_ratio", r.fitness.inlier_ratio},
                     {"inlier_rmse_m", r.fitness.inlier_rmse},
                     {"degenerate_directions", r.degenerate_directions},
                     {"information_diagonal",
                      {r.information(0, 0), r.information(1, 1), r.information(2, 2),
                       r.information(3, 3), r.information(4, 4), r.information(5, 5)}},
                     {"iterations", r.iterations},
                     {"T_target_query",
                      {c.translation().x(), c.translation().y(), c.translation().z(), q.x(), q.y(),
                       q.z(), q.w()}},
                     {"verified", l.verified},
                     {"accepted", l.accepted},
                     {"hypothesis", l.hypothesis},
                     {"seen_through", l.seen_through},
                     {"reason", l.accepted ? std::string("accepted") : l.reason}});
    }
    return a.dump(1) + "\n";
}

std::vector<io::StampedPose> WorldTrajectory(const AnchorSession& session,
                                             const std::vector<Eigen::Isometry3d>& world) {
    const auto& kfs = session.session.keyframes;
    std::vector<io::StampedPose> out;
    if (session.session.trajectory.empty()) {
        for (size_t k = 0; k < world.size(); ++k) {
            out.push_back(io::StampedPose::FromIsometry(kfs[k].stamp_ns, world[k]));
        }
        return out;
    }
    std::vector<Eigen::Isometry3d> correction;  // T_world_local at each keyframe
    for (size_t k = 0; k < world.size(); ++k)
        correction.push_back(world[k] * session.poses[k].inverse());
    size_t k = 0;
    for (const io::StampedPose& p : session.session.trajectory) {
        while (k + 1 < kfs.size() && kfs[k + 1].stamp_ns <= p.stamp_ns) ++k;
        Eigen::Isometry3d C = correction[k];
        if (k + 1 < kfs.size() && p.stamp_ns > kfs[k].stamp_ns) {
            const double a = double(p.stamp_ns - kfs[k].stamp_ns) /
                             double(kfs[k + 1].stamp_ns - kfs[k].stamp_ns);
            C = common::Interpolate(correction[k], correction[k + 1], a);
        }
        out.push_back(io::StampedPose::FromIsometry(p.stamp_ns, C * p.Pose()));
    }
    return out;
}

std::vector<io::StampedPose> WorldTrajectory(const AnchorSession& session,
                                             const std::vector<Eigen::Isometry3d>& world,
                                             const std::vector<bool>& placed) {
    const std::vector<OdometryStretch>& st = session.odometry.stretches;
    if (st.empty() && std::find(placed.begin(), placed.end(), false) == placed.end())
        return WorldTrajectory(session, world);
    const auto& kfs = session.session.keyframes;
    std::vector<io::StampedPose> out;
    if (session.session.trajectory.empty()) {
        for (size_t k = 0; k < world.size(); ++k) {
            if (placed[k]) out.push_back(io::StampedPose::FromIsometry(kfs[k].stamp_ns, world[k]));
        }
        return out;
    }
    std::vector<Eigen::Isometry3d> correction;  // T_world_local at each keyframe
    for (size_t k = 0; k < world.size(); ++k)
        correction.push_back(world[k] * session.poses[k].inverse());
    const size_t n = kfs.size();
    size_t k = 0;
    for (const io::StampedPose& p : session.session.trajectory) {
        const int64_t t = p.stamp_ns;
        if (n == 0 || StretchBetween(st, t, t)) continue;
        while (k + 1 < n && kfs[k + 1].stamp_ns <= t) ++k;
        // The keyframes before and after the scan that the odometry joins to it.
        const int64_t tk = kfs[k].stamp_ns;
        const bool after_first = t >= tk;
        const bool left = after_first && placed[k] && !StretchBetween(st, tk, t);
        const size_t r = after_first ? k + 1 : 0;
        const bool right = r < n && placed[r] && !StretchBetween(st, t, kfs[r].stamp_ns);
        Eigen::Isometry3d C;
        if (left && right) {
            const double a = double(t - tk) / double(kfs[r].stamp_ns - tk);
            C = common::Interpolate(correction[k], correction[r], a);
        } else if (left) {
            C = correction[k];
        } else if (right) {
            C = correction[r];
        } else {
            continue;
        }
        out.push_back(io::StampedPose::FromIsometry(t, C * p.Pose()));
    }
    return out;
}

std::vector<fs::path> WriteAnchorOutput(const fs::path& out,
                                        const std::vector<AnchorSession>& sessions,
                                        const AnchorResult& result, const AnchorConfig& config,
                                        bool overwrite) {
    if (fs::exists(out) && !fs::is_empty(out) && !overwrite) {
        throw common::FileError(common::StatusCode::kAlreadyExists, out.string(), 0,
                                "exists and is not empty (--overwrite replaces it)");
    }
    fs::create_directories(out);
    std::vector<fs::path> written;
    for (size_t q = 0; q < result.sessions.size(); ++q) {
        const SessionResult& s = result.sessions[q];
        const AnchorSession& in = sessions[q + 1];
        fs::path dir = out / s.name;
        if (s.verdict != Verdict::kAnchored && s.verdict != Verdict::kAnchoredInParts) {
            if (overwrite) fs::remove_all(dir);
            continue;
        }
        // Anchored in parts: the keyframes of the anchored pieces, renumbered; an edge only
        // within a piece.
        const std::vector<bool> placed =
            s.placed.empty() ? std::vector<bool>(in.keyframes(), true) : s.placed;
        std::vector<int> piece(in.keyframes(), s.pieces.empty() ? 0 : -1);
        for (size_t p = 0; p < s.pieces.size(); ++p) {
            for (size_t k = s.pieces[p].span.first; k <= s.pieces[p].span.last; ++k)
                piece[k] = int(p);
        }
        std::vector<long> index(in.keyframes(), -1);
        long written_count = 0;
        for (size_t k = 0; k < in.keyframes(); ++k) {
            if (placed[k]) index[k] = written_count++;
        }
        io::SessionManifest m = in.session.manifest;
        m.world_frame = "bim";
        m.created.clear();
        m.counts = {};
        m.descriptor = scancontext::SessionDescriptor(config.descriptor);
        io::SessionWriter w(
            dir, m, {.overwrite = overwrite, .flush_every = 1000000, .sync_each_file = false});
        for (size_t k = 0; k < in.keyframes(); ++k) {
            if (!placed[k]) continue;
            io::SessionKeyframe kf;
            kf.stamp_ns = in.session.keyframes[k].stamp_ns;
            kf.T_world_lidar = s.world_poses[k];
            kf.T_odom_lidar = in.session.keyframes[k].T_odom_lidar.value_or(in.poses[k]);
            kf.descriptor = in.descriptors[k];
            kf.cloud = io::ReadPcd(io::KeyframeCloudPath(in.dir, k));
            w.AddKeyframe(kf);
        }
        for (io::SessionEdge e : in.session.edges) {
            if (e.from >= index.size() || e.to >= index.size() || index[e.from] < 0 ||
                index[e.to] < 0 || piece[e.from] != piece[e.to])
                continue;
            e.from = uint32_t(index[e.from]);
            e.to = uint32_t(index[e.to]);
            w.AddEdge(e);
        }
        const std::vector<io::StampedPose> traj = WorldTrajectory(in, s.world_poses, placed);
        for (const io::StampedPose& p : traj) w.AddScanPose(p);
        w.Finish();
        io::WriteTum(dir / "trajectory_bim.tum", traj);
        written.push_back(dir);
    }
    io::WriteFileAtomic(out / "anchor.json", AnchorSummaryJson(sessions, result, config));
    io::WriteFileAtomic(out / "loops.json", LoopsJson(sessions, result));
    io::WriteFileAtomic(out / "posegraph.g2o", posegraph::SerializeMultiSessionG2o(result.graph));
    return written;
}

}  // namespace bimslam::anchor
