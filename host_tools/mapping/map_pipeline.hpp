// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// `bimslam map`: an IFC model and rig recordings to an anchored map, a change report and one
// HTML page, in-process, step by step (README.md of this folder), into a project of the
// building's visits (map_project.hpp: OUT/project.json; V = OUT/visits/<label>/):
//   reference  the BIM reference session (Step 1), OUT/reference/; reused while the model's
//              SHA-256 and the parameters are the same
//   odometry   each recording through the on-board odometry, V/odometry/<name>/ (+ <name>.json:
//              the run's figures and every scan's time)
//   anchor     each visit's sessions into BIM coordinates (Step 2), V/anchor/
//   changes    each anchored session against the model (Step 3), V/changes/<name>/ (with
//              changes.bcf; OUT/changes.bcf holds the newest visit's topics)
//   report     OUT/report/report.html of the newest visit (host_tools/report)
// <stamps>/<step>.json records what each step was made from (StepStamp; OUT/stamps for the
// reference and report, V/stamps for the others); a re-run skips the steps whose stamp still
// holds, so an earlier visit is not processed again. V/summary.json gathers a visit's figures
// from its steps' files, and, for simulated captures (ground_truth.tum, changes.json beside the
// pcap), the APE in BIM coordinates with no alignment and the change scores; OUT/summary.json is
// the newest visit's with the list of visits.
#pragma once

#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "algorithms/changes/change_detector.hpp"
#include "host_tools/anchor/anchor_config.hpp"
#include "host_tools/mapping/map_inputs.hpp"
#include "host_tools/mapping/map_project.hpp"

namespace bimslam::mapping {

struct MapConfig {
    // Empty: the project's in `out` (`bimslam map OUT --add ...`), which must exist.
    std::filesystem::path model;
    // New visits' recordings, or the project's again (recognised: map_project.hpp). May be empty
    // when `out` holds a project.
    std::vector<std::filesystem::path> recordings;
    std::filesystem::path out;
    // The visit the new recordings go to (--visit); empty: each its UTC day's.
    std::string visit;
    bool adding = false;  // --add: a recording already in the project is noted as not added
    // --near: where this run's recordings start (map_project.hpp keeps it per recording).
    std::optional<anchor::StartHint> start;
    bool force = false;           // run every step, stamps or not
    bool report = true;           // the report step
    int threads = 0;              // anchoring (0: all cores)
    double keyframe_gap_m = 1.0;  // the reference session's
    double odometry_budget_ms = 50;
    anchor::AnchorConfig anchor;
    changes::ChangeDetectorConfig changes;
    // A survey of elements as built for the change step's refinement (`bimslam changes --datum`,
    // host_tools/changes/survey_datum.hpp); empty: none.
    std::filesystem::path datum;
    // changes.bcf's BCF-XML version, "2.1" or "3.0" (`--bcf-version`).
    std::string bcf_version = "2.1";
    void Validate() const;  // throws common::Error (kInvalidArgument) naming the field
};

// A step that failed while working: which step, on which file, why. The steps before it keep
// their files and stamps.
class StepFailure : public std::runtime_error {
public:
    StepFailure(const std::string& step, const std::string& file, const std::string& why);
    const std::string& step() const { return step_; }

private:
    std::string step_;
};

struct StepRun {
    std::string
        step;  // "reference", "odometry <name>", "anchor <visit>", "changes <visit>", "report"
    bool skipped = false;
    // Skipped, but made by another build of bimslam (StepStamp::MadeByThisProgram): its results
    // are that build's; --force makes them again with this one.
    bool other_build = false;
    double seconds = 0;
};

struct MapRun {
    std::vector<StepRun> steps;
    // What the user should know of the inputs: a recording given again under another path, or
    // given to --add while already in the project.
    std::vector<std::string> notes;
    nlohmann::json summary;  // what OUT/summary.json holds
};

// (step, fraction done of that step).
using MapProgress = std::function<void(const std::string&, double)>;

// Checks the inputs (throws common::FileError, exit-2 material, before any step), then runs the
// steps. Throws StepFailure when a step fails.
MapRun RunMap(const MapConfig& config, const MapProgress& progress = {});

// A visit's summary from the files its steps wrote in `visit` (OUT/visits/<label>) and the
// reference in `out`: OUT/visits/<label>/summary.json; OUT/summary.json is the newest visit's
// with the list of every visit (`visits`, `visit`), which `bimslam report` reads.
nlohmann::json BuildSummary(const std::filesystem::path& out, const std::filesystem::path& visit,
                            const std::filesystem::path& model,
                            const std::vector<RecordingInput>& recordings);
// OUT/summary.json: the newest visit's summary (the last of `visit_summaries`, one per visit of
// the project), with `visit` and `visits`: every visit's label, date-time, folder and recordings
// (name, path, date-time, odometry and anchoring verdicts, change counts).
nlohmann::json ProjectSummary(const std::filesystem::path& out, const Project& project,
                              std::vector<nlohmann::json> visit_summaries);

// A recording's headline change scores (summary.json's `seen_scores`, issue 31 item 8): of what
// the walk's keyframes saw (host_tools/changes/change_evaluation.hpp, "seen"). Added objects of
// 0.3 m and more on which the keyframes put at least the detector's smallest object of map points
// (30 more than 5 cm off the model, a quarter of them seen by two keyframes or more), and removed
// elements whose place the keyframes' beams reached over 0.25 m^2 or more, count in recall ("in
// view"); the others are counted apart (out of view; of those, how many no beam of any scan hit);
// the all-objects figures are kept beside them. Null when the evaluation (evaluation.json) is
// null or older.
nlohmann::json SeenScores(const nlohmann::json& evaluation);
// The rule, one line: "in view = the keyframes put >= 30 map points on it, more than 5 cm off
// the model, 25 % of them seen twice; removed: >= 0.25 m2 of it in their beams".
std::string InViewRuleText(const nlohmann::json& seen_scores);
// One line each, as `bimslam map` and `bimslam demo` print them: "in view: added >= 0.3 m P 0.90
// R 0.95 F1 0.92 (19 of 20; 12 out of view, 4 of them in no beam); removed P 1.00 R 1.00 (3 of 3;
// 1 out of view, 0 of them in no beam)" and "all: added >= 0.3 m P .. R .. F1 .. (19 of 32);
// removed P .. R .. (3 of 4)".
std::string SeenScoresText(const nlohmann::json& seen_scores);
std::string AllScoresText(const nlohmann::json& seen_scores);

}  // namespace bimslam::mapping
