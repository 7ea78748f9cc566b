// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/odometry/preprocess.hpp"

#include <algorithm>
#include <cmath>

#include "algorithms/common/status.hpp"
#include "algorithms/common/voxel_hash.hpp"

namespace bimslam::odometry {
using common::Require;
namespace {

constexpr size_t kRangeSamples = 4096;
constexpr size_t kAhead = 16;  // VoxelFilter's prefetch distance in points

size_t NextPowerOfTwo(size_t n) {
    size_t p = 1;
    while (p < n) p <<= 1;
    return p;
}

}  // namespace

void ScanMotion::SetConstantVelocity(const common::Vector6d& xi_per_s, double duration_s) {
    duration_s_ = duration_s;
    for (int k = 0; k < kKnots; ++k) {
        const Eigen::Isometry3d T = common::ExpSE3(xi_per_s * KnotTime(k));
        q_[size_t(k)] = Eigen::Quaterniond(T.linear());
        t_[size_t(k)] = T.translation();
    }
}

void ScanMotion::SetRotations(const std::array<Eigen::Quaterniond, kKnots>& q_start_tau) {
    q_ = q_start_tau;
}

void ScanMotion::SetTranslationAlong(const Eigen::Vector3d& axis,
                                     const std::array<double, kKnots>& d) {
    for (size_t k = 0; k < size_t(kKnots); ++k) t_[k] += (d[k] - axis.dot(t_[k])) * axis;
}

Eigen::Isometry3d ScanMotion::At(double tau_s) const {
    const double x =
        duration_s_ > 0 ? std::clamp(tau_s / duration_s_, 0.0, 1.0) * (kKnots - 1) : 0.0;
    const int k = std::min(static_cast<int>(x), kKnots - 2);
    const double a = x - k;
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = q_[size_t(k)].slerp(a, q_[size_t(k) + 1]).toRotationMatrix();
    T.translation() = (1 - a) * t_[size_t(k)] + a * t_[size_t(k) + 1];
    return T;
}

void PreprocessConfig::Validate() const {
    const char* c = "PreprocessConfig";
    Require(min_range >= 0 && std::isfinite(min_range), c, "min_range", min_range, "must be >= 0");
    Require(max_range > min_range && std::isfinite(max_range), c, "max_range", max_range,
            "must be finite and > min_range");
    Require(self_box_min.allFinite() && self_box_max.allFinite(), c, "self_box", 0,
            "must be finite");
    Require(map_voxel >= 0.01 && map_voxel <= 5, c, "map_voxel", map_voxel,
            "must be in [0.01, 5] m");
    Require(registration_voxel >= map_voxel && registration_voxel <= 5, c, "registration_voxel",
            registration_voxel, "must be in [map_voxel, 5] m");
    Require(max_map_voxel >= map_voxel && max_map_voxel <= 5, c, "max_map_voxel", max_map_voxel,
            "must be in [map_voxel, 5] m");
    Require(max_registration_voxel >= registration_voxel && max_registration_voxel <= 10, c,
            "max_registration_voxel", max_registration_voxel,
            "must be in [registration_voxel, 10] m");
    Require(target_map_points == 0 || target_map_points >= 1000, c, "target_map_points",
            double(target_map_points), "must be 0 (fixed voxels) or >= 1000");
    Require(
        target_registration_points == 0 || (target_registration_points >= 100 &&
                                            target_registration_points <= max_registration_points),
        c, "target_registration_points", double(target_registration_points),
        "must be 0 (fixed voxels) or in [100, max_registration_points]");
    Require(max_registration_points >= 100, c, "max_registration_points",
            double(max_registration_points), "must be >= 100");
    Require(max_points >= 1024, c, "max_points", double(max_points), "must be >= 1024");
}

Preprocessor::Preprocessor(const PreprocessConfig& config) : config_(config) {
    config_.Validate();
    deskewed_.Reserve(config_.max_points);
    deskewed_.intensity.reserve(config_.max_points);
    deskewed_.ring.reserve(config_.max_points);
    deskewed_.time_offset_ns.reserve(config_.max_points);
    alpha_.reserve(config_.max_points);
    map_points_.reserve(config_.max_points);
    map_alpha_.reserve(config_.max_points);
    refilter_points_.reserve(config_.max_points);
    refilter_alpha_.reserve(config_.max_points);
    registration_points_.reserve(config_.max_points);
    registration_alpha_.reserve(config_.max_points);
    poses_.reserve(config_.max_points);
    moves_.reserve(config_.max_points);
    for (auto* v : {&pose_, &map_pose_, &registration_pose_, &refilter_pose_})
        v->reserve(config_.max_points);
    range_sample_.reserve(kRangeSamples);
    const size_t slots = NextPowerOfTwo(2 * config_.max_points);
    table_.assign(slots, common::VoxelHash::kEmpty);
    used_.reserve(config_.max_points);
    ResetVoxels();
}

void Preprocessor::ResetVoxels() {
    map_voxel_ = config_.map_voxel;
    registration_voxel_ = config_.registration_voxel;
}

namespace {
// q -> M q + b for the correction at fraction alpha (CorrectPoint as a matrix: I + A + A^2 / 2,
// A = [alpha phi]x), applied to points in column order (consecutive points share alpha).
void Correct(std::span<Eigen::Vector3f> points, std::span<const float> alpha,
             const Eigen::Vector3f& rho, const Eigen::Vector3f& phi) {
    float last = -1;
    Eigen::Matrix3f M = Eigen::Matrix3f::Identity();
    Eigen::Vector3f b = Eigen::Vector3f::Zero();
    for (size_t i = 0; i < points.size(); ++i) {
        if (alpha[i] != last) {
            last = alpha[i];
            const Eigen::Vector3f a = last * phi;
            Eigen::Matrix3f A;
            A << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
            M = Eigen::Matrix3f::Identity() + A + 0.5f * A * A;
            b = last * rho;
        }
        points[i] = M * points[i] + b;
    }
}
}  // namespace

void Preprocessor::ApplyCorrection(const common::Vector6d& xi) {
    if (xi.isZero()) return;
    const Eigen::Vector3f rho = xi.head<3>().cast<float>(), phi = xi.tail<3>().cast<float>();
    Correct(deskewed_.xyz, alpha_, rho, phi);
    Correct(map_points_, map_alpha_, rho, phi);
}

void Preprocessor::Redeskew(const ScanMotion& motion) {
    if (poses_.empty() || pose_.size() != deskewed_.size()) return;  // Run() did not deskew
    // Each pose's move q -> D q + e, with D = R' R^T and e = t' - D t (R', t': the new motion's
    // T_start_tau at its time); the pose becomes the new one, for another round.
    moves_.clear();
    for (SweepPose& s : poses_) {
        const Eigen::Isometry3d T = motion.At(s.tau_ns * 1e-9);
        const SweepPose now{s.tau_ns, T.linear().cast<float>(), T.translation().cast<float>()};
        const Eigen::Matrix3f D = now.R * s.R.transpose();
        moves_.push_back({s.tau_ns, D, now.t - D * s.t});
        s = now;
    }
    const auto move = [this](std::span<Eigen::Vector3f> points, std::span<const uint32_t> pose) {
        for (size_t i = 0; i < points.size(); ++i) {
            const SweepPose& m = moves_[pose[i]];
            points[i] = m.R * points[i] + m.t;
        }
    };
    move(deskewed_.xyz, pose_);
    move(map_points_, map_pose_);
    move(registration_points_, registration_pose_);
}

double Preprocessor::Adapt(double voxel, size_t count, size_t target, double finest,
                           double coarsest) {
    if (target == 0 || count == 0) return voxel;
    // Damped (the square root of the ratio's square root) so that one odd scan does not swing it.
    const double ratio = std::sqrt(double(count) / double(target));
    return std::clamp(voxel * std::sqrt(ratio), finest, coarsest);
}

void Preprocessor::VoxelFilter(std::span<const Eigen::Vector3f> in, std::span<const float> in_alpha,
                               std::span<const uint32_t> in_pose, std::span<const uint16_t> ring,
                               double voxel, std::vector<Eigen::Vector3f>* out,
                               std::vector<float>* out_alpha, std::vector<uint32_t>* out_pose,
                               size_t* expected) {
    // The table's lookups are cache misses (a mixed hash scatters neighbouring voxels), ~60 % of
    // the filter's time over a full table (2 x max_points slots, 4 MB). So only as many slots are
    // used as the last scan's output needs at a load of at most 1/2 (a 128-beam scan's 20 000 map
    // voxels: 64 k slots, 512 kB); an output that outgrows them starts again on the whole table.
    const size_t all = table_.size();
    size_t slots =
        std::min(all, NextPowerOfTwo(std::max<size_t>(4096, 2 * (*expected + *expected / 4))));
    for (;;) {
        out->clear();
        out_alpha->clear();
        out_pose->clear();
        used_.clear();
        const size_t mask = slots - 1, limit = slots / 2;
        const float inv = static_cast<float>(1.0 / voxel);
        bool full = false;
        // Points come column by column and ring by ring, so neighbours in the scan often share a
        // voxel: the previous point's key (the ring below, same column) and its ring's last key
        // (the column before) are checked before the table. Both are keys already in the table,
        // so skipping on them changes nothing; a ring's entry is one of kRingKeys by its low bits.
        uint64_t previous = common::VoxelHash::kEmpty;
        ring_keys_.fill(common::VoxelHash::kEmpty);
        // A lookup in the table is a cache miss the loop would wait for (27 % of the filter's
        // samples were on the one load of the slot, `perf annotate`), and no point's key depends
        // on it: the keys are computed kAhead points early and their slots prefetched.
        std::array<uint64_t, kAhead> ahead;
        const auto look_ahead = [&](size_t j) {
            const uint64_t key = common::VoxelKey(in[j], inv);
            ahead[j % kAhead] = key;
            __builtin_prefetch(&table_[common::MixKey(key) & mask]);
        };
        for (size_t j = 0; j < std::min(kAhead, in.size()); ++j) look_ahead(j);
        for (size_t i = 0; i < in.size() && !full; ++i) {
            const uint64_t key = ahead[i % kAhead];
            if (i + kAhead < in.size()) look_ahead(i + kAhead);
            if (key == previous) continue;
            previous = key;
            if (!ring.empty()) {
                uint64_t& last = ring_keys_[ring[i] & (kRingKeys - 1)];
                if (last == key) continue;
                last = key;
            }
            for (size_t slot = common::MixKey(key) & mask;; slot = (slot + 1) & mask) {
                uint64_t& k = table_[slot];
                if (k == common::VoxelHash::kEmpty) {
                    k = key;
                    used_.push_back(uint32_t(slot));
                    out->push_back(in[i]);
                    out_alpha->push_back(in_alpha[i]);
                    if (!in_pose.empty()) out_pose->push_back(in_pose[i]);
                    full = out->size() > limit && slots < all;
                    break;
                }
                if (k == key) break;
            }
        }
        for (const uint32_t slot : used_) table_[slot] = common::VoxelHash::kEmpty;
        if (!full) break;
        slots = all;
    }
    *expected = out->size();
}

const PreprocessStats& Preprocessor::Run(const common::PointCloud& scan, const ScanMotion& motion) {
    stats_ = PreprocessStats{};
    KeepAndDeskew(scan, motion);
    FilterMapPoints();
    const size_t found = FilterRegistrationPoints();
    // The next scan's sizes.
    map_voxel_ = Adapt(map_voxel_, map_points_.size(), config_.target_map_points, config_.map_voxel,
                       config_.max_map_voxel);
    registration_voxel_ = Adapt(registration_voxel_, found, config_.target_registration_points,
                                config_.registration_voxel, config_.max_registration_voxel);
    return stats_;
}

void Preprocessor::KeepAndDeskew(const common::PointCloud& scan, const ScanMotion& motion) {
    const size_t n = std::min(scan.size(), config_.max_points);
    stats_.input = scan.size();
    deskewed_.Clear();
    alpha_.clear();
    poses_.clear();
    pose_.clear();
    deskewed_.stamp = scan.stamp;
    deskewed_.frame = scan.frame;
    const bool with_i = scan.HasIntensity(), with_r = scan.HasRing(), with_t = scan.HasTime();
    const bool deskew = config_.deskew && with_t;
    const double min2 = config_.min_range * config_.min_range;
    const double max2 = config_.max_range * config_.max_range;
    const Eigen::Vector3f box_min = config_.self_box_min.cast<float>();
    const Eigen::Vector3f box_max = config_.self_box_max.cast<float>();
    const bool box = (box_min.array() <= box_max.array()).all();
    uint32_t max_offset = 0;
    if (with_t) {
        for (size_t i = 0; i < n; ++i) max_offset = std::max(max_offset, scan.time_offset_ns[i]);
    }
    duration_s_ = max_offset * 1e-9;
    const float inv_duration = max_offset > 0 ? 1.0f / float(max_offset) : 0.0f;
    // Every k-th point's range, for the extent (a sample keeps this cheap).
    range_sample_.clear();
    const size_t sample_step = std::max<size_t>(1, n / kRangeSamples);

    // Points come column by column, so consecutive points share a time: the pose is looked up
    // once per distinct time offset.
    uint32_t pose_time = 0;
    Eigen::Matrix3f R = Eigen::Matrix3f::Identity();
    Eigen::Vector3f t = Eigen::Vector3f::Zero();
    bool have_pose = false;
    for (size_t i = 0; i < n; ++i) {
        const Eigen::Vector3f& p = scan.xyz[i];
        if (!p.allFinite()) {
            ++stats_.non_finite;
            continue;
        }
        const double r2 = p.squaredNorm();
        if (r2 == 0) {
            ++stats_.zero_range;
            continue;
        }
        if (r2 < min2 || r2 > max2) {
            ++stats_.cropped;
            continue;
        }
        if (box && (p.array() >= box_min.array()).all() && (p.array() <= box_max.array()).all()) {
            ++stats_.self;
            continue;
        }
        if (i % sample_step == 0 && range_sample_.size() < kRangeSamples) {
            range_sample_.push_back(static_cast<float>(std::sqrt(r2)));
        }
        Eigen::Vector3f q = p;
        if (deskew) {
            const uint32_t tau = scan.time_offset_ns[i];
            if (!have_pose || tau != pose_time) {
                const Eigen::Isometry3d T = motion.At(tau * 1e-9);
                R = T.linear().cast<float>();
                t = T.translation().cast<float>();
                pose_time = tau;
                have_pose = true;
                poses_.push_back({tau, R, t});
            }
            q = R * p + t;
            pose_.push_back(uint32_t(poses_.size() - 1));
        }
        deskewed_.xyz.push_back(q);
        alpha_.push_back(with_t ? float(scan.time_offset_ns[i]) * inv_duration : 0.0f);
        if (with_i) deskewed_.intensity.push_back(scan.intensity[i]);
        if (with_r) deskewed_.ring.push_back(scan.ring[i]);
        if (with_t) deskewed_.time_offset_ns.push_back(scan.time_offset_ns[i]);
    }
    stats_.kept = deskewed_.size();
    if (!range_sample_.empty()) {
        const size_t k = range_sample_.size() * 9 / 10;
        std::nth_element(range_sample_.begin(), range_sample_.begin() + long(k),
                         range_sample_.end());
        stats_.range_p90 = range_sample_[k];
    }
}

void Preprocessor::FilterMapPoints() {
    VoxelFilter(deskewed_.xyz, alpha_, pose_, deskewed_.ring, map_voxel_, &map_points_, &map_alpha_,
                &map_pose_, &expected_map_);
    const size_t map_target = config_.target_map_points;
    if (map_target > 0 && map_points_.size() > 2 * map_target) {
        const double v =
            std::min(map_voxel_ * std::sqrt(double(map_points_.size()) / double(map_target)),
                     config_.max_map_voxel);
        if (v > map_voxel_) {
            map_voxel_ = v;
            map_points_.swap(refilter_points_);  // all reserved: no allocation
            map_alpha_.swap(refilter_alpha_);
            map_pose_.swap(refilter_pose_);
            VoxelFilter(refilter_points_, refilter_alpha_, refilter_pose_, {}, map_voxel_,
                        &map_points_, &map_alpha_, &map_pose_, &expected_map_);
        }
    }
    stats_.map_voxel = map_voxel_;
    stats_.map_points = map_points_.size();
}

size_t Preprocessor::FilterRegistrationPoints() {
    stats_.registration_voxel = registration_voxel_;
    VoxelFilter(map_points_, map_alpha_, map_pose_, {}, std::max(registration_voxel_, map_voxel_),
                &registration_points_, &registration_alpha_, &registration_pose_,
                &expected_registration_);
    const size_t found = registration_points_.size();
    // Cap: keep every k-th point (they are in column order, so this thins evenly in azimuth).
    const size_t cap = config_.max_registration_points;
    if (registration_points_.size() > cap) {
        const double step = double(registration_points_.size()) / double(cap);
        const bool with_pose = !registration_pose_.empty();
        for (size_t k = 0; k < cap; ++k) {
            registration_points_[k] = registration_points_[size_t(k * step)];
            registration_alpha_[k] = registration_alpha_[size_t(k * step)];
            if (with_pose) registration_pose_[k] = registration_pose_[size_t(k * step)];
        }
        registration_points_.resize(cap);
        registration_alpha_.resize(cap);
        if (with_pose) registration_pose_.resize(cap);
    }
    stats_.registration_points = registration_points_.size();
    return found;
}

}  // namespace bimslam::odometry
