// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "firmware/modules/session_recorder.hpp"

#include <ctime>
#include <system_error>

#include "algorithms/common/status.hpp"
#include "algorithms/io/file_util.hpp"
#include "algorithms/localization/relocalizer.hpp"
#include "firmware/runtime/process_stats.hpp"

namespace bimslam::rig {
namespace fs = std::filesystem;

namespace {
std::string StartName() {
    const std::time_t now = std::time(nullptr);
    std::tm tm{};
    gmtime_r(&now, &tm);
    char buf[32];
    std::strftime(buf, sizeof(buf), "%Y%m%d-%H%M%S", &tm);
    return buf;
}
}  // namespace

SessionRecorder::SessionRecorder(const SessionRecorderConfig& config,
                                 runtime::SpscQueue<PoseItem>& poses,
                                 runtime::SpscQueue<KeyframeItem>& keyframes,
                                 runtime::Wakeup& wakeup, runtime::SpscQueue<BimStepItem>* steps)
    : config_(config), poses_(poses), keyframes_(keyframes), wakeup_(wakeup), steps_(steps) {
    std::error_code ec;
    fs::create_directories(config_.root, ec);
    if (ec || !fs::is_directory(config_.root)) {
        throw common::FileError(common::StatusCode::kIoError, config_.root.string(), 0,
                                "cannot create the session folder: " + ec.message());
    }
    Open();
    first_dir_ = dir_;
}

SessionRecorder::~SessionRecorder() = default;

void SessionRecorder::Open() {
    const std::string base = StartName();
    fs::path dir = config_.root / base;
    for (int n = 2; fs::exists(dir); ++n) dir = config_.root / (base + "-" + std::to_string(n));
    io::SessionWriterOptions options;
    options.flush_every = 1;  // a power loss loses at most the keyframe being written
    options.sync_each_file = true;
    writer_.reset();
    writer_.emplace(dir, config_.manifest, options);
    dir_ = dir;
    last_written_selector_ = -1;
    ++c_.sessions;
    std::lock_guard<std::mutex> lock(dir_mutex_);
    dir_text_ = dir.string();
}

std::string SessionRecorder::current_dir() const {
    std::lock_guard<std::mutex> lock(dir_mutex_);
    return dir_text_;
}

void SessionRecorder::Write(const KeyframeItem& k) {
    c_.disk_free_bytes = runtime::FreeDiskBytes(config_.root.string());
    c_.disk_low = c_.disk_free_bytes >= 0 && c_.disk_free_bytes < config_.min_free_bytes;
    if (c_.disk_low) {
        ++c_.keyframes_skipped_disk;
        return;
    }
    // Written indices are contiguous; the selector's may have gaps (a full queue, a full disk).
    io::SessionKeyframe kf = k.keyframe;  // NOLINT: the writer thread may allocate
    const size_t index = writer_->AddKeyframe(kf);
    if (k.edge && int64_t(k.edge->from) == last_written_selector_ && index > 0) {
        io::SessionEdge e = *k.edge;
        e.from = uint32_t(index - 1);
        e.to = uint32_t(index);
        writer_->AddEdge(e);
    } else if (k.edge) {
        ++c_.edges_dropped;
    }
    last_written_selector_ = int64_t(k.keyframe_index);
    ++c_.keyframes;
    c_.bytes_written += int64_t(k.keyframe.cloud.size()) * 22 + 8 * 1200;
}

void SessionRecorder::AddVerdict(const PoseItem& p) {
    const size_t scan = size_t(p.scan_index);
    if (!session_has_scans_) session_first_scan_ = scan;
    session_has_scans_ = true;
    session_last_scan_ = scan;
    const std::vector<odometry::FailedStretch>& s = trust_.stretches();
    const size_t before = s.size();
    const size_t last_before = before > 0 ? s.back().last_scan : 0;
    trust_.Add(scan, p.t_s, p.flags, p.check_reasons, p.pose.stamp_ns);
    if (s.size() > verdict_stretches_) {
        WriteVerdict();  // a new stretch: on disk now, whatever happens to the rig next
    } else if (s.size() != before || (before > 0 && s.back().last_scan != last_before)) {
        verdict_dirty_ = true;  // the last stretch grew: written with the next flush
    }
}

void SessionRecorder::WriteVerdict() {
    // A failed write is counted (FAULT_DISK_WRITE) and does not stop the poses and keyframes.
    try {
        io::WriteFileAtomic(
            dir_ / odometry::TrajectoryTrust::kSessionFile,
            trust_.SessionJson(session_first_scan_, session_last_scan_).dump(1) + "\n");
        verdict_stretches_ = trust_.stretches().size();
        verdict_dirty_ = false;
    } catch (const std::exception&) {
        ++c_.write_errors;
    }
}

void SessionRecorder::Run(runtime::ThreadStats& stats, const std::atomic<bool>& producer_done) {
    int64_t last_flush = runtime::MonotonicNs();
    int64_t last_verdict = last_flush;
    bool dirty = false;
    for (;;) {
        stats.Beat();
        const uint32_t seen = wakeup_.Sequence();
        bool worked = false;
        const int64_t t0 = runtime::MonotonicNs();
        try {
            while (PoseItem* p = poses_.Front()) {
                if (p->segment != segment_) {
                    // A clock jump: the next session; the keyframes of this one were queued
                    // before the jump, so they go first.
                    while (KeyframeItem* k = keyframes_.Front()) {
                        if (k->segment != segment_) break;
                        Write(*k);
                        keyframes_.Pop();
                    }
                    WriteVerdict();
                    ApplySteps(true);
                    writer_->Finish();
                    segment_ = p->segment;
                    current_.reset();
                    last_state_ = -1;
                    Open();
                    session_has_scans_ = false;
                }
                writer_->AddScanPose(p->pose);
                if (steps_ != nullptr) {
                    pending_.push_back(p->pose);
                    last_pose_ns_ = p->pose.stamp_ns;
                }
                AddVerdict(*p);
                ++c_.poses;
                dirty = true;
                poses_.Pop();
                worked = true;
            }
            while (KeyframeItem* k = keyframes_.Front()) {
                if (k->segment != segment_) break;
                Write(*k);
                keyframes_.Pop();
                dirty = false;  // AddKeyframe flushed the line files
                worked = true;
            }
            if (steps_ != nullptr && ApplySteps(false)) {
                dirty = true;
                worked = true;
            }
            if (dirty && runtime::MonotonicNs() - last_flush > config_.flush_period_ns) {
                writer_->Flush();
                dirty = false;
                last_flush = runtime::MonotonicNs();
            }
            if (verdict_dirty_ && runtime::MonotonicNs() - last_verdict > config_.flush_period_ns) {
                WriteVerdict();
                last_verdict = runtime::MonotonicNs();
            }
        } catch (const std::exception& e) {
            ++c_.write_errors;  // the health thread logs FAULT_DISK_WRITE
            if (poses_.Front()) poses_.Pop();
        }
        if (worked) stats.Cycle(runtime::MonotonicNs() - t0, 0);
        counters_.Store(c_);
        if (!worked && producer_done.load(std::memory_order_acquire) && !poses_.Front() &&
            !keyframes_.Front()) {
            break;
        }
        if (!worked) wakeup_.Wait(seen, 100'000'000);
    }
    WriteVerdict();  // before session.json, as `bimslam odometry` writes it
    try {
        ApplySteps(true);
        writer_->Finish();
    } catch (const std::exception&) {
        ++c_.write_errors;
    }
    counters_.Store(c_);
}

bool SessionRecorder::ApplySteps(bool all) {
    if (steps_ == nullptr) return false;  // no map package
    bool applied = false;
    while (BimStepItem* s = steps_->Front()) {
        if (s->segment < segment_) {  // an earlier session's: it has been closed
            steps_->Pop();
            continue;
        }
        // A later session's, or a keyframe whose scan's pose has not been written yet: later
        // (the localiser's queue and the poses' are separate; either may be seen first).
        if (s->segment > segment_) break;
        if (!all && s->keyframe_stamp_ns > last_pose_ns_) break;
        ApplyStep(*s);
        steps_->Pop();
        applied = true;
    }
    if (all) WritePending(std::numeric_limits<int64_t>::max());
    return applied;
}

void SessionRecorder::ApplyStep(const BimStepItem& s) {
    WritePending(s.keyframe_stamp_ns);
    current_ = s;
    if (int(s.state) != last_state_) {
        const std::string storey =
            s.localised && s.storey >= 0 && size_t(s.storey) < config_.storeys.size()
                ? config_.storeys[size_t(s.storey)]
                : "";
        writer_->AddLocalizationState(
            s.keyframe_stamp_ns, localization::ToString(localization::RelocalizerState(s.state)),
            s.consistent_loops, s.hypotheses, storey);
        last_state_ = int(s.state);
    }
}

void SessionRecorder::WritePending(int64_t before_ns) {
    while (!pending_.empty() && pending_.front().stamp_ns < before_ns) {
        const io::StampedPose& p = pending_.front();
        if (current_ && current_->localised) {
            writer_->AddLivePose(localization::LivePose(current_->T_bim_odom, p));
        }
        pending_.pop_front();
    }
}

}  // namespace bimslam::rig
