// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// bimslam map: an IFC model and rig recordings to an anchored map, changes and a report, every
// step in-process with a stamp so that a re-run skips what is up to date
// (host_tools/mapping/README.md); bimslam report: the page of such an output folder alone.
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "algorithms/common/status.hpp"
#include "host_tools/cli/command.hpp"
#include "host_tools/cli/progress.hpp"
#include "host_tools/mapping/map_pipeline.hpp"
#include "host_tools/report/report_page.hpp"

namespace bimslam::cli {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

struct MapArgs {
    std::vector<std::string> inputs;  // MODEL RECORDING ... (with -o), or OUT (a project)
    std::vector<std::string> add;     // --add RECORDING ...
    std::string visit;
    std::vector<double> near;  // --near X Y [R]
    std::string out;
    std::string outliers = "pcm";
    bool force = false;
    bool no_report = false;
    bool no_refine = false;
    std::string datum;
    bool json = false;
    mapping::MapConfig config;
};

// Every visit's recordings and their verdicts ("visits" of summary.json).
void PrintVisits(const json& visits) {
    for (const json& v : visits) {
        std::cout << "visit     " << v["label"].get<std::string>() << " ("
                  << v["start"].get<std::string>() << ", " << v["dir"].get<std::string>() << "):";
        for (const json& r : v["recordings"]) {
            std::cout << " " << r["name"].get<std::string>() << " "
                      << (r["anchor_verdict"].is_null() ? std::string("not anchored")
                                                        : r["anchor_verdict"].get<std::string>());
        }
        std::cout << "\n";
    }
}

// The newest visit's changes since the previous visit and since the model (history.json).
void PrintHistory(const json& S) {
    if (!S.contains("history")) return;
    const json& h = S["history"];
    const auto count = [](const json& j, const char* k) { return j.value(k, 0); };
    if (h.contains("since_previous")) {
        const json& p = h["since_previous"];
        std::cout << "history   since " << p["previous"].get<std::string>() << ": "
                  << count(p, "new") << " new objects, " << count(p, "gone") << " gone, "
                  << count(p, "moved") << " moved; elements " << count(p, "newly_missing")
                  << " newly missing, " << count(p, "newly_deviating") << " newly deviating, "
                  << count(p, "reappeared") << " reappeared\n";
    }
    if (h.contains("since_model")) {
        const json& m = h["since_model"];
        std::cout << "history   since the model: " << count(m, "new_objects") << " new objects, "
                  << count(m, "missing") << " missing, " << count(m, "deviating") << " deviating; "
                  << h.value("contradictions", 0) << " contradictions over the visits ("
                  << h.value("file", std::string()) << ")\n";
    }
    if (h.contains("building_map_voxels")) {
        std::cout << "map       the building's map (building_map.ply, .las), 5 cm voxels after "
                     "each visit:";
        for (const json& n : h["building_map_voxels"]) std::cout << " " << n.get<size_t>();
        std::cout << "\n";
    }
}

// The summary as the user reads it: every visit, then per recording of the newest what each step
// found.
void PrintSummary(const mapping::MapRun& run) {
    std::cout << "steps     ";
    std::vector<std::string> other_build;
    for (size_t k = 0; k < run.steps.size(); ++k) {
        const mapping::StepRun& s = run.steps[k];
        std::cout << (k ? ", " : "") << s.step << " "
                  << (s.skipped ? "up to date" : Fixed(s.seconds, 1) + " s");
        if (s.other_build) other_build.push_back(s.step);
    }
    std::cout << "\n";
    if (!other_build.empty()) {
        std::cout << "          made by another build of bimslam, kept:";
        for (const std::string& s : other_build) std::cout << " " << s << ";";
        std::cout << " --force makes every step again with this one\n";
    }
    const json& S = run.summary;
    std::cout << "model     " << S["model"]["file"].get<std::string>();
    if (S.contains("reference")) {
        std::cout << " (reference session: " << S["reference"]["keyframes"] << " keyframes)";
    }
    std::cout << "\n";
    PrintVisits(S["visits"]);
    std::cout << "newest    " << S["visit"]["label"].get<std::string>() << "\n";
    for (const json& r : S["recordings"]) {
        std::cout << "recording " << r["name"].get<std::string>() << " ("
                  << r["path"].get<std::string>() << ")\n";
        if (!r["odometry"].is_null()) {
            const json& o = r["odometry"];
            std::cout << "  odometry  " << o["scans"] << " scans, " << o["keyframes"]
                      << " keyframes, " << Fixed(o["distance_m"], 1) << " m, p50 "
                      << Fixed(o["scan_ms_p50"], 1) << " ms per scan\n";
            if (o.value("verdict", "trusted") == "untrusted") {
                std::cout << "  ODOMETRY  " << o.value("verdict_text", std::string("untrusted"))
                          << "\n";
            }
        }
        if (!r["anchor"].is_null()) {
            const json& a = r["anchor"];
            std::cout << "  anchoring " << a["verdict"].get<std::string>() << ": "
                      << a["reason"].get<std::string>() << "\n";
        }
        if (!r["accuracy"].is_null()) {
            const json& a = r["accuracy"];
            std::cout << "  accuracy  APE " << Fixed(a["ape_trans_rmse_m"].get<double>() * 100, 2)
                      << " cm RMSE (max " << Fixed(a["ape_trans_max_m"].get<double>() * 100, 1)
                      << "), " << Fixed(a["ape_rot_rmse_deg"], 2)
                      << " deg in BIM coordinates, no alignment (" << a["matched"] << " poses)\n";
        }
        if (!r["changes"].is_null()) {
            const json& c = r["changes"];
            std::cout << "  changes   " << c["new_objects"] << " new objects, " << c["missing"]
                      << " missing, " << c["deviating"] << " deviating (" << c["moved"]
                      << " moved), " << c["confirmed"] << " confirmed, " << c["not_observed"]
                      << " not observed, " << c["transients"] << " transients\n";
        }
        if (!r["seen_scores"].is_null()) {  // what the walk saw first, then everything
            const json& e = r["change_scores"];
            std::cout << "  scores    " << mapping::SeenScoresText(r["seen_scores"]) << "\n"
                      << "            (" << mapping::InViewRuleText(r["seen_scores"]) << ")\n"
                      << "            " << mapping::AllScoresText(r["seen_scores"])
                      << "; walls within 1 cm: " << e["as_built"]["within_1cm"] << "/"
                      << e["as_built"]["observed"]
                      << "; people as objects: " << e["people"]["reported_as_new_objects"] << "\n";
        }
    }
    PrintHistory(S);
    if (S.contains("report")) std::cout << "report    " << S["report"].get<std::string>() << "\n";
}

int MapMain(MapArgs& a) {
    mapping::MapConfig& c = a.config;
    if (!anchor::ParseOutlierMethod(a.outliers, &c.anchor.outliers)) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            "--outliers " + a.outliers + ": expected pcm, gnc or none");
    }
    if (a.out.empty()) {  // bimslam map OUT [--add RECORDING ...]: the project's model
        if (a.inputs.size() != 1) {
            common::ThrowInvalid(
                "-o: no output folder given (bimslam map MODEL RECORDING ... -o "
                "OUT, or bimslam map OUT --add RECORDING ...)");
        }
        c.out = a.inputs[0];
        c.recordings.assign(a.add.begin(), a.add.end());
        c.adding = true;
    } else {
        if (!a.add.empty()) {
            common::ThrowInvalid(
                "--add: give the project folder, not -o (bimslam map OUT --add "
                "RECORDING ...), or the recordings after the model");
        }
        c.model = a.inputs[0];
        c.recordings.assign(a.inputs.begin() + 1, a.inputs.end());
        c.out = a.out;
    }
    c.visit = a.visit;
    if (!a.near.empty()) c.start = anchor::StartHint::FromList(a.near);
    c.force = a.force;
    c.report = !a.no_report;
    c.changes.refinement.enabled = !a.no_refine;
    c.datum = a.datum;
    ProgressBar bar(!a.json && ProgressBar::Terminal());
    const mapping::MapRun run =
        mapping::RunMap(c, [&](const std::string& step, double f) { bar.Update(step, f); });
    bar.Clear();
    for (const std::string& note : run.notes) std::cerr << "bimslam: note: " << note << "\n";
    // Every visit's recordings: one not anchored, anchored in parts or untrusted stays a failure
    // (exit 1) in every later run, until it is mapped again.
    bool anchored = true;
    std::vector<std::string> untrusted;  // recordings whose odometry failed its checks
    std::vector<std::string> in_parts;   // recordings anchored in pieces (anchoring.hpp)
    for (const json& v : run.summary["visits"]) {
        for (const json& r : v["recordings"]) {
            const std::string verdict =
                r["anchor_verdict"].is_null() ? "" : r["anchor_verdict"].get<std::string>();
            if (verdict == "anchored-in-parts") in_parts.push_back(r["name"].get<std::string>());
            anchored = anchored && (verdict == "anchored" || verdict == "anchored-in-parts");
            if (r["odometry_verdict"] == "untrusted")
                untrusted.push_back(r["name"].get<std::string>());
        }
    }
    if (a.json) {
        json j = run.summary;
        j["steps"] = json::array();
        for (const auto& s : run.steps) {
            j["steps"].push_back({{"step", s.step},
                                  {"skipped", s.skipped},
                                  {"other_build", s.other_build},
                                  {"seconds", s.seconds}});
        }
        std::cout << j.dump(2) << "\n";
    } else {
        PrintSummary(run);
        if (fs::exists(c.out / "changes.bcf")) {
            std::cout << "bcf       " << (c.out / "changes.bcf").string() << " (BCF "
                      << c.bcf_version << " issues of the newest visit's changes, for BIM tools)\n";
        }
        if (!anchored) {
            std::cout << "NOT ANCHORED: a recording could not be placed in BIM coordinates (see "
                         "above); the report shows its odometry map in its own frame\n";
        }
        for (const std::string& name : untrusted) {
            std::cout << "ODOMETRY UNTRUSTED: " << name
                      << "'s trajectory failed its registration checks (the stretches above); "
                         "the anchoring splits its session there into pieces that no odometry "
                         "joins, and its map, anchoring and changes there are not to be trusted\n";
        }
        for (const std::string& name : in_parts) {
            std::cout << "ANCHORED IN PARTS: " << name
                      << ": only the pieces between its odometry's failed stretches that were "
                         "anchored are placed in BIM coordinates and compared (see above)\n";
        }
    }
    return anchored && untrusted.empty() && in_parts.empty() ? kExitOk : kExitFailure;
}

int ReportMain(const std::string& out, std::string html) {
    if (html.empty()) html = (fs::path(out) / "report" / "report.html").string();
    ProgressBar bar(ProgressBar::Terminal());
    fs::create_directories(fs::absolute(html).parent_path());
    report::WriteReport(out, html, [&](const std::string& s, double f) { bar.Update(s, f); });
    bar.Clear();
    std::cout << "report    " << html << " (" << fs::file_size(html) / 1024 << " kB)\n";
    return kExitOk;
}

}  // namespace

void AddMapCommand(CLI::App& app, int& exit_code) {
    auto a = std::make_shared<MapArgs>();
    CLI::App* cmd = app.add_subcommand(
        "map",
        "an IFC model and rig recordings to an anchored map, changes and a report: every step, "
        "re-runs skip what is up to date");
    cmd->add_option("inputs", a->inputs,
                    "MODEL RECORDING ... with -o: the IFC model (IFC2X3 or IFC4) and recordings: "
                    "capture folders (lidar.pcap, metadata.json, go1_can.log ...), x.pcap with "
                    "x.json beside it, or ROS 1 bags from ouster-ros (.bag); without -o: OUT, a "
                    "project folder")
        ->type_name("MODEL RECORDING ...|OUT")
        ->required();
    cmd->add_option("-o,--output", a->out,
                    "output folder: the project (kept between runs; a later run adds its new "
                    "recordings as visits)");
    cmd->add_option("--add", a->add,
                    "bimslam map OUT --add RECORDING ...: new recordings into the project OUT, "
                    "mapped against its model");
    cmd->add_option("--visit", a->visit,
                    "the visit the new recordings go to (default: each its recording's UTC day, "
                    "YYYY-MM-DD)");
    cmd->add_option("--near", a->near,
                    "X Y [R]: where the recordings given now start, in model metres (within R, "
                    "default 3 m), kept in the project for them: their anchoring sets aside "
                    "placements that start elsewhere. For buildings of identical parts (two "
                    "dwellings one turned 180 degrees), where a walk is otherwise ambiguous, and "
                    "to accept a placement that a wall taken away since the model explains")
        ->expected(2, 3);
    cmd->add_option("--outliers", a->outliers, "anchoring's outlier rejection: pcm, gnc or none")
        ->capture_default_str();
    cmd->add_option("--threads", a->config.threads, "anchoring threads (0: all cores)")
        ->check(CLI::NonNegativeNumber);
    cmd->add_option("--keyframe-gap", a->config.keyframe_gap_m,
                    "the reference session's keyframe spacing, m")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    cmd->add_option("--budget-ms", a->config.odometry_budget_ms,
                    "odometry budget per scan, ms of the odometry thread's CPU time (bimslam "
                    "odometry --budget-cpu): the odometry stops refining a scan at it, the same "
                    "on a loaded machine as on an idle one")
        ->check(CLI::Range(1.0, 100000.0))
        ->capture_default_str();
    cmd->add_option("--threshold", a->config.changes.new_object_threshold_m,
                    "change detection: distance from the model that starts a new object, m")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    cmd->add_option("--tolerance", a->config.changes.elements.tolerance_m,
                    "QA tolerance each element's measured deviation is judged against: "
                    "elements.csv tolerance_verdict (within, beyond, not_observed) and the "
                    "report's colour scale, m; unlike bimslam changes --deviation-tolerance, it "
                    "changes none of the changes reported")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    cmd->add_flag("--no-refine", a->no_refine,
                  "change detection: compare on the anchored poses as they are, without refining "
                  "them jointly with the elements' as-built offsets first");
    cmd->add_option("--datum", a->datum,
                    "change detection: CSV of elements surveyed as built, 'GlobalId[,dx,dy,dz]' "
                    "(m), which fix the refinement's frame (as bimslam changes --datum)");
    cmd->add_option("--bcf-version", a->config.bcf_version,
                    "changes.bcf's BCF-XML version: 2.1 or 3.0")
        ->capture_default_str();
    cmd->add_flag("--force", a->force,
                  "run every step again, up to date or not (also those another build of bimslam "
                  "made, which a run keeps and names)");
    cmd->add_flag("--no-report", a->no_report, "skip the HTML report");
    cmd->add_flag("--json", a->json, "print OUT/summary.json (and the steps) instead of the text");
    cmd->footer(
        "bimslam map MODEL RECORDING ... -o OUT, then bimslam map OUT --add RECORDING ... (or the "
        "first command line again with more recordings): OUT is a project, the building's "
        "visits. OUT/project.json: the model (path, SHA-256) and the visits in date order, each "
        "with its label, date-time and recordings. A recording's date-time is its capture's "
        "(capture.json's start), else its first packet's (a pcap record's, a bag message's); "
        "recordings of the same calendar day (UTC) form one visit labelled YYYY-MM-DD unless "
        "--visit names it. A recording already in the project (the same size, first packet and "
        "first MiB: a copy or a move too) is not added again (a note says so; a moved one takes "
        "its new path, and is not mapped again if its size and time are kept, as by mv or cp -a; "
        "one re-recorded at a path of the project replaces the old one). Earlier "
        "visits are not processed again (their stamps hold), but for the anchoring of visits dated "
        "after one added.\n"
        "Steps, each into its own folder with a stamp in its stamps/ folder:\n"
        "  reference  OUT/reference/   the BIM reference session (Step 1): every storey, joined "
        "by walking the stairs, cast with the earliest visit's first recording's sensor; cached "
        "by the model's SHA-256\n"
        "  odometry   OUT/visits/<visit>/odometry/<recording>/ and <recording>.json (figures, "
        "time per scan)\n"
        "  anchor     OUT/visits/<visit>/anchor/   the visit's recordings together against the "
        "reference and the anchored sessions of the visits before it (held by priors at their "
        "poses: one graph; a walk through what the model lacks anchors through an earlier visit "
        "that saw it; a visit added with an earlier date re-anchors the later ones): anchor.json, "
        "loops.json, sessions in BIM coordinates; a recording whose "
        "odometry failed somewhere is anchored in pieces split at the failed stretches (verdict "
        "anchored-in-parts: only the anchored pieces are placed and compared)\n"
        "  changes    OUT/visits/<visit>/changes/<recording>/ as `bimslam changes` writes them "
        "(+ evaluation.json; changes.bcf dated by the recording's time); OUT/changes.bcf: the "
        "newest visit's topics, every recording's in one\n"
        "  history    OUT/history.json: every element's verdict per visit (first and last "
        "seen as built, its deviations), the new objects followed from visit to visit (seen "
        "again, moved with their offset, gone when their place was seen empty, not observed), "
        "each visit's changes since the previous visit and since the model, and the "
        "contradictions (missing, then built again); OUT/model_asis.ifc: the model file as is, "
        "the objects present as proxies, every observed element's history as a property set "
        "(bimslam_History), the elements missing as of the newest visit in a group; "
        "OUT/building_map.ply and .las (and .json, its size per visit): the building's map in "
        "BIM coordinates, one point per 5 cm of surface with the visits that first and last saw "
        "it, "
        "what a later visit saw again or found gone replaced, transients left out\n"
        "  report     OUT/report/report.html (`bimslam report`) of the newest visit\n"
        "OUT/visits/<visit>/summary.json gathers a visit's figures, OUT/summary.json the newest "
        "visit's with the list of every visit (`visits`); with a simulated capture's "
        "ground_truth.tum and "
        "changes.json beside the recording, the APE in BIM coordinates (no alignment) and the "
        "change scores: first of what the walk's keyframes saw (in view: added objects with at "
        "least 30 of the map's points on them more than 5 cm off the model, a quarter seen by two "
        "keyframes or more: the detector's smallest object; removed elements whose place the "
        "keyframes' beams reached over 0.25 m2 or more; how many were out of view), then of all. "
        "Exit 0 when every visit's recordings are anchored and their odometry trusted, 1 when "
        "one is not, or is anchored in parts only (its report still written) or a step failed "
        "(the message names the step and the file); a re-run with nothing new skips every step "
        "and exits as the run before. Exit 2 before any step (nothing written) for a model that "
        "is not IFC, a recording that is not an Ouster capture, an OUT that is not a project "
        "(--add), or a damaged visit folder (a file its stamps say was made is missing or "
        "unreadable: the message names the folder; remove it to process that visit again).");
    cmd->callback([a, &exit_code] { exit_code = Run([&] { return MapMain(*a); }); });

    auto out = std::make_shared<std::string>();
    auto html = std::make_shared<std::string>();
    CLI::App* rep = app.add_subcommand(
        "report", "one self-contained HTML page (no network) of a `bimslam map` output folder");
    rep->add_option("out", *out, "the output folder of `bimslam map`")->required();
    rep->add_option("-o,--output", *html, "the page to write (default OUT/report/report.html)");
    rep->footer(
        "The page holds the summary, the visits' timeline, a floor plan per storey (walls, doors, "
        "the stairs, the part of the reference walk and of the selected visit's walks on that "
        "storey, flights dashed on both, loops, the listed changes, a scale bar, the elements "
        "coloured by their deviation against the map's --tolerance), plots (a Scan-vs-BIM "
        "histogram of the map's distances to the model per storey among them), the change list "
        "(since the previous visit, since the model or each recording's detections; "
        "contradictions marked; a row's history on click) and a 3D view with a storey filter "
        "(three.js r111 from Debian's libjs-three, embedded). Opens offline. "
        "host_tools/report/README.md.");
    rep->callback(
        [out, html, &exit_code] { exit_code = Run([&] { return ReportMain(*out, *html); }); });
}

}  // namespace bimslam::cli
