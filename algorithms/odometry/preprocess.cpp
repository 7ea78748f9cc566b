#include "algorithms/odometry/preprocess.hpp"

#include <algorithm>
#include <cmath>

#include "algorithms/common/status.hpp"
#include "algorithms/common/voxel_hash.hpp"

namespace bimslam::odometry {
using common::Require;
namespace {

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
    map_points_.reserve(config_.max_points);
    registration_points_.reserve(config_.max_points);
    const size_t slots = NextPowerOfTwo(2 * config_.max_points);
    table_keys_.assign(slots, 0);
    table_generation_.assign(slots, 0);
}

void Preprocessor::VoxelFilter(std::span<const Eigen::Vector3f> in, double voxel,
                               std::vector<Eigen::Vector3f>* out) {
    out->clear();
    if (++generation_ == 0) {  // wrapped: forget every old tag
        std::fill(table_generation_.begin(), table_generation_.end(), 0u);
        generation_ = 1;
    }
    const float inv = static_cast<float>(1.0 / voxel);
    const size_t mask = table_keys_.size() - 1;
    for (const Eigen::Vector3f& p : in) {
        const uint64_t key = common::VoxelKey(p, inv);
        for (size_t slot = common::MixKey(key) & mask;; slot = (slot + 1) & mask) {
            if (table_generation_[slot] != generation_) {
                table_generation_[slot] = generation_;
                table_keys_[slot] = key;
                out->push_back(p);
                break;
            }
            if (table_keys_[slot] == key) break;
        }
    }
}

const PreprocessStats& Preprocessor::Run(const common::PointCloud& scan, const ScanMotion& motion) {
    stats_ = PreprocessStats{};
    const size_t n = std::min(scan.size(), config_.max_points);
    stats_.input = scan.size();
    deskewed_.Clear();
    deskewed_.stamp = scan.stamp;
    deskewed_.frame = scan.frame;
    const bool with_i = scan.HasIntensity(), with_r = scan.HasRing(), with_t = scan.HasTime();
    const bool deskew = config_.deskew && with_t;
    const double min2 = config_.min_range * config_.min_range;
    const double max2 = config_.max_range * config_.max_range;
    const Eigen::Vector3f box_min = config_.self_box_min.cast<float>();
    const Eigen::Vector3f box_max = config_.self_box_max.cast<float>();
    const bool box = (box_min.array() <= box_max.array()).all();

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
        Eigen::Vector3f q = p;
        if (deskew) {
            const uint32_t tau = scan.time_offset_ns[i];
            if (!have_pose || tau != pose_time) {
                const Eigen::Isometry3d T = motion.At(tau * 1e-9);
                R = T.linear().cast<float>();
                t = T.translation().cast<float>();
                pose_time = tau;
                have_pose = true;
            }
            q = R * p + t;
        }
        deskewed_.xyz.push_back(q);
        if (with_i) deskewed_.intensity.push_back(scan.intensity[i]);
        if (with_r) deskewed_.ring.push_back(scan.ring[i]);
        if (with_t) deskewed_.time_offset_ns.push_back(scan.time_offset_ns[i]);
    }
    stats_.kept = deskewed_.size();

    VoxelFilter(deskewed_.xyz, config_.map_voxel, &map_points_);
    VoxelFilter(map_points_, config_.registration_voxel, &registration_points_);
    // Cap: keep every k-th point (they are in column order, so this thins evenly in azimuth).
    const size_t cap = config_.max_registration_points;
    if (registration_points_.size() > cap) {
        const double step = double(registration_points_.size()) / double(cap);
        for (size_t k = 0; k < cap; ++k) {
            registration_points_[k] = registration_points_[size_t(k * step)];
        }
        registration_points_.resize(cap);
    }
    stats_.map_points = map_points_.size();
    stats_.registration_points = registration_points_.size();
    return stats_;
}

}  // namespace bimslam::odometry
