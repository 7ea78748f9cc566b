// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "firmware/app/health.hpp"

#include <cmath>
#include <sstream>
#include <thread>

namespace bimslam::rig {
namespace {
const char* const kFaultNames[kNumFaults] = {
    "LIDAR_TIMEOUT",  "LIDAR_REJECTS",       "LIDAR_INCOMPLETE",
    "LIDAR_RESTART",  "IMU_TIMEOUT",         "CAN_TIMEOUT",
    "CAN_E2E",        "GO1_BRIDGE",          "DEADLINE_MISS",
    "QUEUE_OVERFLOW", "CPU_OVERLOAD",        "DISK_LOW",
    "DISK_WRITE",     "ODOMETRY_DEGENERATE", "ODOMETRY_OVER_BUDGET",
    "ODOMETRY_LOST",  "CLOCK_JUMP",          "CONFIG",
    "LCM_PUBLISH",    "THREAD_STALLED",      "BIM_MAP",
    "BIM_LOST"};
enum Bit {
    kLidarTimeout,
    kLidarRejects,
    kLidarIncomplete,
    kLidarRestart,
    kImuTimeout,
    kCanTimeout,
    kCanE2e,
    kGo1Bridge,
    kDeadlineMiss,
    kQueueOverflow,
    kCpuOverload,
    kDiskLow,
    kDiskWrite,
    kDegenerate,
    kOverBudget,
    kLost,
    kClockJump,
    kConfig,
    kLcmPublish,
    kThreadStalled,
    kBimMap,
    kBimLost
};

// STS_BridgeState's values (go1_odometry.dbc VAL_ 320).
std::string BridgeStateName(int state) {
    switch (state) {
        case -1:
            return "unknown (no STATUS frame yet)";
        case 0:
            return "INIT";
        case 1:
            return "RUNNING";
        case 2:
            return "DEGRADED";
        case 3:
            return "FAULT";
    }
    return std::to_string(state);
}
}  // namespace

const char* FaultName(int bit) { return bit >= 0 && bit < kNumFaults ? kFaultNames[bit] : "?"; }

bool HeartbeatStale(runtime::ThreadTable& threads, size_t i, int64_t now_ns) {
    const runtime::ThreadStats& s = threads.stats(i);
    return !s.finished.load() && now_ns - s.heartbeat_ns.load() > threads.spec(i).stale_ns;
}

bool HeartbeatsFresh(runtime::ThreadTable& threads, int64_t now_ns) {
    for (size_t i = 0; i < threads.size(); ++i) {
        if (HeartbeatStale(threads, i, now_ns)) return false;
    }
    return true;
}

Health::Health(HealthInputs inputs) : in_(std::move(inputs)) {
    for (int i = 0; i < kNumFaults; ++i) {
        limiters_.emplace_back(int64_t(in_.config.log_interval_s * 1e9));
    }
}

void Health::Run(runtime::ThreadStats& stats) {
    start_mono_ = last_mono_ = runtime::MonotonicNs();
    start_rt_ = last_rt_ = runtime::RealtimeNs();
    rt_minus_mono_ = start_rt_ - start_mono_;
    last_cpu_ = runtime::ProcessCpuNs();
    thread_cpu_.assign(in_.threads.size(), 0);
    last_thread_misses_.assign(in_.threads.size(), 0);
    thread_stalls_.assign(in_.threads.size(), 0);
    thread_stale_.assign(in_.threads.size(), false);
    for (size_t i = 0; i < in_.threads.size(); ++i) thread_cpu_[i] = in_.threads.CpuNs(i);
    const int64_t period = int64_t(in_.config.health_period_s * 1e9);
    // The watchdog wants a ping at least every WatchdogSec / 2; ping at a quarter.
    const int64_t watchdog = in_.notifier.watchdog_ns();
    const int64_t tick = watchdog > 0 ? std::min(period, watchdog / 4) : period;
    int64_t next_period = last_mono_ + period;
    while (!in_.stop.load()) {
        const int64_t now = runtime::MonotonicNs();
        stats.Beat();
        if (now >= next_period) {
            Period(now);
            next_period += period;
            if (next_period <= now) next_period = now + period;
            stats.Cycle(runtime::MonotonicNs() - now, period);
        }
        if (watchdog > 0 && HeartbeatsFresh(in_.threads, now)) {
            in_.notifier.Notify("WATCHDOG=1");
        }
        const int64_t sleep = std::min(tick, std::max<int64_t>(next_period - now, 1'000'000));
        std::this_thread::sleep_for(
            std::chrono::nanoseconds(std::min<int64_t>(sleep, 100'000'000)));
    }
}

// Every module's counters, read once a period.
struct Health::Snapshot {
    int64_t now = 0, now_rt = 0, cpu = 0;
    double interval_s = 0, cpu_percent = 0;
    IngestCounters ic;
    WorkerCounters wc;
    LcmCounters lc;
    CanCounters cc;
    RecorderCounters rc;
    uint64_t queue_drops = 0;
};

// The faults found in one period, each with the text the log gives it.
struct Health::Faults {
    uint64_t bits = 0;
    std::array<std::string, kNumFaults> why;

    void Set(int bit, bool on, const std::string& text) {
        if (!on) return;
        bits |= uint64_t(1) << bit;
        why[size_t(bit)] = text;
    }
};

void Health::Period(int64_t now) {
    const Snapshot n = Read(now);
    Faults f;
    DetectLidarFaults(n, f);
    DetectGo1Faults(n, f);
    DetectRigFaults(n, f);
    DetectStalledThreads(n, f);
    CountAndLog(f, now);
    QueueHealth(n);
    QueueOusterStats(n);
    NotifyStatus(n);
    last_ingest_ = n.ic;
    last_can_ = n.cc;
    last_worker_ = n.wc;
    last_recorder_ = n.rc;
    last_lcm_ = n.lc;
    last_queue_drops_ = n.queue_drops;
    last_mono_ = now;
    last_rt_ = n.now_rt;
    last_cpu_ = n.cpu;
}

Health::Snapshot Health::Read(int64_t now) const {
    Snapshot n;
    n.now = now;
    n.now_rt = runtime::RealtimeNs();
    n.ic = in_.ingest.counters();
    n.wc = in_.worker.counters();
    n.lc = in_.publisher.counters();
    n.cc = in_.can ? in_.can->counters() : CanCounters{};
    n.rc = in_.recorder ? in_.recorder->counters() : RecorderCounters{};
    for (const runtime::QueueBase* q : in_.queues) n.queue_drops += q->Stats().drops;
    n.interval_s = std::max(1e-9, double(now - last_mono_) * 1e-9);
    n.cpu = runtime::ProcessCpuNs();
    n.cpu_percent = 100.0 * double(n.cpu - last_cpu_) * 1e-9 / n.interval_s;
    return n;
}

void Health::DetectLidarFaults(const Snapshot& n, Faults& f) const {
    const IngestCounters& ic = n.ic;
    const int64_t silent_ns =
        ic.last_packet_mono_ns ? n.now - ic.last_packet_mono_ns : n.now - start_mono_;
    f.Set(kLidarTimeout,
          (!ic.finished && silent_ns > int64_t(in_.config.sensor_timeout_s * 1e9)) ||
              ic.silences > last_ingest_.silences,
          "no lidar packet for " + std::to_string(silent_ns / 1'000'000) + " ms (" +
              std::to_string(ic.silences) + " silences so far)");
    const uint64_t rejected = ic.lidar.TotalRejected(),
                   last_rejected = last_ingest_.lidar.TotalRejected();
    f.Set(kLidarRejects, rejected > last_rejected,
          std::to_string(rejected - last_rejected) + " lidar packets rejected (" +
              std::to_string(ic.lidar.Rejected(ouster::Reject::kCrc)) + " CRC failures in all)");
    f.Set(kLidarIncomplete, ic.lidar.frames_incomplete > last_ingest_.lidar.frames_incomplete,
          std::to_string(ic.lidar.columns_lost - last_ingest_.lidar.columns_lost) +
              " columns lost (packet loss)");
    f.Set(kLidarRestart, ic.init_id_changes > last_ingest_.init_id_changes,
          "the sensor restarted: init_id " + std::to_string(ic.init_id));
    f.Set(kImuTimeout,
          ic.lidar_datagrams > last_ingest_.lidar_datagrams &&
              ic.imu_datagrams == last_ingest_.imu_datagrams && in_.config.use_imu,
          "lidar packets but no IMU packet in the period");
}

// The Go1's CAN, and what the bridge says of itself in it. A bridge that sends nothing is as
// much a bridge fault as one that reports its link to the Go1 down or a state other than
// RUNNING (rig_health_t FAULT_GO1_BRIDGE).
void Health::DetectGo1Faults(const Snapshot& n, Faults& f) const {
    if (!in_.can) return;
    const CanCounters& cc = n.cc;
    const CanCounters& last = last_can_;
    const bool stale = cc.frames == last.frames && !cc.finished;
    f.Set(kCanTimeout, cc.timed_out != 0 || cc.decoder.timeout > last.decoder.timeout || stale,
          stale ? "no CAN frame in the period"
                : std::to_string(cc.decoder.timeout - last.decoder.timeout) +
                      " Go1 CAN message timeouts");
    const auto e2e = [](const CanCounters& c) {
        return c.decoder.crc + c.decoder.counter_resync + c.decoder.counter_repeat +
               c.decoder.counter_invalid;
    };
    f.Set(kCanE2e, e2e(cc) > e2e(last),
          std::to_string(e2e(cc) - e2e(last)) + " Go1 CAN E2E errors (CRC, counter)");
    const bool link_down = cc.bridge_link_down > last.bridge_link_down;
    const bool not_running = cc.bridge_not_running > last.bridge_not_running;
    std::string why = stale ? "the Go1 bridge is silent (no CAN frame in the period)"
                            : "the Go1 bridge reports state " + BridgeStateName(cc.bridge_state);
    if (link_down) why += ", its UDP link to the Go1 down";
    if (cc.bridge_lost > last.bridge_lost) {
        why += ", " + std::to_string(cc.bridge_lost - last.bridge_lost) + " HighStates lost";
    }
    f.Set(kGo1Bridge, stale || link_down || not_running, why);
}

void Health::DetectRigFaults(const Snapshot& n, Faults& f) {
    const WorkerCounters& wc = n.wc;
    f.Set(kDeadlineMiss, wc.deadline_misses > last_worker_.deadline_misses,
          std::to_string(wc.deadline_misses - last_worker_.deadline_misses) + " scans later than " +
              std::to_string(int(in_.config.deadline_ms)) + " ms");
    f.Set(kQueueOverflow, n.queue_drops > last_queue_drops_,
          std::to_string(n.queue_drops - last_queue_drops_) + " items dropped by full queues");
    f.Set(kCpuOverload, n.cpu_percent > 90.0 && !in_.unpaced_replay,
          std::to_string(int(n.cpu_percent)) + " % CPU");
    f.Set(kDiskLow, n.rc.disk_low,
          "disk almost full (" + std::to_string(n.rc.disk_free_bytes / 1'000'000) +
              " MB free): keyframe clouds are no longer written");
    f.Set(kDiskWrite, n.rc.write_errors > last_recorder_.write_errors, "session write failed");
    f.Set(kDegenerate, wc.degenerate > last_worker_.degenerate, "degenerate registration");
    f.Set(kOverBudget, wc.over_budget > last_worker_.over_budget, "odometry over its budget");
    f.Set(kLost, wc.failed > last_worker_.failed, "registration failed");
    // A wall clock step: CLOCK_REALTIME - CLOCK_MONOTONIC moved by more than 50 ms. Not the
    // ingest's arrival times going back (LidarCounters::clock_backwards): datagrams read in
    // batches, one socket after the other, go back between the sockets by the batch's span
    // whenever they come faster than they are read, and the ingest keeps them in order; a step
    // of the clock those kernel stamps come from (CLOCK_REALTIME) is the step seen here.
    const int64_t offset = n.now_rt - n.now;
    const bool step = std::llabs(offset - rt_minus_mono_) > 50'000'000;
    rt_minus_mono_ = offset;
    f.Set(kClockJump, step || wc.clock_jumps > last_worker_.clock_jumps,
          step ? "the wall clock stepped" : "the sensor clock jumped (the odometry started again)");
    f.Set(kLcmPublish, n.lc.failures > last_lcm_.failures, "LCM publish failed");
    f.Set(kBimMap, !in_.bim_map_error.empty(),
          in_.bim_map_error + " (no relocalisation: the rig maps in its own frame)");
    if (in_.localizer != nullptr) {
        const BimPoseState b = in_.localizer->latest();
        const double unlocalised_s =
            b.unlocalised_since_ns > 0 ? double(n.now - b.unlocalised_since_ns) * 1e-9 : 0.0;
        f.Set(kBimLost, unlocalised_s > in_.config.bim_lost_fault_s,
              "not localised in the model for " + std::to_string(int(unlocalised_s)) + " s (" +
                  std::string(localization::ToString(b.state)) + ")");
    }
}

// The watchdog's rule (HeartbeatStale), per thread: the log names each stuck thread and how long
// ago it last beat; thread_stalls_ counts the episodes of each.
void Health::DetectStalledThreads(const Snapshot& n, Faults& f) {
    std::string why;
    for (size_t i = 0; i < in_.threads.size(); ++i) {
        const bool stale = HeartbeatStale(in_.threads, i, n.now);
        if (stale && !thread_stale_[i]) ++thread_stalls_[i];
        thread_stale_[i] = stale;
        if (!stale) continue;
        const int64_t age_ms = (n.now - in_.threads.stats(i).heartbeat_ns.load()) / 1'000'000;
        why += (why.empty() ? "" : ", ") + ("thread '" + in_.threads.spec(i).name + "'") +
               " has not beaten for " + std::to_string(age_ms) + " ms";
    }
    f.Set(kThreadStalled, !why.empty(), why + " (the watchdog pings stop)");
}

// Counts each fault once per episode (when it becomes active), logs it rate-limited, and keeps
// the active and latched bits.
void Health::CountAndLog(const Faults& f, int64_t now) {
    for (int i = 0; i < kNumFaults; ++i) {
        const uint64_t bit = uint64_t(1) << i;
        if ((f.bits & bit) && !(active_ & bit)) ++counts_[size_t(i)];
        if ((f.bits & bit) && limiters_[size_t(i)].Allow(now)) {
            runtime::Log("fault", std::string(kFaultNames[i]) + ": " + f.why[size_t(i)]);
        }
    }
    active_ = f.bits;
    latched_ |= f.bits;
}

void Health::QueueHealth(const Snapshot& snapshot) {
    const int64_t now = snapshot.now, now_rt = snapshot.now_rt;
    const double interval_s = snapshot.interval_s, cpu_percent = snapshot.cpu_percent;
    const RecorderCounters& rc = snapshot.rc;
    if (bimslam::rig_health_t* h = in_.health_out.BeginPushWaiting(in_.replay, never_)) {
        h->schema_version = bimslam::rig_health_t::SCHEMA_VERSION;
        h->sample_time_ns = now_rt;
        h->publish_time_ns = now_rt;
        h->interval_start_time_ns = last_rt_;
        h->uptime_ns = now - start_mono_;
        h->faults = int64_t(active_);
        h->faults_latched = int64_t(latched_);
        h->num_fault_counts = kNumFaults;
        h->fault_counts.assign(counts_.begin(), counts_.end());
        const size_t n = in_.threads.size();
        h->num_threads = int32_t(n);
        h->thread_name.resize(n);
        h->thread_cycles.resize(n);
        h->thread_deadline_misses.resize(n);
        h->thread_deadline_ns.resize(n);
        h->thread_max_cycle_ns.resize(n);
        h->thread_cpu_percent.resize(n);
        h->thread_stalls.assign(thread_stalls_.begin(), thread_stalls_.end());
        for (size_t i = 0; i < n; ++i) {
            runtime::ThreadStats& s = in_.threads.stats(i);
            h->thread_name[i] = in_.threads.spec(i).name;
            h->thread_cycles[i] = int64_t(s.cycles.load());
            h->thread_deadline_misses[i] = int64_t(s.deadline_misses.load());
            h->thread_deadline_ns[i] =
                in_.threads.spec(i).deadline_ns > 0 ? in_.threads.spec(i).deadline_ns : -1;
            h->thread_max_cycle_ns[i] = s.max_cycle_ns.exchange(-1);
            const int64_t t = in_.threads.CpuNs(i);
            h->thread_cpu_percent[i] =
                t >= 0 && thread_cpu_[i] >= 0
                    ? float(100.0 * double(t - thread_cpu_[i]) * 1e-9 / interval_s)
                    : std::nanf("");
            thread_cpu_[i] = t;
        }
        h->num_queues = int32_t(in_.queues.size());
        h->queue_name.clear();
        h->queue_depth.clear();
        h->queue_max_depth.clear();
        h->queue_capacity.clear();
        h->queue_drops.clear();
        for (const runtime::QueueBase* q : in_.queues) {
            const runtime::QueueStats s = q->Stats();
            h->queue_name.push_back(s.name);
            h->queue_depth.push_back(int32_t(s.depth));
            h->queue_max_depth.push_back(int32_t(s.max_depth));
            h->queue_capacity.push_back(int32_t(s.capacity));
            h->queue_drops.push_back(int64_t(s.drops));
            const_cast<runtime::QueueBase*>(q)->ResetMaxDepth();
        }
        h->process_cpu_percent = float(cpu_percent);
        h->process_rss_bytes = runtime::ResidentBytes();
        h->disk_free_bytes =
            in_.recorder ? runtime::FreeDiskBytes(in_.config.session_root) : int64_t(-1);
        h->session_bytes_written = rc.bytes_written;
        h->session_dir = in_.recorder ? in_.recorder->current_dir() : "";
        in_.health_out.CommitPush();
    } else {
        in_.health_out.CountDrop();
    }
}

void Health::QueueOusterStats(const Snapshot& n) {
    const IngestCounters& ic = n.ic;
    const int64_t now_rt = n.now_rt;
    if (bimslam::ouster_stats_t* s = in_.stats_out.BeginPushWaiting(in_.replay, never_)) {
        const ouster::LidarStats& l = ic.lidar;
        s->schema_version = bimslam::ouster_stats_t::SCHEMA_VERSION;
        s->sample_time_ns = now_rt;
        s->publish_time_ns = now_rt;
        s->counting_since_ns = start_rt_;
        s->interval_start_time_ns = last_rt_;
        s->prod_sn = int64_t(in_.info.prod_sn);
        s->init_id = int32_t(ic.init_id);
        s->lidar_packets_received = int64_t(ic.lidar_datagrams);
        s->lidar_packets_accepted = int64_t(l.accepted);
        s->imu_packets_received = int64_t(ic.imu_datagrams);
        uint64_t imu_rejected = 0;
        for (uint64_t r : ic.imu.rejected) imu_rejected += r;
        s->imu_packets_accepted = int64_t(ic.imu.packets - imu_rejected);
        s->bytes_received = int64_t(ic.bytes);
        s->frames_complete = int64_t(l.frames_complete);
        s->frames_incomplete = int64_t(l.frames_incomplete);
        s->columns_lost = int64_t(l.columns_lost);
        const int cpp = std::max(1, in_.info.format.columns_per_packet);
        s->packets_lost = int64_t(l.columns_lost / uint64_t(cpp));
        s->sensor_restarts = int64_t(ic.init_id_changes + l.sensor_restarts);
        s->rejected_wrong_size = int64_t(l.Rejected(ouster::Reject::kSize));
        s->rejected_wrong_prod_sn = int64_t(l.Rejected(ouster::Reject::kProdSn));
        s->rejected_wrong_init_id = int64_t(l.Rejected(ouster::Reject::kInitId));
        s->rejected_crc = int64_t(l.Rejected(ouster::Reject::kCrc));
        s->rejected_late = int64_t(l.Rejected(ouster::Reject::kLate));
        s->rejected_unknown_port = int64_t(ic.other_datagrams);
        s->rejected_not_ouster = int64_t(l.Rejected(ouster::Reject::kPacketType) +
                                         l.Rejected(ouster::Reject::kMeasurementId));
        s->crc_checked = int64_t(l.crc_checked);
        s->crc_failures = int64_t(l.Rejected(ouster::Reject::kCrc));
        s->latency_mean_ns = -1;
        s->latency_max_ns = -1;
        s->latency_frames = 0;
        in_.stats_out.CommitPush();
    } else {
        in_.stats_out.CountDrop();
    }
}

// systemd's status line.
void Health::NotifyStatus(const Snapshot& n) {
    std::ostringstream status;
    status << "scans " << n.wc.scans << ", keyframes " << n.wc.keyframes << ", CPU "
           << int(n.cpu_percent) << " %, faults";
    if (active_ == 0) status << " none";
    for (int i = 0; i < kNumFaults; ++i) {
        if (active_ & (uint64_t(1) << i)) status << " " << kFaultNames[i];
    }
    in_.notifier.Notify("STATUS=" + status.str());
}

}  // namespace bimslam::rig
