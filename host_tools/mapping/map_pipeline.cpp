#include "host_tools/mapping/map_pipeline.hpp"

#include <chrono>
#include <system_error>

#include "algorithms/common/status.hpp"
#include "algorithms/common/stopwatch.hpp"
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
#include "host_tools/changes/change_evaluation.hpp"
#include "host_tools/changes/change_report.hpp"
#include "host_tools/changes/ifc_update.hpp"
#include "host_tools/changes/session_input.hpp"
#include "host_tools/changes/survey_datum.hpp"
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
    if (recordings.empty()) bad("no recording given");
    if (out.empty()) bad("-o: no output folder given");
    if (!(keyframe_gap_m > 0)) bad("keyframe_gap_m " + std::to_string(keyframe_gap_m));
    if (!(odometry_budget_ms > 0)) bad("odometry_budget_ms " + std::to_string(odometry_budget_ms));
    if (threads < 0) bad("threads " + std::to_string(threads));
    anchor.Validate();
    changes.Validate();
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
    Stepper(const fs::path& out, bool force, MapRun* run) : out_(out), force_(force), run_(run) {
        fs::create_directories(out_ / "stamps");
    }
    bool Run(const std::string& step, const std::string& stamp_name, StepStamp& stamp,
             const std::string& file, const std::function<void()>& body) {
        const fs::path file_stamp = out_ / "stamps" / (stamp_name + ".json");
        const auto t0 = Clock::now();
        if (!force_ && stamp.Matches(file_stamp)) {
            run_->steps.push_back({step, true, 0.0});
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
        run_->steps.push_back({step, false, common::SecondsSince(t0)});
        return true;
    }

private:
    fs::path out_;
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

}  // namespace

MapRun RunMap(const MapConfig& config, const MapProgress& progress_in) {
    config.Validate();
    // Every input checked before any step: exit 2 names the file, and nothing is written.
    CheckModelFile(config.model);
    const std::vector<RecordingInput> recordings = CheckRecordings(config.recordings);
    const MapProgress progress = progress_in ? progress_in : [](const std::string&, double) {};

    // The model is read (IFC++, seconds for a big one) only by the steps that run, and for a datum.
    std::optional<bim::BimModel> plain_model;
    auto model = [&]() -> const bim::BimModel& {
        if (!plain_model) {
            progress("reading the model", 0.0);
            plain_model = bim::LoadIfc(config.model);
        }
        return *plain_model;
    };
    // The datum names the model's GlobalIds: checked against it now, as the other inputs.
    if (!config.datum.empty()) (void)change_detection::ReadSurveyDatum(config.datum, model());

    const fs::path& out = config.out;
    MapRun run;
    Stepper stepper(out, config.force, &run);
    const std::string model_file = config.model.string();
    const std::string sha256 = io::Sha256File(config.model);

    // 1. The reference session, by the model's content.
    // It is cast with the first recording's sensor (its beam table and columns), so that its
    // scans and descriptors look like the recordings' own; the walk takes the stairs between the
    // storeys (bim/reference_walk.hpp).
    const ReferenceSensor sensor = ReferenceSensorOf(recordings);
    StepStamp reference("reference");
    reference.AddParameter("model_sha256", sha256);
    reference.AddParameter("keyframe_gap_m", config.keyframe_gap_m);
    reference.AddParameter("lidar", sensor.stamp);
    reference.AddParameter("walk", "every storey, joined by the stairs");
    stepper.Run("reference", "reference", reference, model_file, [&] {
        bim::ReferenceSessionOptions ro;
        ro.overwrite = true;
        ro.lidar = sensor.lidar;
        ro.sensor_model = sensor.name;
        ro.keyframe_gap_m = config.keyframe_gap_m;
        ro.progress = [&](size_t d, size_t n) { progress("reference", n ? double(d) / n : 0.0); };
        bim::WriteReferenceSession(model(), sha256, out / "reference", ro);
    });

    // 2. Odometry of each recording.
    std::vector<StepStamp> odometry;
    for (const RecordingInput& r : recordings) {
        StepStamp s("odometry_" + r.name);
        s.AddFileTime("pcap", r.files.packets);  // a pcap or a bag
        if (!r.files.metadata.empty()) s.AddFileTime("metadata", r.files.metadata);
        if (!r.files.can_log.empty()) s.AddFileTime("can_log", r.files.can_log);
        if (!r.files.capture_json.empty()) s.AddFileTime("capture_json", r.files.capture_json);
        s.AddParameter("budget_ms", config.odometry_budget_ms);
        s.AddParameter("budget_clock", "thread cpu");
        // The session carries the odometry's verdict (odometry_verdict.json) since this version:
        // an older session is made again, so that anchoring sees where it failed.
        s.AddParameter("verdict_in_session", 1);
        const std::string step = "odometry " + r.name;
        stepper.Run(step, "odometry_" + r.name, s, r.files.packets.string(), [&] {
            replay::CaptureOdometryOptions o;
            o.capture_dir = r.path;
            o.session_dir = out / "odometry" / r.name;
            o.overwrite = true;
            o.odometry.budget_ms = config.odometry_budget_ms;
            // Counted in the thread's CPU time: an offline run's results depend on the work, not
            // on what else the machine does (a scan preempted for 170 ms of wall time was cut
            // short, failed its checks and made a whole run untrusted on a loaded machine).
            o.odometry.registration.cpu_time_budget = true;
            double capture_s = 0;
            o.on_scan = [&, n = size_t(0),
                         first = int64_t(-1)](const odometry::OdometryResult& res) mutable {
                const int64_t t = res.stamp_ns;
                if (first < 0) first = t;
                if (++n % 20 == 0) progress(step + " (" + std::to_string(n) + " scans)", 0.0);
                capture_s = double(t - first) * 1e-9;
            };
            fs::create_directories(out / "odometry");
            const replay::CaptureOdometryReport rep = replay::RunCaptureOdometry(o);
            const json stats = {{"recording", r.path.string()},
                                {"pcap", r.files.packets.string()},
                                {"scans", rep.scans},
                                {"keyframes", rep.keyframes},
                                {"incomplete_frames", rep.incomplete_frames},
                                {"imu_samples", rep.imu_samples},
                                {"body_samples", rep.body_samples},
                                {"used_can", rep.used_can},
                                {"distance_m", rep.distance_m},
                                {"capture_s", rep.capture_s},
                                {"wall_s", rep.wall_s},
                                {"scan_ms_p50", replay::Percentile(rep.scan_ms, 0.5)},
                                {"scan_ms_p99", replay::Percentile(rep.scan_ms, 0.99)},
                                {"scan_ms_max", replay::Percentile(rep.scan_ms, 1.0)},
                                {"over_budget", rep.over_budget},
                                {"degenerate", rep.degenerate},
                                {"failed", rep.failed},
                                {"check_failed", rep.check_failed},
                                {"verdict", rep.trust.Verdict()},
                                {"verdict_text", rep.trust.Describe()},
                                {"failed_stretches", rep.trust.ToJson().at("failed_stretches")},
                                {"bridged_by_prior", rep.trust.bridged_by_prior()},
                                {"bridged_over_budget", rep.trust.bridged_over_budget()},
                                {"scan_ms", rep.scan_ms},
                                {"notes", rep.notes}};
            io::WriteFileAtomic(out / "odometry" / (r.name + ".json"), stats.dump() + "\n");
        });
        odometry.push_back(std::move(s));
    }

    // 3. Anchoring: every session at once (loops between them help).
    StepStamp anchoring("anchor");
    anchoring.AddUpstream(reference);
    for (const StepStamp& s : odometry) anchoring.AddUpstream(s);
    anchoring.AddParameter("anchor", AnchorParameters(config.anchor));
    stepper.Run("anchor", "anchor", anchoring, (out / "odometry").string(), [&] {
        anchor::AnchorConfig ac = config.anchor;
        ac.threads = config.threads;
        anchor::LoadOptions lo;
        lo.cloud = ac.cloud;
        lo.descriptor = ac.descriptor;
        lo.threads = config.threads;
        std::vector<anchor::AnchorSession> sessions;
        sessions.push_back(anchor::LoadAnchorSession(out / "reference", lo));
        for (size_t k = 0; k < recordings.size(); ++k) {
            progress("anchor: reading " + recordings[k].name, double(k) / recordings.size());
            sessions.push_back(
                anchor::LoadAnchorSession(out / "odometry" / recordings[k].name, lo));
        }
        const anchor::AnchorResult r =
            anchor::Anchor(sessions, ac, [&](const std::string& s, size_t d, size_t n) {
                progress("anchor: " + s, n ? double(d) / double(n) : 0.0);
            });
        anchor::WriteAnchorOutput(out / "anchor", sessions, r, ac, true);
    });

    // 4. Change detection of each anchored session, as `bimslam changes` does it.
    StepStamp change("changes");
    change.AddUpstream(anchoring);
    change.AddParameter("model_sha256", sha256);
    change.AddParameter("changes", ChangeParameters(config.changes));
    for (const RecordingInput& r : recordings) {
        if (!r.truth_changes.empty()) change.AddFileTime("truth_" + r.name, r.truth_changes);
    }
    // The scores' in-view rule: an output scored by an older rule is scored again.
    change.AddParameter("in_view_rule", "keyframes' map points on the object (issue 31)");
    if (!config.datum.empty()) change.AddFileTime("datum", config.datum);
    stepper.Run("changes", "changes", change, model_file, [&] {
        fs::remove_all(out / "changes");
        fs::create_directories(out / "changes");
        const std::vector<std::string> anchored = AnchoredNames(out / "anchor");
        if (anchored.empty()) return;  // nothing in BIM coordinates to compare
        bim::IfcLoadOptions load;
        load.space_geometry = true;
        load.progress = [&](double f) { progress("changes: reading the model", f); };
        const bim::BimModel m = bim::LoadIfc(config.model, load);
        const changes::ChangeModel change_model = change_detection::ToChangeModel(m);
        changes::ChangeDetectorConfig detector = config.changes;
        if (!config.datum.empty()) {
            detector.refinement.datum = change_detection::ReadSurveyDatum(config.datum, m);
        }
        const std::string original = io::ReadFileToString(config.model);
        const change_detection::ModelInfo info{config.model, sha256};
        for (const std::string& label : anchored) {
            const fs::path dir = out / "changes" / label;
            const change_detection::SessionInput input =
                change_detection::LoadAnchoredSession(out / "anchor" / label, m.origin_m);
            change_detection::SessionChanges found;
            found.label = label;
            found.input = &input;
            found.result = changes::DetectChanges(
                change_model, input.keyframes, input.edges, detector,
                [&](std::string_view stage, double f) {
                    progress("changes " + label + ": " + std::string(stage), f);
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
                change_detection::UpdateIfc(model_file, original, m, found, seed).text);
            for (const RecordingInput& r : recordings) {
                if (r.name != label || r.truth_changes.empty()) continue;
                const change_detection::ChangeEvaluation ev = change_detection::EvaluateChanges(
                    change_detection::ReadTruthChanges(r.truth_changes),
                    change_detection::ReadFoundChanges(dir));
                io::WriteFileAtomic(dir / "evaluation.json", ev.ToJson().dump(2) + "\n");
            }
        }
    });

    run.summary = BuildSummary(out, config.model, recordings);
    io::WriteFileAtomic(out / "summary.json", run.summary.dump(2) + "\n");

    // 5. The report.
    if (config.report) {
        StepStamp page("report");
        page.AddUpstream(change);
        for (const StepStamp& s : odometry) page.AddUpstream(s);
        page.AddParameter("page", report::PageVersion());
        for (const RecordingInput& r : recordings) {  // the APE over time in the page
            if (!r.ground_truth.empty()) page.AddFileTime("truth_" + r.name, r.ground_truth);
        }
        const fs::path html = out / "report" / "report.html";
        stepper.Run("report", "report", page, html.string(), [&] {
            fs::create_directories(out / "report");
            report::WriteReport(
                out, html, [&](const std::string& s, double f) { progress("report: " + s, f); });
        });
        run.summary["report"] = html.string();
    }
    return run;
}

}  // namespace bimslam::mapping
