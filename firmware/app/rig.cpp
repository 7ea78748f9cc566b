// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "firmware/app/rig.hpp"

#include <signal.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>

#include "algorithms/common/se3.hpp"
#include "algorithms/common/status.hpp"
#include "algorithms/io/capture_files.hpp"
#include "algorithms/keyframes/keyframe_selector.hpp"
#include "algorithms/localization/relocalizer.hpp"
#include "algorithms/localization/rig_map.hpp"
#include "drivers/net/ros_packet_bag.hpp"
#include "drivers/ouster/metadata.hpp"
#include "firmware/app/health.hpp"
#include "firmware/modules/bim_localizer.hpp"
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

// The latency's stages as percentiles in ms.
std::vector<StageLatency> StagePercentiles(
    const std::array<runtime::LatencyHistogram, LatencyStages::kCount>& stages) {
    std::vector<StageLatency> out;
    for (size_t i = 0; i < LatencyStages::kCount; ++i) {
        out.push_back({LatencyStages::kNames[i], stages[i].PercentileMs(0.5),
                       stages[i].PercentileMs(0.99), stages[i].PercentileMs(1.0)});
    }
    return out;
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

// The sensor, the recording and the mount, from the configuration and the recording.
struct Inputs {
    bool replay = false;
    io::CaptureFiles files;
    std::string can_log, can_source;
    Eigen::Isometry3d T_base_lidar;
    fs::path metadata_path;
    ouster::SensorInfo info;
};

Inputs ResolveInputs(const RunOptions& o) {
    const RigConfig& cfg = o.config;
    Inputs in;
    in.replay = !o.recording.empty();
    in.can_log = cfg.can_log;
    in.can_source = cfg.handheld ? "none" : cfg.can_source;
    in.T_base_lidar = MountFrom(cfg.mount);
    if (in.replay) {
        in.files = io::ResolveCapture(o.recording);
        if (!cfg.handheld && cfg.can_source != "none") {
            if (in.can_log.empty()) in.can_log = in.files.can_log.string();
            in.can_source = in.can_log.empty() ? "none" : "log";
        }
        if (!in.files.capture_json.empty()) {
            if (const auto mount = io::ReadCaptureMount(in.files.capture_json)) {
                in.T_base_lidar = *mount;
            }
        }
    } else if (in.can_source == "log") {
        throw common::Error(StatusCode::kInvalidArgument,
                            "can.source: log reads a recording, which only replay does; live "
                            "takes socketcan, lcm or none");
    } else if (cfg.metadata.empty()) {
        throw common::Error(StatusCode::kInvalidArgument,
                            "sensor.metadata: live mode needs the sensor's metadata JSON");
    }
    // A bag's metadata is one of its topics (unless sensor.metadata is set).
    in.metadata_path = in.replay ? in.files.metadata : fs::path(cfg.metadata);
    in.info = !in.metadata_path.empty() ? ouster::LoadMetadata(in.metadata_path)
                                        : LoadBagMetadata(in.files.packets);
    return in;
}

// Every queue of the rig (firmware/runtime/README.md), every slot allocated here.
struct Queues {
    Queues(const RigConfig& cfg, size_t points)
        : scans(
              "scans", size_t(cfg.scan_queue),
              [points](ScanSlot& s) { s.scan.cloud.Reserve(points); }, &worker_wakeup),
          imu("imu", size_t(cfg.imu_queue), {}, &worker_wakeup),
          bodies("go1_samples", size_t(cfg.body_queue), {}, &worker_wakeup),
          odometry_out("odometry_out", size_t(cfg.publish_queue), {}, &lcm_wakeup),
          keyframes_lcm("keyframes_lcm", size_t(cfg.keyframe_queue), ReserveKeyframe(points),
                        &lcm_wakeup),
          keyframes_session("keyframes_session", size_t(cfg.keyframe_queue),
                            ReserveKeyframe(points), &writer_wakeup),
          // One slot without a map package (nothing uses it then).
          keyframes_localizer("keyframes_localizer",
                              cfg.bim_map.empty() ? 1 : size_t(cfg.keyframe_queue),
                              ReserveKeyframe(cfg.bim_map.empty() ? 0 : points), &localizer_wakeup),
          poses("poses", size_t(cfg.publish_queue) * 4, {}, &writer_wakeup),
          bim_steps("bim_steps", size_t(cfg.keyframe_queue) * 8, {}, &writer_wakeup),
          imu_lcm("imu_lcm", size_t(cfg.publish_queue) * 4, {}, &lcm_wakeup),
          go1_lcm("go1_lcm", size_t(cfg.publish_queue) * 4, {}, &lcm_wakeup),
          health_lcm("health_lcm", 4, {}, &lcm_wakeup),
          stats_lcm("ouster_stats_lcm", 4, {}, &lcm_wakeup) {}

    static std::function<void(KeyframeItem&)> ReserveKeyframe(size_t points) {
        return [points](KeyframeItem& k) {
            k.keyframe.cloud.Reserve(points);
            k.keyframe.descriptor.resize(20, 60);
        };
    }
    std::vector<const runtime::QueueBase*> All() const {
        return {&scans,
                &imu,
                &bodies,
                &odometry_out,
                &keyframes_lcm,
                &keyframes_session,
                &keyframes_localizer,
                &poses,
                &bim_steps,
                &imu_lcm,
                &go1_lcm,
                &health_lcm,
                &stats_lcm};
    }

    // Declared first: built first.
    runtime::Wakeup worker_wakeup, writer_wakeup, lcm_wakeup, localizer_wakeup;
    runtime::SpscQueue<ScanSlot> scans;
    runtime::SpscQueue<ImuItem> imu;
    runtime::SpscQueue<BodyItem> bodies;
    runtime::SpscQueue<OdometryItem> odometry_out;
    runtime::SpscQueue<KeyframeItem> keyframes_lcm, keyframes_session, keyframes_localizer;
    runtime::SpscQueue<PoseItem> poses;
    runtime::SpscQueue<BimStepItem> bim_steps;  // localizer -> writer
    runtime::SpscQueue<OusterImuItem> imu_lcm;
    runtime::SpscQueue<Go1Item> go1_lcm;
    runtime::SpscQueue<bimslam::rig_health_t> health_lcm;
    runtime::SpscQueue<bimslam::ouster_stats_t> stats_lcm;
};

size_t PointsPerScan(const ouster::SensorInfo& info) {
    return size_t(std::max(1, info.format.pixels_per_column)) *
           size_t(std::max(1, info.format.columns_per_frame));
}

// One run of the rig: built from the options (the modules and their queues), then Run: the
// threads started, the wait for the end, the orderly stop, the summary.
class Rig {
public:
    explicit Rig(const RunOptions& o)
        : o_(o), cfg_(o.config), in_(ResolveInputs(o)), q_(cfg_, PointsPerScan(in_.info)) {
        clock_.speed = o.speed;
        LoadBimMap();
        MakeModules();
        AddThreads();
    }

    RunSummary Run() {
        Start();
        WaitForEnd();
        StopInOrder();
        Summarize();
        return summary_;
    }

private:
    void LoadBimMap();
    void MakeModules();
    void AddThreads();
    void Start();
    void WaitForEnd();
    void StopInOrder();
    void Summarize();
    void SummarizeCan();
    void SummarizeLocalizer();

    const RunOptions& o_;
    const RigConfig& cfg_;
    Inputs in_;
    Queues q_;
    std::optional<localization::RigMap> bim_map_;  // localization.map, once read and accepted
    ReplayClock clock_;
    OdometryWorkerConfig wc_;
    std::optional<LidarIngest> ingest_;
    std::optional<CanIngest> can_;
    std::optional<OdometryWorker> worker_;
    std::optional<SessionRecorder> recorder_;
    std::optional<LcmPublisher> publisher_;
    std::optional<BimLocalizer> localizer_;  // a map package loaded
    std::atomic<bool> localizer_done_{true};
    std::atomic<bool> stop_sources_{false}, ingest_done_{false}, can_done_{true},
        worker_done_{false}, health_stop_{false}, health_done_{false}, lcm_inputs_done_{false};
    runtime::ThreadTable threads_;
    runtime::SdNotifier notifier_;
    std::optional<Health> health_;
    sigset_t signals_{};
    int64_t cpu0_ = 0, t0_ = 0;
    RunSummary summary_;
};

// The map package (localization.map): read before any thread starts, in time and memory bounded
// by its size (ReadRigMap: kRigMapMaxBytes). One that cannot be used is refused with the reason
// (FAULT_BIM_MAP, the summary's warnings) and the rig maps in its own frame: a run never fails
// for want of a package.
void Rig::LoadBimMap() {
    if (cfg_.bim_map.empty()) return;
    summary_.bim_map = cfg_.bim_map;
    const int64_t t0 = runtime::MonotonicNs();
    try {
        localization::RigMap map = localization::ReadRigMap(cfg_.bim_map);
        if (!cfg_.bim_model_sha256.empty() && map.model_sha256 != cfg_.bim_model_sha256) {
            throw common::FileError(StatusCode::kInvalidArgument, cfg_.bim_map, 0,
                                    "a package of " + map.model_file + " (SHA-256 " +
                                        map.model_sha256 + "), not of the model " +
                                        cfg_.bim_model_sha256 + " (localization.model_sha256)");
        }
        // The localiser compares the rig's keyframe descriptors with the package's: a package
        // made with another indoor cell rule (one from before z_stack) would compare unlike
        // things (algorithms/scancontext/config.hpp).
        const scancontext::ScanContextConfig mine = keyframes::KeyframeConfig{}.descriptor;
        if (map.descriptor.kind == "indoor" &&
            map.descriptor.cell_rule != scancontext::ToString(mine.indoor_rule)) {
            throw common::FileError(StatusCode::kInvalidArgument, cfg_.bim_map, 0,
                                    "its descriptors are made with the '" +
                                        map.descriptor.cell_rule +
                                        "' indoor cell rule, the rig's keyframes with '" +
                                        std::string(scancontext::ToString(mine.indoor_rule)) +
                                        "': make it again with bimslam rig-map");
        }
        // A package the localiser thread could not take is refused here, before any thread.
        localization::Relocalizer::Check(map);
        summary_.bim_map_keyframes = map.keyframes.size();
        summary_.bim_map_storeys = map.storeys.size();
        summary_.bim_map_model = map.model_file;
        std::error_code ec;
        summary_.bim_map_bytes = uint64_t(fs::file_size(cfg_.bim_map, ec));
        bim_map_ = std::move(map);
    } catch (const common::Error& e) {
        summary_.bim_map_error = std::string("localization.map refused: ") + e.what();
        summary_.warnings.push_back(summary_.bim_map_error);
    }
    summary_.bim_map_load_ms = double(runtime::MonotonicNs() - t0) * 1e-6;
}

void Rig::MakeModules() {
    const bool replay = in_.replay;
    LidarIngestConfig li;
    li.bind_address = cfg_.bind_address;
    li.sensor_address = cfg_.sensor_address;
    // Live: the configured ports, else the metadata's. Replay: the recorded ones (the metadata's).
    li.lidar_port = uint16_t(cfg_.lidar_port && !replay ? cfg_.lidar_port
                                                        : in_.info.udp_port_lidar.value_or(7502));
    li.imu_port =
        uint16_t(cfg_.imu_port && !replay ? cfg_.imu_port : in_.info.udp_port_imu.value_or(7503));
    li.receive_buffer_bytes = cfg_.receive_buffer_bytes;
    li.sensor_timeout_ns = int64_t(cfg_.sensor_timeout_s * 1e9);
    li.publish_imu = cfg_.publish_imu;
    if (replay) li.recording = in_.files.packets;
    ingest_.emplace(li, in_.info, q_.scans, q_.imu, q_.imu_lcm, replay ? &clock_ : nullptr);

    if (in_.can_source != "none") {
        CanIngestConfig cc;
        cc.source = in_.can_source;
        cc.interface_name = cfg_.can_interface;
        cc.log = in_.can_log;
        cc.lcm_url = cfg_.lcm_url;
        cc.lcm_channel = cfg_.can_lcm_channel;
        cc.publish_go1_state = cfg_.publish_go1_state;
        can_.emplace(cc, q_.bodies, q_.go1_lcm, replay ? &clock_ : nullptr);
        can_done_.store(false);
    }

    pipeline::ScanPipelineConfig& pc = wc_.pipeline;
    pc.odometry.budget_ms = cfg_.budget_ms;
    pc.odometry.preprocess.deskew = cfg_.deskew;
    pc.odometry.use_imu = cfg_.use_imu;
    pc.odometry.edge_features = cfg_.edge_features;
    pc.odometry.T_base_lidar = in_.T_base_lidar;
    pc.odometry.use_body_motion = can_.has_value();
    pc.keyframes.distance_m = cfg_.keyframe_distance_m;
    pc.keyframes.angle_deg = cfg_.keyframe_angle_deg;
    wc_.can_wait_ns = int64_t(cfg_.can_wait_ms * 1e6);
    wc_.deadline_ns = int64_t(cfg_.deadline_ms * 1e6);
    wc_.lossless = replay;  // a replay loses nothing, at any speed
    wc_.record = cfg_.record;
    worker_.emplace(wc_,
                    WorkerQueues{q_.scans, q_.imu, q_.bodies, q_.odometry_out, q_.keyframes_lcm,
                                 q_.keyframes_session, q_.poses, q_.worker_wakeup,
                                 bim_map_ ? &q_.keyframes_localizer : nullptr},
                    can_ ? &*can_ : nullptr);
    if (bim_map_) {
        std::optional<localization::StartHint> start;
        if (!cfg_.bim_near.empty()) start = localization::StartHint::FromList(cfg_.bim_near);
        localizer_.emplace(*bim_map_, q_.keyframes_localizer, q_.localizer_wakeup,
                           int64_t(cfg_.localizer_deadline_ms * 1e6),
                           cfg_.record ? &q_.bim_steps : nullptr, replay, start);
        localizer_done_.store(false);
    }

    if (cfg_.record) {
        SessionRecorderConfig rc;
        rc.root = cfg_.session_root;
        rc.manifest = pipeline::MakeSessionManifest(in_.info, in_.metadata_path.filename().string(),
                                                    pc.keyframes);
        rc.min_free_bytes = int64_t(cfg_.min_free_mb * 1e6);
        if (bim_map_) {
            for (const localization::RigMapStorey& s : bim_map_->storeys)
                rc.storeys.push_back(s.name);
        }
        recorder_.emplace(rc, q_.poses, q_.keyframes_session, q_.writer_wakeup,
                          localizer_ ? &q_.bim_steps : nullptr);
        summary_.session_dir = recorder_->first_dir().string();
    }
    LcmOutputConfig lcm_output;
    if (replay) {  // live runs are never paced
        lcm_output.pace_bytes_per_s = cfg_.lcm_replay_rate_mb_s * 1e6;
        lcm_output.pace_messages_per_s = cfg_.lcm_replay_messages_per_s;
    }
    lcm_output.log_path = o_.lcm_log;
    lcm_output.localizer = localizer_ ? &*localizer_ : nullptr;
    lcm_output.T_base_lidar = in_.T_base_lidar;
    publisher_.emplace(cfg_.lcm_url, pc.keyframes,
                       LcmQueues{q_.odometry_out, q_.keyframes_lcm, q_.imu_lcm, q_.go1_lcm,
                                 q_.health_lcm, q_.stats_lcm, q_.lcm_wakeup},
                       lcm_output);
}

// The thread table (firmware/runtime/README.md).
void Rig::AddThreads() {
    threads_.Add(Spec("ingest", cfg_.ingest, 0, 0, "lidar/IMU datagrams",
                      in_.replay ? "the recording (paced)" : "the two UDP sockets"),
                 [this](runtime::ThreadStats& s) {
                     ingest_->Run(s, stop_sources_);
                     ingest_done_.store(true);
                     q_.worker_wakeup.Notify();
                 });
    if (can_) {
        threads_.Add(Spec("can", cfg_.can, 0, 0, "CAN frames",
                          in_.can_source == "log" ? "the log (paced)" : "the CAN source"),
                     [this](runtime::ThreadStats& s) {
                         can_->Run(s, stop_sources_);
                         can_done_.store(true);
                     });
    }
    threads_.Add(Spec("odometry", cfg_.odometry, 0, wc_.deadline_ns, "a scan (10 Hz)",
                      "the scan queue; the CAN progress (bounded)"),
                 [this](runtime::ThreadStats& s) {
                     worker_->Run(s, stop_sources_, ingest_done_);
                     worker_done_.store(true);
                     q_.writer_wakeup.Notify();
                     q_.lcm_wakeup.Notify();
                     q_.localizer_wakeup.Notify();
                 });
    if (localizer_) {
        threads_.Add(Spec("localizer", cfg_.localizer, 0, int64_t(cfg_.localizer_deadline_ms * 1e6),
                          "a keyframe (about 1 Hz)", "the keyframe queue"),
                     [this](runtime::ThreadStats& s) {
                         localizer_->Run(s, worker_done_);
                         localizer_done_.store(true);
                         q_.writer_wakeup.Notify();
                     });
    }
    if (recorder_) {
        threads_.Add(Spec("writer", cfg_.writer, 0, 0, "poses, keyframes", "the disk (fsync)"),
                     // With a localiser, its steps come after the odometry's last output.
                     [this](runtime::ThreadStats& s) {
                         recorder_->Run(s, localizer_ ? localizer_done_ : worker_done_);
                     });
    }
    threads_.Add(Spec("lcm", cfg_.lcm, 0, 0, "messages", "the LCM socket"),
                 [this](runtime::ThreadStats& s) { publisher_->Run(s, lcm_inputs_done_); });
    health_.emplace(HealthInputs{threads_, *ingest_, can_ ? &*can_ : nullptr, *worker_,
                                 recorder_ ? &*recorder_ : nullptr, *publisher_, q_.All(),
                                 q_.health_lcm, q_.stats_lcm, notifier_, cfg_, in_.info,
                                 health_stop_, in_.replay, in_.replay && clock_.unpaced(),
                                 summary_.bim_map_error, localizer_ ? &*localizer_ : nullptr});
    threads_.Add(Spec("health", cfg_.health, int64_t(cfg_.health_period_s * 1e9), 0, "period",
                      "nothing (reads atomics)"),
                 [this](runtime::ThreadStats& s) {
                     health_->Run(s);
                     health_done_.store(true);
                     q_.lcm_wakeup.Notify();
                 });
}

// Start-up: memory, signals (handled by this thread only: blocked in every other), threads.
void Rig::Start() {
    if (cfg_.lock_memory) {
        const std::string w = runtime::LockMemory();
        if (!w.empty()) summary_.warnings.push_back(w);
    }
    if (const std::string w = ingest_->receive_buffer_warning(); !w.empty()) {
        summary_.warnings.push_back(w);
    }
    sigemptyset(&signals_);
    sigaddset(&signals_, SIGINT);
    sigaddset(&signals_, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &signals_, nullptr);
    runtime::Log("info", ingest_->description());
    if (can_) runtime::Log("info", can_->description());
    if (recorder_) runtime::Log("info", "session " + recorder_->first_dir().string());
    runtime::Log("info", "threads:\n" + threads_.Describe());
    if (in_.replay) {
        const int64_t first =
            std::min(ingest_->first_capture_ns(), can_ ? can_->first_capture_ns() : kEndOfStream);
        clock_.start_capture_ns.store(first);
        clock_.start_mono_ns = runtime::MonotonicNs();
    }
    cpu0_ = runtime::ProcessCpuNs();
    t0_ = runtime::MonotonicNs();
    for (const std::string& w : threads_.Start()) summary_.warnings.push_back(w);
    for (const std::string& w : summary_.warnings) runtime::Log("warning", w);
    notifier_.Notify("READY=1\nSTATUS=running");
}

// Waits for a signal, the end of the recording or the duration.
void Rig::WaitForEnd() {
    const int64_t end = o_.duration_s > 0 ? t0_ + int64_t(o_.duration_s * 1e9) : kEndOfStream;
    while (true) {
        const timespec wait{0, 100'000'000};
        const int sig = sigtimedwait(&signals_, nullptr, &wait);
        if (sig == SIGINT || sig == SIGTERM) {
            summary_.stop_signal = sig;
            break;
        }
        if (ingest_done_.load()) break;
        if (runtime::MonotonicNs() >= end) break;
    }
}

// Orderly stop: sources, then (as each drains) the odometry, the writer, health, LCM.
void Rig::StopInOrder() {
    notifier_.Notify("STOPPING=1\nSTATUS=stopping: draining the queues, finishing the session");
    stop_sources_.store(true);
    q_.worker_wakeup.Notify();
    while (!worker_done_.load()) {
        const timespec wait{0, 20'000'000};
        if (sigtimedwait(&signals_, nullptr, &wait) > 0) break;  // a second signal: hurry
    }
    while (!worker_done_.load() || !can_done_.load() || !localizer_done_.load()) {
        const timespec wait{0, 20'000'000};
        nanosleep(&wait, nullptr);
    }
    health_stop_.store(true);
    while (!health_done_.load()) {
        const timespec wait{0, 20'000'000};
        nanosleep(&wait, nullptr);
    }
    lcm_inputs_done_.store(true);
    q_.lcm_wakeup.Notify();
    threads_.Join();
}

void Rig::SummarizeCan() {
    if (!can_) return;
    const CanCounters cc = can_->counters();
    summary_.go1_samples = cc.decoder.samples;
    summary_.can_timeouts = cc.decoder.timeout;
    summary_.can_e2e_errors = cc.decoder.crc + cc.decoder.counter_resync +
                              cc.decoder.counter_repeat + cc.decoder.counter_invalid;
    summary_.go1_bridge_link_down = cc.bridge_link_down;
    summary_.go1_bridge_not_running = cc.bridge_not_running;
    summary_.go1_bridge_lost = cc.bridge_lost;
    summary_.go1_bridge_state = cc.bridge_state;
}

void Rig::Summarize() {
    RunSummary& s = summary_;
    s.wall_s = double(runtime::MonotonicNs() - t0_) * 1e-9;
    s.cpu_percent =
        100.0 * double(runtime::ProcessCpuNs() - cpu0_) * 1e-9 / std::max(s.wall_s, 1e-9);
    s.rss_mb = double(runtime::ResidentBytes()) / 1e6;
    const IngestCounters ic = ingest_->counters();
    const WorkerCounters w = worker_->counters();
    s.scans = w.scans;
    s.keyframes = w.keyframes;
    s.scans_dropped = ic.scans_dropped;
    s.deadline_misses = w.deadline_misses;
    s.lidar_packets = ic.lidar_datagrams;
    s.imu_samples = ic.imu.samples;
    s.frames_incomplete = ic.lidar.frames_incomplete;
    s.columns_lost = ic.lidar.columns_lost;
    s.crc_failures = ic.lidar.Rejected(ouster::Reject::kCrc);
    s.silences = ic.silences;
    s.sensor_restarts = ic.init_id_changes;
    s.clock_jumps = w.clock_jumps;
    s.trust = worker_->trust();
    s.can_late = w.can_late;
    SummarizeCan();
    for (const runtime::QueueBase* q : q_.All()) s.queue_drops += q->Stats().drops;
    for (size_t i = 0; i < threads_.size(); ++i) {
        const uint64_t stalls = health_->thread_stalls()[i];
        if (stalls > 0) s.threads_stalled.emplace_back(threads_.spec(i).name, stalls);
    }
    if (recorder_) {
        const RecorderCounters rc = recorder_->counters();
        s.keyframes_written = rc.keyframes;
        s.keyframes_skipped_disk = rc.keyframes_skipped_disk;
        s.write_errors = rc.write_errors;
    }
    const LcmCounters lc = publisher_->counters();
    s.lcm_failures = lc.failures;
    s.lcm_odometry = lc.odometry;
    s.lcm_keyframes = lc.keyframes;
    s.lcm_imu = lc.imu;
    s.lcm_go1_state = lc.go1;
    s.lcm_rig_health = lc.health;
    s.lcm_ouster_stats = lc.ouster_stats;
    s.lcm_logged = lc.logged;
    s.lcm_paced_s = double(lc.paced_ns) * 1e-9;
    s.latency_p50_ms = publisher_->latency().PercentileMs(0.5);
    s.latency_p99_ms = publisher_->latency().PercentileMs(0.99);
    s.latency_max_ms = publisher_->latency().PercentileMs(1.0);
    s.latency_stages = StagePercentiles(publisher_->latency_stages());
    s.lcm_bim_pose = lc.bim_pose;
    if (localizer_) SummarizeLocalizer();
}

// The localiser's run: its states per keyframe, when it first localised (seconds of sensor time
// from the first keyframe), its CPU per keyframe and share of one core, its last state.
void Rig::SummarizeLocalizer() {
    RunSummary& s = summary_;
    const LocalizerCounters c = localizer_->counters();
    s.localization_keyframes = c.keyframes;
    s.localization_states = {{"searching", c.searching},
                             {"candidate", c.candidate},
                             {"localised", c.localised},
                             {"ambiguous", c.ambiguous},
                             {"lost", c.lost}};
    s.localization_final = localizer_->latest().any
                               ? std::string(localization::ToString(localizer_->latest().state))
                               : "";
    s.localization_time_to_localised_s =
        c.first_localised_ns >= 0 ? double(c.first_localised_ns - c.first_keyframe_ns) * 1e-9
                                  : -1.0;
    s.localization_cpu_ms_p50 = localizer_->cpu().PercentileMs(0.5);
    s.localization_cpu_ms_p99 = localizer_->cpu().PercentileMs(0.99);
    s.localization_cpu_percent = 100.0 * double(c.cpu_ns) * 1e-9 / std::max(s.wall_s, 1e-9);
    s.localization_deadline_misses = c.deadline_misses;
}

}  // namespace

RunSummary RunRig(const RunOptions& o) {
    ValidateConfig(o.config);
    Rig rig(o);
    return rig.Run();
}

}  // namespace bimslam::rig
