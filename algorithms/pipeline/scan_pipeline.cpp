// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/pipeline/scan_pipeline.hpp"

#include <algorithm>
#include <limits>

#include "algorithms/common/status.hpp"
#include "algorithms/scancontext/session_descriptor.hpp"

namespace bimslam::pipeline {

void ScanPipelineConfig::Validate() const {
    odometry.Validate();
    keyframes.Validate();
    common::Require(pending_capacity >= 16 && pending_capacity <= (1u << 20), "ScanPipelineConfig",
                    "pending_capacity", double(pending_capacity), "must be in [16, 1048576]");
    common::Require(clock_jump_back_s > 0, "ScanPipelineConfig", "clock_jump_back_s",
                    clock_jump_back_s, "must be positive");
    common::Require(clock_jump_forward_s > 0.2, "ScanPipelineConfig", "clock_jump_forward_s",
                    clock_jump_forward_s, "must be above 0.2 s (two scan periods)");
}

void FrameToScan(const ouster::LidarFrame& frame, int64_t emitted_arrival_ns, uint64_t imu_before,
                 ScanInput* out) {
    ouster::ToPointCloud(frame, &out->cloud);
    out->complete = frame.complete;
    out->frame_id = frame.frame_id;
    out->last_column_ns = -1;
    for (int v = frame.w - 1; v >= 0; --v) {  // the packet stamp of the last valid column
        if (frame.ColumnValid(v)) {
            out->last_column_ns = static_cast<int64_t>(frame.timestamp[v]);
            break;
        }
    }
    out->last_arrival_ns = frame.last_arrival_ns;
    out->emitted_arrival_ns = emitted_arrival_ns;
    out->imu_before = imu_before;
}

odometry::ImuMeasurement ImuFromOuster(const ouster::ImuSample& s) {
    odometry::ImuMeasurement m;
    m.t_ns = static_cast<int64_t>(s.gyro_time_ns);
    m.gyro = s.gyro;
    m.accel = s.accel;
    return m;
}

BodyInput BodyFromGo1(const can::Go1Sample& s) {
    BodyInput b;
    b.received_ns = s.host_time_ns;
    b.measured_ns = s.host_time_ns - int64_t(s.sample_age_us) * 1000;
    b.sample.v_xy = {s.vx, s.vy};
    b.sample.yaw_rate = s.yaw_rate;
    b.sample.velocity_valid = b.sample.yaw_rate_valid = (s.valid & can::kGroupBodyVel) != 0;
    if (s.valid & can::kGroupQuat) {
        b.sample.attitude =
            Eigen::Quaterniond(s.quat_wxyz[0], s.quat_wxyz[1], s.quat_wxyz[2], s.quat_wxyz[3]);
    }
    return b;
}

ScanPipeline::ScanPipeline(const ScanPipelineConfig& config) : config_(config) {
    config_.Validate();
    imu_.resize(config_.pending_capacity);
    body_.resize(config_.pending_capacity);
    Restart();
}

void ScanPipeline::Restart() {
    // Set-up, or a clock jump (rare: the one place after start-up that allocates).
    odometry_.emplace(config_.odometry);
    selector_.emplace(config_.keyframes);
    offset_known_ = false;
    offset_ns_ = 0;
    have_last_stamp_ = false;
}

void ScanPipeline::AddImu(const odometry::ImuMeasurement& m) {
    if (imu_count_ == imu_.size()) {  // full: the oldest goes
        imu_head_ = (imu_head_ + 1) % imu_.size();
        --imu_count_;
        ++imu_first_seq_;
        ++stats_.pending_dropped;
    }
    imu_[(imu_head_ + imu_count_) % imu_.size()] = m;
    ++imu_count_;
    ++imu_added_;
}

void ScanPipeline::AddBody(const BodyInput& b) {
    if (!config_.odometry.use_body_motion) return;
    if (body_count_ > 0) {
        // Same order as the old join: a sample not after the last one added is ignored.
        const PendingBody& last = body_[(body_head_ + body_count_ - 1) % body_.size()];
        if (b.measured_ns <= last.measured_ns) return;
    }
    if (body_count_ == body_.size()) {
        body_head_ = (body_head_ + 1) % body_.size();
        --body_count_;
        ++stats_.pending_dropped;
    }
    body_[(body_head_ + body_count_) % body_.size()] = {b.received_ns, b.measured_ns, b.sample};
    ++body_count_;
}

const ScanOutput& ScanPipeline::Process(const ScanInput& scan) {
    const int64_t stamp = scan.cloud.stamp.ns;
    out_ = ScanOutput{};
    out_.scan_index = stats_.scans;
    out_.stamp_ns = stamp;
    out_.complete = scan.complete;
    // A sensor clock that jumps (a restart starts it again near 0; a time source steps) starts
    // the odometry again: its map, velocity and samples belong to another time line.
    if (have_last_stamp_) {
        const int64_t step = stamp - last_stamp_ns_;
        if (step < -int64_t(config_.clock_jump_back_s * 1e9) ||
            step > int64_t(config_.clock_jump_forward_s * 1e9)) {
            ++stats_.clock_jumps;
            out_.clock_jump = true;
            Restart();
        }
    }
    have_last_stamp_ = true;
    last_stamp_ns_ = stamp;

    if (scan.last_column_ns >= 0 && scan.last_arrival_ns != 0) {
        const int64_t o = scan.last_arrival_ns - scan.last_column_ns;
        if (!offset_known_ || o < offset_ns_) offset_ns_ = o;
        offset_known_ = true;
    }
    // The Ouster IMU samples that arrived before this scan was emitted.
    while (imu_count_ > 0 && imu_first_seq_ < scan.imu_before) {
        if (config_.odometry.use_imu) {
            odometry_->AddImu(imu_[imu_head_]);
            ++stats_.imu_samples;
        }
        imu_head_ = (imu_head_ + 1) % imu_.size();
        --imu_count_;
        ++imu_first_seq_;
    }
    // The Go1 samples received by then, moved to the sensor clock.
    if (config_.odometry.use_body_motion && offset_known_) {
        while (body_count_ > 0 && body_[body_head_].received_ns <= scan.emitted_arrival_ns) {
            odometry::BodyMotionSample s = body_[body_head_].sample;
            s.t_ns = body_[body_head_].measured_ns - offset_ns_;
            odometry_->AddBodyMotion(s);
            ++stats_.body_samples;
            body_head_ = (body_head_ + 1) % body_.size();
            --body_count_;
        }
    }
    const odometry::OdometryResult& r = odometry_->Process(scan.cloud);
    out_.odometry = &r;
    ++stats_.scans;
    stats_.incomplete_scans += scan.complete ? 0 : 1;
    stats_.over_budget += (r.flags & odometry::kOverBudget) ? 1 : 0;
    stats_.degenerate += (r.flags & odometry::kDegenerate) ? 1 : 0;
    stats_.failed += (r.flags & (odometry::kRegistrationFailed | odometry::kCheckFailed)) ? 1 : 0;
    stats_.check_failed += (r.flags & odometry::kCheckFailed) ? 1 : 0;
    stats_.not_converged += (r.flags & odometry::kNotConverged) ? 1 : 0;
    stats_.contradicted_gyro += (r.flags & odometry::kContradictsGyro) ? 1 : 0;
    stats_.contradicted_legs += (r.flags & odometry::kContradictsLegs) ? 1 : 0;
    if (stats_.scans > 1 && !out_.clock_jump) {
        stats_.distance_m += (r.T_odom_lidar.translation() - last_position_).norm();
    }
    last_position_ = r.T_odom_lidar.translation();
    if (selector_->Add(r, odometry_->deskewed())) {
        out_.keyframe = true;
        out_.keyframe_index = selector_->count() - 1;
        out_.keyframe_data = &selector_->keyframe();
        out_.edge = selector_->edge() ? &*selector_->edge() : nullptr;
        ++stats_.keyframes;
    }
    stats_.host_minus_sensor_ns = offset_known_ ? offset_ns_ : 0;
    stats_.offset_known = offset_known_;
    return out_;
}

io::SessionManifest MakeSessionManifest(const ouster::SensorInfo& info,
                                        const std::string& metadata_file,
                                        const keyframes::KeyframeConfig& keyframes) {
    io::SessionManifest manifest;
    manifest.source = "rig";
    manifest.world_frame = "odom";
    manifest.sensor = {info.prod_line.empty() ? "OS-1-32" : info.prod_line,
                       info.format.pixels_per_column, info.format.columns_per_frame, metadata_file};
    manifest.keyframe = {keyframes.distance_m, keyframes.angle_deg};
    manifest.descriptor = scancontext::SessionDescriptor(keyframes.descriptor);
    return manifest;
}

void WriteScan(const ScanOutput& out, io::SessionWriter& writer) {
    writer.AddScanPose(io::StampedPose::FromIsometry(out.stamp_ns, out.odometry->T_odom_lidar));
    if (out.keyframe) {
        writer.AddKeyframe(*out.keyframe_data);
        if (out.edge != nullptr) writer.AddEdge(*out.edge);
    }
}

}  // namespace bimslam::pipeline
