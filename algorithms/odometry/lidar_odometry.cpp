// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/odometry/lidar_odometry.hpp"

#include <algorithm>
#include <cmath>
#include <type_traits>

#include "algorithms/common/status.hpp"

namespace bimslam::odometry {
using common::Require;
namespace {

double Ms(LidarOdometry::Clock::duration d) {
    return std::chrono::duration<double, std::milli>(d).count();
}

}  // namespace

std::string BudgetCutText(uint32_t steps) {
    std::string s;
    const auto add = [&](uint32_t bit, const char* text) {
        if (!(steps & bit)) return;
        if (!s.empty()) s += ", ";
        s += text;
    };
    add(kCutRegistration, "registration");
    add(kCutGyroGate, "gyro gate");
    add(kCutHeadings, "other headings");
    add(kCutStartRefinement, "start refinement");
    add(kCutDeskewRound, "deskew round");
    return s;
}

void LidarOdometryConfig::Validate() const {
    const char* c = "LidarOdometryConfig";
    preprocess.Validate();
    map.Validate();
    if (edge_features) {
        edges.Validate();
        edge_map.Validate();
        Require(edge_map.fit_lines, c, "edge_map.fit_lines", 0, "must be true");
    }
    registration.Validate();
    check.Validate();
    body_prior.Validate();
    Require(budget_ms > 0 && budget_ms <= 10000, c, "budget_ms", budget_ms,
            "must be in (0, 10000]");
    Require(map_update_share >= 0 && map_update_share < 1, c, "map_update_share", map_update_share,
            "must be in [0, 1)");
    Require(common::IsValidRigid(T_base_lidar, 1e-6), c, "T_base_lidar", 0,
            "must be a rigid transform");
    Require(imu_capacity >= 16, c, "imu_capacity", double(imu_capacity), "must be >= 16");
    Require(max_imu_gap_s > 0 && max_imu_gap_s <= 1, c, "max_imu_gap_s", max_imu_gap_s,
            "must be in (0, 1]");
    Require(gravity_window_s > 0 && gravity_window_s <= 10, c, "gravity_window_s", gravity_window_s,
            "must be in (0, 10]");
    imu_height_filter.Validate();
    imu_tilt_filter.Validate();
    Require(rest_accel_sigma > 0, c, "rest_accel_sigma", rest_accel_sigma, "must be > 0");
    Require(rest_gyro > 0, c, "rest_gyro", rest_gyro, "must be > 0");
    Require(height_seen_share > 0 && height_seen_share <= 1, c, "height_seen_share",
            height_seen_share, "must be in (0, 1]");
    Require(height_ambiguous_sigma > 0, c, "height_ambiguous_sigma", height_ambiguous_sigma,
            "must be > 0");
    Require(vertical_deskew_share >= 0 && vertical_deskew_share <= 1, c, "vertical_deskew_share",
            vertical_deskew_share, "must be in [0, 1]");

    Require(constant_velocity_sigma.allFinite() && (constant_velocity_sigma.array() > 0).all(), c,
            "constant_velocity_sigma", constant_velocity_sigma.minCoeff(), "must all be > 0");
    Require(imu_rotation_sigma > 0, c, "imu_rotation_sigma", imu_rotation_sigma, "must be > 0");
    Require(imu_rotation_gate >= 0, c, "imu_rotation_gate", imu_rotation_gate, "must be >= 0");
    Require(body_translation_gate >= 0, c, "body_translation_gate", body_translation_gate,
            "must be >= 0");
    Require(redeskew_threshold > 0, c, "redeskew_threshold", redeskew_threshold, "must be > 0");
    Require(gyro_redeskew_threshold > 0, c, "gyro_redeskew_threshold", gyro_redeskew_threshold,
            "must be > 0");
    Require(max_redeskew_move >= 0, c, "max_redeskew_move", max_redeskew_move, "must be >= 0");
    Require(max_deskew_rounds >= 0 && max_deskew_rounds <= 5, c, "max_deskew_rounds",
            max_deskew_rounds, "must be in [0, 5]");
    Require(deskew_step > 0 && deskew_step <= 1, c, "deskew_step", deskew_step,
            "must be in (0, 1]");
    Require(correction_sigma.allFinite() && (correction_sigma.array() >= 0).all(), c,
            "correction_sigma", correction_sigma.minCoeff(), "must all be >= 0");
    Require(imu_correction_sigma > 0, c, "imu_correction_sigma", imu_correction_sigma,
            "must be > 0");
    Require(correction_flag_m > 0, c, "correction_flag_m", correction_flag_m, "must be > 0");
    Require(min_correspondence_distance > 0 &&
                min_correspondence_distance <= max_correspondence_distance,
            c, "min_correspondence_distance", min_correspondence_distance,
            "must be in (0, max_correspondence_distance]");
    Require(max_correspondence_distance <= 10, c, "max_correspondence_distance",
            max_correspondence_distance, "must be <= 10 m");
    Require(initial_correspondence_distance >= min_correspondence_distance &&
                initial_correspondence_distance <= max_correspondence_distance,
            c, "initial_correspondence_distance", initial_correspondence_distance,
            "must be in [min_correspondence_distance, max_correspondence_distance]");
    Require(model_error_scans >= 1, c, "model_error_scans", model_error_scans, "must be >= 1");
    Require(start_refinements >= 0 && start_refinements <= 5, c, "start_refinements",
            start_refinements, "must be in [0, 5]");
    Require(map_extent_factor > 0, c, "map_extent_factor", map_extent_factor, "must be > 0");
    Require(min_map_radius > 0 && min_map_radius <= map.max_distance, c, "min_map_radius",
            min_map_radius, "must be in (0, map.max_distance]");
    Require(self_box_base_min.allFinite() && self_box_base_max.allFinite(), c, "self_box_base", 0,
            "must be finite");
    Require(velocity_window >= 1 && velocity_window <= 50, c, "velocity_window", velocity_window,
            "must be in [1, 50]");
}

namespace {
// The preprocessing configuration with the self-filter box moved into the lidar frame: the
// axis-aligned box around the base-frame box's corners seen from the lidar.
PreprocessConfig WithSelfBox(const LidarOdometryConfig& c) {
    PreprocessConfig p = c.preprocess;
    if (!c.self_box_in_base) return p;
    const Eigen::Isometry3d T_lidar_base = c.T_base_lidar.inverse();
    Eigen::AlignedBox3d box;
    for (int k = 0; k < 8; ++k) {
        const Eigen::Vector3d corner((k & 1) ? c.self_box_base_max.x() : c.self_box_base_min.x(),
                                     (k & 2) ? c.self_box_base_max.y() : c.self_box_base_min.y(),
                                     (k & 4) ? c.self_box_base_max.z() : c.self_box_base_min.z());
        box.extend(T_lidar_base * corner);
    }
    p.self_box_min = box.min();
    p.self_box_max = box.max();
    return p;
}
}  // namespace

LidarOdometry::LidarOdometry(const LidarOdometryConfig& config)
    : config_(config),
      preprocessor_((config.Validate(), WithSelfBox(config))),
      map_(config.map),
      registration_(config.registration,
                    config.preprocess.max_registration_points +
                        (config.edge_features ? 2 * config.edges.max_edges : 0)),
      body_prior_(config.body_prior),
      imu_height_(config.imu_height_filter),
      gravity_tilt_(config.imu_tilt_filter) {
    config_.Validate();
    if (config_.edge_features) {
        edge_extractor_.emplace(config_.edges, config_.preprocess.max_points);
        edge_map_.emplace(config_.edge_map);
    }
    imu_.resize(config_.imu_capacity);
    world_points_.reserve(config_.preprocess.max_points);
    past_.resize(size_t(config_.velocity_window) + 1);
    first_scan_.Reserve(config_.preprocess.max_points);
    first_scan_.intensity.reserve(config_.preprocess.max_points);
    first_scan_.ring.reserve(config_.preprocess.max_points);
    first_scan_.time_offset_ns.reserve(config_.preprocess.max_points);
}

common::Vector6d LidarOdometry::CorrectionSigma(bool gyro) const {
    common::Vector6d s = config_.correction_sigma;
    if (gyro && (s.array() > 0).all()) s.tail<3>().setConstant(config_.imu_correction_sigma);
    return s;
}

double LidarOdometry::Duration(const common::PointCloud& scan) {
    uint32_t max_offset = 0;
    for (const uint32_t t : scan.time_offset_ns) max_offset = std::max(max_offset, t);
    return std::max(1e-3, max_offset * 1e-9);
}

void LidarOdometry::AddImu(const ImuMeasurement& imu) {
    if (!imu.gyro.allFinite() || !imu.accel.allFinite() ||
        (imu_count_ > 0 && imu.t_ns <= Imu(imu_count_ - 1).t_ns)) {
        ++dropped_inputs_;
        return;
    }
    if (imu_count_ == imu_.size()) {
        imu_head_ = (imu_head_ + 1) % imu_.size();
        --imu_count_;
    }
    imu_[(imu_head_ + imu_count_) % imu_.size()] = imu;
    ++imu_count_;
}

void LidarOdometry::AddBodyMotion(const BodyMotionSample& sample) {
    if (!body_prior_.Add(sample).ok()) ++dropped_inputs_;
}

template <typename Piece>
bool LidarOdometry::ForImuPieces(int64_t t0, int64_t t1, Piece&& piece) const {
    if (imu_count_ < 2 || t1 < t0) return false;
    const int64_t gap = static_cast<int64_t>(config_.max_imu_gap_s * 1e9);
    if (Imu(0).t_ns > t0 + gap || Imu(imu_count_ - 1).t_ns < t1 - gap) return false;
    size_t lo = 0, hi = imu_count_ - 1;  // the last sample at or before t0 (binary search)
    while (lo < hi) {
        const size_t mid = (lo + hi + 1) / 2;
        if (Imu(mid).t_ns <= t0)
            lo = mid;
        else
            hi = mid - 1;
    }
    // The gaps first, so that nothing is called on an interval that is not covered.
    size_t last = lo;
    for (; last + 1 < imu_count_ && Imu(last).t_ns < t1; ++last) {
        const int64_t a = std::max(t0, last == 0 ? t0 : Imu(last).t_ns);
        const int64_t b = std::min(t1, Imu(last + 1).t_ns);
        if (Imu(last + 1).t_ns - Imu(last).t_ns > gap && b > a) return false;
    }
    for (size_t i = lo; i < imu_count_; ++i) {
        const int64_t a = std::max(t0, i == 0 ? t0 : Imu(i).t_ns);
        const int64_t b = std::min(t1, i + 1 < imu_count_ ? Imu(i + 1).t_ns : t1);
        if (b > a) piece(Imu(i), double(b - a) * 1e-9);
        if (b >= t1) break;
    }
    return true;
}

bool LidarOdometry::IntegrateGyro(int64_t t0, int64_t t1, Eigen::Quaterniond* q) const {
    // The gyro held piecewise constant from each sample to the next (the last one beyond it),
    // integrated over the overlap of each piece with [t0, t1].
    *q = Eigen::Quaterniond::Identity();
    Eigen::Quaterniond acc = Eigen::Quaterniond::Identity();
    const bool covered = ForImuPieces(t0, t1, [&](const ImuMeasurement& m, double dt) {
        acc = acc * Eigen::Quaterniond(common::ExpSO3(m.gyro * dt));
    });
    if (!covered) return false;
    *q = acc.normalized();
    return true;
}

void LidarOdometry::StartImuHeight() {
    // Gravity's direction: the accelerometers' mean over the gravity_window_s before this scan
    // (a person's steps put +-2.5 m/s^2 on it at 2 Hz: a shorter mean was 20 % short), in the
    // odometry frame (this scan's pose rotates it there). Still over the window (the specific
    // force's spread and the gyro's largest rate under rest_accel_sigma and rest_gyro), the rig
    // is at rest: its vertical velocity is known, and the vertical bias is the mean's size less
    // gravity.
    const int64_t t1 = work_.stamp;
    const int64_t t0 = t1 - static_cast<int64_t>(config_.gravity_window_s * 1e9);
    if (imu_count_ == 0 || Imu(0).t_ns > t0) return;  // not yet a whole window
    Eigen::Vector3d sum = Eigen::Vector3d::Zero(), sum_sq = Eigen::Vector3d::Zero();
    double max_rate = 0;
    int n = 0;
    for (size_t i = 0; i < imu_count_; ++i) {
        if (Imu(i).t_ns < t0 || Imu(i).t_ns > t1) continue;
        sum += Imu(i).accel;
        sum_sq += Imu(i).accel.cwiseAbs2();
        max_rate = std::max(max_rate, Imu(i).gyro.norm());
        ++n;
    }
    if (n < 2 || !(sum.norm() > 0)) return;
    const Eigen::Vector3d mean = sum / n;
    const double spread = std::sqrt(std::max(0.0, (sum_sq / n - mean.cwiseAbs2()).sum()));
    const bool at_rest = spread < config_.rest_accel_sigma && max_rate < config_.rest_gyro;
    const Eigen::Vector3d up = (work_.T.linear() * mean).normalized();
    imu_height_.Reset(up.dot(work_.T.translation()), up, at_rest, mean.norm() - kStandardGravity);
    if (config_.imu_tilt) gravity_tilt_.Reset(up, work_.T.linear(), at_rest);
}

template <typename Sample>
bool LidarOdometry::ForImuRotations(int64_t t0, int64_t t1, const Eigen::Matrix3d& R0,
                                    Eigen::Quaterniond* q, Sample&& sample) const {
    // Each sample at the lidar's rotation halfway through its piece.
    return ForImuPieces(t0, t1, [&](const ImuMeasurement& m, double dt) {
        const Eigen::Quaterniond half = *q * Eigen::Quaterniond(common::ExpSO3(m.gyro * (dt / 2)));
        sample(R0 * half.toRotationMatrix(), m, dt);
        *q = *q * Eigen::Quaterniond(common::ExpSO3(m.gyro * dt));
    });
}

bool LidarOdometry::PropagateHeight(ImuHeight* f, int64_t t0, int64_t t1, const Eigen::Matrix3d& R0,
                                    Eigen::Quaterniond* q) const {
    return ForImuRotations(t0, t1, R0, q,
                           [&](const Eigen::Matrix3d& R, const ImuMeasurement& m, double dt) {
                               f->Propagate(R, m.accel, dt);
                           });
}

bool LidarOdometry::PropagateImuHeight(int64_t t0, int64_t t1, const Eigen::Matrix3d& R0) {
    Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
    const bool covered = PropagateHeight(&imu_height_, t0, t1, R0, &q);
    if (!covered) imu_height_ = ImuHeight(config_.imu_height_filter);
    return covered;
}

void LidarOdometry::PredictHeight() {
    // After a scan that did not see the height, the predicted motion's vertical part is the
    // accelerometers' (the horizontal keeps the constant velocity's or the legs': imu_height.hpp
    // says why).
    ScanWork& w = work_;
    OdometryResult& r = result_;
    if (!config_.use_imu || !config_.imu_height || !imu_height_.initialized()) return;
    const bool ready = imu_height_.ready();
    const double h0 = imu_height_.height();
    if (!PropagateImuHeight(last_stamp_ns_, w.stamp, w.T_prev.linear())) return;
    // Once it predicts, it goes on until a scan sees the height again, ready or not: the
    // constant velocity's vertical part would only carry on the filter's last velocity.
    const bool used_last = last_height_from_imu_;
    last_height_from_imu_ = false;
    if (!(ready || used_last) || last_height_seen_ || !(r.flags & kImuUsed)) return;
    const Eigen::Vector3d& up = imu_height_.up();
    const Eigen::Vector3d d_cv = w.T_prev.linear() * w.delta.translation();  // odometry frame
    const double dh = imu_height_.height() - h0;
    w.delta.translation() = w.T_prev.linear().transpose() * (d_cv + up * (dh - up.dot(d_cv)));
    r.flags |= kImuHeight;
    last_height_from_imu_ = true;
}

ScanMotion LidarOdometry::MotionFor(const common::Vector6d& twist, double duration, int64_t stamp,
                                    bool* used_gyro) const {
    ScanMotion motion;
    motion.SetConstantVelocity(twist, duration);
    if (used_gyro) *used_gyro = false;
    if (config_.use_imu) {
        std::array<Eigen::Quaterniond, ScanMotion::kKnots> knots;
        for (int k = 0; k < ScanMotion::kKnots; ++k) {
            if (!IntegrateGyro(stamp, stamp + static_cast<int64_t>(motion.KnotTime(k) * 1e9),
                               &knots[size_t(k)])) {
                return motion;
            }
        }
        motion.SetRotations(knots);
        if (used_gyro) *used_gyro = true;
    }
    return motion;
}

void LidarOdometry::VerticalFromImu(const Eigen::Matrix3d& R_start, int64_t stamp,
                                    ScanMotion* motion) const {
    if (!config_.use_imu || !config_.imu_height || !config_.imu_vertical_deskew ||
        !imu_height_.initialized() || !imu_height_.ready() ||
        last_height_share_ < config_.vertical_deskew_share) {
        return;
    }
    // The filter stands at the scan's start (PredictHeight carried it there); a copy goes on
    // through the sweep, knot by knot, as PropagateImuHeight moves it between scans.
    ImuHeight f = imu_height_;
    const double h0 = f.height();
    std::array<double, ScanMotion::kKnots> d{};
    Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
    int64_t t0 = stamp;
    for (int k = 1; k < ScanMotion::kKnots; ++k) {
        const int64_t t1 = stamp + static_cast<int64_t>(motion->KnotTime(k) * 1e9);
        if (!PropagateHeight(&f, t0, t1, R_start, &q)) return;
        d[size_t(k)] = f.height() - h0;
        t0 = t1;
    }
    motion->SetTranslationAlong(R_start.transpose() * f.up(), d);
}

const OdometryResult& LidarOdometry::Process(const common::PointCloud& scan) {
    const Clock::time_point start = Clock::now();
    if (initialized_ && scan.stamp.ns <= last_stamp_ns_) {
        result_.flags = kTooFewPoints;
        return result_;
    }
    BeginScan(scan);
    Predict();
    // 2. Preprocessing, deskewed with the predicted velocity (the gyro inside the scan).
    OdometryResult& r = result_;
    ScanWork& w = work_;
    w.duration = Duration(scan);
    const common::Vector6d twist =
        w.dt > 0 ? common::Vector6d(common::LogSE3(w.delta) / w.dt) : common::Vector6d::Zero();
    w.motion = MotionFor(twist, w.duration, w.stamp, &w.gyro);
    if (w.gyro) VerticalFromImu((w.T_prev * w.delta).linear(), w.stamp, &w.motion);
    const Clock::time_point preprocess_start = BudgetClockNow();
    PreprocessScan(scan, w.motion);
    w.preprocess_time = BudgetClockNow() - preprocess_start;
    const Clock::time_point preprocessed = Clock::now();
    r.preprocess_ms = Ms(preprocessed - start);
    // The scene's extent, smoothed over a few scans (the map radius and the threshold use it).
    const double range = std::min(60.0, r.preprocess.range_p90);
    extent_ = extent_ > 0 ? 0.8 * extent_ + 0.2 * range : range;

    // 3. Registration to the local map, from the prediction.
    w.T_pred = w.T_prev * w.delta;
    w.T = w.T_pred;
    r.registration = RegistrationResult{};
    r.covariance = w.sigma.cwiseAbs2().asDiagonal();
    // The adaptive threshold (header of the configuration).
    const std::optional<double> sigma = PredictionSigma();
    r.correspondence_distance = sigma
                                    ? std::clamp(3.0 * *sigma, config_.min_correspondence_distance,
                                                 config_.max_correspondence_distance)
                                    : config_.initial_correspondence_distance;
    if (!initialized_ && TooFewPoints()) {
        // Nothing to start the map with: the odometry starts at the next scan that has points.
        r.flags |= kTooFewPoints;
        r.total_ms = Ms(Clock::now() - start);
        return r;
    }
    if (initialized_) Register();
    if (initialized_) LevelWithGravity();
    if (r.budget_cut != 0) r.flags |= kOverBudget;
    const Clock::time_point registered = Clock::now();
    r.register_ms = Ms(registered - preprocessed);

    UpdateMap();
    if (!initialized_ && config_.start_refinements > 0) first_scan_ = scan;
    UpdateVelocity();
    const Clock::time_point end = Clock::now();
    r.map_ms = Ms(end - registered);
    r.total_ms = Ms(end - start);
    return r;
}

void LidarOdometry::BeginScan(const common::PointCloud& scan) {
    OdometryResult& r = result_;
    ScanWork& w = work_;
    w.scan = &scan;
    w.stamp = scan.stamp.ns;
    w.T_prev = r.T_odom_lidar;
    w.dt = initialized_ ? double(w.stamp - last_stamp_ns_) * 1e-9 : 0.0;
    w.gyro = false;
    w.pin_rotation = false;
    w.registered = false;
    w.cut = false;
    w.align_time = {};
    w.deadline = BudgetClockNow() + std::chrono::duration_cast<Clock::duration>(
                                        std::chrono::duration<double, std::milli>(
                                            config_.budget_ms * (1 - config_.map_update_share)));
    r.flags = 0;
    r.deskew_rounds = 0;
    r.deskew_stop = DeskewStop::kNotTried;
    r.check_reasons = 0;
    r.budget_cut = 0;
    r.stamp_ns = w.stamp;
    ++scans_;
}

void LidarOdometry::Predict() {
    // 1. Prediction of the motion since the previous scan.
    OdometryResult& r = result_;
    ScanWork& w = work_;
    w.delta = Eigen::Isometry3d::Identity();
    Eigen::Isometry3d cv_delta = Eigen::Isometry3d::Identity();
    w.sigma = config_.constant_velocity_sigma;
    if (!initialized_) {
        r.flags |= kFirstScan;
        return;
    }
    w.delta = common::ExpSE3(velocity_ * w.dt);
    cv_delta = w.delta;
    if (config_.use_body_motion) {
        if (const auto rel = body_prior_.Between(last_stamp_ns_, w.stamp)) {
            const Eigen::Isometry3d& B = config_.T_base_lidar;
            w.delta = B.inverse() * rel->T_a_b * B;
            const common::Matrix6d cov = common::Adjoint(B.inverse()) * rel->covariance *
                                         common::Adjoint(B.inverse()).transpose();
            w.sigma = cov.diagonal().cwiseSqrt().cwiseMax(1e-3);
            r.flags |= kBodyPriorUsed;
        }
    }
    Eigen::Quaterniond q;
    if (config_.use_imu && IntegrateGyro(last_stamp_ns_, w.stamp, &q)) {
        w.delta.linear() = q.toRotationMatrix();
        w.sigma.tail<3>().setConstant(config_.imu_rotation_sigma);
        r.flags |= kImuUsed;
    }
    PredictHeight();
    // The legs against the LiDAR's own velocity (body_translation_gate): a foot that slips. The
    // scan is then deskewed and registered from the LiDAR's translation.
    if ((r.flags & kBodyPriorUsed) && (r.flags & kImuUsed) && config_.body_translation_gate > 0 &&
        !last_degenerate_ && past_count_ > size_t(config_.velocity_window) &&
        (w.delta.translation() - cv_delta.translation()).norm() >
            config_.body_translation_gate * w.dt) {
        w.delta.translation() = cv_delta.translation();
        r.flags |= kContradictsLegs;
    }
}

void LidarOdometry::PreprocessScan(const common::PointCloud& cloud, const ScanMotion& motion) {
    result_.preprocess = preprocessor_.Run(cloud, motion);
    ExtractEdges();
}

void LidarOdometry::ExtractEdges() {
    if (edge_extractor_) edges_ = edge_extractor_->Run(preprocessor_.deskewed());
    result_.edge_points = edges_.size();
}

bool LidarOdometry::TooFewPoints() const {
    // Checked again after a second deskew, which can change the count.
    return preprocessor_.registration_points().size() <
           size_t(config_.registration.min_correspondences);
}

bool LidarOdometry::Align(const Eigen::Isometry3d& from, BudgetStep step) {
    OdometryResult& r = result_;
    ScanWork& w = work_;
    w.cut = false;
    if (TooFewPoints()) {
        r.flags |= kTooFewPoints | kRegistrationFailed;
        return false;
    }
    AlignInput in;
    in.points = preprocessor_.registration_points();
    in.alpha = preprocessor_.registration_alpha();
    in.T0 = from;
    in.prior_sigma = w.sigma;
    in.correction_sigma = config_.preprocess.deskew && w.scan->HasTime() ? CorrectionSigma(w.gyro)
                                                                         : common::Vector6d::Zero();
    in.max_correspondence_distance = r.correspondence_distance;
    in.prediction_error = w.start_error;
    in.fix_rotation = w.pin_rotation;
    in.edges = edges_;
    in.edge_map = edge_map_ ? &*edge_map_ : nullptr;
    if (imu_height_.initialized()) {  // what the scan sees of the height (imu_height.hpp)
        in.axis = from.linear().transpose() * imu_height_.up();
        // Predicted from the accelerometers: kept unless the scan sees it.
        if (r.flags & kImuHeight) in.hold_axis_below = config_.height_seen_share;
    }
    const RegistrationResult before = r.registration;
    const Clock::time_point start = BudgetClockNow();
    r.registration = registration_.Align(in, map_, w.deadline);
    w.align_time = BudgetClockNow() - start;
    const RegistrationResult& reg = r.registration;
    if (reg.over_budget) r.budget_cut |= step;
    if (reg.over_budget && reg.iterations == 0) {
        // Stopped before its first iteration: no correspondence was looked for, so there is no
        // evidence to judge (the check read it as no overlap with the map: the demo's walk, scan
        // 860, on a loaded CI machine). The registration before it stands; without one, the
        // prediction does, as when a registration fails.
        w.cut = true;
        if (w.registered) {
            r.registration = before;
        } else {
            r.flags |= kRegistrationFailed;
        }
        return false;
    }
    if (reg.failed) {
        r.flags |= kRegistrationFailed;
        w.registered = false;
        return false;
    }
    w.registered = true;
    w.T = reg.T_map_lidar;
    r.covariance = reg.covariance;
    r.flags &= ~uint32_t(kDegenerate | kNotConverged);
    if (reg.degenerate_directions > 0) r.flags |= kDegenerate;
    if (!reg.converged && !reg.over_budget) r.flags |= kNotConverged;
    return true;
}

void LidarOdometry::Register() {
    // From the prediction; then the gyro's gate, other headings, a start in motion, deskew rounds.
    OdometryResult& r = result_;
    ScanWork& w = work_;
    w.start_error = PredictionSigma().value_or(0.0);
    bool registered_ok = Align(w.T_pred, kCutRegistration);
    if (registered_ok && (r.flags & kImuUsed) && config_.imu_rotation_gate > 0 &&
        common::RotationAngle(common::Between(w.T_pred, w.T)) >
            config_.imu_rotation_gate * config_.imu_rotation_sigma) {
        // The scan turned against the gyro (imu_rotation_gate): measured on the doors' captures,
        // where it did by 0.5-1.8 deg the estimate was wrong by as much (README.md, "Glass,
        // mirrors and moving doors"). Registered again from the prediction with the gyro's
        // rotation kept, the translation only (the later registrations of this scan keep it).
        // Cut before it began: the registration before it stands (budget_cut says so).
        w.pin_rotation = true;
        registered_ok = Align(w.T_pred, kCutGyroGate) || w.cut;
        r.flags |= kContradictsGyro;
    }
    // Large motion with a weak prediction: other headings when this one fails its checks.
    if (registered_ok) registered_ok = TryOtherHeadings();
    if (registered_ok) RefineStart();
    if (registered_ok && !(r.flags & kStartRefined)) DeskewAgain();
    if (!registered_ok) return;
    JudgeScan(w.T_pred, w.T, w.sigma);
    // The keyframe cloud and the map points where the registration put them.
    const common::Vector6d& xi = r.registration.correction;
    if (xi.head<3>().norm() + 10.0 * xi.tail<3>().norm() > config_.correction_flag_m) {
        r.flags |= kMotionCorrected;
    }
    preprocessor_.ApplyCorrection(xi);
    // How far the prediction was off, for the adaptive threshold.
    const double err = AtExtent(common::Between(w.T_pred, w.T));
    const double a = 1.0 / std::min(double(model_error_count_ + 1), config_.model_error_scans);
    model_error_sq_ = (1 - a) * model_error_sq_ + a * err * err;
    ++model_error_count_;
}

std::optional<double> LidarOdometry::PredictionSigma() const {
    if (model_error_count_ < 3) return std::nullopt;
    return std::sqrt(model_error_sq_);
}

double LidarOdometry::AtExtent(const Eigen::Isometry3d& e) const {
    return e.translation().norm() + std::max(extent_, 1.0) * common::RotationAngle(e);
}

void LidarOdometry::RefineStart() {
    // Not when the registration was degenerate: along a weak direction the velocity is the
    // prediction's, not measured, and deskewing the first scan with it again moved a corridor
    // walk 18 cm off where it stays within 5 cm without (LidarOdometry corridor test).
    OdometryResult& r = result_;
    ScanWork& w = work_;
    if (past_count_ != 1 || config_.start_refinements <= 0 || w.dt <= 0 ||
        (r.flags & kDegenerate) || !config_.preprocess.deskew || !w.scan->HasTime() ||
        !first_scan_.HasTime()) {
        return;
    }
    // A start in motion (header, step 3): the first scan was deskewed with no motion, so its
    // smear is in the map. With the velocity from the first two poses, deskew it again,
    // rebuild the map from it and register this scan again.
    const double first_duration = Duration(first_scan_);
    for (int k = 0; k < config_.start_refinements; ++k) {
        if (BudgetClockNow() >= w.deadline) {
            r.budget_cut |= kCutStartRefinement;
            break;
        }
        const common::Vector6d v = common::LogSE3(w.T) / w.dt;  // the first pose is the identity
        map_.Clear();
        if (edge_map_) edge_map_->Clear();
        PreprocessScan(first_scan_, MotionFor(v, first_duration, first_scan_.stamp.ns));
        map_.Insert(preprocessor_.map_points(), Eigen::Vector3f::Zero());
        if (edge_map_) edge_map_->Insert(edges_);
        w.motion = MotionFor(v, w.duration, w.stamp);
        PreprocessScan(*w.scan, w.motion);
        if (!Align(w.T, kCutStartRefinement)) break;
        r.flags |= kStartRefined;
    }
}

void LidarOdometry::DeskewAgain() {
    // The scan was deskewed with a predicted motion; while the estimated one differs by more
    // than redeskew_threshold over the sweep (a start, a stop, a sudden turn without the
    // IMU), the scan is deskewed again with it and registered once more (max_deskew_rounds).
    // A round starts only when its time still fits before the deadline: the last round's, or
    // before the first, the preprocessing's and the last registration's. A round started late
    // ran the scan over budget (11 of 1800 hand-held scans without the IMU, the rounds' whole
    // cost being the LiDAR-only case), and one begun with no time left had its registration
    // stopped before it began. A round that was needed and not made counts as cut.
    OdometryResult& r = result_;
    ScanWork& w = work_;
    const bool correcting = (config_.correction_sigma.array() > 0).all();
    if (correcting || w.dt <= 0 || !config_.preprocess.deskew || !w.scan->HasTime()) return;
    Clock::duration last_round = w.preprocess_time + w.align_time;
    r.deskew_stop = DeskewStop::kRoundsDone;
    for (int round = 0; round < config_.max_deskew_rounds; ++round) {
        const Clock::time_point round_start = BudgetClockNow();
        if (round > 0 && (r.flags & kDegenerate)) {
            r.deskew_stop = DeskewStop::kDegenerate;
            break;
        }
        const ScanMotion estimated = EstimatedMotion();
        const Eigen::Isometry3d diff = common::Between(w.motion.End(), estimated.End());
        const double move = diff.translation().norm() + 10.0 * common::RotationAngle(diff);
        const double threshold = w.gyro && !(r.flags & kDegenerate)
                                     ? config_.gyro_redeskew_threshold
                                     : config_.redeskew_threshold;
        if (move <= threshold) {
            r.deskew_stop = DeskewStop::kHolds;
            break;
        }
        if (round_start + last_round >= w.deadline) {
            r.deskew_stop = DeskewStop::kDeadline;
            r.budget_cut |= kCutDeskewRound;
            break;
        }
        w.motion = estimated;
        if (w.gyro && move <= config_.max_redeskew_move) {
            // The points the filters chose, moved to where the new motion puts them.
            preprocessor_.Redeskew(w.motion);
            ExtractEdges();
        } else {
            PreprocessScan(*w.scan, w.motion);
        }
        // From the registered pose, off by what the new deskew moves the points.
        w.start_error = AtExtent(diff);
        if (!Align(w.T, kCutDeskewRound)) {
            r.deskew_stop = w.cut ? DeskewStop::kDeadline : DeskewStop::kFailed;
            break;
        }
        r.flags |= kDeskewedAgain;
        ++r.deskew_rounds;
        last_round = BudgetClockNow() - round_start;
    }
}

ScanMotion LidarOdometry::EstimatedMotion() const {
    // The motion the pose implies over the sweep, a deskew_step of the way from the one the scan
    // was deskewed with (without the gyro; lidar_odometry.hpp says why).
    const ScanWork& w = work_;
    common::Vector6d twist = common::LogSE3(common::Between(w.T_prev, w.T)) / w.dt;
    if (!w.gyro && config_.deskew_step < 1) {
        const common::Vector6d used = common::LogSE3(w.motion.End()) / w.duration;
        twist = used + config_.deskew_step * (twist - used);
    }
    ScanMotion motion = MotionFor(twist, w.duration, w.stamp);
    if (w.gyro) VerticalFromImu(w.T.linear(), w.stamp, &motion);
    return motion;
}

void LidarOdometry::UpdateMap() {
    // 4. The map update at the estimated pose, and what lies beyond the scene's extent dropped.
    OdometryResult& r = result_;
    const Eigen::Isometry3d& T = work_.T;
    const Eigen::Matrix3f R = T.linear().cast<float>();
    const Eigen::Vector3f t = T.translation().cast<float>();
    r.map_radius = std::clamp(config_.map_extent_factor * extent_, config_.min_map_radius,
                              config_.map.max_distance);
    const auto update = [&](VoxelMap& map, std::span<const Eigen::Vector3f> points) {
        world_points_.resize(points.size());
        for (size_t i = 0; i < points.size(); ++i) world_points_[i] = R * points[i] + t;
        map.Insert(world_points_, t);
        map.Prune(T.translation(), r.map_radius);
    };
    update(map_, preprocessor_.map_points());
    if (edge_map_) update(*edge_map_, edges_);
    r.map_voxels = map_.voxels();
    r.map_points = map_.points();
}

void LidarOdometry::UpdateVelocity() {
    OdometryResult& r = result_;
    const ScanWork& w = work_;
    r.T_prev_lidar = common::Between(w.T_prev, w.T);
    r.T_odom_lidar = w.T;
    // The velocity over the window: the relative motion from the oldest pose kept, expressed as
    // a twist in the current lidar frame.
    past_[past_count_ % past_.size()] = {w.stamp, w.T};
    ++past_count_;
    if (past_count_ >= 2) {
        const size_t n = std::min(past_count_, past_.size());
        const PastPose& oldest = past_[(past_count_ - n) % past_.size()];
        const double span = double(w.stamp - oldest.stamp_ns) * 1e-9;
        if (span > 0) {
            const common::Vector6d xi =
                common::LogSE3(common::Between(w.T, oldest.T_odom_lidar)) / span;
            velocity_ = -xi;  // the motion from the oldest to now, seen from now
        }
    }
    UpdateImuHeight();
    if (config_.use_imu && config_.imu_height && imu_height_.initialized()) {
        result_.height_sigma = std::sqrt(imu_height_.covariance()(0, 0));
    }
    initialized_ = true;
    last_degenerate_ = (r.flags & (kDegenerate | kRegistrationFailed)) != 0;
    last_stamp_ns_ = w.stamp;
}

void LidarOdometry::LevelWithGravity() {
    // The accelerometers since the last scan, turned into the frame by its pose's rotation and
    // the gyro, as the height filter's are (ForImuRotations); at the end of a window the pose
    // levelled by what the filter learnt (gravity_tilt.hpp).
    if (!config_.use_imu || !config_.imu_tilt || !gravity_tilt_.initialized()) return;
    ScanWork& w = work_;
    Eigen::Vector3d Rf_dt = Eigen::Vector3d::Zero();
    Eigen::Matrix3d R_dt = Eigen::Matrix3d::Zero();
    double dt = 0;
    Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
    const bool covered =
        ForImuRotations(last_stamp_ns_, w.stamp, w.T_prev.linear(), &q,
                        [&](const Eigen::Matrix3d& R, const ImuMeasurement& m, double d) {
                            Rf_dt += R * m.accel * d;
                            R_dt += R * d;
                            dt += d;
                        });
    const bool failed = (result_.flags & (kRegistrationFailed | kCheckFailed | kTooFewPoints)) != 0;
    const Eigen::Matrix3d C =
        gravity_tilt_.AddScan(w.stamp, w.T.translation(), Rf_dt, R_dt, dt, covered && !failed);
    w.T.linear() = C * w.T.linear();
}

void LidarOdometry::UpdateImuHeight() {
    // The filter learns the scan's height where the scan saw it: surfaces facing up or down
    // carried height_seen_share of its weights (the registration's own degenerate_ratio counts
    // the walls' noise: in a 2.4 m shaft some scans passed it and reported the guess's height
    // with a 5 mm sigma). A scan that failed (kept the prediction), failed its checks or did not
    // see the height only moves the filter's height to the pose's.
    if (!config_.use_imu || !config_.imu_height) return;
    const OdometryResult& r = result_;
    const ScanWork& w = work_;
    if (!imu_height_.initialized()) {
        if (!(r.flags & kTooFewPoints)) StartImuHeight();
        last_height_seen_ = true;
        return;
    }
    const Eigen::Vector3d up_lidar = w.T.linear().transpose() * imu_height_.up();
    const double h = imu_height_.up().dot(w.T.translation());
    const bool failed = (r.flags & (kRegistrationFailed | kCheckFailed | kTooFewPoints)) != 0;
    const bool seen_before = last_height_seen_;
    last_height_seen_ = !failed && r.registration.axis_share >= config_.height_seen_share;
    last_height_share_ = failed ? 0.0 : r.registration.axis_share;
    if (!last_height_seen_) {
        result_.flags |= kHeightUnseen;
        imu_height_.Hold(h);
        return;
    }
    // Seen again after scans that did not see it, the filter's height this uncertain: the
    // registration settled on the surface nearest its guess (the filter's own start, its
    // velocity unknown, is not this: the scans before saw the height).
    if (!seen_before &&
        std::sqrt(imu_height_.covariance()(0, 0)) > config_.height_ambiguous_sigma) {
        result_.flags |= kHeightAmbiguous;
    }
    imu_height_.Update(h, up_lidar.dot(r.covariance.topLeftCorner<3, 3>() * up_lidar));
}

}  // namespace bimslam::odometry
