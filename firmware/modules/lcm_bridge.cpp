// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "firmware/modules/lcm_bridge.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <lcm/lcm-cpp.hpp>
#include <limits>
#include <thread>

#include "algorithms/common/se3.hpp"
#include "algorithms/common/status.hpp"

namespace bimslam::rig {
namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}

// bim_pose_t.state is RelocalizerState's value.
static_assert(
    int(localization::RelocalizerState::kSearching) == bimslam::bim_pose_t::STATE_SEARCHING &&
    int(localization::RelocalizerState::kCandidate) == bimslam::bim_pose_t::STATE_CANDIDATE &&
    int(localization::RelocalizerState::kLocalised) == bimslam::bim_pose_t::STATE_LOCALISED &&
    int(localization::RelocalizerState::kAmbiguous) == bimslam::bim_pose_t::STATE_AMBIGUOUS &&
    int(localization::RelocalizerState::kLost) == bimslam::bim_pose_t::STATE_LOST);

void ToMessage(const BimPoseState& bim, const localization::RigMap& map, const OdometryItem& item,
               uint32_t segment, const Eigen::Isometry3d& T_base_lidar, int64_t publish_ns,
               bimslam::bim_pose_t* m) {
    using B = bimslam::bim_pose_t;
    using localization::RelocalizerState;
    const bool here = bim.any && bim.segment == segment;
    const RelocalizerState state = here ? bim.state : RelocalizerState::kSearching;
    m->schema_version = B::SCHEMA_VERSION;
    m->sample_time_ns = item.result.stamp_ns;
    m->publish_time_ns = publish_ns;
    m->keyframe_time_ns = here ? bim.keyframe_stamp_ns : 0;
    m->state = int8_t(state);  // RelocalizerState's order is STATE_*'s
    m->consistent_loops = here ? int32_t(bim.consistent_loops) : 0;
    m->num_hypotheses = here ? int32_t(bim.hypotheses) : 0;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const bool localised = state == RelocalizerState::kLocalised;
    const Eigen::Isometry3d T =
        bim.T_bim_odom() * item.result.T_odom_lidar * T_base_lidar.inverse();
    const Eigen::Quaterniond q(T.rotation());
    for (int i = 0; i < 3; ++i) m->position[i] = localised ? T.translation()[i] : nan;
    const double qv[4] = {q.w(), q.x(), q.y(), q.z()};
    for (int i = 0; i < 4; ++i) m->orientation[i] = localised ? qv[i] : nan;
    if (localised) {
        // From the registration that fixed T_bim_odom to this scan's base.
        const Eigen::Isometry3d T_odom_base = item.result.T_odom_lidar * T_base_lidar.inverse();
        const Eigen::Isometry3d T_fix = bim.T_odom_lidar_fix();
        const common::Matrix6d C = localization::LiveCovariance(
            bim.FixInformation(), T_fix.inverse() * T_odom_base,
            (item.result.T_odom_lidar.translation() - T_fix.translation()).norm(), {});
        for (int i = 0; i < 36; ++i) m->pose_covariance[i] = C(i / 6, i % 6);
    } else {
        for (double& c : m->pose_covariance) c = nan;
    }
    m->storey = localised && bim.storey >= 0 && size_t(bim.storey) < map.storeys.size()
                    ? map.storeys[size_t(bim.storey)].name
                    : "";
    const int space = localised ? localization::SpaceAt(map, T.translation()) : -1;
    m->space_name = space >= 0 ? map.spaces[size_t(space)].name : "";
    m->space_global_id = space >= 0 ? map.spaces[size_t(space)].global_id : "";
}

void ToMessage(const OdometryItem& item, int64_t publish_ns, bimslam::odometry_t* m) {
    using O = bimslam::odometry_t;
    const odometry::OdometryResult& r = item.result;
    m->schema_version = O::SCHEMA_VERSION;
    m->sample_time_ns = r.stamp_ns;
    m->publish_time_ns = publish_ns;
    m->scan_start_time_ns = r.stamp_ns;
    m->scan_end_time_ns = item.scan_end_ns > 0 ? item.scan_end_ns : 0;
    m->scan_index = int64_t(item.scan_index);
    const bool valid = (r.flags & odometry::kTooFewPoints) == 0 || (r.flags & odometry::kFirstScan);
    int32_t status = 0;
    if (valid) status |= O::STATUS_VALID;
    if (r.flags & odometry::kDegenerate) status |= O::STATUS_DEGENERATE;
    if (r.flags & odometry::kOverBudget) status |= O::STATUS_OVER_BUDGET;
    if (r.flags & odometry::kImuUsed) status |= O::STATUS_PRIOR_USED_IMU;
    if (r.flags & odometry::kBodyPriorUsed) status |= O::STATUS_PRIOR_USED_GO1;
    if (r.flags & odometry::kFirstScan) status |= O::STATUS_INITIALISING;
    if (item.reset) status |= O::STATUS_RESET;
    if (r.preprocess.input > 0) status |= O::STATUS_DESKEWED;
    if (!item.complete) status |= O::STATUS_SCAN_INCOMPLETE;
    if (r.flags & odometry::kNotConverged) status |= O::STATUS_NOT_CONVERGED;
    if (r.flags & odometry::kRegistrationFailed) status |= O::STATUS_FEW_CORRESPONDENCES;
    if (item.keyframe) status |= O::STATUS_KEYFRAME;
    m->status = status;
    m->degenerate_directions = r.registration.degenerate_directions;
    const Eigen::Vector3d t = r.T_odom_lidar.translation();
    const Eigen::Quaterniond q(r.T_odom_lidar.linear());
    for (int i = 0; i < 3; ++i) m->position[i] = valid ? t[i] : kNaN;
    m->orientation_w = valid ? q.w() : kNaN;
    m->orientation_x = valid ? q.x() : kNaN;
    m->orientation_y = valid ? q.y() : kNaN;
    m->orientation_z = valid ? q.z() : kNaN;
    // The twist of the motion since the previous scan, over the time between the scans.
    const common::Vector6d twist = common::LogSE3(r.T_prev_lidar);
    const double dt = 0.1;  // the scan period at 10 Hz; a twist per scan otherwise
    for (int i = 0; i < 3; ++i) {
        m->linear_velocity[i] = valid ? twist[i] / dt : kNaN;
        m->angular_velocity[i] = valid ? twist[3 + i] / dt : kNaN;
    }
    for (int i = 0; i < 36; ++i) m->pose_covariance[i] = valid ? r.covariance(i / 6, i % 6) : kNaN;
    m->solve_time_ns = int64_t(r.total_ms * 1e6);
    m->iterations = r.registration.iterations;
    m->num_scan_points = int32_t(r.preprocess.registration_points);
    m->num_correspondences = r.registration.correspondences;
    m->num_map_points = int32_t(r.map_points);
    m->residual_rms = float(r.registration.rms);
    m->min_information_eigenvalue = float(r.registration.min_eigen_ratio);
}

void ToMessage(const KeyframeItem& item, const keyframes::KeyframeConfig& config,
               int64_t publish_ns, bimslam::keyframe_t* m) {
    const io::SessionKeyframe& k = item.keyframe;
    m->schema_version = bimslam::keyframe_t::SCHEMA_VERSION;
    m->sample_time_ns = k.stamp_ns;
    m->publish_time_ns = publish_ns;
    m->keyframe_id = int64_t(item.keyframe_index);
    m->scan_index = int64_t(item.scan_index);
    const Eigen::Isometry3d T = k.T_odom_lidar ? *k.T_odom_lidar : k.T_world_lidar;
    const Eigen::Quaterniond q(T.linear());
    for (int i = 0; i < 3; ++i) m->position[i] = T.translation()[i];
    m->orientation_w = q.w();
    m->orientation_x = q.x();
    m->orientation_y = q.y();
    m->orientation_z = q.z();
    m->descriptor_kind = bimslam::keyframe_t::DESCRIPTOR_SCAN_CONTEXT_INDOOR;
    m->num_rings = int32_t(k.descriptor.rows());
    m->num_sectors = int32_t(k.descriptor.cols());
    m->max_radius = float(config.descriptor.max_radius);
    m->num_cells = m->num_rings * m->num_sectors;
    m->cells.assign(k.descriptor.data(), k.descriptor.data() + k.descriptor.size());
    m->voxel_size = 0;
    const size_t n = k.cloud.size();
    m->num_points = int32_t(n);
    m->x.resize(n);
    m->y.resize(n);
    m->z.resize(n);
    m->intensity.resize(n);
    for (size_t i = 0; i < n; ++i) {
        m->x[i] = k.cloud.xyz[i].x();
        m->y[i] = k.cloud.xyz[i].y();
        m->z[i] = k.cloud.xyz[i].z();
        m->intensity[i] = k.cloud.HasIntensity() ? k.cloud.intensity[i] : 0.0f;
    }
}

void ToMessage(const OusterImuItem& item, int64_t publish_ns, bimslam::imu_sample_t* m) {
    using I = bimslam::imu_sample_t;
    m->schema_version = I::SCHEMA_VERSION;
    m->sample_time_ns = int64_t(item.sample.gyro_time_ns);
    m->publish_time_ns = publish_ns;
    m->accel_time_offset_ns = int64_t(item.sample.time_ns) - int64_t(item.sample.gyro_time_ns);
    m->source = I::SOURCE_OUSTER;
    m->sequence = int64_t(item.sequence);
    m->flags = int32_t(I::FLAG_ANGULAR_VELOCITY_VALID) | int32_t(I::FLAG_LINEAR_ACCELERATION_VALID);
    for (int i = 0; i < 3; ++i) {
        m->angular_velocity[i] = item.sample.gyro[i];
        m->linear_acceleration[i] = item.sample.accel[i];
    }
    m->orientation_w = m->orientation_x = m->orientation_y = m->orientation_z = kNaN;
}

void ToMessage(const Go1Item& item, int64_t publish_ns, bimslam::go1_state_t* m) {
    using G = bimslam::go1_state_t;
    const can::Go1Sample& s = item.sample;
    const auto f = [](bool ok, double v) { return ok ? float(v) : std::nanf(""); };
    m->schema_version = G::SCHEMA_VERSION;
    m->sample_time_ns = s.bridge_time_ns;
    m->publish_time_ns = publish_ns;
    m->receive_time_ns = s.host_time_ns;
    m->alive_counter = s.counter;
    m->valid_groups = s.valid;
    m->fresh_groups = s.fresh;
    m->timed_out_groups = item.timed_out;
    int32_t flags = 0;
    if (s.udp_link_ok)
        flags |= int32_t(G::FLAG_SYNC_UDP_LINK_OK) | int32_t(G::FLAG_STATUS_UDP_LINK_OK);
    if (s.highstate_crc_ok)
        flags |= int32_t(G::FLAG_SYNC_HIGHSTATE_CRC_OK) | int32_t(G::FLAG_STATUS_HIGHSTATE_CRC_OK);
    if (s.gyro_saturated) flags |= G::FLAG_GYRO_SATURATED;
    if (s.accel_saturated) flags |= G::FLAG_ACCEL_SATURATED;
    if (s.odom_reset) flags |= G::FLAG_ODOM_RESET;
    m->flags = flags;
    m->bridge_time_raw_us = (s.bridge_time_ns / 1000) & 0xFFFFFFFFll;
    m->sample_age_us = int32_t(s.sample_age_us);
    const bool vel = s.valid & can::kGroupBodyVel, st = s.valid & can::kGroupBodyState;
    m->velocity_x = f(vel, s.vx);
    m->velocity_y = f(vel, s.vy);
    m->yaw_rate = f(vel, s.yaw_rate);
    m->velocity_z = f(st, s.vz);
    m->body_height = f(st, s.body_height);
    m->foot_raise_height = f(st, s.foot_raise_height);
    for (int i = 0; i < 3; ++i) {
        m->gyro[i] = f(s.valid & can::kGroupGyro, s.gyro[size_t(i)]);
        m->accel[i] = f(s.valid & can::kGroupAccel, s.accel[size_t(i)]);
    }
    const bool quat = s.valid & can::kGroupQuat;
    m->orientation_w = f(quat, s.quat_wxyz[0]);
    m->orientation_x = f(quat, s.quat_wxyz[1]);
    m->orientation_y = f(quat, s.quat_wxyz[2]);
    m->orientation_z = f(quat, s.quat_wxyz[3]);
    const bool foot = s.valid & can::kGroupFoot;
    for (size_t i = 0; i < 4; ++i) {
        m->foot_contact[i] = foot && s.foot_contact[i];
        m->foot_force_raw[i] = foot ? int16_t(s.foot_force_raw[i]) : int16_t(-1);
    }
    const bool oxy = s.valid & can::kGroupOdomXy, ozy = s.valid & can::kGroupOdomZYaw;
    m->odom_position[0] = oxy ? s.odom_x : kNaN;
    m->odom_position[1] = oxy ? s.odom_y : kNaN;
    m->odom_position[2] = ozy ? s.odom_z : kNaN;
    m->odom_yaw = f(ozy, s.odom_yaw);
    const bool sts = s.valid & can::kGroupStatus;
    m->mode = sts ? s.mode : -1;
    m->gait = sts ? s.gait : -1;
    m->battery_soc_percent = sts ? s.battery_soc : -1;
    m->imu_temperature_degc = sts ? s.imu_temperature_c : -128;
    m->udp_rx_lost = sts ? s.udp_rx_lost : -1;
    m->bridge_state = sts ? s.bridge_state : -1;
    const can::Go1DecoderStats& d = item.stats;
    m->frames_received = int64_t(d.frames - d.foreign_id);
    m->frames_unknown_id = int64_t(d.foreign_id);
    m->e2e_crc_errors = int64_t(d.crc);
    m->e2e_counter_lost = int64_t(d.counter_lost);
    m->e2e_counter_repeats = int64_t(d.counter_repeat);
    m->e2e_counter_resyncs = int64_t(d.counter_resync);
    m->e2e_timeouts = int64_t(d.timeout);
}

LatencyStages LatencyStages::From(const ScanTimes& t, int64_t published_ns) {
    const std::array<int64_t, kStages + 1> at = {
        t.last_packet, t.ingested, t.queued, t.started, t.odometry_done, t.handed, published_ns};
    LatencyStages s;
    for (size_t i = 0; i < kStages; ++i) s.us[i] = int32_t((at[i + 1] - at[i]) / 1000);
    s.us[kStages] = int32_t(t.odometry_cpu_ns / 1000);
    return s;
}

PublishPacer::PublishPacer(double bytes_per_s, double messages_per_s, double burst_bytes)
    : rate_(bytes_per_s * 1e-9),
      min_cost_(bytes_per_s / messages_per_s),
      burst_(burst_bytes),
      tokens_(burst_bytes) {}

int64_t PublishPacer::Take(int64_t bytes, int64_t now_ns) {
    if (last_ns_ >= 0) tokens_ = std::min(burst_, tokens_ + rate_ * double(now_ns - last_ns_));
    last_ns_ = now_ns;
    int64_t slept = 0;
    if (tokens_ < 0) {
        slept = int64_t(std::ceil(-tokens_ / rate_));
        std::this_thread::sleep_for(std::chrono::nanoseconds(slept));
        const int64_t woke = runtime::MonotonicNs();
        tokens_ = std::min(burst_, tokens_ + rate_ * double(woke - last_ns_));
        last_ns_ = woke;
    }
    tokens_ -= std::max(double(bytes), min_cost_);
    return slept;
}

LcmPublisher::LcmPublisher(const std::string& url, const keyframes::KeyframeConfig& keyframes,
                           LcmQueues queues, const LcmOutputConfig& output)
    : lcm_(std::make_unique<lcm::LCM>(url)),
      keyframes_(keyframes),
      q_(queues),
      localizer_(output.localizer),
      T_base_lidar_(output.T_base_lidar) {
    // A burst of 256 kB: small messages pass at once, a keyframe waits for a full bucket.
    if (output.pace_bytes_per_s > 0) {
        pacer_.emplace(output.pace_bytes_per_s, output.pace_messages_per_s, 256.0 * 1024);
    }
    if (!output.log_path.empty()) {
        log_ = std::make_unique<lcm::LogFile>(output.log_path, "w");
        if (!log_->good()) {
            throw common::FileError(common::StatusCode::kIoError, output.log_path, 0,
                                    "cannot be created as an LCM log");
        }
        log_buffer_.reserve(1 << 20);
    }
    if (!lcm_->good()) {
        throw common::Error(common::StatusCode::kUnavailable,
                            "LCM " + url +
                                ": cannot open (UDP multicast needs a route: "
                                "toolchain/setup-multicast.sh, or set lcm.url)");
    }
    counters_.Store(c_);
}

LcmPublisher::~LcmPublisher() = default;

// The message as LCM's own log event (what lcm-logger writes of what it receives). Host time;
// a write that fails is counted with the publish failures.
template <typename Msg>
void LcmPublisher::Log(const char* channel, const Msg& msg, int size) {
    log_buffer_.resize(size_t(size));
    if (msg.encode(log_buffer_.data(), 0, size) != size) {
        ++c_.failures;
        return;
    }
    lcm::LogEvent event{};
    event.timestamp = runtime::RealtimeNs() / 1000;
    event.channel = channel;
    event.datalen = size;
    event.data = log_buffer_.data();
    if (log_->writeEvent(&event) == 0) {
        ++c_.logged;
    } else {
        ++c_.failures;
    }
}

template <typename Msg>
void LcmPublisher::Publish(const char* channel, const Msg& msg) {
    const int size = msg.getEncodedSize();
    if (pacer_) c_.paced_ns += pacer_->Take(size, runtime::MonotonicNs());
    if (log_) Log(channel, msg, size);
    if (lcm_->publish(channel, &msg) == 0) {
        ++c_.published;
    } else {
        ++c_.failures;
    }
}

void LcmPublisher::Run(runtime::ThreadStats& stats, const std::atomic<bool>& producers_done) {
    bimslam::odometry_t odometry;
    bimslam::keyframe_t keyframe;
    bimslam::imu_sample_t imu;
    bimslam::go1_state_t go1;
    bimslam::bim_pose_t bim_pose;
    for (;;) {
        stats.Beat();
        const uint32_t seen = q_.wakeup.Sequence();
        const int64_t t0 = runtime::MonotonicNs();
        bool worked = false;
        while (OdometryItem* o = q_.odometry.Front()) {
            ToMessage(*o, runtime::RealtimeNs(), &odometry);
            Publish(kOdometryChannel, odometry);
            const int64_t published = runtime::MonotonicNs();
            latency_.Add(published - o->times.last_packet);
            const LatencyStages stages = LatencyStages::From(o->times, published);
            for (size_t i = 0; i < LatencyStages::kCount; ++i) {
                stages_[i].Add(int64_t(stages.us[i]) * 1000);
            }
            if (o->reset) ++segment_;
            if (localizer_ != nullptr) {
                ToMessage(localizer_->latest(), localizer_->map(), *o, segment_, T_base_lidar_,
                          runtime::RealtimeNs(), &bim_pose);
                Publish(kBimPoseChannel, bim_pose);
                ++c_.bim_pose;
            }
            q_.odometry.Pop();
            ++c_.odometry;
            worked = true;
        }
        while (OusterImuItem* i = q_.imu.Front()) {
            ToMessage(*i, runtime::RealtimeNs(), &imu);
            Publish(kImuChannel, imu);
            q_.imu.Pop();
            ++c_.imu;
            worked = true;
        }
        while (Go1Item* g = q_.go1.Front()) {
            ToMessage(*g, runtime::RealtimeNs(), &go1);
            Publish(kGo1StateChannel, go1);
            q_.go1.Pop();
            ++c_.go1;
            worked = true;
        }
        while (bimslam::rig_health_t* h = q_.health.Front()) {
            h->publish_time_ns = runtime::RealtimeNs();
            Publish(kRigHealthChannel, *h);
            q_.health.Pop();
            ++c_.health;
            worked = true;
        }
        while (bimslam::ouster_stats_t* s = q_.ouster_stats.Front()) {
            s->publish_time_ns = runtime::RealtimeNs();
            Publish(kOusterStatsChannel, *s);
            q_.ouster_stats.Pop();
            ++c_.ouster_stats;
            worked = true;
        }
        // Keyframes last: the largest messages, one per turn, so that a burst of them does not
        // hold up the next odometry message.
        if (KeyframeItem* k = q_.keyframes.Front()) {
            ToMessage(*k, keyframes_, runtime::RealtimeNs(), &keyframe);
            Publish(kKeyframeChannel, keyframe);
            q_.keyframes.Pop();
            ++c_.keyframes;
            worked = true;
        }
        if (worked) stats.Cycle(runtime::MonotonicNs() - t0, 0);
        counters_.Store(c_);
        if (!worked && producers_done.load(std::memory_order_acquire)) break;
        if (!worked) q_.wakeup.Wait(seen, 100'000'000);
    }
    counters_.Store(c_);
}

}  // namespace bimslam::rig
