// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/odometry/voxel_map.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <atomic>
#include <cmath>

#include "algorithms/common/status.hpp"
#include "algorithms/common/voxel_hash.hpp"

namespace bimslam::odometry {
using common::Require;
namespace {

size_t Hash(const Eigen::Vector3i& k, bool back) {
    // The spatial hash of Teschner et al. 2003 (three large primes, xor); a back twin moved off.
    return static_cast<size_t>((uint64_t(uint32_t(k.x())) * 73856093u) ^
                               (uint64_t(uint32_t(k.y())) * 19349669u) ^
                               (uint64_t(uint32_t(k.z())) * 83492791u)) +
           (back ? 1 : 0);
}

}  // namespace

void VoxelMapConfig::Validate() const {
    const char* c = "VoxelMapConfig";
    Require(voxel_size >= 0.05 && voxel_size <= 10, c, "voxel_size", voxel_size,
            "must be in [0.05, 10] m");
    Require(max_points_per_voxel >= 3 && max_points_per_voxel <= kMaxPointsPerVoxel, c,
            "max_points_per_voxel", max_points_per_voxel, "must be in [3, 24]");
    Require(min_point_spacing >= 0 && min_point_spacing < voxel_size, c, "min_point_spacing",
            min_point_spacing, "must be in [0, voxel_size)");
    Require(max_voxels >= 64 && max_voxels <= (1u << 24), c, "max_voxels", double(max_voxels),
            "must be in [64, 2^24]");
    Require(max_distance > voxel_size && std::isfinite(max_distance), c, "max_distance",
            max_distance, "must be finite and > voxel_size");
    Require(min_plane_points >= 3 && min_plane_points <= max_points_per_voxel, c,
            "min_plane_points", min_plane_points, "must be in [3, max_points_per_voxel]");
    Require(max_plane_thickness > 0 && max_plane_thickness < voxel_size, c, "max_plane_thickness",
            max_plane_thickness, "must be in (0, voxel_size)");
    Require(min_judged_spread >= 0 && min_judged_spread < voxel_size, c, "min_judged_spread",
            min_judged_spread, "must be in [0, voxel_size)");
}

namespace {
// A voxel seen from beyond kRefreshBeyond and then from under 1/kRefreshRatio of that range
// starts again from the nearer view (voxel_map.hpp).
constexpr float kRefreshRatio = 2.0f;
constexpr float kRefreshBeyond = 10.0f;  // m
// Versions are drawn from one counter, so that two maps (or one map at two times) share one only
// when one is a copy of the other.
uint64_t NextVersion() {
    static std::atomic<uint64_t> next{1};
    return next.fetch_add(1, std::memory_order_relaxed);
}
}  // namespace

VoxelMap::VoxelMap(const VoxelMapConfig& config) : config_(config), version_(NextVersion()) {
    config_.Validate();
    inv_size_ = static_cast<float>(1.0 / config_.voxel_size);
    voxels_.reserve(config_.max_voxels);
    size_t slots = 1;
    while (slots < 2 * config_.max_voxels) slots <<= 1;  // load factor <= 1/2
    slots_.assign(slots, -1);
    touched_.reserve(config_.max_voxels);
}

Eigen::Vector3i VoxelMap::KeyOf(const Eigen::Vector3f& p) const {
    return common::VoxelOf(p * inv_size_);
}

size_t VoxelMap::Slot(const Eigen::Vector3i& key, bool back) const {
    const size_t mask = slots_.size() - 1;
    for (size_t s = Hash(key, back) & mask;; s = (s + 1) & mask) {
        const int32_t i = slots_[s];
        if (i < 0 || (voxels_[size_t(i)].key == key && voxels_[size_t(i)].back == back)) return s;
    }
}

int32_t VoxelMap::Find(const Eigen::Vector3i& key, bool back) const {
    return slots_[Slot(key, back)];
}

int32_t VoxelMap::FindOrAdd(const Eigen::Vector3i& key, bool back) {
    const size_t s = Slot(key, back);
    if (slots_[s] >= 0) return slots_[s];
    if (voxels_.size() >= config_.max_voxels) return -1;
    const auto i = static_cast<int32_t>(voxels_.size());
    voxels_.emplace_back();
    voxels_.back().key = key;
    voxels_.back().back = back;
    slots_[s] = i;
    return i;
}

int32_t VoxelMap::Resolve(const Eigen::Vector3i& key, const Eigen::Vector3f* viewpoint) {
    const int32_t i = FindOrAdd(key, false);
    if (i < 0) return -1;
    // Seen from behind the cell's one-sided plane: the other face of a thin wall (header), kept
    // in the cell's back twin.
    const VoxelPlane& front = voxels_[size_t(i)].plane;
    if (!viewpoint || !front.valid || !front.one_sided ||
        front.normal.dot(*viewpoint) >= front.offset) {
        return i;
    }
    const int32_t twin = FindOrAdd(key, true);
    if (twin >= 0) voxels_[size_t(i)].has_back = true;
    return twin;
}

void VoxelMap::Insert(std::span<const Eigen::Vector3f> points) { InsertPoints(points, nullptr); }

void VoxelMap::Insert(std::span<const Eigen::Vector3f> points, const Eigen::Vector3f& viewpoint) {
    InsertPoints(points, &viewpoint);
}

void VoxelMap::InsertPoints(std::span<const Eigen::Vector3f> points,
                            const Eigen::Vector3f* viewpoint) {
    version_ = NextVersion();
    touched_.clear();
    const float spacing2 =
        static_cast<float>(config_.min_point_spacing * config_.min_point_spacing);
    // Points come column by column, so consecutive ones often share a cell: the last cell's voxel
    // is kept. The planes are fitted after the loop, so a cell resolves to the same voxel (front
    // or back twin, or none when the map is full) for every point of this call.
    Eigen::Vector3i last_key(INT32_MIN, INT32_MIN, INT32_MIN);
    int32_t last = -1;
    for (const Eigen::Vector3f& p : points) {
        if (!p.allFinite()) continue;
        const Eigen::Vector3i key = KeyOf(p);
        if (key != last_key) {
            last_key = key;
            last = Resolve(key, viewpoint);
        }
        const int32_t i = last;
        if (i < 0) {
            ++dropped_;
            continue;
        }
        Voxel& v = voxels_[size_t(i)];
        const Eigen::Vector3f to_sensor =
            viewpoint ? Eigen::Vector3f(*viewpoint - p) : Eigen::Vector3f::Zero();
        const float range = to_sensor.norm();
        // seen_from is only ever set with a point in the voxel: no count to check.
        if (v.seen_from > kRefreshBeyond && range * kRefreshRatio < v.seen_from) StartAgain(v);
        if (v.count >= config_.max_points_per_voxel) continue;
        bool near = false;
        for (int k = 0; k < v.count && !near; ++k) {
            near = (v.points[size_t(k)] - p).squaredNorm() < spacing2;
        }
        if (near) continue;
        v.points[size_t(v.count++)] = p;
        ++points_;
        if (range > 0) {  // seen from a viewpoint
            v.view_sum += to_sensor / range;
            ++v.viewed;
            v.seen_from = v.seen_from > 0 ? std::min(v.seen_from, range) : range;
        }
        if (!v.dirty) {
            v.dirty = true;
            touched_.push_back(i);
        }
    }
    for (const int32_t i : touched_) {
        Voxel& v = voxels_[size_t(i)];
        Fit(v);
        v.dirty = false;
    }
}

void VoxelMap::StartAgain(Voxel& v) {
    points_ -= size_t(v.count);
    v.count = v.viewed = 0;
    v.view_sum.setZero();
    v.seen_from = 0;
}

void VoxelMap::Fit(Voxel& v) const {
    v.plane.valid = false;
    v.line.valid = false;
    if (v.count < config_.min_plane_points) return;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (int k = 0; k < v.count; ++k) mean += v.points[size_t(k)].cast<double>();
    mean /= v.count;
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (int k = 0; k < v.count; ++k) {
        const Eigen::Vector3d d = v.points[size_t(k)].cast<double>() - mean;
        cov += d * d.transpose();
    }
    cov /= v.count;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
    eig.computeDirect(cov);
    const Eigen::Vector3d lambda = eig.eigenvalues();  // ascending
    if (config_.fit_lines) {
        const double across = std::sqrt(std::max(0.0, lambda(1)));
        if (across > config_.max_plane_thickness ||
            std::sqrt(std::max(0.0, lambda(2))) < 3 * across) {
            return;
        }
        v.line.point = mean.cast<float>();
        v.line.direction = eig.eigenvectors().col(2).normalized().cast<float>();
        v.line.valid = true;
        return;
    }
    const double thickness = std::sqrt(std::max(0.0, lambda(0)));
    const double spread = std::sqrt(std::max(0.0, lambda(1)));
    if (thickness > config_.max_plane_thickness || spread < 3 * thickness) return;
    Eigen::Vector3d n = eig.eigenvectors().col(0).normalized();
    // The front (header): where the points were seen from, when that is clearly one side.
    const double facing = v.viewed > 0 ? n.dot(v.view_sum.cast<double>()) / v.viewed : 0.0;
    if (facing < 0) n = -n;
    v.plane.one_sided = std::abs(facing) >= kMinFacing;
    v.plane.line_like = spread < config_.min_judged_spread;
    v.plane.normal = n.cast<float>();
    v.plane.offset = static_cast<float>(n.dot(mean));
    v.plane.valid = true;
}

using common::kVoxelAndFaceNeighbours;  // where FindPlane and FindLine look

const VoxelLine* VoxelMap::FindLine(const Eigen::Vector3f& p, float* distance) const {
    const Eigen::Vector3i key = KeyOf(p);
    const VoxelLine* best = nullptr;
    for (const Eigen::Vector3i& d : kVoxelAndFaceNeighbours) {
        const int32_t i = Find(key + d, false);
        if (i < 0) continue;
        const VoxelLine& line = voxels_[size_t(i)].line;
        if (!line.valid) continue;
        const Eigen::Vector3f q = p - line.point;
        const float r = (q - line.direction * line.direction.dot(q)).norm();
        if (!best || r < *distance) {
            best = &line;
            *distance = r;
        }
    }
    return best;
}

const VoxelPlane* VoxelMap::FindPlane(const Eigen::Vector3f& p, float* distance,
                                      const Eigen::Vector3f* sensor) const {
    NearestPlane nearest(p, sensor);
    ForNeighbourPlanes(KeyOf(p), [&](const VoxelPlane& plane) { nearest.Consider(plane); });
    if (nearest.best()) *distance = nearest.distance();
    return nearest.best();
}

// Linear probing's deletion: the slot emptied, and the entries probed past it moved back into
// the hole unless their home slot lies after it (cyclically in (hole, j]).
void VoxelMap::EraseSlot(size_t hole) {
    const size_t mask = slots_.size() - 1;
    slots_[hole] = -1;
    for (size_t j = (hole + 1) & mask; slots_[j] >= 0; j = (j + 1) & mask) {
        const Voxel& v = voxels_[size_t(slots_[j])];
        const size_t home = Hash(v.key, v.back) & mask;
        const bool stays = hole < j ? (hole < home && home <= j) : (hole < home || home <= j);
        if (stays) continue;
        slots_[hole] = slots_[j];
        slots_[j] = -1;
        hole = j;
    }
}

void VoxelMap::Remove(size_t i) {
    points_ -= size_t(voxels_[i].count);
    EraseSlot(Slot(voxels_[i].key, voxels_[i].back));
    const size_t last = voxels_.size() - 1;
    if (i != last) {
        voxels_[i] = voxels_[last];  // its slot still names `last`, which still holds it
        slots_[Slot(voxels_[i].key, voxels_[i].back)] = static_cast<int32_t>(i);
    }
    voxels_.pop_back();
}

void VoxelMap::Prune(const Eigen::Vector3d& sensor, double max_radius) {
    const Eigen::Vector3f c = ((sensor.cast<float>() * inv_size_).array() - 0.5f).matrix();
    double radius =
        max_radius > 0 ? std::min(max_radius, config_.max_distance) : config_.max_distance;
    const size_t before = voxels_.size();
    bool shrinking = false;
    for (;;) {
        // Voxel centres are key + 0.5 in voxel units: compare squared distances in those units.
        const float r2 = static_cast<float>(radius * radius) * inv_size_ * inv_size_;
        // A few voxels leave each scan: each is taken out of the table and the last voxel moved
        // into its place (compacting all and rehashing them cost a scan a copy of half the map).
        for (size_t i = 0; i < voxels_.size();) {
            if ((voxels_[i].key.cast<float>() - c).squaredNorm() <= r2) {
                ++i;
            } else {
                Remove(i);  // the last voxel is at i now: look at it next
            }
        }
        // More than 90 % full: shrink the radius until at most three-quarters full.
        const size_t n = voxels_.size(), cap = config_.max_voxels;
        if (shrinking ? 4 * n <= 3 * cap : 10 * n <= 9 * cap) break;
        shrinking = true;
        radius *= 0.8;
        if (radius < config_.voxel_size) break;
    }
    if (voxels_.size() != before) version_ = NextVersion();
}

void VoxelMap::Clear() {
    voxels_.clear();
    std::fill(slots_.begin(), slots_.end(), -1);
    points_ = 0;
    version_ = NextVersion();
}

}  // namespace bimslam::odometry
