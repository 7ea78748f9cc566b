// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/common/stopwatch.hpp"
// bimslam changes: anchored sessions against the building model (Step 3): new objects, missing
// and deviating elements, transients, an updated IFC (host_tools/changes/README.md).
#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>
#include <utility>

#include "algorithms/common/status.hpp"
#include "algorithms/common/utc_time.hpp"
#include "algorithms/io/file_util.hpp"
#include "algorithms/io/sha256.hpp"
#include "host_tools/bim/ifc_model.hpp"
#include "host_tools/bim/ifc_writer.hpp"
#include "host_tools/changes/bim_change_model.hpp"
#include "host_tools/changes/change_bcf.hpp"
#include "host_tools/changes/change_evaluation.hpp"
#include "host_tools/changes/change_report.hpp"
#include "host_tools/changes/ifc_update.hpp"
#include "host_tools/changes/session_input.hpp"
#include "host_tools/changes/survey_datum.hpp"
#include "host_tools/cli/command.hpp"
#include "host_tools/cli/progress.hpp"

namespace bimslam::cli {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

struct ChangesArgs {
    std::string model;
    std::vector<std::string> sessions;
    std::vector<std::string> truths;
    std::string out;
    bool overwrite = false;
    bool json = false;
    changes::ChangeDetectorConfig config;
    bool no_transients = false;
    bool no_wall_split = false, no_wall_join = false;
    bool no_moved = false;
    bool keep_outside = false;
    bool no_refine = false;
    std::string datum;  // --datum FILE (host_tools/changes/survey_datum.hpp)
    std::string bcf_version = "2.1";
    std::string date;  // --date: changes.bcf's topics' date (ISO 8601); empty: the session's
};

[[noreturn]] void BadInput(const std::string& what) {
    throw common::Error(common::StatusCode::kInvalidArgument, what);
}

uint64_t Fnv1a(std::string_view s) {
    uint64_t h = 0xCBF29CE484222325ull;
    for (const char c : s) h = (h ^ uint8_t(c)) * 0x100000001B3ull;
    return h;
}

// Folder names for the sessions' outputs: OUT itself for one session, else OUT/<name> (made
// unique with the session's position).
std::vector<std::pair<std::string, fs::path>> OutputFolders(const ChangesArgs& a) {
    std::vector<std::pair<std::string, fs::path>> out;
    std::set<std::string> used;
    for (size_t k = 0; k < a.sessions.size(); ++k) {
        std::string label = fs::path(a.sessions[k]).lexically_normal().filename().string();
        if (label.empty() || label == ".") label = "session";
        if (!used.insert(label).second) label += "_" + std::to_string(k);
        used.insert(label);
        out.emplace_back(label, a.sessions.size() == 1 ? fs::path(a.out) : fs::path(a.out) / label);
    }
    return out;
}

// What the change detection of one session found, counted for the summary.
struct Tally {
    size_t objects = 0, moved = 0, missing = 0, deviating = 0, confirmed = 0, unseen = 0;
    double volume_m3 = 0;
};

Tally Count(const bim::BimModel& model, const changes::ChangeResult& r) {
    Tally t;
    for (const auto& o : r.objects) {
        if (o.moved_element == changes::kNoElement) ++t.objects, t.volume_m3 += o.volume_m3;
    }
    for (size_t e = 0; e < r.elements.size(); ++e) {
        if (!change_detection::Listed(model.elements[e])) continue;
        const changes::ElementReport& rep = r.elements[e];
        t.moved += rep.moved;
        t.missing += rep.verdict == changes::Verdict::kMissing;
        t.deviating += rep.verdict == changes::Verdict::kDeviating;
        t.confirmed += rep.verdict == changes::Verdict::kConfirmed;
        t.unseen += rep.verdict == changes::Verdict::kNotObserved;
    }
    return t;
}

// One session's run: its input, what was found and what was written.
struct SessionRun {
    SessionRun(std::string l, fs::path d, change_detection::SessionInput in)
        : label(std::move(l)), dir(std::move(d)), input(std::move(in)) {}

    std::string label;
    fs::path dir;
    change_detection::SessionInput input;
    change_detection::SessionChanges found;  // found.input points at input: not moved
    change_detection::IfcUpdate ifc;
    size_t bcf_topics = 0;
    double bcf_seconds = 0, seconds = 0;
    Tally tally;
};

// A `bimslam changes` run: its arguments, the model and what every session shares (the change
// model, the IFC file's text, the snapshots' renderer).
class ChangesRun {
public:
    explicit ChangesRun(ChangesArgs& a) : a_(a), bar_(!a.json && ProgressBar::Terminal()) {}
    int Run();

private:
    void CheckArguments();
    void LoadModel();
    void Detect(Clock::time_point t0, SessionRun* s);
    json SessionJson(size_t k, const SessionRun& s) const;
    void Print(const SessionRun& s) const;
    json Evaluate(size_t k, const fs::path& dir) const;

    ChangesArgs& a_;
    change_detection::BcfVersion bcf_version_{};
    int64_t date_ns_ = 0;
    ProgressBar bar_;
    bim::BimModel model_;
    changes::ChangeModel change_model_;
    std::string original_;  // the IFC file's text
    change_detection::ModelInfo info_;
    size_t compared_ = 0;  // elements compared
    // changes.bcf's snapshots: the model's meshes, uploaded once.
    std::unique_ptr<change_detection::SnapshotRenderer> renderer_;
};

void ChangesRun::CheckArguments() {
    a_.config.detect_transients = !a_.no_transients;
    a_.config.walls.split_corners = !a_.no_wall_split;
    a_.config.walls.join_hidden_gaps = !a_.no_wall_join;
    a_.config.moved.enabled = !a_.no_moved;
    a_.config.crop_to_footprint = !a_.keep_outside;
    a_.config.refinement.enabled = !a_.no_refine;
    a_.config.Validate();
    bcf_version_ = change_detection::ParseBcfVersion(a_.bcf_version);
    if (!a_.date.empty()) {
        try {
            date_ns_ = common::ParseUtcTime(a_.date);
        } catch (const common::Error& e) {
            BadInput("--date: " + std::string(e.what()));
        }
    }
    if (!a_.datum.empty()) {
        change_detection::CheckSurveyDatumOption(a_.datum, a_.config.refinement.enabled);
    }
    if (!a_.truths.empty() && a_.truths.size() != a_.sessions.size()) {
        BadInput("--truth: give one per --session (" + std::to_string(a_.sessions.size()) +
                 " sessions, " + std::to_string(a_.truths.size()) + " truths)");
    }
    // Every session checked before the model is loaded (which takes seconds for a big one).
    for (const std::string& s : a_.sessions) {
        change_detection::LoadAnchoredSession(s, Eigen::Vector3d::Zero(), false);
    }
    if (fs::exists(a_.out) && !fs::is_empty(a_.out) && !a_.overwrite) {
        throw common::Error(common::StatusCode::kAlreadyExists,
                            a_.out + ": exists and is not empty (--overwrite replaces its files)");
    }
}

void ChangesRun::LoadModel() {
    // The model, with its spaces (for the space a new object stands in).
    bim::IfcLoadOptions load;
    load.space_geometry = true;
    load.progress = [&](double f) { bar_.Update("loading the model", f); };
    model_ = bim::LoadIfc(a_.model, load);
    bar_.Clear();
    change_model_ = change_detection::ToChangeModel(model_);
    if (!a_.datum.empty())
        a_.config.refinement.datum = change_detection::ReadSurveyDatum(a_.datum, model_);
    original_ = io::ReadFileToString(a_.model);
    info_ = {a_.model, io::Sha256File(a_.model)};
    for (const bim::BimElement& e : model_.elements)
        compared_ += change_detection::Listed(e) && e.triangle_count > 0;
    if (!a_.json) {
        std::cout << "model     " << a_.model << ": " << model_.schema << ", "
                  << model_.storeys.size() << " storeys, " << compared_ << " elements compared, "
                  << change_model_.mesh.triangles.size() << " triangles\n";
    }
}

// Detects a session's changes and writes its files: changes.json and the others, the updated IFC,
// changes.bcf. t0: when its reading began.
void ChangesRun::Detect(Clock::time_point t0, SessionRun* s) {
    change_detection::SessionChanges& found = s->found;
    found.label = s->label;
    found.input = &s->input;
    found.result = changes::DetectChanges(change_model_, s->input.keyframes, s->input.edges,
                                          a_.config, [&](std::string_view stage, double f) {
                                              bar_.Update(s->label + ": " + std::string(stage), f);
                                          });
    found.places = change_detection::PlaceObjects(model_, found.result.objects);
    const uint64_t seed = Fnv1a(info_.sha256 + "/" + s->label);
    for (size_t o = 0; o < found.result.objects.size(); ++o) {
        found.object_global_ids.push_back(
            bim::IfcWriter::GlobalId(seed, "new object " + std::to_string(o)));
    }
    bar_.Update(s->label + ": writing", 0.0);
    fs::create_directories(s->dir);
    change_detection::WriteChangeFiles(s->dir, model_, info_, found, a_.config);
    s->ifc = change_detection::UpdateIfc(a_.model, original_, model_, found, seed);
    io::WriteFileAtomic(s->dir / "model_updated.ifc", s->ifc.text);
    bar_.Update(s->label + ": changes.bcf", 0.0);
    change_detection::ChangeBcfOptions bcf_options;
    bcf_options.version = bcf_version_;
    bcf_options.date_ns = a_.date.empty() ? change_detection::SessionDate(s->input) : date_ns_;
    bcf_options.model_sha256 = info_.sha256;
    const auto t_bcf = Clock::now();
    const change_detection::ChangeBcf bcf =
        change_detection::ChangesBcf(model_, found, a_.config, bcf_options, *renderer_);
    io::WriteFileAtomic(s->dir / "changes.bcf", bcf.zip);
    s->bcf_topics = bcf.topics;
    s->bcf_seconds = common::SecondsSince(t_bcf);
    bar_.Clear();
    s->seconds = common::SecondsSince(t0);
    s->tally = Count(model_, found.result);
}

json ChangesRun::SessionJson(size_t k, const SessionRun& s) const {
    const changes::ChangeResult& r = s.found.result;
    const Tally& t = s.tally;
    return {{"label", s.label},
            {"session", a_.sessions[k]},
            {"output", s.dir.string()},
            {"keyframes", s.input.session.keyframes.size()},
            {"points", s.input.points},
            {"map_points", r.map.size()},
            {"new_objects", t.objects},
            {"new_objects_volume_m3", t.volume_m3},
            {"moved_elements", t.moved},
            {"transient_clusters", r.transients.size()},
            {"missing", t.missing},
            {"deviating", t.deviating},
            {"confirmed", t.confirmed},
            {"not_observed", t.unseen},
            {"refinement",
             {{"enabled", a_.config.refinement.enabled},
              {"poses_moved_1cm", r.refinement.moved_1cm},
              {"datum_elements", a_.config.refinement.datum.size()},
              {"datum_seen", r.refinement.datum_seen},
              {"mean_correction_m", r.refinement.mean_correction_m},
              {"max_correction_m", r.refinement.max_correction_m}}},
            {"ifc",
             {{"file", (s.dir / "model_updated.ifc").string()},
              {"proxies", s.ifc.proxies},
              {"element_property_sets", s.ifc.element_property_sets},
              {"entities_added", s.ifc.entities},
              {"notes", s.ifc.notes}}},
            {"bcf",
             {{"file", (s.dir / "changes.bcf").string()},
              {"version", change_detection::ToString(bcf_version_)},
              {"topics", s.bcf_topics},
              {"seconds", s.bcf_seconds}}},
            {"seconds", s.seconds}};
}

void ChangesRun::Print(const SessionRun& s) const {
    const changes::ChangeResult& r = s.found.result;
    const Tally& t = s.tally;
    std::cout << "session   " << s.label << ": " << s.input.session.keyframes.size()
              << " keyframes, " << s.input.points << " points -> map of " << r.map.size()
              << " points (" << a_.config.map.voxel_m * 100 << " cm voxels)\n";
    if (a_.config.refinement.enabled) {
        const changes::PoseRefinement& p = r.refinement;
        std::cout << "refined   " << p.moved_1cm << " of " << p.T_world_lidar.size()
                  << " keyframes moved by more than 1 cm (mean "
                  << Fixed(100 * p.mean_correction_m, 2) << " cm, max "
                  << Fixed(100 * p.max_correction_m, 2) << " cm, " << Fixed(p.max_correction_deg, 2)
                  << " deg), " << s.input.edges.size() << " edges, " << Fixed(p.seconds, 1)
                  << " s\n";
        if (!a_.config.refinement.datum.empty()) {
            std::cout << "datum     " << p.datum_seen << " of " << a_.config.refinement.datum.size()
                      << " surveyed elements seen; they hold the frame"
                      << (p.datum_seen == 0 ? " (none seen: the offsets' mean does)" : "") << "\n";
        }
    }
    std::cout << "objects   " << t.objects << " new (" << Fixed(t.volume_m3, 2) << " m3), "
              << t.moved << " moved elements, " << r.transients.size() << " transient clusters ("
              << r.counts.transient_points << " points)\n"
              << "elements  " << t.missing << " missing, " << t.deviating << " deviating, "
              << t.confirmed << " confirmed, " << t.unseen << " not observed\n"
              << "ifc       " << s.ifc.proxies << " proxies and " << s.ifc.element_property_sets
              << " verdict property sets added (" << s.ifc.entities << " entities)\n";
    for (const std::string& note : s.ifc.notes) std::cout << "          note: " << note << "\n";
    std::cout << "bcf       " << s.bcf_topics << " topics with viewpoints and snapshots (BCF "
              << change_detection::ToString(bcf_version_) << ", " << Fixed(s.bcf_seconds, 2)
              << " s)\n";
    std::cout << "time      " << Fixed(s.seconds, 1) << " s (refinement "
              << Fixed(r.seconds.refinement_s, 1) << ", map " << Fixed(r.seconds.map_s, 1)
              << ", distances " << Fixed(r.seconds.distance_s, 1) << ", transients "
              << Fixed(r.seconds.transient_s, 1) << ", objects " << Fixed(r.seconds.cluster_s, 1)
              << ", rays " << Fixed(r.seconds.evidence_s, 1) << ")\n"
              << "written   " << s.dir.string()
              << "/: changes.json, new_objects.ply, map_bim.ply, map_bim.las, "
                 "elements.csv, model_updated.ifc, changes.bcf"
              << (r.refinement.T_world_lidar.empty() ? "" : ", keyframes_refined.tum") << "\n";
}

// Session k's changes against its --truth: evaluation.json, and the scores printed.
json ChangesRun::Evaluate(size_t k, const fs::path& dir) const {
    const change_detection::ChangeEvaluation ev = change_detection::EvaluateChanges(
        change_detection::ReadTruthChanges(a_.truths[k]), change_detection::ReadFoundChanges(dir));
    const json ej = ev.ToJson();
    io::WriteFileAtomic(dir / "evaluation.json", ej.dump(2) + "\n");
    if (a_.json) return ej;
    const auto& al = ev.added_large;
    const auto& rl = ev.removed_large;
    std::cout << "truth     added >= 0.3 m: P " << Fixed(al.precision(), 2) << " R "
              << Fixed(al.recall(), 2) << " F1 " << Fixed(al.f1(), 2) << " (" << al.truth_matched
              << "/" << al.truth << "); removed >= 1 m2: P " << Fixed(rl.precision(), 2) << " R "
              << Fixed(rl.recall(), 2) << " (" << rl.truth_matched << "/" << rl.truth
              << "); walls within 1 cm: " << ej["as_built"]["within_1cm"].get<size_t>() << "/"
              << ev.walls.size()
              << (ev.walls_datum > 0 ? " (and " + std::to_string(ev.walls_datum) + " surveyed)"
                                     : std::string())
              << "; people as objects: " << ev.people_as_objects << "\n"
              << "seen      added >= 0.3 m in view: R " << Fixed(ev.added_seen_large.recall(), 2)
              << " F1 " << Fixed(ev.added_seen_large.f1(), 2) << " ("
              << ev.added_seen_large.truth_matched << "/" << ev.added_seen_large.truth << ", "
              << ev.added_large_out_of_view << " out of view); removed in view: R "
              << Fixed(ev.removed_seen.recall(), 2) << " (" << ev.removed_seen.truth_matched << "/"
              << ev.removed_seen.truth << ", " << ev.removed_out_of_view << " out of view)\n"
              << "          (" << (dir / "evaluation.json").string() << ")\n";
    return ej;
}

int ChangesRun::Run() {
    CheckArguments();
    const auto t_start = Clock::now();
    LoadModel();
    renderer_ = std::make_unique<change_detection::SnapshotRenderer>(model_, 640, 480);
    json sessions_json = json::array();
    for (const auto& [label, dir] : OutputFolders(a_)) {
        const size_t k = sessions_json.size();
        const auto t0 = Clock::now();
        SessionRun s(label, dir,
                     change_detection::LoadAnchoredSession(a_.sessions[k], model_.origin_m));
        Detect(t0, &s);
        json sj = SessionJson(k, s);
        if (!a_.json) Print(s);
        if (!a_.truths.empty()) sj["evaluation"] = Evaluate(k, dir);
        sessions_json.push_back(sj);
    }
    if (a_.json) {
        std::cout << json{{"model", a_.model},
                          {"output", a_.out},
                          {"elements_compared", compared_},
                          {"sessions", sessions_json},
                          {"seconds", common::SecondsSince(t_start)}}
                         .dump(2)
                  << "\n";
    }
    return kExitOk;
}

int Changes(ChangesArgs& a) { return ChangesRun(a).Run(); }

}  // namespace

void AddChangesCommand(CLI::App& app, int& exit_code) {
    auto a = std::make_shared<ChangesArgs>();
    CLI::App* cmd = app.add_subcommand(
        "changes",
        "anchored sessions against the BIM: new objects (voxel meshes), missing and deviating "
        "elements, transients, an updated IFC");
    cmd->footer(
        "Each --session must be anchored (session.json frames.world = \"bim\", as `bimslam "
        "anchor` writes it). OUT receives changes.json, new_objects.ply, map_bim.ply, "
        "map_bim.las (LAS 1.4), elements.csv, model_updated.ifc and changes.bcf (BCF issues: one "
        "topic per new object, missing, deviating and moved element, each with a viewpoint and a "
        "snapshot; with several sessions, one folder per session). "
        "--truth compares with a simulated capture's changes.json (evaluation.json). Method, "
        "defaults and the JSON schema: host_tools/changes/README.md.");
    cmd->add_option("--model", a->model, "the IFC model (IFC2X3 or IFC4)")->required();
    cmd->add_option("--session", a->sessions, "an anchored session folder (repeatable)")
        ->required();
    cmd->add_option("-o,--output", a->out, "output folder")->required();
    cmd->add_option("--truth", a->truths,
                    "a simulated capture's changes.json to score against, one per --session");
    cmd->add_flag("--overwrite", a->overwrite, "replace the files of an existing output folder");
    cmd->add_flag("--json", a->json, "print the results as JSON");
    cmd->add_option("--bcf-version", a->bcf_version,
                    "changes.bcf's BCF-XML version: 2.1 (default) or 3.0");
    cmd->add_option("--date", a->date,
                    "changes.bcf's topics' date, the recording's (ISO 8601, e.g. "
                    "2026-03-02T09:30:00Z; default: the keyframes' stamps when they are UTC, else "
                    "session.json's created)");
    auto& c = a->config;
    cmd->add_option("--voxel", c.map.voxel_m, "map voxel and new-object voxel, m (0.05)")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--max-range", c.map.max_range_m,
                    "keyframe points farther are left out, m (25)")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--threshold", c.new_object_threshold_m,
                    "distance from the model that starts a new object, m (0.10)")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--band", c.band_threshold_m,
                    "new objects grow into points down to this distance, m (0.05)")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--eps", c.dbscan.eps_m, "DBSCAN radius, m (0.15)")->check(CLI::PositiveNumber);
    cmd->add_option("--min-points", c.dbscan.min_points, "DBSCAN core points (8)")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--min-object-points", c.min_object_points,
                    "smallest new object, map points (30)")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--min-multi-view", c.min_multi_view_fraction,
                    "a new object needs this fraction of its points seen by two keyframes or "
                    "more, else one keyframe's pose error could have made it (0.25; 0: off)")
        ->check(CLI::Range(0.0, 1.0));
    cmd->add_option("--deviation-tolerance", c.elements.deviation_tolerance_m,
                    "an element offset by more is a deviating change (changes.json, the BCF "
                    "issues, the updated IFC), m (0.02)")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--tolerance", c.elements.tolerance_m,
                    "QA tolerance each element's measured deviation is judged against: "
                    "elements.csv tolerance_verdict (within, beyond, not_observed) and the "
                    "report's colour scale, m (0.01). Unlike --deviation-tolerance, it changes "
                    "none of the changes reported")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--min-judged-area", c.elements.min_judged_area_m2,
                    "less expected visible surface is 'not observed', m2 (0.25)")
        ->check(CLI::NonNegativeNumber);
    cmd->add_flag("--no-transients", a->no_transients, "skip the free-space check for transients");
    cmd->add_flag("--no-wall-split", a->no_wall_split,
                  "keep new walls that meet at corners (two to four, each at least 1.5 m long "
                  "and high: an L, a U) as one object");
    cmd->add_flag("--no-wall-join", a->no_wall_join,
                  "keep the pieces of one new wall apart even where no beam went through the gap "
                  "between them (a wall seen through two windows)");
    cmd->add_flag("--no-moved", a->no_moved, "do not pair missing elements with new objects");
    cmd->add_flag("--no-refine", a->no_refine,
                  "compare on the anchored poses as they are, without refining them jointly with "
                  "the elements' as-built offsets first");
    cmd->add_option("--refine-sigma", c.refinement.element_sigma_m,
                    "the refinement's prior on an element's as-built offset, m (0.02)")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--datum", a->datum,
                    "CSV of elements surveyed as built, 'GlobalId[,dx,dy,dz]' (m): they fix the "
                    "refinement's frame, which is otherwise the elements' mean offset");
    cmd->add_option("--datum-sigma", c.refinement.datum_sigma_m,
                    "the survey's accuracy, the prior on a datum element's offset, m (0.003)")
        ->check(CLI::PositiveNumber);
    cmd->add_flag("--keep-outside", a->keep_outside,
                  "compare points with no element below them too (the ground outside, things at "
                  "the entrances), which are otherwise outside the building");
    cmd->add_option("--extension-margin", c.extension_margin_m,
                    "off the model's footprint, compare what stands more than 0.2 m above the "
                    "ground around it within this many metres of the model's box in plan: an "
                    "annex or a shed the model lacks, reported as new objects outside the "
                    "footprint; 0: the footprint alone (5)")
        ->check(CLI::NonNegativeNumber);
    cmd->callback([a, &exit_code] { exit_code = Run([&] { return Changes(*a); }); });
}

}  // namespace bimslam::cli
