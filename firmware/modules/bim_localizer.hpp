// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The localiser thread (issue 35, item 2): each keyframe the odometry makes goes through the
// relocaliser (algorithms/localization/relocalizer.hpp) against the map package the rig loaded.
// Its own thread, queue and deadline: it never holds up the odometry, whose worker hands it the
// keyframes as it hands them to the session writer and LCM. The latest result is shared through
// a seqlock: the LCM thread composes it with every scan's odometry into bim_pose_t.
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <atomic>
#include <cstdint>
#include <optional>

#include "algorithms/localization/relocalizer.hpp"
#include "algorithms/localization/rig_map.hpp"
#include "firmware/modules/rig_types.hpp"
#include "firmware/runtime/latency_histogram.hpp"
#include "firmware/runtime/seqlock.hpp"
#include "firmware/runtime/thread_table.hpp"

namespace bimslam::rig {

// The relocaliser's latest word, for the LCM thread (and the health thread).
struct BimPoseState {
    bool any = false;  // a keyframe was processed
    localization::RelocalizerState state = localization::RelocalizerState::kSearching;
    // T_bim_odom, localised only: its 4x4 matrix column-major (a seqlock copies bytes).
    std::array<double, 16> T_bim_odom_matrix = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    Eigen::Isometry3d T_bim_odom() const {
        return Eigen::Isometry3d(Eigen::Matrix4d::Map(T_bim_odom_matrix.data()));
    }
    // Localised: RelocalizerStep's fix (its information, row-major, and the fix keyframe's
    // T_odom_lidar, column-major) for bim_pose_t's covariance (localization::LiveCovariance).
    std::array<double, 36> fix_information = {};
    std::array<double, 16> T_odom_lidar_fix_matrix = {1, 0, 0, 0, 0, 1, 0, 0,
                                                      0, 0, 1, 0, 0, 0, 0, 1};
    Eigen::Isometry3d T_odom_lidar_fix() const {
        return Eigen::Isometry3d(Eigen::Matrix4d::Map(T_odom_lidar_fix_matrix.data()));
    }
    common::Matrix6d FixInformation() const {
        return Eigen::Map<const Eigen::Matrix<double, 6, 6, Eigen::RowMajor>>(
            fix_information.data());
    }
    int64_t keyframe_stamp_ns = 0;  // sensor clock: the keyframe it came from
    uint32_t segment = 0;           // the odometry's segment (a clock jump starts another)
    uint32_t consistent_loops = 0, hypotheses = 0;
    int32_t storey = -1;  // into the package's storeys
    // CLOCK_MONOTONIC ns since when the state has not been localised after a localisation
    // (FAULT_BIM_LOST); 0 while localised or before the first localisation.
    int64_t unlocalised_since_ns = 0;
};

struct LocalizerCounters {
    uint64_t keyframes = 0, localised = 0, candidate = 0, searching = 0, ambiguous = 0, lost = 0;
    uint64_t registrations = 0, deadline_misses = 0, restarts = 0;
    uint64_t errors = 0;              // keyframes the relocaliser threw on (none expected: counted)
    uint64_t steps_dropped = 0;       // steps the session writer's full queue refused (live)
    int64_t first_keyframe_ns = -1;   // sensor clock
    int64_t first_localised_ns = -1;  // sensor clock: the keyframe it was first localised at
    int64_t cpu_ns = 0;               // the relocaliser's CPU time, all keyframes
};

class BimLocalizer {
public:
    // `map` must outlive it. deadline_ns: a keyframe's relocalisation longer than this is a miss.
    // `wakeup`: the one the keyframe queue notifies. `steps`: each keyframe's step for the
    // session writer (nullptr: none), waiting for room when `lossless` (a replay).
    // `start`: where the walk starts (localization.near), for the odometry's first segment only
    // (a later segment starts where the odometry started again, not where the walk did).
    BimLocalizer(const localization::RigMap& map, runtime::SpscQueue<KeyframeItem>& keyframes,
                 runtime::Wakeup& wakeup, int64_t deadline_ns,
                 runtime::SpscQueue<BimStepItem>* steps = nullptr, bool lossless = false,
                 std::optional<localization::StartHint> start = std::nullopt);

    // Until `producers_done` and the queue is empty.
    void Run(runtime::ThreadStats& stats, const std::atomic<bool>& producers_done);

    BimPoseState latest() const { return latest_.Load(); }
    LocalizerCounters counters() const { return counters_.Load(); }
    const localization::RigMap& map() const { return map_; }
    // CPU per keyframe, the whole run's, in fixed memory; read after Run returns.
    const runtime::LatencyHistogram& cpu() const { return cpu_; }

private:
    void Process(const KeyframeItem& k);

    const localization::RigMap& map_;
    runtime::SpscQueue<KeyframeItem>& keyframes_;
    runtime::Wakeup& wakeup_;
    int64_t deadline_ns_;
    runtime::SpscQueue<BimStepItem>* steps_;
    bool lossless_;
    std::atomic<bool> never_{false};  // BeginPushWaiting's stop: the writer always drains
    std::optional<localization::Relocalizer> relocalizer_;
    std::optional<localization::StartHint> start_;
    bool first_segment_ = true;
    uint32_t segment_ = 0;
    double path_m_ = 0;
    Eigen::Vector3d last_position_ = Eigen::Vector3d::Zero();
    bool was_localised_ = false;
    BimPoseState state_;
    LocalizerCounters c_;
    runtime::Seqlock<BimPoseState> latest_;
    runtime::Seqlock<LocalizerCounters> counters_;
    runtime::LatencyHistogram cpu_;
};

}  // namespace bimslam::rig
