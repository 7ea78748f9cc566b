#include "firmware/app/rig.hpp"

#include <signal.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "algorithms/common/se3.hpp"
#include "algorithms/common/status.hpp"
#include "algorithms/io/capture_files.hpp"
#include "drivers/net/ros_packet_bag.hpp"
#include "drivers/ouster/metadata.hpp"
#include "firmware/app/health.hpp"
#include "firmware/modules/can_ingest.hpp"
#include "firmware/modules/lcm_bridge.hpp"
#include "firmware/modules/lidar_ingest.hpp"
#include "firmware/modules/odometry_worker.hpp"
#include "firmware/modules/session_recorder.hpp"
#include "firmware/runtime/process_stats.hpp"
#include "firmware/runtime/sd_notify.hpp"
#include "firmware/runtime/thread_table.hpp"

namespace bimslam::rig {
namespace fs = std::filesystem;
using common::StatusCode;

namespace {

// The sensor of a ROS bag: its metadata topic (host tools: capture::LoadRecordingInfo, which the
// firmware may not link).
ouster::SensorInfo LoadBagMetadata(const fs::path& bag_path) {
    const net::RosPacketBag bag(bag_path);
    return ouster::ParseMetadata(bag_path.string() + ":" + bag.topics().metadata,
                                 bag.ReadMetadata());
}

double Percentile(std::vector<int64_t> v, double p) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return double(v[std::min(v.size() - 1, size_t(p * double(v.size() - 1) + 0.5))]) * 1e-6;
}

Eigen::Isometry3d MountFrom(const std::vector<double>& m) {
    return common::PoseFromXyzRpyDeg({m[0], m[1], m[2]}, {m[3], m[4], m[5]});
}

runtime::ThreadSpec Spec(const std::string& name, const ThreadConfig& t, int64_t period_ns,
                         int64_t deadline_ns, const std::string& trigger,
                         const std::string& blocks_on) {
    runtime::ThreadSpec s;
    s.name = name;
    s.priority = t.priority;
    s.cpu = t.cpu;
    s.period_ns = period_ns;
    s.deadline_ns = deadline_ns;
    s.trigger = trigger;
    s.blocks_on = blocks_on;
    return s;
}

}  // namespace

RunSummary RunRig(const RunOptions& o) {
    const RigConfig& cfg = o.config;
    ValidateConfig(cfg);
    const bool replay = !o.recording.empty();
    RunSummary summary;

    // The sensor, the recording and the mount.
    io::CaptureFiles files;
    std::string can_log = cfg.can_log;
    std::string can_source = cfg.handheld ? "none" : cfg.can_source;
    Eigen::Isometry3d T_base_lidar = MountFrom(cfg.mount);
    if (replay) {
        files = io::ResolveCapture(o.recording);
        if (!cfg.handheld && cfg.can_source != "none") {
            if (can_log.empty()) can_log = files.can_log.string();
            can_source = can_log.empty() ? "none" : "log";
        }
        if (!files.capture_json.empty()) {
            if (const auto mount = io::ReadCaptureMount(files.capture_json)) T_base_lidar = *mount;
        }
    } else if (can_source == "log") {
        throw common::Error(StatusCode::kInvalidArgument,
                            "can.source: log reads a recording, which only replay does; live "
                            "takes socketcan, lcm or none");
    } else if (cfg.metadata.empty()) {
        throw common::Error(StatusCode::kInvalidArgument,
                            "sensor.metadata: live mode needs the sensor's metadata JSON");
    }
    // A bag's metadata is one of its topics (unless sensor.metadata is set).
    const fs::path metadata_path = replay ? files.metadata : fs::path(cfg.metadata);
    const ouster::SensorInfo info = !metadata_path.empty() ? ouster::LoadMetadata(metadata_path)
                                                           : LoadBagMetadata(files.packets);

    // Queues, every slot allocated here.
    runtime::Wakeup worker_wakeup, writer_wakeup, lcm_wakeup;
    const size_t points = size_t(std::max(1, info.format.pixels_per_column)) *
                          size_t(std::max(1, info.format.columns_per_frame));
    const auto reserve_scan = [points](ScanSlot& s) { s.scan.cloud.Reserve(points); };
    const auto reserve_keyframe = [points](KeyframeItem& k) {
        k.keyframe.cloud.Reserve(points);
        k.keyframe.descriptor.resize(20, 60);
    };
    runtime::SpscQueue<ScanSlot> scans("scans", size_t(cfg.scan_queue), reserve_scan,
                                       &worker_wakeup);
    runtime::SpscQueue<ImuItem> imu("imu", size_t(cfg.imu_queue), {}, &worker_wakeup);
    runtime::SpscQueue<BodyItem> bodies("go1_samples", size_t(cfg.body_queue), {}, &worker_wakeup);
    runtime::SpscQueue<OdometryItem> odometry_out("odometry_out", size_t(cfg.publish_queue), {},
                                                  &lcm_wakeup);
    runtime::SpscQueue<KeyframeItem> keyframes_lcm("keyframes_lcm", size_t(cfg.keyframe_queue),
                                                   reserve_keyframe, &lcm_wakeup);
    runtime::SpscQueue<KeyframeItem> keyframes_session(
        "keyframes_session", size_t(cfg.keyframe_queue), reserve_keyframe, &writer_wakeup);
    runtime::SpscQueue<PoseItem> poses("poses", size_t(cfg.publish_queue) * 4, {}, &writer_wakeup);
    runtime::SpscQueue<OusterImuItem> imu_lcm("imu_lcm", size_t(cfg.publish_queue) * 4, {},
                                              &lcm_wakeup);
    runtime::SpscQueue<Go1Item> go1_lcm("go1_lcm", size_t(cfg.publish_queue) * 4, {}, &lcm_wakeup);
    runtime::SpscQueue<bimslam::rig_health_t> health_lcm("health_lcm", 4, {}, &lcm_wakeup);
    runtime::SpscQueue<bimslam::ouster_stats_t> stats_lcm("ouster_stats_lcm", 4, {}, &lcm_wakeup);
    const std::vector<const runtime::QueueBase*> all_queues = {
        &scans, &imu,     &bodies,  &odometry_out, &keyframes_lcm, &keyframes_session,
        &poses, &imu_lcm, &go1_lcm, &health_lcm,   &stats_lcm};

    // Modules.
    ReplayClock clock;
    clock.speed = o.speed;
    LidarIngestConfig li;
    li.bind_address = cfg.bind_address;
    li.sensor_address = cfg.sensor_address;
    // Live: the configured ports, else the metadata's. Replay: the recorded ones (the metadata's).
    li.lidar_port =
        uint16_t(cfg.lidar_port && !replay ? cfg.lidar_port : info.udp_port_lidar.value_or(7502));
    li.imu_port =
        uint16_t(cfg.imu_port && !replay ? cfg.imu_port : info.udp_port_imu.value_or(7503));
    li.receive_buffer_bytes = cfg.receive_buffer_bytes;
    li.sensor_timeout_ns = int64_t(cfg.sensor_timeout_s * 1e9);
    li.publish_imu = cfg.publish_imu;
    if (replay) li.recording = files.packets;
    LidarIngest ingest(li, info, scans, imu, imu_lcm, replay ? &clock : nullptr);

    std::optional<CanIngest> can;
    if (can_source != "none") {
        CanIngestConfig cc;
        cc.source = can_source;
        cc.interface_name = cfg.can_interface;
        cc.log = can_log;
        cc.lcm_url = cfg.lcm_url;
        cc.lcm_channel = cfg.can_lcm_channel;
        cc.publish_go1_state = cfg.publish_go1_state;
        can.emplace(cc, bodies, go1_lcm, replay ? &clock : nullptr);
    }

    OdometryWorkerConfig wc;
    pipeline::ScanPipelineConfig& pc = wc.pipeline;
    pc.odometry.budget_ms = cfg.budget_ms;
    pc.odometry.preprocess.deskew = cfg.deskew;
    pc.odometry.use_imu = cfg.use_imu;
    pc.odometry.edge_features = cfg.edge_features;
    pc.odometry.T_base_lidar = T_base_lidar;
    pc.odometry.use_body_motion = can.has_value();
    pc.keyframes.distance_m = cfg.keyframe_distance_m;
    pc.keyframes.angle_deg = cfg.keyframe_angle_deg;
    wc.can_wait_ns = int64_t(cfg.can_wait_ms * 1e6);
    wc.deadline_ns = int64_t(cfg.deadline_ms * 1e6);
    wc.lossless = replay;  // a replay loses nothing, at any speed
    wc.record = cfg.record;
    OdometryWorker worker(
        wc,
        {scans, imu, bodies, odometry_out, keyframes_lcm, keyframes_session, poses, worker_wakeup},
        can ? &*can : nullptr);

    std::optional<SessionRecorder> recorder;
    if (cfg.record) {
        SessionRecorderConfig rc;
        rc.root = cfg.session_root;
        rc.manifest =
            pipeline::MakeSessionManifest(info, metadata_path.filename().string(), pc.keyframes);
        rc.min_free_bytes = int64_t(cfg.min_free_mb * 1e6);
        recorder.emplace(rc, poses, keyframes_session, writer_wakeup);
        summary.session_dir = recorder->first_dir().string();
    }
    LcmOutputConfig lcm_output;
    if (replay) {  // live runs are never paced
        lcm_output.pace_bytes_per_s = cfg.lcm_replay_rate_mb_s * 1e6;
        lcm_output.pace_messages_per_s = cfg.lcm_replay_messages_per_s;
    }
    lcm_output.log_path = o.lcm_log;
    LcmPublisher publisher(
        cfg.lcm_url, pc.keyframes,
        {odometry_out, keyframes_lcm, imu_lcm, go1_lcm, health_lcm, stats_lcm, lcm_wakeup},
        lcm_output);

    // The thread table (firmware/runtime/README.md).
    std::atomic<bool> stop_sources{false}, ingest_done{false}, can_done{!can.has_value()},
        worker_done{false}, health_stop{false}, health_done{false}, lcm_inputs_done{false};
    runtime::ThreadTable threads;
    threads.Add(Spec("ingest", cfg.ingest, 0, 0, "lidar/IMU datagrams",
                     replay ? "the recording (paced)" : "the two UDP sockets"),
                [&](runtime::ThreadStats& s) {
                    ingest.Run(s, stop_sources);
                    ingest_done.store(true);
                    worker_wakeup.Notify();
                });
    if (can) {
        threads.Add(Spec("can", cfg.can, 0, 0, "CAN frames",
                         can_source == "log" ? "the log (paced)" : "the CAN source"),
                    [&](runtime::ThreadStats& s) {
                        can->Run(s, stop_sources);
                        can_done.store(true);
                    });
    }
    threads.Add(Spec("odometry", cfg.odometry, 0, wc.deadline_ns, "a scan (10 Hz)",
                     "the scan queue; the CAN progress (bounded)"),
                [&](runtime::ThreadStats& s) {
                    worker.Run(s, stop_sources, ingest_done);
                    worker_done.store(true);
                    writer_wakeup.Notify();
                    lcm_wakeup.Notify();
                });
    if (recorder) {
        threads.Add(Spec("writer", cfg.writer, 0, 0, "poses, keyframes", "the disk (fsync)"),
                    [&](runtime::ThreadStats& s) { recorder->Run(s, worker_done); });
    }
    threads.Add(Spec("lcm", cfg.lcm, 0, 0, "messages", "the LCM socket"),
                [&](runtime::ThreadStats& s) { publisher.Run(s, lcm_inputs_done); });
    runtime::SdNotifier notifier;
    HealthInputs hi{threads,
                    ingest,
                    can ? &*can : nullptr,
                    worker,
                    recorder ? &*recorder : nullptr,
                    publisher,
                    all_queues,
                    health_lcm,
                    stats_lcm,
                    notifier,
                    cfg,
                    info,
                    health_stop,
                    replay,
                    replay && clock.unpaced()};
    Health health(hi);
    threads.Add(Spec("health", cfg.health, int64_t(cfg.health_period_s * 1e9), 0, "period",
                     "nothing (reads atomics)"),
                [&](runtime::ThreadStats& s) {
                    health.Run(s);
                    health_done.store(true);
                    lcm_wakeup.Notify();
                });

    // Start-up: memory, signals (handled by this thread only: blocked in every other), threads.
    if (cfg.lock_memory) {
        const std::string w = runtime::LockMemory();
        if (!w.empty()) summary.warnings.push_back(w);
    }
    if (const std::string w = ingest.receive_buffer_warning(); !w.empty()) {
        summary.warnings.push_back(w);
    }
    sigset_t signals;
    sigemptyset(&signals);
    sigaddset(&signals, SIGINT);
    sigaddset(&signals, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &signals, nullptr);
    runtime::Log("info", ingest.description());
    if (can) runtime::Log("info", can->description());
    if (recorder) runtime::Log("info", "session " + recorder->first_dir().string());
    runtime::Log("info", "threads:\n" + threads.Describe());
    if (replay) {
        const int64_t first =
            std::min(ingest.first_capture_ns(), can ? can->first_capture_ns() : kEndOfStream);
        clock.start_capture_ns.store(first);
        clock.start_mono_ns = runtime::MonotonicNs();
    }
    const int64_t cpu0 = runtime::ProcessCpuNs();
    const int64_t t0 = runtime::MonotonicNs();
    for (const std::string& w : threads.Start()) summary.warnings.push_back(w);
    for (const std::string& w : summary.warnings) runtime::Log("warning", w);
    notifier.Notify("READY=1\nSTATUS=running");

    // Wait for a signal, the end of the recording or the duration.
    const int64_t end = o.duration_s > 0 ? t0 + int64_t(o.duration_s * 1e9) : kEndOfStream;
    while (true) {
        const timespec wait{0, 100'000'000};
        const int sig = sigtimedwait(&signals, nullptr, &wait);
        if (sig == SIGINT || sig == SIGTERM) {
            summary.stop_signal = sig;
            break;
        }
        if (ingest_done.load()) break;
        if (runtime::MonotonicNs() >= end) break;
    }
    notifier.Notify("STOPPING=1\nSTATUS=stopping: draining the queues, finishing the session");
    // Orderly stop: sources, then (as each drains) the odometry, the writer, health, LCM.
    stop_sources.store(true);
    worker_wakeup.Notify();
    while (!worker_done.load()) {
        const timespec wait{0, 20'000'000};
        if (sigtimedwait(&signals, nullptr, &wait) > 0) break;  // a second signal: hurry
    }
    while (!worker_done.load() || !can_done.load()) {
        const timespec wait{0, 20'000'000};
        nanosleep(&wait, nullptr);
    }
    health_stop.store(true);
    while (!health_done.load()) {
        const timespec wait{0, 20'000'000};
        nanosleep(&wait, nullptr);
    }
    lcm_inputs_done.store(true);
    lcm_wakeup.Notify();
    threads.Join();

    // The summary.
    summary.wall_s = double(runtime::MonotonicNs() - t0) * 1e-9;
    summary.cpu_percent =
        100.0 * double(runtime::ProcessCpuNs() - cpu0) * 1e-9 / std::max(summary.wall_s, 1e-9);
    summary.rss_mb = double(runtime::ResidentBytes()) / 1e6;
    const IngestCounters ic = ingest.counters();
    const WorkerCounters w = worker.counters();
    summary.scans = w.scans;
    summary.keyframes = w.keyframes;
    summary.scans_dropped = ic.scans_dropped;
    summary.deadline_misses = w.deadline_misses;
    summary.lidar_packets = ic.lidar_datagrams;
    summary.imu_samples = ic.imu.samples;
    summary.frames_incomplete = ic.lidar.frames_incomplete;
    summary.columns_lost = ic.lidar.columns_lost;
    summary.crc_failures = ic.lidar.Rejected(ouster::Reject::kCrc);
    summary.silences = ic.silences;
    summary.sensor_restarts = ic.init_id_changes;
    summary.clock_jumps = w.clock_jumps;
    summary.trust = worker.trust();
    summary.can_late = w.can_late;
    if (can) {
        const CanCounters cc = can->counters();
        summary.go1_samples = cc.decoder.samples;
        summary.can_timeouts = cc.decoder.timeout;
        summary.can_e2e_errors = cc.decoder.crc + cc.decoder.counter_resync +
                                 cc.decoder.counter_repeat + cc.decoder.counter_invalid;
        summary.go1_bridge_link_down = cc.bridge_link_down;
        summary.go1_bridge_not_running = cc.bridge_not_running;
        summary.go1_bridge_lost = cc.bridge_lost;
        summary.go1_bridge_state = cc.bridge_state;
    }
    for (const runtime::QueueBase* q : all_queues) summary.queue_drops += q->Stats().drops;
    for (size_t i = 0; i < threads.size(); ++i) {
        const uint64_t stalls = health.thread_stalls()[i];
        if (stalls > 0) summary.threads_stalled.emplace_back(threads.spec(i).name, stalls);
    }
    if (recorder) {
        const RecorderCounters rc = recorder->counters();
        summary.keyframes_written = rc.keyframes;
        summary.keyframes_skipped_disk = rc.keyframes_skipped_disk;
        summary.write_errors = rc.write_errors;
    }
    const LcmCounters lc = publisher.counters();
    summary.lcm_failures = lc.failures;
    summary.lcm_odometry = lc.odometry;
    summary.lcm_keyframes = lc.keyframes;
    summary.lcm_imu = lc.imu;
    summary.lcm_go1_state = lc.go1;
    summary.lcm_rig_health = lc.health;
    summary.lcm_ouster_stats = lc.ouster_stats;
    summary.lcm_logged = lc.logged;
    summary.lcm_paced_s = double(lc.paced_ns) * 1e-9;
    summary.latency_p50_ms = Percentile(publisher.latencies(), 0.5);
    summary.latency_p99_ms = Percentile(publisher.latencies(), 0.99);
    summary.latency_max_ms = Percentile(publisher.latencies(), 1.0);
    return summary;
}

}  // namespace bimslam::rig
