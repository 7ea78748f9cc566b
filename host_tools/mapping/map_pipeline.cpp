// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/mapping/map_pipeline.hpp"

#include <algorithm>
#include <chrono>
#include <optional>
#include <system_error>

#include "algorithms/common/status.hpp"
#include "algorithms/common/stopwatch.hpp"
#include "algorithms/common/utc_time.hpp"
#include "algorithms/io/file_util.hpp"
#include "algorithms/io/sha256.hpp"
#include "host_tools/anchor/anchor_output.hpp"
#include "host_tools/anchor/anchoring.hpp"
#include "host_tools/bim/ifc_model.hpp"
#include "host_tools/bim/ifc_writer.hpp"
#include "host_tools/bim/lidar_from_metadata.hpp"
#include "host_tools/bim/reference_session.hpp"
#include "host_tools/capture/ouster_capture.hpp"
#include "host_tools/changes/bim_change_model.hpp"
#include "host_tools/changes/change_bcf.hpp"
#include "host_tools/changes/change_evaluation.hpp"
#include "host_tools/changes/change_report.hpp"
#include "host_tools/changes/ifc_update.hpp"
#include "host_tools/changes/session_input.hpp"
#include "host_tools/changes/survey_datum.hpp"
#include "host_tools/mapping/asis_model.hpp"
#include "host_tools/mapping/building_map.hpp"
#include "host_tools/mapping/map_history.hpp"
#include "host_tools/mapping/map_project.hpp"
#include "host_tools/mapping/step_stamp.hpp"
#include "host_tools/replay/capture_odometry.hpp"
#include "host_tools/report/report_page.hpp"

namespace bimslam::mapping {
namespace fs = std::filesystem;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

void MapConfig::Validate() const {
    auto bad = [](const std::string& what) {
        throw common::Error(common::StatusCode::kInvalidArgument, what);
    };
    if (out.empty()) bad("-o: no output folder given");
    if (!(keyframe_gap_m > 0)) bad("keyframe_gap_m " + std::to_string(keyframe_gap_m));
    if (!(odometry_budget_ms > 0)) bad("odometry_budget_ms " + std::to_string(odometry_budget_ms));
    if (threads < 0) bad("threads " + std::to_string(threads));
    anchor.Validate();
    changes.Validate();
    (void)change_detection::ParseBcfVersion(bcf_version);
    if (!datum.empty()) change_detection::CheckSurveyDatumOption(datum, changes.refinement.enabled);
}

StepFailure::StepFailure(const std::string& step, const std::string& file, const std::string& why)
    : std::runtime_error("step '" + step + "' failed" + (file.empty() ? "" : " on " + file) + ": " +
                         why + " (the steps before it are kept)"),
      step_(step) {}

namespace {

uint64_t Fnv1a(std::string_view s) {  // as `bimslam changes` seeds the new objects' GlobalIds
    uint64_t h = 0xCBF29CE484222325ull;
    for (const char c : s) h = (h ^ uint8_t(c)) * 0x100000001B3ull;
    return h;
}

// Runs a step unless its stamp holds; names the step and the file when it throws. The stamp is
// removed first, so that an interrupted step runs again next time.
class Stepper {
public:
    Stepper(bool force, MapRun* run) : force_(force), run_(run) {}
    // `stamps`: the folder of the step's stamp (OUT/stamps, or a visit's).
    bool Run(const std::string& step, const fs::path& stamps, const std::string& stamp_name,
             StepStamp& stamp, const std::string& file, const std::function<void()>& body) {
        fs::create_directories(stamps);
        const fs::path file_stamp = stamps / (stamp_name + ".json");
        const auto t0 = Clock::now();
        if (!force_ && stamp.Matches(file_stamp)) {
            run_->steps.push_back({step, true, !stamp.MadeByThisProgram(), 0.0});
            return false;
        }
        std::error_code ec;
        fs::remove(file_stamp, ec);
        try {
            body();
        } catch (const common::FileError& e) {
            throw StepFailure(step, e.path(), e.detail());
        } catch (const std::exception& e) {
            throw StepFailure(step, file, e.what());
        }
        stamp.MarkMade();
        stamp.Write(file_stamp);
        run_->steps.push_back({step, false, false, common::SecondsSince(t0)});
        return true;
    }

private:
    bool force_;
    MapRun* run_;
};

json AnchorParameters(const anchor::AnchorConfig& c) {
    return {{"outliers", anchor::ToString(c.outliers)},
            {"seed", c.seed},
            {"sc_candidates", c.sc_candidates},
            {"max_sc_distance", c.max_sc_distance},
            {"min_inlier_ratio", c.min_inlier_ratio},
            {"proximity_radius_m", c.proximity_radius_m},
            {"max_rounds", c.max_rounds}};
}

json ChangeParameters(const changes::ChangeDetectorConfig& c) {
    return {{"voxel_m", c.map.voxel_m},
            {"max_range_m", c.map.max_range_m},
            {"threshold_m", c.new_object_threshold_m},
            {"band_m", c.band_threshold_m},
            {"eps_m", c.dbscan.eps_m},
            {"min_points", c.dbscan.min_points},
            {"min_object_points", c.min_object_points},
            {"min_multi_view_fraction", c.min_multi_view_fraction},
            {"deviation_tolerance_m", c.elements.deviation_tolerance_m},
            {"tolerance_m", c.elements.tolerance_m},  // elements.csv's verdicts, the page's scale
            {"min_judged_area_m2", c.elements.min_judged_area_m2},
            {"transients", c.detect_transients},
            {"moved", c.moved.enabled},
            {"refine", c.refinement.enabled},
            {"refine_sigma_m", c.refinement.element_sigma_m}};
}

// The anchored sessions in anchor.json (those with a folder in OUT/anchor): a session anchored in
// parts (its odometry failed somewhere) is compared over its anchored pieces, which its folder
// holds.
std::vector<std::string> AnchoredNames(const fs::path& anchor_dir) {
    std::vector<std::string> names;
    const json a = json::parse(io::ReadFileToString(anchor_dir / "anchor.json"));
    for (const json& q : a.at("sessions")) {
        if (q.at("verdict") == "anchored" || q.at("verdict") == "anchored-in-parts")
            names.push_back(q.at("name").get<std::string>());
    }
    return names;
}

// The sensor the reference is cast with: the first recording's (its metadata, or a bag's
// metadata topic), with what identifies it in the step's stamp.
struct ReferenceSensor {
    simulation::LidarModel lidar;
    std::string name;
    json stamp;
};

ReferenceSensor ReferenceSensorOf(const std::vector<RecordingInput>& recordings) {
    ReferenceSensor s{simulation::LidarModel::DefaultOs1_32(), "OS-1-32", "OS-1-32 1024 default"};
    if (recordings.empty()) return s;
    const ouster::SensorInfo info = capture::LoadRecordingInfo(recordings.front().files);
    s.lidar = bim::LidarModelFromSensorInfo(info);
    s.name = (info.prod_line.empty() ? std::string("Ouster") : info.prod_line) + " " +
             info.lidar_mode + " (" + recordings.front().name + ")";
    s.stamp = {{"altitude_deg", s.lidar.beam_altitude_deg},
               {"azimuth_deg", s.lidar.beam_azimuth_deg},
               {"columns", s.lidar.columns},
               {"rate_hz", s.lidar.frame_rate_hz},
               {"origin_mm", {s.lidar.beam_origin_mm, s.lidar.beam_z_mm}}};
    return s;
}

// What every step reads: the configuration, the output folder, the model (read on first use:
// IFC++ takes seconds for a big one, and only the steps that run need it).
struct MapContext {
    const MapConfig& config;
    MapProgress progress;
    fs::path out;
    fs::path model_file;
    std::string sha256;
    std::optional<bim::BimModel> plain_model;

    const bim::BimModel& Model() {
        if (!plain_model) {
            progress("reading the model", 0.0);
            plain_model = bim::LoadIfc(model_file);
        }
        return *plain_model;
    }
};

// 1. The reference session, by the model's content. It is cast with the project's first
// recording's sensor (its beam table and columns), so that its scans and descriptors look like
// the recordings' own; the walk takes the stairs between the storeys (bim/reference_walk.hpp).
StepStamp ReferenceStep(MapContext& c, Stepper& stepper, const ReferenceSensor& sensor) {
    StepStamp reference("reference");
    reference.AddParameter("model_sha256", c.sha256);
    reference.AddParameter("keyframe_gap_m", c.config.keyframe_gap_m);
    reference.AddParameter("lidar", sensor.stamp);
    reference.AddParameter("walk", "every storey, joined by the stairs");
    stepper.Run("reference", c.out / "stamps", "reference", reference, c.model_file.string(), [&] {
        bim::ReferenceSessionOptions ro;
        ro.overwrite = true;
        ro.lidar = sensor.lidar;
        ro.sensor_model = sensor.name;
        ro.keyframe_gap_m = c.config.keyframe_gap_m;
        ro.progress = [&](size_t d, size_t n) { c.progress("reference", n ? double(d) / n : 0.0); };
        bim::WriteReferenceSession(c.Model(), c.sha256, c.out / "reference", ro);
    });
    return reference;
}

// The odometry's figures and every scan's time: odometry/<name>.json.
json OdometryStats(const RecordingInput& r, const replay::CaptureOdometryReport& rep) {
    json j = replay::ReportJson(rep);
    j["recording"] = r.path.string();
    j["pcap"] = r.files.packets.string();
    j["scan_ms"] = rep.scan_ms;
    return j;
}

// 2. Odometry of one recording of a visit, into the visit's folder.
StepStamp OdometryStep(MapContext& c, Stepper& stepper, const fs::path& visit,
                       const RecordingInput& r) {
    StepStamp s("odometry_" + r.name);
    s.AddFileTime("pcap", r.files.packets);  // a pcap or a bag
    if (!r.files.metadata.empty()) s.AddFileTime("metadata", r.files.metadata);
    if (!r.files.can_log.empty()) s.AddFileTime("can_log", r.files.can_log);
    if (!r.files.capture_json.empty()) s.AddFileTime("capture_json", r.files.capture_json);
    s.AddParameter("budget_ms", c.config.odometry_budget_ms);
    s.AddParameter("budget_clock", "thread cpu");
    // The session carries the odometry's verdict (odometry_verdict.json) since this version:
    // an older session is made again, so that anchoring sees where it failed.
    s.AddParameter("verdict_in_session", 1);
    // And the recording host's clock offset since this version (session.json clocks: the GPS
    // times of map_bim.las).
    s.AddParameter("clock_offset_in_session", 1);
    const std::string step = "odometry " + r.name;
    stepper.Run(step, visit / "stamps", "odometry_" + r.name, s, r.files.packets.string(), [&] {
        replay::CaptureOdometryOptions o;
        o.capture_dir = r.path;
        o.session_dir = visit / "odometry" / r.name;
        o.overwrite = true;
        o.odometry.budget_ms = c.config.odometry_budget_ms;
        // Counted in the thread's CPU time: an offline run's results depend on the work, not
        // on what else the machine does (a scan preempted for 170 ms of wall time was cut
        // short, failed its checks and made a whole run untrusted on a loaded machine).
        o.odometry.registration.cpu_time_budget = true;
        o.on_scan = [&, n = size_t(0)](const odometry::OdometryResult&) mutable {
            if (++n % 20 == 0) c.progress(step + " (" + std::to_string(n) + " scans)", 0.0);
        };
        fs::create_directories(visit / "odometry");
        const replay::CaptureOdometryReport rep = replay::RunCaptureOdometry(o);
        io::WriteFileAtomic(visit / "odometry" / (r.name + ".json"),
                            OdometryStats(r, rep).dump() + "\n");
    });
    return s;
}

// An earlier visit whose anchoring the next visits use as a target: its folder, its label and
// its anchor step's stamp.
struct EarlierVisit {
    fs::path dir;
    std::string label;
    StepStamp anchoring;
};

// The anchored sessions of the earlier visits (anchored or anchored in parts: the keyframes their
// folders hold are in BIM coordinates), named "<label>/<name>", each with the keyframes that
// stand for it (EarlierTargets) and only their clouds read.
std::vector<anchor::AnchorSession> EarlierSessions(const std::vector<EarlierVisit>& earlier,
                                                   const anchor::LoadOptions& lo, double spacing) {
    std::vector<anchor::AnchorSession> sessions;
    std::vector<size_t> visit;
    anchor::LoadOptions poses_only = lo;
    poses_only.load_clouds = false;
    for (size_t v = 0; v < earlier.size(); ++v) {
        for (const std::string& name : AnchoredNames(earlier[v].dir / "anchor")) {
            sessions.push_back(
                anchor::LoadEarlierSession(earlier[v].dir / "anchor" / name, poses_only));
            sessions.back().name = earlier[v].label + "/" + name;
            visit.push_back(v);
        }
    }
    const std::vector<std::vector<size_t>> keep = anchor::EarlierTargets(sessions, visit, spacing);
    std::vector<anchor::AnchorSession> targets;  // a session the later ones stand for is left out
    for (size_t s = 0; s < sessions.size(); ++s) {
        if (keep[s].empty()) continue;
        if (keep[s].size() < sessions[s].keyframes()) anchor::KeepKeyframes(&sessions[s], keep[s]);
        anchor::LoadClouds(&sessions[s], lo);
        targets.push_back(std::move(sessions[s]));
    }
    return targets;
}

// 3. Anchoring: the visit's sessions at once (loops between them help), against the reference
// and the earlier visits' anchored sessions (anchoring.hpp, step 7).
StepStamp AnchorStep(MapContext& c, Stepper& stepper, const fs::path& visit, const Visit& info,
                     const std::vector<RecordingInput>& recordings, const StepStamp& reference,
                     const std::vector<StepStamp>& odometry,
                     const std::vector<EarlierVisit>& earlier) {
    const std::string& label = info.label;
    StepStamp anchoring("anchor");
    anchoring.AddUpstream(reference);
    for (const StepStamp& s : odometry) anchoring.AddUpstream(s);
    anchoring.AddParameter("anchor", AnchorParameters(c.config.anchor));
    // Where the recordings start, when said (--near): only then, so that older stamps hold.
    json near = json::array();
    bool any_near = false;
    for (const ProjectRecording& r : info.recordings) {
        near.push_back(r.start ? json(r.start->List()) : json(nullptr));
        any_near = any_near || r.start.has_value();
    }
    if (any_near) anchoring.AddParameter("near", near);
    if (!earlier.empty()) {  // the visits before it: re-anchored, this one is anchored again
        json before = json::array();
        for (const EarlierVisit& e : earlier)
            before.push_back({{"label", e.label}, {"anchor", e.anchoring.Digest()}});
        anchoring.AddParameter("earlier_visits", before);
        anchoring.AddParameter(
            "earlier_sigma", {c.config.anchor.earlier_sigma_m, c.config.anchor.earlier_sigma_deg});
        anchoring.AddParameter("earlier_spacing_m", c.config.anchor.earlier_spacing_m);
    }
    const std::string step = "anchor " + label;
    stepper.Run(step, visit / "stamps", "anchor", anchoring, (visit / "odometry").string(), [&] {
        anchor::AnchorConfig ac = c.config.anchor;
        ac.threads = c.config.threads;
        anchor::LoadOptions lo;
        lo.cloud = ac.cloud;
        lo.descriptor = ac.descriptor;
        lo.threads = c.config.threads;
        std::vector<anchor::AnchorSession> sessions;
        sessions.push_back(anchor::LoadAnchorSession(c.out / "reference", lo));
        for (size_t k = 0; k < recordings.size(); ++k) {
            c.progress(step + ": reading " + recordings[k].name, double(k) / recordings.size());
            sessions.push_back(
                anchor::LoadAnchorSession(visit / "odometry" / recordings[k].name, lo));
            sessions.back().start = info.recordings[k].start;  // in the same order
        }
        c.progress(step + ": reading the earlier visits", 1.0);
        for (anchor::AnchorSession& s : EarlierSessions(earlier, lo, ac.earlier_spacing_m))
            sessions.push_back(std::move(s));
        const anchor::AnchorResult r =
            anchor::Anchor(sessions, ac, [&](const std::string& s, size_t d, size_t n) {
                c.progress(step + ": " + s, n ? double(d) / double(n) : 0.0);
            });
        anchor::WriteAnchorOutput(visit / "anchor", sessions, r, ac, true);
    });
    return anchoring;
}

// The changes of one anchored session against the model, as `bimslam changes` finds them, with
// the updated IFC and, given the simulator's truth, their scores.
void SessionChanges(MapContext& c, const fs::path& visit, const std::string& label, uint16_t number,
                    const bim::BimModel& m, const changes::ChangeModel& change_model,
                    const changes::ChangeDetectorConfig& detector, const std::string& original,
                    const std::vector<RecordingInput>& recordings, const Visit& visit_info,
                    change_detection::SnapshotRenderer& renderer) {
    const change_detection::ModelInfo info{c.model_file, c.sha256};
    const fs::path dir = visit / "changes" / label;
    const change_detection::SessionInput input =
        change_detection::LoadAnchoredSession(visit / "anchor" / label, m.origin_m);
    change_detection::SessionChanges found;
    found.label = label;
    found.input = &input;
    found.visit = number;
    found.result =
        changes::DetectChanges(change_model, input.keyframes, input.edges, detector,
                               [&](std::string_view stage, double f) {
                                   c.progress("changes " + label + ": " + std::string(stage), f);
                               });
    found.places = change_detection::PlaceObjects(m, found.result.objects);
    const uint64_t seed = Fnv1a(info.sha256 + "/" + label);
    for (size_t o = 0; o < found.result.objects.size(); ++o) {
        found.object_global_ids.push_back(
            bim::IfcWriter::GlobalId(seed, "new object " + std::to_string(o)));
    }
    fs::create_directories(dir);
    change_detection::WriteChangeFiles(dir, m, info, found, detector);
    io::WriteFileAtomic(
        dir / "model_updated.ifc",
        change_detection::UpdateIfc(c.model_file.string(), original, m, found, seed).text);
    // changes.bcf, dated by the recording's time (project.json), else the visit's.
    change_detection::ChangeBcfOptions bcf;
    bcf.version = change_detection::ParseBcfVersion(c.config.bcf_version);
    bcf.date_ns = visit_info.start_ns();
    for (const ProjectRecording& r : visit_info.recordings) {
        if (r.name == label) bcf.date_ns = r.start_ns;
    }
    bcf.model_sha256 = c.sha256;
    c.progress("changes " + label + ": changes.bcf", 1.0);
    io::WriteFileAtomic(dir / "changes.bcf",
                        change_detection::ChangesBcf(m, found, detector, bcf, renderer).zip);
    for (const RecordingInput& r : recordings) {
        if (r.name != label || r.truth_changes.empty()) continue;
        const change_detection::ChangeEvaluation ev =
            change_detection::EvaluateChanges(change_detection::ReadTruthChanges(r.truth_changes),
                                              change_detection::ReadFoundChanges(dir));
        io::WriteFileAtomic(dir / "evaluation.json", ev.ToJson().dump(2) + "\n");
    }
}

// 4. Change detection of each anchored session of the visit, as `bimslam changes` does it.
// `number`: the visit's 1-based place in date order (map_bim.las's point source id).
StepStamp ChangesStep(MapContext& c, Stepper& stepper, const fs::path& visit,
                      const Visit& visit_info, uint16_t number,
                      const std::vector<RecordingInput>& recordings, const StepStamp& anchoring) {
    const std::string& label = visit_info.label;
    StepStamp change("changes");
    change.AddUpstream(anchoring);
    change.AddParameter("model_sha256", c.sha256);
    change.AddParameter("changes", ChangeParameters(c.config.changes));
    for (const RecordingInput& r : recordings) {
        if (!r.truth_changes.empty()) change.AddFileTime("truth_" + r.name, r.truth_changes);
    }
    // The scores' in-view rule: an output scored by an older rule is scored again.
    change.AddParameter("in_view_rule", "keyframes' map points on the object (issue 31)");
    // map_bim.las (issue 34) carries the visit's number: made again when it is new or changed.
    change.AddParameter("las_visit_number", number);
    if (!c.config.datum.empty()) change.AddFileTime("datum", c.config.datum);
    change.AddParameter("bcf", {{"version", c.config.bcf_version}, {"snapshot", "640x480"}});
    stepper.Run(
        "changes " + label, visit / "stamps", "changes", change, c.model_file.string(), [&] {
            fs::remove_all(visit / "changes");
            fs::create_directories(visit / "changes");
            const std::vector<std::string> anchored = AnchoredNames(visit / "anchor");
            if (anchored.empty()) return;  // nothing in BIM coordinates to compare
            bim::IfcLoadOptions load;
            load.space_geometry = true;
            load.progress = [&](double f) { c.progress("changes: reading the model", f); };
            const bim::BimModel m = bim::LoadIfc(c.model_file, load);
            const changes::ChangeModel change_model = change_detection::ToChangeModel(m);
            changes::ChangeDetectorConfig detector = c.config.changes;
            if (!c.config.datum.empty()) {
                detector.refinement.datum = change_detection::ReadSurveyDatum(c.config.datum, m);
            }
            const std::string original = io::ReadFileToString(c.model_file);
            change_detection::SnapshotRenderer renderer(m, 640, 480);
            for (const std::string& name : anchored) {
                SessionChanges(c, visit, name, number, m, change_model, detector, original,
                               recordings, visit_info, renderer);
            }
        });
    return change;
}

// OUT/changes.bcf: the newest visit's topics, every recording's changes.bcf in one (their topics
// are the recordings' own: GUIDs by recording), dated by the visit. None when no recording of it
// was anchored.
void ProjectBcf(const fs::path& out, const Visit& newest) {
    std::vector<fs::path> files;
    const fs::path changes = VisitDir(out, newest.label) / "changes";
    if (fs::is_directory(changes)) {
        for (const fs::directory_entry& d : fs::directory_iterator(changes)) {
            if (fs::is_regular_file(d.path() / "changes.bcf"))
                files.push_back(d.path() / "changes.bcf");
        }
    }
    std::sort(files.begin(), files.end());
    if (files.empty()) {
        fs::remove(out / "changes.bcf");
        return;
    }
    WriteIfChanged(out / "changes.bcf", change_detection::MergeBcf(files, newest.start_ns()));
}

// 5. The building's history over the visits (map_history.hpp): OUT/history.json, and the as-is
// model (asis_model.hpp): OUT/model_asis.ifc; made again when a visit's changes were.
void HistoryStep(MapContext& c, Stepper& stepper, const Project& project,
                 const std::vector<StepStamp>& changes, json* summary) {
    StepStamp history("history");
    for (const StepStamp& s : changes) history.AddUpstream(s);
    history.AddParameter("history", HistoryConfig().ToJson());
    history.AddParameter("model_sha256", c.sha256);
    history.AddParameter("as_is", "model_asis.ifc");
    history.AddParameter("building_map", "building_map.ply, 5 cm");
    const fs::path file = c.out / "history.json";
    stepper.Run("history", c.out / "stamps", "history", history, file.string(), [&] {
        std::vector<VisitFindings> visits;
        for (const Visit& v : project.visits) {
            c.progress("history: reading " + v.label,
                       double(visits.size()) / project.visits.size());
            visits.push_back(ReadVisitFindings(VisitDir(c.out, v.label), v.label, v.start_ns()));
        }
        const json h = BuildHistory(visits);
        io::WriteFileAtomic(file, h.dump(1) + "\n");
        c.progress("history: the building's map", 1.0);
        std::vector<std::string> made_from;
        for (const StepStamp& s : changes) made_from.push_back(s.Digest());
        WriteBuildingMap(c.out, visits, h, made_from);
        c.progress("history: the as-is model", 1.0);
        const change_detection::IfcUpdate asis =
            AsIsIfc(c.out, c.model_file.string(), io::ReadFileToString(c.model_file), c.Model(), h,
                    Fnv1a(c.sha256 + "/as-is"));
        io::WriteFileAtomic(c.out / "model_asis.ifc", asis.text);
    });
    (*summary)["history"] = HistoryCounts(json::parse(io::ReadFileToString(file)));
    const json map = json::parse(io::ReadFileToString(c.out / "building_map.json"));
    json voxels = json::array();
    for (const json& v : map.at("visits")) voxels.push_back(v.at("voxels"));
    (*summary)["history"]["building_map_voxels"] = voxels;  // after each visit
}

// 6. The report of the newest visit, with the list of every visit (OUT/summary.json), each
// visit's walks and the history (every visit's changes, upstream of history.json and after each
// visit's anchoring).
void ReportStep(MapContext& c, Stepper& stepper, const std::vector<StepStamp>& changes,
                const std::vector<StepStamp>& newest_odometry,
                const std::vector<RecordingInput>& newest, const json& visits, json* summary) {
    StepStamp page("report");
    for (const StepStamp& s : changes) page.AddUpstream(s);
    for (const StepStamp& s : newest_odometry) page.AddUpstream(s);
    page.AddParameter("page", report::PageVersion());
    page.AddParameter("visits", visits);
    for (const RecordingInput& r : newest) {  // the APE over time in the page
        if (!r.ground_truth.empty()) page.AddFileTime("truth_" + r.name, r.ground_truth);
    }
    const fs::path html = c.out / "report" / "report.html";
    stepper.Run("report", c.out / "stamps", "report", page, html.string(), [&] {
        fs::create_directories(c.out / "report");
        report::WriteReport(c.out, html,
                            [&](const std::string& s, double f) { c.progress("report: " + s, f); });
    });
    (*summary)["report"] = html.string();
}

}  // namespace

MapRun RunMap(const MapConfig& config, const MapProgress& progress) {
    config.Validate();
    // Every input checked before any step (the model, every recording of the project, the
    // earlier visits' folders): exit 2 names the file, and nothing is written.
    ProjectInputs p = OpenProject(config.out, config.model, config.recordings, config.visit,
                                  config.adding, config.start);
    for (const Visit& v : p.project.visits) CheckVisitFolder(config.out, v);
    const MapProgress quiet = [](const std::string&, double) {};
    MapContext c{config,          progress ? progress : quiet, config.out,
                 p.project.model, p.project.model_sha256,      std::nullopt};
    // The datum names the model's GlobalIds: checked against it now, as the other inputs.
    if (!config.datum.empty()) (void)change_detection::ReadSurveyDatum(config.datum, c.Model());
    SaveProject(config.out, p.project);

    MapRun run;
    run.notes = p.notes;
    Stepper stepper(config.force, &run);
    const StepStamp reference = ReferenceStep(c, stepper, ReferenceSensorOf(p.visits.front()));

    // Each visit in date order; an earlier one's stamps hold, so only new visits run.
    std::vector<json> summaries;
    std::vector<StepStamp> odometry, changes;
    std::vector<EarlierVisit> earlier;  // the visits before the one in hand, in date order
    for (size_t v = 0; v < p.project.visits.size(); ++v) {
        const std::string& label = p.project.visits[v].label;
        const std::vector<RecordingInput>& recordings = p.visits[v];
        const fs::path dir = VisitDir(config.out, label);
        odometry.clear();
        for (const RecordingInput& r : recordings)
            odometry.push_back(OdometryStep(c, stepper, dir, r));
        const StepStamp anchoring = AnchorStep(c, stepper, dir, p.project.visits[v], recordings,
                                               reference, odometry, earlier);
        earlier.push_back({dir, label, anchoring});
        changes.push_back(ChangesStep(c, stepper, dir, p.project.visits[v],
                                      uint16_t(std::min<size_t>(v + 1, 65535)), recordings,
                                      anchoring));
        summaries.push_back(BuildSummary(config.out, dir, p.project.model, recordings));
        WriteIfChanged(dir / "summary.json", summaries.back().dump(2) + "\n");
    }
    ProjectBcf(config.out, p.project.visits.back());
    run.summary = ProjectSummary(config.out, p.project, std::move(summaries));
    HistoryStep(c, stepper, p.project, changes, &run.summary);
    WriteIfChanged(config.out / "summary.json", run.summary.dump(2) + "\n");
    run.summary["history"]["file"] = (config.out / "history.json").string();
    if (config.report) {
        ReportStep(c, stepper, changes, odometry, p.visits.back(), run.summary.at("visits"),
                   &run.summary);
    }
    return run;
}

}  // namespace bimslam::mapping
