// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/replay/capture_odometry.hpp"

#include <algorithm>
#include <chrono>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "algorithms/common/se3.hpp"
#include "algorithms/common/status.hpp"
#include "algorithms/io/capture_files.hpp"
#include "algorithms/io/file_util.hpp"
#include "algorithms/io/session.hpp"
#include "algorithms/odometry/scan_registration.hpp"
#include "algorithms/pipeline/scan_pipeline.hpp"
#include "drivers/can/go1_decoder.hpp"
#include "drivers/ouster/metadata.hpp"
#include "host_tools/capture/can_log.hpp"
#include "host_tools/capture/ouster_capture.hpp"
#include "host_tools/replay/cloud_folder.hpp"
#include "host_tools/replay/imu_csv.hpp"

namespace bimslam::replay {
namespace fs = std::filesystem;
using common::StatusCode;

namespace {

// Every Go1 sample of a CAN log, in receive order.
std::vector<pipeline::BodyInput> ReadGo1(const fs::path& path) {
    capture::CanLog log(path);
    can::Go1Decoder decoder;
    std::vector<pipeline::BodyInput> out;
    const auto take = [&out](std::span<const can::Go1Sample> ready) {
        for (const can::Go1Sample& s : ready) out.push_back(pipeline::BodyFromGo1(s));
    };
    common::CanFrame frame;
    while (log.Next(frame)) {
        if (decoder.Feed(frame).samples > 0) take(decoder.ready());
    }
    if (decoder.Flush() > 0) take(decoder.ready());
    return out;
}

}  // namespace

double Percentile(std::vector<double> v, double p) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, size_t(p * double(v.size() - 1) + 0.5))];
}

nlohmann::json ReportJson(const CaptureOdometryReport& r) {
    const auto p = [](const std::vector<double>& v, double q) { return Percentile(v, q); };
    nlohmann::json j = {{"scans", r.scans},
                        {"keyframes", r.keyframes},
                        {"incomplete_frames", r.incomplete_frames},
                        {"imu_samples", r.imu_samples},
                        {"body_samples", r.body_samples},
                        {"used_can", r.used_can},
                        {"mount_from_capture", r.mount_from_capture},
                        {"distance_m", r.distance_m},
                        {"capture_s", r.capture_s},
                        {"wall_s", r.wall_s},
                        {"scan_ms_p50", p(r.scan_ms, 0.5)},
                        {"scan_ms_p99", p(r.scan_ms, 0.99)},
                        {"scan_ms_max", p(r.scan_ms, 1.0)},
                        {"scan_cpu_ms_p50", p(r.scan_cpu_ms, 0.5)},
                        {"scan_cpu_ms_p99", p(r.scan_cpu_ms, 0.99)},
                        {"scan_cpu_ms_max", p(r.scan_cpu_ms, 1.0)},
                        {"preprocess_ms_p50", p(r.preprocess_ms, 0.5)},
                        {"preprocess_ms_p99", p(r.preprocess_ms, 0.99)},
                        {"register_ms_p50", p(r.register_ms, 0.5)},
                        {"register_ms_p99", p(r.register_ms, 0.99)},
                        {"map_ms_p50", p(r.map_ms, 0.5)},
                        {"map_ms_p99", p(r.map_ms, 0.99)},
                        {"mean_registration_points", r.mean_registration_points},
                        {"mean_iterations", r.mean_iterations},
                        {"mean_map_points", r.mean_map_points},
                        {"over_budget", r.over_budget},
                        {"degenerate", r.degenerate},
                        {"failed", r.failed},
                        {"check_failed", r.check_failed},
                        {"verdict_text", r.trust.Describe()},
                        {"not_converged", r.not_converged},
                        {"contradicted_gyro", r.contradicted_gyro},
                        {"contradicted_legs", r.contradicted_legs},
                        {"notes", r.notes}};
    j.update(r.trust.ToJson());  // the verdict, its stretches and bridged counts
    return j;
}

namespace {

io::SessionWriterOptions WriterOptions(bool overwrite) {
    return {.overwrite = overwrite, .flush_every = 50, .sync_each_file = false};
}

// One run of the odometry over a recording or a folder of clouds: the input, the pipeline, the
// session being written and the report, held together while the scans go through.
class CaptureOdometryRun {
public:
    explicit CaptureOdometryRun(const CaptureOdometryOptions& o) : o_(o) {}
    CaptureOdometryReport Run();

private:
    void ResolveInput();
    void ReadBody();
    void OpenSensor();
    bool NextScan(pipeline::ScanInput* scan);
    bool NextCloud(pipeline::ScanInput* scan);
    bool Process(const pipeline::ScanInput& scan);
    void StartNextSession(const pipeline::ScanOutput& out);
    void WriteVerdict(size_t last);
    void Finish();

    const CaptureOdometryOptions& o_;
    const std::chrono::steady_clock::time_point wall_start_ = std::chrono::steady_clock::now();
    CaptureOdometryReport report_;
    std::optional<CloudFolder> clouds_;  // a folder of per-scan clouds (cloud_folder.hpp)
    io::CaptureFiles files_;             // else an Ouster recording
    odometry::LidarOdometryConfig config_;
    std::vector<pipeline::BodyInput> body_;
    ouster::SensorInfo info_;
    std::string metadata_name_;
    std::optional<capture::OusterCapture> capture_;
    std::optional<pipeline::ScanPipeline> join_;
    std::vector<odometry::ImuMeasurement> folder_imu_;  // a cloud folder's imu.csv
    size_t next_imu_ = 0, next_cloud_ = 0, next_body_ = 0;
    int64_t first_stamp_ = -1;
    std::optional<io::SessionWriter> writer_;
    // The odometry's verdict on the scans a session holds goes into that session (before its
    // session.json), so that anchoring does not join its keyframes across a failed stretch.
    size_t session_first_scan_ = 0, last_scan_ = 0;
};

void CaptureOdometryRun::ResolveInput() {
    if (IsCloudFolder(o_.capture_dir)) {
        clouds_ = ResolveCloudFolder(o_.capture_dir);
        files_.packets = clouds_->dir;
    } else {
        files_ = io::ResolveCapture(o_.capture_dir);
    }
    config_ = o_.odometry;
    config_.use_imu = config_.use_imu && o_.use_imu;
    if (o_.mount) {
        config_.T_base_lidar = *o_.mount;
    } else if (!files_.capture_json.empty()) {
        if (const auto mount = io::ReadCaptureMount(files_.capture_json)) {
            config_.T_base_lidar = *mount;
            report_.mount_from_capture = true;
        }
    }
}

// The Go1's samples from the CAN log (the body-motion prior), or a note why there are none.
void CaptureOdometryRun::ReadBody() {
    const fs::path can_log = o_.can_log.empty() ? files_.can_log : o_.can_log;
    if (o_.use_can && !can_log.empty()) {
        if (!fs::is_regular_file(can_log)) {
            throw common::FileError(StatusCode::kNotFound, can_log.string(), 0, "missing");
        }
        body_ = ReadGo1(can_log);
        for (pipeline::BodyInput& b : body_) b.measured_ns += o_.time_offset_ns;
        report_.used_can = true;
    } else if (o_.use_can && clouds_) {
        report_.notes.push_back("a folder of point clouds: no CAN (--can LOG adds one)");
    } else if (o_.use_can) {
        report_.notes.push_back(files_.folder ? "no go1_can.log: no body-motion prior"
                                              : "no CAN log (a recording without a capture folder; "
                                                "--can LOG adds one): no body-motion prior");
    }
    config_.use_body_motion = report_.used_can && !body_.empty();
}

// The sensor's description, the recording's reader and the pipeline, the IMU joined to it.
void CaptureOdometryRun::OpenSensor() {
    if (clouds_) {
        info_.prod_line = "point clouds (" + clouds_->extension + ")";
        info_.format.pixels_per_column = info_.format.columns_per_frame = 0;
    } else {
        info_ = capture::LoadRecordingInfo(files_);
        if (!o_.imu_rotation_rpy_deg.isZero()) {
            info_.imu_to_sensor_transform.topLeftCorner<3, 3>() *=
                common::RotationFromRpyDeg(o_.imu_rotation_rpy_deg);
        }
    }
    // The session names its metadata file: the JSON's, the bag's (whose metadata topic it is),
    // or a cloud folder's times file.
    metadata_name_ =
        clouds_ ? clouds_->times.filename().string()
                : (files_.metadata.empty() ? files_.packets : files_.metadata).filename().string();
    if (!clouds_) capture_.emplace(files_.packets, info_);
    pipeline::ScanPipelineConfig pc;
    pc.odometry = config_;
    pc.keyframes = o_.keyframes;
    join_.emplace(pc);
    if (capture_) {
        capture_->OnImu([this](const ouster::ImuSample& s) {
            odometry::ImuMeasurement m = pipeline::ImuFromOuster(s);
            m.t_ns += o_.time_offset_ns;
            join_->AddImu(m);
        });
    }
    // A cloud folder's IMU file: its samples join the scans as the packets' would.
    if (clouds_ && !clouds_->imu.empty() && config_.use_imu) {
        folder_imu_ = ReadImuCsv(clouds_->imu);
        for (odometry::ImuMeasurement& m : folder_imu_) m.t_ns += o_.time_offset_ns;
    } else if (clouds_ && config_.use_imu) {
        report_.notes.push_back("no imu.csv beside the clouds: no IMU");
    }
}

// The next scan into `scan`: a frame of the recording, or the folder's next cloud.
bool CaptureOdometryRun::NextScan(pipeline::ScanInput* scan) {
    if (!capture_) return NextCloud(scan);
    const ouster::LidarFrame* frame = capture_->NextFrame();
    if (frame == nullptr) return false;
    // The packet that emitted the frame: the last one read (the end of the file for the frame
    // Flush emits, after every record).
    pipeline::FrameToScan(*frame, capture_->last_arrival_ns(), join_->imu_added(), scan);
    return true;
}

bool CaptureOdometryRun::NextCloud(pipeline::ScanInput* scan) {
    if (next_cloud_ == clouds_->scans.size()) return false;
    scan->cloud = ReadScanCloud(*clouds_, next_cloud_);
    if (next_cloud_ == 0 && !scan->cloud.HasTime()) {
        report_.notes.push_back("the scans of " + clouds_->dir.string() +
                                " carry no per-point time: deskew is off (each scan is taken "
                                "as if captured at one instant)");
    }
    // The IMU samples up to the scan's end, as a recording delivers them before the scan is
    // emitted.
    int64_t end_ns = scan->cloud.stamp.ns;
    for (const uint32_t dt : scan->cloud.time_offset_ns)
        end_ns = std::max(end_ns, scan->cloud.stamp.ns + int64_t(dt));
    for (; next_imu_ < folder_imu_.size() && folder_imu_[next_imu_].t_ns <= end_ns; ++next_imu_) {
        join_->AddImu(folder_imu_[next_imu_]);
    }
    scan->complete = true;
    scan->frame_id = int64_t(next_cloud_++);
    scan->last_column_ns = -1;
    scan->last_arrival_ns = 0;
    scan->emitted_arrival_ns = scan->cloud.stamp.ns;
    scan->imu_before = join_->imu_added();
    return true;
}

void CaptureOdometryRun::WriteVerdict(size_t last) {
    io::WriteFileAtomic(writer_->dir() / odometry::TrajectoryTrust::kSessionFile,
                        report_.trust.SessionJson(session_first_scan_, last).dump(1) + "\n");
}

// A sensor restart or clock step: a new odometry frame, so a new session next to the first
// (SESSION-2, -3, ...).
void CaptureOdometryRun::StartNextSession(const pipeline::ScanOutput& out) {
    if (last_scan_ > 0) WriteVerdict(last_scan_ - 1);
    session_first_scan_ = last_scan_;
    writer_->Finish();
    const fs::path next =
        o_.session_dir.string() + "-" + std::to_string(join_->stats().clock_jumps + 1);
    report_.notes.push_back("the sensor clock jumped at scan " + std::to_string(out.scan_index) +
                            ": the odometry started again in " + next.string());
    writer_.reset();
    writer_.emplace(next, pipeline::MakeSessionManifest(info_, metadata_name_, o_.keyframes),
                    WriterOptions(o_.overwrite));
}

// One scan through the pipeline, its figures into the report and its keyframe into the session.
// False: the scan is past --duration and was not processed.
bool CaptureOdometryRun::Process(const pipeline::ScanInput& scan) {
    const int64_t stamp = scan.cloud.stamp.ns;
    if (first_stamp_ < 0) first_stamp_ = stamp;
    if (o_.max_duration_s > 0 && double(stamp - first_stamp_) * 1e-9 > o_.max_duration_s)
        return false;
    for (; next_body_ < body_.size() && body_[next_body_].received_ns <= scan.emitted_arrival_ns;
         ++next_body_) {
        join_->AddBody(body_[next_body_]);
    }
    const auto cpu_start = odometry::BudgetNow(true);
    const pipeline::ScanOutput& out = join_->Process(scan);
    report_.scan_cpu_ms.push_back(
        std::chrono::duration<double, std::milli>(odometry::BudgetNow(true) - cpu_start).count());
    const odometry::OdometryResult& r = *out.odometry;
    report_.scan_ms.push_back(r.total_ms);
    report_.preprocess_ms.push_back(r.preprocess_ms);
    report_.register_ms.push_back(r.register_ms);
    report_.map_ms.push_back(r.map_ms);
    report_.mean_registration_points += double(r.preprocess.registration_points);
    report_.mean_iterations += double(r.registration.iterations);
    report_.mean_map_points += double(r.preprocess.map_points);
    report_.capture_s = double(stamp - first_stamp_) * 1e-9;
    report_.trust.Add(size_t(out.scan_index), report_.capture_s, r.flags, r.check_reasons,
                      out.stamp_ns);
    last_scan_ = size_t(out.scan_index);
    if (writer_ && out.clock_jump) StartNextSession(out);
    if (writer_) pipeline::WriteScan(out, *writer_);
    if (o_.on_scan) o_.on_scan(*out.odometry);
    return true;
}

// The pipeline's counts into the report; the session's verdict and session.json.
void CaptureOdometryRun::Finish() {
    const pipeline::ScanPipelineStats& st = join_->stats();
    report_.scans = st.scans;
    report_.incomplete_frames = st.incomplete_scans;
    report_.imu_samples = st.imu_samples;
    report_.body_samples = st.body_samples;
    report_.over_budget = st.over_budget;
    report_.degenerate = st.degenerate;
    report_.failed = st.failed;
    report_.check_failed = st.check_failed;
    report_.not_converged = st.not_converged;
    report_.contradicted_gyro = st.contradicted_gyro;
    report_.contradicted_legs = st.contradicted_legs;
    report_.distance_m = st.distance_m;
    if (report_.scans == 0) {
        throw common::FileError(StatusCode::kDataLoss, files_.packets.string(), 0,
                                "no lidar frame in the capture");
    }
    report_.keyframes = st.keyframes;
    report_.mean_registration_points /= double(report_.scans);
    report_.mean_iterations /= double(report_.scans);
    report_.mean_map_points /= double(report_.scans);
    report_.host_minus_sensor_ns = st.host_minus_sensor_ns;
    if (writer_) {
        WriteVerdict(last_scan_);
        // The clock offset since the last clock jump: this session's (map_bim.las's GPS times).
        if (st.host_minus_sensor_ns != 0) writer_->SetHostMinusSensorNs(st.host_minus_sensor_ns);
        writer_->Finish();
    }
}

CaptureOdometryReport CaptureOdometryRun::Run() {
    ResolveInput();
    ReadBody();
    OpenSensor();
    if (!o_.session_dir.empty()) {
        writer_.emplace(o_.session_dir,
                        pipeline::MakeSessionManifest(info_, metadata_name_, o_.keyframes),
                        WriterOptions(o_.overwrite));
    }
    pipeline::ScanInput scan;
    // A capture that turns out corrupt part way: the error names the file and the byte; the
    // session so far stays on disk without session.json (SessionWriter's destructor flushes it),
    // recoverable up to its last complete keyframe, and the message says so.
    try {
        while (NextScan(&scan) && Process(scan)) {
        }
    } catch (const common::FileError& e) {
        if (!writer_ || join_->stats().keyframes == 0) throw;
        throw common::FileError(e.code(), e.path(), e.line(),
                                e.detail() + "; the session up to scan " +
                                    std::to_string(join_->stats().scans) + " (" +
                                    std::to_string(join_->stats().keyframes) +
                                    " keyframes) is left in " + o_.session_dir.string() +
                                    " without session.json: `bimslam session info` recovers it");
    }
    Finish();
    report_.wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start_).count();
    return report_;
}

}  // namespace

CaptureOdometryReport RunCaptureOdometry(const CaptureOdometryOptions& o) {
    return CaptureOdometryRun(o).Run();
}

}  // namespace bimslam::replay
