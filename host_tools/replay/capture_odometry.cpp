#include "host_tools/replay/capture_odometry.hpp"

#include <algorithm>
#include <chrono>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "algorithms/common/status.hpp"
#include "algorithms/io/session.hpp"
#include "drivers/can/go1_decoder.hpp"
#include "drivers/ouster/metadata.hpp"
#include "host_tools/capture/can_log.hpp"
#include "host_tools/capture/ouster_capture.hpp"

namespace bimslam::replay {
namespace fs = std::filesystem;
using common::StatusCode;

namespace {

struct TimedBodySample {
    int64_t host_ns = 0;
    odometry::BodyMotionSample sample;
};

// Every Go1 sample of a CAN log, dated at the bridge's receive of its HighState (host clock).
std::vector<TimedBodySample> ReadGo1(const fs::path& path) {
    capture::CanLog log(path);
    can::Go1Decoder decoder;
    std::vector<TimedBodySample> out;
    const auto take = [&out](std::span<const can::Go1Sample> ready) {
        for (const can::Go1Sample& s : ready) {
            TimedBodySample t;
            t.host_ns = s.host_time_ns - int64_t(s.sample_age_us) * 1000;
            t.sample.v_xy = {s.vx, s.vy};
            t.sample.yaw_rate = s.yaw_rate;
            t.sample.velocity_valid = t.sample.yaw_rate_valid = (s.valid & can::kGroupBodyVel) != 0;
            if (s.valid & can::kGroupQuat) {
                t.sample.attitude = Eigen::Quaterniond(s.quat_wxyz[0], s.quat_wxyz[1],
                                                       s.quat_wxyz[2], s.quat_wxyz[3]);
            }
            if (out.empty() || t.host_ns > out.back().host_ns) out.push_back(t);
        }
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

std::optional<Eigen::Isometry3d> ReadCaptureMount(const fs::path& path) {
    std::ifstream in(path);
    if (!in) return std::nullopt;
    std::stringstream text;
    text << in.rdbuf();
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(text.str());
    } catch (const nlohmann::json::exception& e) {
        throw common::FileError(StatusCode::kParseError, path.string(), 0, e.what());
    }
    const auto sensor = j.find("sensor");
    if (sensor == j.end() || !sensor->is_object() || !sensor->contains("T_base_sensor")) {
        return std::nullopt;
    }
    const nlohmann::json& m = (*sensor)["T_base_sensor"];
    if (!m.is_array() || m.size() != 16 ||
        !std::all_of(m.begin(), m.end(), [](const auto& x) { return x.is_number(); })) {
        throw common::FileError(StatusCode::kParseError, path.string(), 0,
                                "sensor.T_base_sensor: expected 16 numbers (row-major 4x4)");
    }
    Eigen::Matrix4d M;
    for (int i = 0; i < 16; ++i) M(i / 4, i % 4) = m[size_t(i)].get<double>();
    Eigen::Isometry3d T;
    T.matrix() = M;
    if (!common::IsValidRigid(T, 1e-6)) {
        throw common::FileError(StatusCode::kParseError, path.string(), 0,
                                "sensor.T_base_sensor is not a rigid transform");
    }
    return T;
}

CaptureOdometryReport RunCaptureOdometry(const CaptureOdometryOptions& o) {
    const auto wall_start = std::chrono::steady_clock::now();
    CaptureOdometryReport report;
    const fs::path pcap = o.capture_dir / "lidar.pcap";
    const fs::path metadata = o.capture_dir / "metadata.json";
    const fs::path can_log = o.capture_dir / "go1_can.log";
    if (!fs::is_directory(o.capture_dir)) {
        throw common::FileError(StatusCode::kNotFound, o.capture_dir.string(), 0,
                                "not a folder (expected a capture: lidar.pcap, metadata.json)");
    }
    for (const fs::path& p : {pcap, metadata}) {
        if (!fs::is_regular_file(p)) {
            throw common::FileError(StatusCode::kNotFound, p.string(), 0, "missing");
        }
    }
    odometry::LidarOdometryConfig config = o.odometry;
    config.use_imu = config.use_imu && o.use_imu;
    if (const auto mount = ReadCaptureMount(o.capture_dir / "capture.json")) {
        config.T_base_lidar = *mount;
        report.mount_from_capture = true;
    }
    std::vector<TimedBodySample> body;
    if (o.use_can && fs::is_regular_file(can_log)) {
        body = ReadGo1(can_log);
        report.used_can = true;
    } else if (o.use_can) {
        report.notes.push_back("no go1_can.log: no body-motion prior");
    }
    config.use_body_motion = report.used_can && !body.empty();

    const ouster::SensorInfo info = ouster::LoadMetadata(metadata);
    capture::OusterCapture capture(pcap, info);
    odometry::LidarOdometry lo(config);
    keyframes::KeyframeSelector selector(o.keyframes);
    capture.OnImu([&](const ouster::ImuSample& s) {
        if (!config.use_imu) return;
        odometry::ImuMeasurement m;
        m.t_ns = static_cast<int64_t>(s.gyro_time_ns);
        m.gyro = s.gyro;
        m.accel = s.accel;
        lo.AddImu(m);
        ++report.imu_samples;
    });

    std::optional<io::SessionWriter> writer;
    if (!o.session_dir.empty()) {
        io::SessionManifest manifest;
        manifest.source = "rig";
        manifest.world_frame = "odom";
        manifest.sensor = {info.prod_line.empty() ? "OS-1-32" : info.prod_line,
                           info.format.pixels_per_column, info.format.columns_per_frame,
                           metadata.filename().string()};
        manifest.keyframe = {o.keyframes.distance_m, o.keyframes.angle_deg};
        const auto& sc = o.keyframes.descriptor;
        manifest.descriptor = {"indoor",      sc.num_rings,         sc.num_sectors,
                               sc.max_radius, sc.indoor_min_points, sc.indoor_min_z_span};
        writer.emplace(o.session_dir, manifest,
                       io::SessionWriterOptions{
                           .overwrite = o.overwrite, .flush_every = 50, .sync_each_file = false});
    }

    common::PointCloud cloud;
    int64_t offset = std::numeric_limits<int64_t>::max();  // host - sensor, see the header
    size_t next_body = 0;
    int64_t first_stamp = -1;
    Eigen::Vector3d last_position = Eigen::Vector3d::Zero();
    // A capture that turns out corrupt part way: the error names the file and the byte; the
    // session so far stays on disk without session.json (SessionWriter's destructor flushes it),
    // recoverable up to its last complete keyframe, and the message says so.
    try {
        while (const ouster::LidarFrame* frame = capture.NextFrame()) {
            if (!frame->complete) ++report.incomplete_frames;
            for (int v = frame->w - 1; v >= 0; --v) {  // the packet stamp of the last column
                if (!frame->ColumnValid(v) || frame->last_arrival_ns == 0) continue;
                offset = std::min(offset, frame->last_arrival_ns - int64_t(frame->timestamp[v]));
                break;
            }
            ouster::ToPointCloud(*frame, &cloud);
            const int64_t stamp = cloud.stamp.ns;
            if (first_stamp < 0) first_stamp = stamp;
            if (o.max_duration_s > 0 && double(stamp - first_stamp) * 1e-9 > o.max_duration_s)
                break;
            // Body motion up to a little past this scan's end.
            if (config.use_body_motion && offset != std::numeric_limits<int64_t>::max()) {
                const int64_t until = stamp + 300'000'000;
                for (; next_body < body.size() && body[next_body].host_ns - offset <= until;
                     ++next_body) {
                    odometry::BodyMotionSample s = body[next_body].sample;
                    s.t_ns = body[next_body].host_ns - offset;
                    lo.AddBodyMotion(s);
                    ++report.body_samples;
                }
            }
            const odometry::OdometryResult& r = lo.Process(cloud);
            ++report.scans;
            report.scan_ms.push_back(r.total_ms);
            report.over_budget += (r.flags & odometry::kOverBudget) ? 1 : 0;
            report.degenerate += (r.flags & odometry::kDegenerate) ? 1 : 0;
            report.failed += (r.flags & odometry::kRegistrationFailed) ? 1 : 0;
            report.not_converged += (r.flags & odometry::kNotConverged) ? 1 : 0;
            if (report.scans > 1) {
                report.distance_m += (r.T_odom_lidar.translation() - last_position).norm();
            }
            last_position = r.T_odom_lidar.translation();
            report.capture_s = double(stamp - first_stamp) * 1e-9;
            if (writer) {
                writer->AddScanPose(io::StampedPose::FromIsometry(stamp, r.T_odom_lidar));
                if (selector.Add(r, lo.deskewed())) {
                    writer->AddKeyframe(selector.keyframe());
                    if (selector.edge()) writer->AddEdge(*selector.edge());
                }
            }
            if (o.on_scan) o.on_scan(r);
        }
    } catch (const common::FileError& e) {
        if (!writer || selector.count() == 0) throw;
        throw common::FileError(e.code(), e.path(), e.line(),
                                e.detail() + "; the session up to scan " +
                                    std::to_string(report.scans) + " (" +
                                    std::to_string(selector.count()) + " keyframes) is left in " +
                                    o.session_dir.string() +
                                    " without session.json: `bimslam session info` recovers it");
    }
    if (report.scans == 0) {
        throw common::FileError(StatusCode::kDataLoss, pcap.string(), 0,
                                "no lidar frame in the capture");
    }
    report.keyframes = selector.count();
    report.host_minus_sensor_ns = offset == std::numeric_limits<int64_t>::max() ? 0 : offset;
    if (writer) writer->Finish();
    report.wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    return report;
}

}  // namespace bimslam::replay
