// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "firmware/modules/bim_localizer.hpp"

#include "firmware/runtime/process_stats.hpp"

namespace bimslam::rig {

using localization::RelocalizerState;

BimLocalizer::BimLocalizer(const localization::RigMap& map,
                           runtime::SpscQueue<KeyframeItem>& keyframes, runtime::Wakeup& wakeup,
                           int64_t deadline_ns, runtime::SpscQueue<BimStepItem>* steps,
                           bool lossless, std::optional<localization::StartHint> start)
    : map_(map),
      keyframes_(keyframes),
      wakeup_(wakeup),
      deadline_ns_(deadline_ns),
      steps_(steps),
      lossless_(lossless),
      start_(start) {}

void BimLocalizer::Process(const KeyframeItem& k) {
    const io::SessionKeyframe& kf = k.keyframe;
    // A new segment: the odometry started again in a new frame, and so does the relocaliser.
    if (!relocalizer_ || k.segment != segment_) {
        if (relocalizer_) ++c_.restarts;
        localization::RelocalizerConfig config;
        if (first_segment_) config.start = start_;
        first_segment_ = false;
        relocalizer_.emplace(map_, config);
        segment_ = k.segment;
        path_m_ = 0;
        last_position_ = kf.T_world_lidar.translation();
    }
    // The distance walked, as `bimslam localize` sums it from the session's keyframes.
    path_m_ += (kf.T_world_lidar.translation() - last_position_).norm();
    last_position_ = kf.T_world_lidar.translation();
    const int64_t cpu0 = runtime::ThreadCpuNs();
    const localization::RelocalizerStep& step = relocalizer_->AddKeyframe(
        kf.cloud, kf.descriptor, kf.T_world_lidar, path_m_, k.height_ambiguous);
    const int64_t cpu = runtime::ThreadCpuNs() - cpu0;
    cpu_.Add(cpu);
    c_.cpu_ns += cpu;
    if (cpu > deadline_ns_) ++c_.deadline_misses;
    ++c_.keyframes;
    c_.registrations += step.registrations;
    if (c_.first_keyframe_ns < 0) c_.first_keyframe_ns = kf.stamp_ns;
    const bool localised = step.state == RelocalizerState::kLocalised;
    switch (step.state) {
        case RelocalizerState::kLocalised:
            ++c_.localised;
            if (c_.first_localised_ns < 0) c_.first_localised_ns = kf.stamp_ns;
            break;
        case RelocalizerState::kCandidate:
            ++c_.candidate;
            break;
        case RelocalizerState::kSearching:
            ++c_.searching;
            break;
        case RelocalizerState::kAmbiguous:
            ++c_.ambiguous;
            break;
        case RelocalizerState::kLost:
            ++c_.lost;
            break;
    }
    // Unlocalised since: set when a localisation ends, cleared when one holds.
    if (localised) {
        state_.unlocalised_since_ns = 0;
    } else if (was_localised_ && state_.unlocalised_since_ns == 0) {
        state_.unlocalised_since_ns = runtime::MonotonicNs();
    }
    was_localised_ = was_localised_ || localised;
    state_.any = true;
    state_.state = step.state;
    const Eigen::Matrix4d T =
        localised ? step.T_bim_odom.matrix() : Eigen::Matrix4d(Eigen::Matrix4d::Identity());
    Eigen::Matrix4d::Map(state_.T_bim_odom_matrix.data()) = T;
    Eigen::Map<Eigen::Matrix<double, 6, 6, Eigen::RowMajor>>(state_.fix_information.data()) =
        localised ? step.fix_information : common::Matrix6d::Zero();
    Eigen::Matrix4d::Map(state_.T_odom_lidar_fix_matrix.data()) =
        localised ? step.T_odom_lidar_fix.matrix() : Eigen::Matrix4d(Eigen::Matrix4d::Identity());
    state_.keyframe_stamp_ns = kf.stamp_ns;
    state_.segment = k.segment;
    state_.consistent_loops = uint32_t(step.consistent_loops);
    state_.hypotheses = uint32_t(step.hypotheses.size());
    state_.storey = step.storey;
    latest_.Store(state_);
    if (steps_ != nullptr) {
        BimStepItem* s = steps_->BeginPushWaiting(lossless_, never_);
        if (s == nullptr) {
            steps_->CountDrop();
            ++c_.steps_dropped;
        } else {
            s->keyframe_stamp_ns = kf.stamp_ns;
            s->segment = k.segment;
            s->state = uint8_t(step.state);
            s->localised = localised;
            s->T_bim_odom = step.T_bim_odom;
            s->consistent_loops = uint32_t(step.consistent_loops);
            s->hypotheses = uint32_t(step.hypotheses.size());
            s->storey = step.storey;
            steps_->CommitPush();
        }
    }
    counters_.Store(c_);
}

void BimLocalizer::Run(runtime::ThreadStats& stats, const std::atomic<bool>& producers_done) {
    for (;;) {
        stats.Beat();
        const uint32_t seen = wakeup_.Sequence();
        if (KeyframeItem* k = keyframes_.Front()) {
            const int64_t t0 = runtime::MonotonicNs();
            try {
                Process(*k);
            } catch (const std::exception&) {  // a keyframe it cannot take: counted, not fatal
                ++c_.errors;
                counters_.Store(c_);
            }
            keyframes_.Pop();
            stats.Cycle(runtime::MonotonicNs() - t0, deadline_ns_);
            continue;
        }
        if (producers_done.load(std::memory_order_acquire)) break;
        wakeup_.Wait(seen, 100'000'000);
    }
    counters_.Store(c_);
}

}  // namespace bimslam::rig
