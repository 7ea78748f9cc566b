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

CaptureOdometryReport RunCaptureOdometry(const CaptureOdometryOptions& o) {
    const auto wall_start = std::chrono::steady_clock::now();
    CaptureOdometryReport report;
    // A folder of per-scan clouds (cloud_folder.hpp), or an Ouster recording.
    std::optional<CloudFolder> clouds;
    io::CaptureFiles files;
    if (IsCloudFolder(o.capture_dir)) {
        clouds = ResolveCloudFolder(o.capture_dir);
        files.packets = clouds->dir;
    } else {
        files = io::ResolveCapture(o.capture_dir);
    }
    const fs::path& pcap = files.packets;
    const fs::path can_log = o.can_log.empty() ? files.can_log : o.can_log;
    odometry::LidarOdometryConfig config = o.odometry;
    config.use_imu = config.use_imu && o.use_imu;
    if (o.mount) {
        config.T_base_lidar = *o.mount;
    } else if (!files.capture_json.empty()) {
        if (const auto mount = io::ReadCaptureMount(files.capture_json)) {
            config.T_base_lidar = *mount;
            report.mount_from_capture = true;
        }
    }
    std::vector<pipeline::BodyInput> body;
    if (o.use_can && !can_log.empty()) {
        if (!fs::is_regular_file(can_log)) {
            throw common::FileError(StatusCode::kNotFound, can_log.string(), 0, "missing");
        }
        body = ReadGo1(can_log);
        for (pipeline::BodyInput& b : body) b.measured_ns += o.time_offset_ns;
        report.used_can = true;
    } else if (o.use_can && clouds) {
        report.notes.push_back("a folder of point clouds: no CAN (--can LOG adds one)");
    } else if (o.use_can) {
        report.notes.push_back(files.folder ? "no go1_can.log: no body-motion prior"
                                            : "no CAN log (a recording without a capture folder; "
                                              "--can LOG adds one): no body-motion prior");
    }
    config.use_body_motion = report.used_can && !body.empty();

    ouster::SensorInfo info;
    if (clouds) {
        info.prod_line = "point clouds (" + clouds->extension + ")";
        info.format.pixels_per_column = info.format.columns_per_frame = 0;
    } else {
        info = capture::LoadRecordingInfo(files);
        if (!o.imu_rotation_rpy_deg.isZero()) {
            info.imu_to_sensor_transform.topLeftCorner<3, 3>() *=
                common::RotationFromRpyDeg(o.imu_rotation_rpy_deg);
        }
    }
    // The session names its metadata file: the JSON's, the bag's (whose metadata topic it is),
    // or a cloud folder's times file.
    const std::string metadata_name =
        clouds ? clouds->times.filename().string()
               : (files.metadata.empty() ? files.packets : files.metadata).filename().string();
    std::optional<capture::OusterCapture> capture;
    if (!clouds) capture.emplace(pcap, info);
    pipeline::ScanPipelineConfig pc;
    pc.odometry = config;
    pc.keyframes = o.keyframes;
    pipeline::ScanPipeline join(pc);
    if (capture) {
        capture->OnImu([&](const ouster::ImuSample& s) {
            odometry::ImuMeasurement m = pipeline::ImuFromOuster(s);
            m.t_ns += o.time_offset_ns;
            join.AddImu(m);
        });
    }
    // A cloud folder's IMU file: its samples join the scans as the packets' would.
    std::vector<odometry::ImuMeasurement> folder_imu;
    if (clouds && !clouds->imu.empty() && config.use_imu) {
        folder_imu = ReadImuCsv(clouds->imu);
        for (odometry::ImuMeasurement& m : folder_imu) m.t_ns += o.time_offset_ns;
    } else if (clouds && config.use_imu) {
        report.notes.push_back("no imu.csv beside the clouds: no IMU");
    }
    size_t next_imu = 0;
    // The next scan into `scan`: a frame of the recording, or the folder's next cloud.
    size_t next_cloud = 0;
    const auto next_scan = [&](pipeline::ScanInput* scan) {
        if (capture) {
            const ouster::LidarFrame* frame = capture->NextFrame();
            if (frame == nullptr) return false;
            // The packet that emitted the frame: the last one read (the end of the file for the
            // frame Flush emits, after every record).
            pipeline::FrameToScan(*frame, capture->last_arrival_ns(), join.imu_added(), scan);
            return true;
        }
        if (next_cloud == clouds->scans.size()) return false;
        scan->cloud = ReadScanCloud(*clouds, next_cloud);
        if (next_cloud == 0 && !scan->cloud.HasTime()) {
            report.notes.push_back("the scans of " + clouds->dir.string() +
                                   " carry no per-point time: deskew is off (each scan is taken "
                                   "as if captured at one instant)");
        }
        // The IMU samples up to the scan's end, as a recording delivers them before the scan
        // is emitted.
        int64_t end_ns = scan->cloud.stamp.ns;
        for (const uint32_t dt : scan->cloud.time_offset_ns)
            end_ns = std::max(end_ns, scan->cloud.stamp.ns + int64_t(dt));
        for (; next_imu < folder_imu.size() && folder_imu[next_imu].t_ns <= end_ns; ++next_imu) {
            join.AddImu(folder_imu[next_imu]);
        }
        scan->complete = true;
        scan->frame_id = int64_t(next_cloud++);
        scan->last_column_ns = -1;
        scan->last_arrival_ns = 0;
        scan->emitted_arrival_ns = scan->cloud.stamp.ns;
        scan->imu_before = join.imu_added();
        return true;
    };

    std::optional<io::SessionWriter> writer;
    if (!o.session_dir.empty()) {
        writer.emplace(o.session_dir,
                       pipeline::MakeSessionManifest(info, metadata_name, o.keyframes),
                       io::SessionWriterOptions{
                           .overwrite = o.overwrite, .flush_every = 50, .sync_each_file = false});
    }

    pipeline::ScanInput scan;
    size_t next_body = 0;
    int64_t first_stamp = -1;
    // The odometry's verdict on the scans a session holds goes into that session (before its
    // session.json), so that anchoring does not join its keyframes across a failed stretch.
    size_t session_first_scan = 0, last_scan = 0;
    const auto write_verdict = [&](size_t last) {
        io::WriteFileAtomic(writer->dir() / odometry::TrajectoryTrust::kSessionFile,
                            report.trust.SessionJson(session_first_scan, last).dump(1) + "\n");
    };
    // A capture that turns out corrupt part way: the error names the file and the byte; the
    // session so far stays on disk without session.json (SessionWriter's destructor flushes it),
    // recoverable up to its last complete keyframe, and the message says so.
    try {
        while (next_scan(&scan)) {
            const int64_t stamp = scan.cloud.stamp.ns;
            if (first_stamp < 0) first_stamp = stamp;
            if (o.max_duration_s > 0 && double(stamp - first_stamp) * 1e-9 > o.max_duration_s)
                break;
            for (;
                 next_body < body.size() && body[next_body].received_ns <= scan.emitted_arrival_ns;
                 ++next_body) {
                join.AddBody(body[next_body]);
            }
            const auto cpu_start = odometry::BudgetNow(true);
            const pipeline::ScanOutput& out = join.Process(scan);
            report.scan_cpu_ms.push_back(
                std::chrono::duration<double, std::milli>(odometry::BudgetNow(true) - cpu_start)
                    .count());
            const odometry::OdometryResult& r = *out.odometry;
            report.scan_ms.push_back(r.total_ms);
            report.preprocess_ms.push_back(r.preprocess_ms);
            report.register_ms.push_back(r.register_ms);
            report.map_ms.push_back(r.map_ms);
            report.mean_registration_points += double(r.preprocess.registration_points);
            report.mean_iterations += double(r.registration.iterations);
            report.mean_map_points += double(r.preprocess.map_points);
            report.capture_s = double(stamp - first_stamp) * 1e-9;
            report.trust.Add(size_t(out.scan_index), report.capture_s, r.flags, r.check_reasons,
                             out.stamp_ns);
            last_scan = size_t(out.scan_index);
            if (writer && out.clock_jump) {
                // A sensor restart or clock step: a new odometry frame, so a new session next
                // to the first (SESSION-2, -3, ...).
                if (last_scan > 0) write_verdict(last_scan - 1);
                session_first_scan = last_scan;
                writer->Finish();
                const fs::path next =
                    o.session_dir.string() + "-" + std::to_string(join.stats().clock_jumps + 1);
                report.notes.push_back("the sensor clock jumped at scan " +
                                       std::to_string(out.scan_index) +
                                       ": the odometry started again in " + next.string());
                writer.reset();
                writer.emplace(
                    next, pipeline::MakeSessionManifest(info, metadata_name, o.keyframes),
                    io::SessionWriterOptions{
                        .overwrite = o.overwrite, .flush_every = 50, .sync_each_file = false});
            }
            if (writer) pipeline::WriteScan(out, *writer);
            if (o.on_scan) o.on_scan(*out.odometry);
        }
    } catch (const common::FileError& e) {
        if (!writer || join.stats().keyframes == 0) throw;
        throw common::FileError(e.code(), e.path(), e.line(),
                                e.detail() + "; the session up to scan " +
                                    std::to_string(join.stats().scans) + " (" +
                                    std::to_string(join.stats().keyframes) +
                                    " keyframes) is left in " + o.session_dir.string() +
                                    " without session.json: `bimslam session info` recovers it");
    }
    const pipeline::ScanPipelineStats& st = join.stats();
    report.scans = st.scans;
    report.incomplete_frames = st.incomplete_scans;
    report.imu_samples = st.imu_samples;
    report.body_samples = st.body_samples;
    report.over_budget = st.over_budget;
    report.degenerate = st.degenerate;
    report.failed = st.failed;
    report.check_failed = st.check_failed;
    report.not_converged = st.not_converged;
    report.contradicted_gyro = st.contradicted_gyro;
    report.contradicted_legs = st.contradicted_legs;
    report.distance_m = st.distance_m;
    if (report.scans == 0) {
        throw common::FileError(StatusCode::kDataLoss, pcap.string(), 0,
                                "no lidar frame in the capture");
    }
    report.keyframes = st.keyframes;
    report.mean_registration_points /= double(report.scans);
    report.mean_iterations /= double(report.scans);
    report.mean_map_points /= double(report.scans);
    report.host_minus_sensor_ns = st.host_minus_sensor_ns;
    if (writer) {
        write_verdict(last_scan);
        // The clock offset since the last clock jump: this session's (map_bim.las's GPS times).
        if (st.host_minus_sensor_ns != 0) writer->SetHostMinusSensorNs(st.host_minus_sensor_ns);
        writer->Finish();
    }
    report.wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    return report;
}

}  // namespace bimslam::replay
