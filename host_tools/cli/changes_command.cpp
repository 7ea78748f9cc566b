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

int Changes(ChangesArgs& a) {
    a.config.detect_transients = !a.no_transients;
    a.config.moved.enabled = !a.no_moved;
    a.config.crop_to_footprint = !a.keep_outside;
    a.config.refinement.enabled = !a.no_refine;
    a.config.Validate();
    const change_detection::BcfVersion bcf_version =
        change_detection::ParseBcfVersion(a.bcf_version);
    int64_t date_ns = 0;
    if (!a.date.empty()) {
        try {
            date_ns = common::ParseUtcTime(a.date);
        } catch (const common::Error& e) {
            BadInput("--date: " + std::string(e.what()));
        }
    }
    if (!a.datum.empty()) {
        change_detection::CheckSurveyDatumOption(a.datum, a.config.refinement.enabled);
    }
    if (!a.truths.empty() && a.truths.size() != a.sessions.size()) {
        BadInput("--truth: give one per --session (" + std::to_string(a.sessions.size()) +
                 " sessions, " + std::to_string(a.truths.size()) + " truths)");
    }
    // Every session checked before the model is loaded (which takes seconds for a big one).
    for (const std::string& s : a.sessions) {
        change_detection::LoadAnchoredSession(s, Eigen::Vector3d::Zero(), false);
    }
    if (fs::exists(a.out) && !fs::is_empty(a.out) && !a.overwrite) {
        throw common::Error(common::StatusCode::kAlreadyExists,
                            a.out + ": exists and is not empty (--overwrite replaces its files)");
    }
    const auto t_start = Clock::now();
    ProgressBar bar(!a.json && ProgressBar::Terminal());

    // The model, with its spaces (for the space a new object stands in).
    bim::IfcLoadOptions load;
    load.space_geometry = true;
    load.progress = [&](double f) { bar.Update("loading the model", f); };
    const bim::BimModel model = bim::LoadIfc(a.model, load);
    bar.Clear();
    const changes::ChangeModel change_model = change_detection::ToChangeModel(model);
    if (!a.datum.empty())
        a.config.refinement.datum = change_detection::ReadSurveyDatum(a.datum, model);
    const std::string original = io::ReadFileToString(a.model);
    const change_detection::ModelInfo info{a.model, io::Sha256File(a.model)};
    size_t compared = 0;
    for (size_t e = 0; e < model.elements.size(); ++e) {
        compared +=
            change_detection::Physical(model.elements[e]) && model.elements[e].triangle_count > 0;
    }
    if (!a.json) {
        std::cout << "model     " << a.model << ": " << model.schema << ", " << model.storeys.size()
                  << " storeys, " << compared << " elements compared, "
                  << change_model.mesh.triangles.size() << " triangles\n";
    }

    // changes.bcf's snapshots: the model's meshes, uploaded once.
    change_detection::SnapshotRenderer renderer(model, 640, 480);
    json sessions_json = json::array();
    for (const auto& [label, dir] : OutputFolders(a)) {
        const size_t k = sessions_json.size();
        const auto t0 = Clock::now();
        const change_detection::SessionInput input =
            change_detection::LoadAnchoredSession(a.sessions[k], model.origin_m);
        change_detection::SessionChanges found;
        found.label = label;
        found.input = &input;
        found.result = changes::DetectChanges(change_model, input.keyframes, input.edges, a.config,
                                              [&](std::string_view stage, double f) {
                                                  bar.Update(label + ": " + std::string(stage), f);
                                              });
        found.places = change_detection::PlaceObjects(model, found.result.objects);
        const uint64_t seed = Fnv1a(info.sha256 + "/" + label);
        for (size_t o = 0; o < found.result.objects.size(); ++o) {
            found.object_global_ids.push_back(
                bim::IfcWriter::GlobalId(seed, "new object " + std::to_string(o)));
        }
        bar.Update(label + ": writing", 0.0);
        fs::create_directories(dir);
        change_detection::WriteChangeFiles(dir, model, info, found, a.config);
        const change_detection::IfcUpdate ifc =
            change_detection::UpdateIfc(a.model, original, model, found, seed);
        io::WriteFileAtomic(dir / "model_updated.ifc", ifc.text);
        bar.Update(label + ": changes.bcf", 0.0);
        change_detection::ChangeBcfOptions bcf_options;
        bcf_options.version = bcf_version;
        bcf_options.date_ns = a.date.empty() ? change_detection::SessionDate(input) : date_ns;
        bcf_options.model_sha256 = info.sha256;
        const auto t_bcf = Clock::now();
        const change_detection::ChangeBcf bcf =
            change_detection::ChangesBcf(model, found, a.config, bcf_options, renderer);
        io::WriteFileAtomic(dir / "changes.bcf", bcf.zip);
        const double bcf_seconds = common::SecondsSince(t_bcf);
        bar.Clear();
        const double seconds = common::SecondsSince(t0);

        const changes::ChangeResult& r = found.result;
        size_t objects = 0, moved = 0, missing = 0, deviating = 0, confirmed = 0, unseen = 0;
        double volume = 0;
        for (const auto& o : r.objects) {
            if (o.moved_element == changes::kNoElement) ++objects, volume += o.volume_m3;
        }
        for (size_t e = 0; e < r.elements.size(); ++e) {
            if (!change_detection::Physical(model.elements[e])) continue;
            const changes::ElementReport& rep = r.elements[e];
            moved += rep.moved;
            missing += rep.verdict == changes::Verdict::kMissing;
            deviating += rep.verdict == changes::Verdict::kDeviating;
            confirmed += rep.verdict == changes::Verdict::kConfirmed;
            unseen += rep.verdict == changes::Verdict::kNotObserved;
        }
        json sj = {{"label", label},
                   {"session", a.sessions[k]},
                   {"output", dir.string()},
                   {"keyframes", input.session.keyframes.size()},
                   {"points", input.points},
                   {"map_points", r.map.size()},
                   {"new_objects", objects},
                   {"new_objects_volume_m3", volume},
                   {"moved_elements", moved},
                   {"transient_clusters", r.transients.size()},
                   {"missing", missing},
                   {"deviating", deviating},
                   {"confirmed", confirmed},
                   {"not_observed", unseen},
                   {"refinement",
                    {{"enabled", a.config.refinement.enabled},
                     {"poses_moved_1cm", r.refinement.moved_1cm},
                     {"datum_elements", a.config.refinement.datum.size()},
                     {"datum_seen", r.refinement.datum_seen},
                     {"mean_correction_m", r.refinement.mean_correction_m},
                     {"max_correction_m", r.refinement.max_correction_m}}},
                   {"ifc",
                    {{"file", (dir / "model_updated.ifc").string()},
                     {"proxies", ifc.proxies},
                     {"element_property_sets", ifc.element_property_sets},
                     {"entities_added", ifc.entities},
                     {"notes", ifc.notes}}},
                   {"bcf",
                    {{"file", (dir / "changes.bcf").string()},
                     {"version", change_detection::ToString(bcf_version)},
                     {"topics", bcf.topics},
                     {"seconds", bcf_seconds}}},
                   {"seconds", seconds}};
        if (!a.json) {
            std::cout << "session   " << label << ": " << input.session.keyframes.size()
                      << " keyframes, " << input.points << " points -> map of " << r.map.size()
                      << " points (" << a.config.map.voxel_m * 100 << " cm voxels)\n";
            if (a.config.refinement.enabled) {
                const changes::PoseRefinement& p = r.refinement;
                std::cout << "refined   " << p.moved_1cm << " of " << p.T_world_lidar.size()
                          << " keyframes moved by more than 1 cm (mean "
                          << Fixed(100 * p.mean_correction_m, 2) << " cm, max "
                          << Fixed(100 * p.max_correction_m, 2) << " cm, "
                          << Fixed(p.max_correction_deg, 2) << " deg), " << input.edges.size()
                          << " edges, " << Fixed(p.seconds, 1) << " s\n";
                if (!a.config.refinement.datum.empty()) {
                    std::cout << "datum     " << p.datum_seen << " of "
                              << a.config.refinement.datum.size()
                              << " surveyed elements seen; they hold the frame"
                              << (p.datum_seen == 0 ? " (none seen: the offsets' mean does)" : "")
                              << "\n";
                }
            }
            std::cout << "objects   " << objects << " new (" << Fixed(volume, 2) << " m3), "
                      << moved << " moved elements, " << r.transients.size()
                      << " transient clusters (" << r.counts.transient_points << " points)\n"
                      << "elements  " << missing << " missing, " << deviating << " deviating, "
                      << confirmed << " confirmed, " << unseen << " not observed\n"
                      << "ifc       " << ifc.proxies << " proxies and " << ifc.element_property_sets
                      << " verdict property sets added (" << ifc.entities << " entities)\n";
            for (const std::string& note : ifc.notes)
                std::cout << "          note: " << note << "\n";
            std::cout << "bcf       " << bcf.topics << " topics with viewpoints and snapshots (BCF "
                      << change_detection::ToString(bcf_version) << ", " << Fixed(bcf_seconds, 2)
                      << " s)\n";
            std::cout << "time      " << Fixed(seconds, 1) << " s (refinement "
                      << Fixed(r.seconds.refinement_s, 1) << ", map " << Fixed(r.seconds.map_s, 1)
                      << ", distances " << Fixed(r.seconds.distance_s, 1) << ", transients "
                      << Fixed(r.seconds.transient_s, 1) << ", objects "
                      << Fixed(r.seconds.cluster_s, 1) << ", rays "
                      << Fixed(r.seconds.evidence_s, 1) << ")\n"
                      << "written   " << dir.string()
                      << "/: changes.json, new_objects.ply, map_bim.ply, map_bim.las, "
                         "elements.csv, model_updated.ifc, changes.bcf"
                      << (r.refinement.T_world_lidar.empty() ? "" : ", keyframes_refined.tum")
                      << "\n";
        }
        if (!a.truths.empty()) {
            const change_detection::ChangeEvaluation ev =
                change_detection::EvaluateChanges(change_detection::ReadTruthChanges(a.truths[k]),
                                                  change_detection::ReadFoundChanges(dir));
            const json ej = ev.ToJson();
            io::WriteFileAtomic(dir / "evaluation.json", ej.dump(2) + "\n");
            sj["evaluation"] = ej;
            if (!a.json) {
                const auto& al = ev.added_large;
                const auto& rl = ev.removed_large;
                std::cout << "truth     added >= 0.3 m: P " << Fixed(al.precision(), 2) << " R "
                          << Fixed(al.recall(), 2) << " F1 " << Fixed(al.f1(), 2) << " ("
                          << al.truth_matched << "/" << al.truth << "); removed >= 1 m2: P "
                          << Fixed(rl.precision(), 2) << " R " << Fixed(rl.recall(), 2) << " ("
                          << rl.truth_matched << "/" << rl.truth
                          << "); walls within 1 cm: " << ej["as_built"]["within_1cm"].get<size_t>()
                          << "/" << ev.walls.size()
                          << (ev.walls_datum > 0
                                  ? " (and " + std::to_string(ev.walls_datum) + " surveyed)"
                                  : std::string())
                          << "; people as objects: " << ev.people_as_objects << "\n"
                          << "seen      added >= 0.3 m in view: R "
                          << Fixed(ev.added_seen_large.recall(), 2) << " F1 "
                          << Fixed(ev.added_seen_large.f1(), 2) << " ("
                          << ev.added_seen_large.truth_matched << "/" << ev.added_seen_large.truth
                          << ", " << ev.added_large_out_of_view
                          << " out of view); removed in view: R "
                          << Fixed(ev.removed_seen.recall(), 2) << " ("
                          << ev.removed_seen.truth_matched << "/" << ev.removed_seen.truth << ", "
                          << ev.removed_out_of_view << " out of view)\n"
                          << "          (" << (dir / "evaluation.json").string() << ")\n";
            }
        }
        sessions_json.push_back(sj);
    }
    if (a.json) {
        std::cout << json{{"model", a.model},
                          {"output", a.out},
                          {"elements_compared", compared},
                          {"sessions", sessions_json},
                          {"seconds", common::SecondsSince(t_start)}}
                         .dump(2)
                  << "\n";
    }
    return kExitOk;
}

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
