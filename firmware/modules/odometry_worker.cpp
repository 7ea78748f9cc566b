// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "firmware/modules/odometry_worker.hpp"

#include <thread>

#include "firmware/runtime/process_stats.hpp"

namespace bimslam::rig {

OdometryWorker::OdometryWorker(const OdometryWorkerConfig& config, WorkerQueues queues,
                               const CanIngest* can)
    : config_(config), q_(queues), can_(can), pipeline_(config.pipeline) {
    counters_.Store(c_);
}

void OdometryWorker::DrainImu() {
    while (ImuItem* item = q_.imu.Front()) {
        pipeline_.AddImu(item->measurement);
        q_.imu.Pop();
    }
}

bool OdometryWorker::ProcessOne(runtime::ThreadStats& stats, const std::atomic<bool>& stop) {
    ScanSlot* slot = q_.scans.Front();
    if (slot == nullptr) return false;
    DrainImu();  // every IMU sample queued before the scan is visible now (same producer)
    const int64_t arrival = slot->scan.emitted_arrival_ns;
    if (can_ != nullptr && can_->progress_ns() < arrival) {
        // Wait for the CAN ingest to pass the scan's arrival: bounded live, until the log has
        // passed it in a replay.
        const int64_t give_up = runtime::MonotonicNs() + config_.can_wait_ns;
        while (can_->progress_ns() < arrival && !stop.load(std::memory_order_relaxed) &&
               (config_.lossless || runtime::MonotonicNs() < give_up)) {
            stats.Beat();
            std::this_thread::sleep_for(std::chrono::microseconds(100));
        }
        if (can_->progress_ns() < arrival) ++c_.can_late;
    }
    while (BodyItem* b = q_.bodies.Front()) {
        if (b->body.received_ns > arrival) break;
        pipeline_.AddBody(b->body);
        q_.bodies.Pop();
    }
    ScanTimes times = slot->times;
    times.started = runtime::MonotonicNs();
    const int64_t cpu0 = runtime::ThreadCpuNs();
    const pipeline::ScanOutput& out = pipeline_.Process(slot->scan);
    times.odometry_cpu_ns = runtime::ThreadCpuNs() - cpu0;
    times.odometry_done = runtime::MonotonicNs();
    const odometry::OdometryResult& r = *out.odometry;
    if (out.clock_jump) {
        ++segment_;
        ++c_.clock_jumps;
    }
    // As host_tools/replay/capture_odometry.cpp: seconds since the run's first scan, the scan's
    // index over the whole run (sessions after a clock jump continue it).
    if (first_stamp_ns_ < 0) first_stamp_ns_ = out.stamp_ns;
    const double t_s = double(out.stamp_ns - first_stamp_ns_) * 1e-9;
    trust_.Add(size_t(out.scan_index), t_s, r.flags, r.check_reasons, out.stamp_ns);
    height_ambiguous_ =
        (height_ambiguous_ && !out.clock_jump) || (r.flags & odometry::kHeightAmbiguous) != 0;
    // Outputs. A full queue drops the item and counts it (the consumer is behind); a replay
    // waits for room even once the sources have stopped: every consumer runs until this thread
    // is done (Rig::StopInOrder). Waiting on `stop` lost the last keyframe on LCM in 2 of 12
    // replays at --speed max, when the end of the recording found the paced LCM queue full.
    const auto push = [&](auto& queue, auto&& fill) {
        auto* item = queue.BeginPushWaiting(config_.lossless, never_);
        if (item == nullptr) {
            queue.CountDrop();
            ++c_.outputs_dropped;
            return false;
        }
        fill(*item);
        queue.CommitPush();
        return true;
    };
    // The odometry first: the LCM thread publishes it before the keyframe (encoding a keyframe
    // of a whole scan takes milliseconds), and the keyframes' copies are not on its path.
    times.handed = runtime::MonotonicNs();
    push(q_.odometry_out, [&](OdometryItem& o) {
        o.result = r;
        o.scan_index = out.scan_index;
        o.scan_end_ns = slot->scan.last_column_ns;
        o.complete = out.complete;
        o.keyframe = out.keyframe;
        o.reset = out.clock_jump;
        o.times = times;
    });
    if (config_.record)
        push(q_.poses, [&](PoseItem& p) {
            p.pose = io::StampedPose::FromIsometry(out.stamp_ns, r.T_odom_lidar);
            p.segment = segment_;
            p.scan_index = out.scan_index;
            p.t_s = t_s;
            p.flags = r.flags;
            p.check_reasons = r.check_reasons;
        });
    if (out.keyframe) {
        const auto fill = [&](KeyframeItem& k) {
            k.keyframe = *out.keyframe_data;  // copies into the slot's reserved buffers
            k.edge.reset();
            if (out.edge != nullptr) k.edge = *out.edge;
            k.keyframe_index = out.keyframe_index;
            k.scan_index = out.scan_index;
            k.segment = segment_;
            k.height_ambiguous = height_ambiguous_;
        };
        if (config_.record) push(q_.keyframes_session, fill);
        push(q_.keyframes_lcm, fill);
        // A keyframe the localiser's full queue refused leaves the flag for its next one.
        if (q_.keyframes_localizer == nullptr || push(*q_.keyframes_localizer, fill))
            height_ambiguous_ = false;
    }
    const int64_t latency = times.handed - times.last_packet;
    stats.Cycle(latency, config_.deadline_ns);
    if (latency > config_.deadline_ns) ++c_.deadline_misses;
    q_.scans.Pop();

    ++c_.scans;
    c_.keyframes += out.keyframe ? 1 : 0;
    c_.incomplete += out.complete ? 0 : 1;
    const pipeline::ScanPipelineStats& s = pipeline_.stats();
    c_.over_budget = s.over_budget;
    c_.degenerate = s.degenerate;
    c_.failed = s.failed;
    c_.distance_m = s.distance_m;
    c_.last_solve_ns = int64_t(r.total_ms * 1e6);
    c_.last_flags = r.flags;
    counters_.Store(c_);
    return true;
}

void OdometryWorker::Run(runtime::ThreadStats& stats, const std::atomic<bool>& stop,
                         const std::atomic<bool>& inputs_done) {
    for (;;) {
        stats.Beat();
        const uint32_t seen = q_.wakeup.Sequence();
        if (ProcessOne(stats, stop)) continue;
        DrainImu();
        if (inputs_done.load(std::memory_order_acquire) && q_.scans.Front() == nullptr) break;
        if (stop.load(std::memory_order_relaxed) && !config_.lossless) {
            if (q_.scans.Front() == nullptr) break;
        }
        q_.wakeup.Wait(seen, 100'000'000);
    }
    counters_.Store(c_);
}

}  // namespace bimslam::rig
