// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The session writer thread: all disk I/O of the rig, off the hot path. Every scan's pose and
// every keyframe go into a session folder (algorithms/io/session.hpp: each keyframe's cloud and
// descriptor, then the line files, each written atomically and synced), so that after a SIGKILL
// or a power loss `bimslam session info` recovers every keyframe that was complete. SIGINT and
// SIGTERM end with Finish() (session.json).
//
// A new folder per start (the start time, UTC, plus -2, -3, ... when it exists): never
// overwriting. A clock jump (the odometry started again) closes the session and opens the next.
// Disk almost full: below min_free_bytes no keyframe is written any more (counted); the poses
// still are, the odometry and LCM go on.
//
// odometry_verdict.json (odometry::TrajectoryTrust::kSessionFile, the file `bimslam odometry`
// writes): the odometry's verdict on the session's scans, from the flags each pose carries,
// written atomically when a new failed stretch appears (a rig killed afterwards still leaves
// it), with the stretch as it has grown at each flush of trajectory.tum, and when the session
// closes (before session.json).
#pragma once

#include <atomic>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <limits>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "algorithms/io/session.hpp"
#include "algorithms/odometry/trajectory_trust.hpp"
#include "firmware/modules/rig_types.hpp"
#include "firmware/runtime/seqlock.hpp"
#include "firmware/runtime/thread_table.hpp"

namespace bimslam::rig {

struct SessionRecorderConfig {
    std::filesystem::path root;
    io::SessionManifest manifest;
    int64_t min_free_bytes = int64_t(1) << 30;
    int64_t flush_period_ns = 2'000'000'000;  // trajectory.tum rewritten at least this often
    // With a map package: the storeys' names (the localiser's steps name them by index).
    std::vector<std::string> storeys;
};

struct RecorderCounters {
    uint64_t poses = 0, keyframes = 0;
    uint64_t keyframes_skipped_disk = 0;  // not written: disk almost full
    uint64_t edges_dropped = 0;           // their keyframe was not written
    uint64_t write_errors = 0;
    uint64_t sessions = 0;
    int64_t bytes_written = 0;
    int64_t disk_free_bytes = -1;
    bool disk_low = false;
};

class SessionRecorder {
public:
    // Creates the first session folder; throws common::FileError when it cannot.
    // `steps`: the localiser's step per keyframe (a map package loaded), for
    // trajectory_bim_live.tum and localization_states.csv; nullptr: none.
    SessionRecorder(const SessionRecorderConfig& config, runtime::SpscQueue<PoseItem>& poses,
                    runtime::SpscQueue<KeyframeItem>& keyframes, runtime::Wakeup& wakeup,
                    runtime::SpscQueue<BimStepItem>* steps = nullptr);
    ~SessionRecorder();

    // Until `producer_done` and both queues are empty; then Finish().
    void Run(runtime::ThreadStats& stats, const std::atomic<bool>& producer_done);

    RecorderCounters counters() const { return counters_.Load(); }
    // The folder being written (first session until a clock jump).
    std::string current_dir() const;
    const std::filesystem::path& first_dir() const { return first_dir_; }

private:
    void Open();
    void Write(const KeyframeItem& k);
    void AddVerdict(const PoseItem& p);
    void WriteVerdict();
    // The localiser's steps (trajectory_bim_live.tum): a scan's live pose is its odometry
    // composed with the step of the last keyframe at or before it, as `bimslam localize` composes
    // them, so each pose waits in pending_ for the next step (or the session's end).
    // Applies the steps whose keyframe's pose has been written (all: every one of this session,
    // and the poses after the last); returns whether it applied any.
    bool ApplySteps(bool all);
    void ApplyStep(const BimStepItem& s);
    void WritePending(int64_t before_ns);

    SessionRecorderConfig config_;
    runtime::SpscQueue<PoseItem>& poses_;
    runtime::SpscQueue<KeyframeItem>& keyframes_;
    runtime::Wakeup& wakeup_;
    std::optional<io::SessionWriter> writer_;
    std::filesystem::path first_dir_;
    std::filesystem::path dir_;
    uint32_t segment_ = 0;
    int64_t last_written_selector_ = -1;  // selector index of the last keyframe written
    // The odometry's verdict over the run; the scans of the current session.
    odometry::TrajectoryTrust trust_;
    size_t session_first_scan_ = 0, session_last_scan_ = 0;
    bool session_has_scans_ = false;
    bool verdict_dirty_ = false;    // the stretches changed since odometry_verdict.json
    size_t verdict_stretches_ = 0;  // stretches when it was last written
    runtime::SpscQueue<BimStepItem>* steps_;
    std::deque<io::StampedPose> pending_;
    std::optional<BimStepItem> current_;  // the last step applied, this session's
    int last_state_ = -1;
    int64_t last_pose_ns_ = std::numeric_limits<int64_t>::min();
    RecorderCounters c_;
    runtime::Seqlock<RecorderCounters> counters_;
    mutable std::mutex dir_mutex_;  // between two slow threads (writer, health)
    std::string dir_text_;
};

}  // namespace bimslam::rig
