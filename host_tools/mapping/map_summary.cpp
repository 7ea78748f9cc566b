// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// BuildSummary: OUT/summary.json, gathered from the files the steps wrote, so that a run that
// skipped every step prints the same figures as the run that made them.
#include <cstdio>
#include <system_error>

#include "algorithms/common/status.hpp"
#include "algorithms/common/utc_time.hpp"
#include "algorithms/io/file_util.hpp"
#include "host_tools/changes/change_evaluation.hpp"
#include "host_tools/evaluation/trajectory_metrics.hpp"
#include "host_tools/mapping/map_pipeline.hpp"

namespace bimslam::mapping {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

json ReadJsonIf(const fs::path& file) {
    std::error_code ec;
    if (!fs::is_regular_file(file, ec)) return nullptr;
    try {
        return json::parse(io::ReadFileToString(file));
    } catch (const json::exception& e) {  // a damaged step output: name it
        throw common::FileError(common::StatusCode::kParseError, file.string(), 0, e.what());
    }
}

json ChangeCounts(const json& c) {
    size_t moved = 0;
    for (const json& d : c.at("deviating")) moved += !d.at("moved").is_null();
    return {{"new_objects", c.at("new_objects").size()},
            {"missing", c.at("missing").size()},
            {"deviating", c.at("deviating").size()},
            {"moved", moved},
            {"confirmed", c.at("confirmed")},
            {"not_observed", c.at("not_observed")},
            {"transients", c.at("transients").size()},
            {"map_points", c.at("map").at("points")}};
}

std::string Pr(const json& s, bool f1) {
    char text[96];
    std::snprintf(text, sizeof text, f1 ? "P %.2f R %.2f F1 %.2f" : "P %.2f R %.2f",
                  s.at("precision").get<double>(), s.at("recall").get<double>(),
                  f1 ? s.at("f1").get<double>() : 0.0);
    return text;
}

std::string Of(const json& s) {
    return std::to_string(s.at("truth_matched").get<size_t>()) + " of " +
           std::to_string(s.at("truth").get<size_t>());
}

}  // namespace

json SeenScores(const json& e) {
    // Null for an evaluation written before issue 31 or before the in-view rule followed the
    // keyframes (its "seen" had min_beam_hits and no rule).
    if (e.is_null() || !e.contains("seen") || !e.at("seen").contains("rule")) return nullptr;
    const json& seen = e.at("seen");
    const json& out = seen.at("out_of_view");
    const json& no_beam = seen.at("no_beam");
    return {{"in_view_rule", seen.at("rule")},
            {"added_in_view", seen.at("added_large")},
            {"added_out_of_view", out.at("added_large")},
            {"added_no_beam", no_beam.at("added_large")},
            {"added_all", e.at("added_large")},
            {"removed_in_view", seen.at("removed")},
            {"removed_out_of_view", out.at("removed")},
            {"removed_no_beam", no_beam.at("removed")},
            {"removed_all", e.at("removed")}};
}

std::string InViewRuleText(const json& s) {
    const json& rule = s.at("in_view_rule");
    char text[200];
    std::snprintf(text, sizeof text,
                  "in view = the keyframes put >= %zu map points on it, more than %.0f cm off the "
                  "model, %.0f %% of them seen twice; removed: >= %.2f m2 of it in their beams",
                  rule.at("min_map_points").get<size_t>(),
                  100 * rule.at("off_model_m").get<double>(),
                  100 * rule.at("min_multi_view_fraction").get<double>(),
                  rule.at("min_expected_area_m2").get<double>());
    return text;
}

std::string SeenScoresText(const json& s) {
    const auto out = [&](const char* kind) {
        return std::to_string(s.at(std::string(kind) + "_out_of_view").get<size_t>()) +
               " out of view, " +
               std::to_string(s.at(std::string(kind) + "_no_beam").get<size_t>()) +
               " of them in no beam";
    };
    return "in view: added >= 0.3 m " + Pr(s.at("added_in_view"), true) + " (" +
           Of(s.at("added_in_view")) + "; " + out("added") + "); removed " +
           Pr(s.at("removed_in_view"), false) + " (" + Of(s.at("removed_in_view")) + "; " +
           out("removed") + ")";
}

std::string AllScoresText(const json& s) {
    return "all: added >= 0.3 m " + Pr(s.at("added_all"), true) + " (" + Of(s.at("added_all")) +
           "); removed " + Pr(s.at("removed_all"), false) + " (" + Of(s.at("removed_all")) + ")";
}

json BuildSummary(const fs::path& out, const fs::path& visit, const fs::path& model,
                  const std::vector<RecordingInput>& recordings) {
    json s = {{"format", "bimslam-map-summary"},
              {"version", 2},
              {"output", out.string()},
              {"visit_dir", visit.lexically_relative(out).string()},
              {"model", {{"file", model.string()}}}};
    const json session = ReadJsonIf(out / "reference" / "session.json");
    if (!session.is_null()) {
        s["model"]["sha256"] = session.value("/model/sha256"_json_pointer, std::string());
        s["reference"] = {
            {"dir", (out / "reference").string()},
            {"keyframes", session.value("/counts/keyframes"_json_pointer, size_t(0))}};
    }
    const json anchor = ReadJsonIf(visit / "anchor" / "anchor.json");
    if (!anchor.is_null()) s["anchor_times_s"] = anchor.at("times_s");
    json recs = json::array();
    for (const RecordingInput& r : recordings) {
        json j = {{"name", r.name},
                  {"path", r.path.string()},
                  {"ground_truth",
                   r.ground_truth.empty() ? json(nullptr) : json(r.ground_truth.string())},
                  {"truth_changes",
                   r.truth_changes.empty() ? json(nullptr) : json(r.truth_changes.string())},
                  {"odometry", nullptr},
                  {"anchor", nullptr},
                  {"accuracy", nullptr},
                  {"changes", nullptr},
                  {"change_scores", nullptr},
                  {"seen_scores", nullptr}};
        json odo = ReadJsonIf(visit / "odometry" / (r.name + ".json"));
        if (!odo.is_null()) {
            odo.erase(
                "scan_ms");  // per scan: the report plots it, the summary needs only quantiles
            j["odometry"] = odo;
        }
        if (!anchor.is_null()) {
            for (const json& q : anchor.at("sessions")) {
                if (q.at("name") != r.name) continue;
                j["anchor"] = {{"verdict", q.at("verdict")},
                               {"reason", q.at("reason")},
                               {"keyframes", q.at("keyframes")},
                               {"candidates", q.at("candidates")},
                               {"verified", q.at("verified")},
                               {"accepted_loops", q.at("accepted_loops")},
                               {"covered_keyframes", q.at("covered_keyframes")}};
            }
        }
        const fs::path trajectory = visit / "anchor" / r.name / "trajectory_bim.tum";
        std::error_code ec;
        if (!r.ground_truth.empty() && fs::is_regular_file(trajectory, ec)) {
            // In BIM coordinates with no alignment: what anchoring alone achieved.
            evaluation::EvaluationConfig none;
            none.align = evaluation::Alignment::kNone;
            const evaluation::EvaluationResult e =
                evaluation::EvaluateFiles(trajectory, r.ground_truth, none);
            j["accuracy"] = {{"align", "none"},
                             {"matched", e.matched},
                             {"ape_trans_rmse_m", e.ape_trans_m.rmse},
                             {"ape_trans_max_m", e.ape_trans_m.max},
                             {"ape_rot_rmse_deg", e.ape_rot_deg.rmse},
                             {"ape_rot_max_deg", e.ape_rot_deg.max}};
        }
        const json changes = ReadJsonIf(visit / "changes" / r.name / "changes.json");
        if (!changes.is_null()) j["changes"] = ChangeCounts(changes);
        j["change_scores"] = ReadJsonIf(visit / "changes" / r.name / "evaluation.json");
        j["seen_scores"] = SeenScores(j["change_scores"]);
        recs.push_back(j);
    }
    s["recordings"] = recs;
    return s;
}

json ProjectSummary(const fs::path& out, const Project& project,
                    std::vector<json> visit_summaries) {
    json visits = json::array();
    for (size_t v = 0; v < project.visits.size(); ++v) {
        const Visit& visit = project.visits[v];
        json recs = json::array();
        for (size_t k = 0; k < visit.recordings.size(); ++k) {
            const ProjectRecording& r = visit.recordings[k];
            const json& s = visit_summaries[v].at("recordings").at(k);
            recs.push_back(
                {{"name", r.name},
                 {"path", r.path.string()},
                 {"start", common::FormatUtcTime(r.start_ns)},
                 {"start_from", r.start_from},
                 {"odometry_verdict", s.at("odometry").is_null()
                                          ? json(nullptr)
                                          : s["odometry"].value("verdict", json("trusted"))},
                 {"anchor_verdict",
                  s.at("anchor").is_null() ? json(nullptr) : s["anchor"].at("verdict")},
                 {"changes", s.at("changes")}});
        }
        visits.push_back({{"label", visit.label},
                          {"start", common::FormatUtcTime(visit.start_ns())},
                          {"dir", (fs::path("visits") / visit.label).string()},
                          {"recordings", recs}});
    }
    json s = std::move(visit_summaries.back());
    s["output"] = out.string();
    s["visit"] = visits.back();
    s["visits"] = visits;
    return s;
}

}  // namespace bimslam::mapping
