// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/registration/surfel_map.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <string>

#include "algorithms/common/status.hpp"
#include "algorithms/common/voxel_hash.hpp"

namespace bimslam::registration {
using common::Require;

void SurfelMapConfig::Validate() const {
    const char* c = "SurfelMapConfig";
    Require(voxel_size > 0.01 && voxel_size <= 10, c, "voxel_size", voxel_size,
            "must be in (0.01, 10] m");
    Require(min_points >= 3, c, "min_points", min_points, "must be at least 3");
    Require(max_thickness > 0 && max_thickness < voxel_size, c, "max_thickness", max_thickness,
            "must be in (0, voxel_size) m");
}

int NormalBin(const Eigen::Vector3f& n) {
    int axis = 0;
    n.cwiseAbs().maxCoeff(&axis);
    return 2 * axis + (n[axis] < 0 ? 1 : 0);
}

SurfelMap::SurfelMap(const SurfelMapConfig& config)
    : config_(config), inv_size_(static_cast<float>(1.0 / config.voxel_size)) {
    config_.Validate();
}

void SurfelMap::Add(const OrientedCloud& cloud, const Eigen::Isometry3d& T_map_cloud) {
    if (built_) throw common::Error(common::StatusCode::kInternal, "SurfelMap: Add after Build");
    const Eigen::Matrix3f R = T_map_cloud.linear().cast<float>();
    const Eigen::Vector3f t = T_map_cloud.translation().cast<float>();
    for (size_t k = 0; k < cloud.size(); ++k) {
        const Eigen::Vector3f p = R * cloud.points[k] + t;
        const Eigen::Vector3f n = R * cloud.normals[k];
        if (!p.allFinite() || !n.allFinite()) continue;
        const int bin = NormalBin(n);
        const uint64_t key = common::VoxelKey(p, inv_size_);
        bool fresh = false;
        const uint32_t i = tables_[bin].FindOrInsert(key, uint32_t(sums_.size()), &fresh);
        if (fresh) {
            sums_.emplace_back();
            sums_.back().origin = p.cast<double>();
            sums_.back().key = key;
            sums_.back().bin = bin;
        }
        Sums& s = sums_[size_t(i)];
        const Eigen::Vector3d q = p.cast<double>() - s.origin;
        s.n += 1;
        s.sum += q;
        s.sum_sq += q * q.transpose();
        s.normal_sum += n.cast<double>();
    }
}

void SurfelMap::Build() {
    for (auto& table : tables_) table.Clear();
    surfels_.clear();
    places_.clear();
    const double max_var = config_.max_thickness * config_.max_thickness;
    for (const Sums& s : sums_) {
        if (s.n < config_.min_points) continue;
        const Eigen::Vector3d mean = s.sum / s.n;
        const Eigen::Matrix3d cov = s.sum_sq / s.n - mean * mean.transpose();
        const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
        const Eigen::Vector3d lambda = eig.eigenvalues().cwiseMax(0.0);  // ascending
        // Flat (across) and spread (within, both directions: a line is no plane).
        if (lambda(0) > max_var || lambda(1) < 9.0 * std::max(lambda(0), 1e-6)) continue;
        Eigen::Vector3d normal = eig.eigenvectors().col(0);
        if (normal.dot(s.normal_sum) < 0) normal = -normal;
        Surfel f;
        f.normal = normal.cast<float>();
        f.centroid = (s.origin + mean).cast<float>();
        f.offset = f.normal.dot(f.centroid);
        f.thickness = static_cast<float>(std::sqrt(lambda(0)));
        f.axis = eig.eigenvectors().col(2).cast<float>();
        f.spread[0] = static_cast<float>(std::sqrt(lambda(2)));
        f.spread[1] = static_cast<float>(std::sqrt(lambda(1)));
        f.points = static_cast<uint32_t>(s.n);
        tables_[s.bin].FindOrInsert(s.key, uint32_t(surfels_.size()));
        surfels_.push_back(f);
        places_.push_back({s.key, uint8_t(s.bin)});
    }
    sums_.clear();
    sums_.shrink_to_fit();
    built_ = true;
}

SurfelMap SurfelMap::Restore(const SurfelMapConfig& config, std::vector<Surfel> surfels,
                             std::vector<Place> places) {
    const auto invalid = [](const std::string& what) {
        throw common::Error(common::StatusCode::kInvalidArgument, "SurfelMap::Restore: " + what);
    };
    if (surfels.size() != places.size()) {
        invalid(std::to_string(surfels.size()) + " surfels but " + std::to_string(places.size()) +
                " places");
    }
    SurfelMap m(config);
    for (size_t i = 0; i < places.size(); ++i) {
        if (places[i].bin >= kNormalBins) invalid("surfel " + std::to_string(i) + ": bad bin");
        bool fresh = false;
        m.tables_[places[i].bin].FindOrInsert(places[i].key, uint32_t(i), &fresh);
        if (!fresh) invalid("surfel " + std::to_string(i) + ": its voxel and bin twice");
    }
    m.surfels_ = std::move(surfels);
    m.places_ = std::move(places);
    m.built_ = true;
    return m;
}

void SurfelMap::MarkPorous(const std::vector<uint32_t>& indices) {
    for (const uint32_t i : indices) {
        if (i >= surfels_.size()) {
            throw common::Error(common::StatusCode::kInvalidArgument,
                                "SurfelMap::MarkPorous: surfel " + std::to_string(i) + " of " +
                                    std::to_string(surfels_.size()));
        }
        surfels_[i].porous = true;
    }
}

using common::kVoxelAndFaceNeighbours;

const Surfel* SurfelMap::Find(const Eigen::Vector3f& p, const Eigen::Vector3f& n,
                              float min_cos_angle, float* distance) const {
    const Eigen::Vector3i v = common::VoxelOf(p * inv_size_);
    const Surfel* best = nullptr;
    auto look = [&](int bin, const Eigen::Vector3i& d) {
        const uint32_t i = tables_[bin].Find(common::PackVoxel(v + d));
        if (i == common::VoxelHash::kAbsent) return;
        const Surfel& s = surfels_[size_t(i)];
        if (s.normal.dot(n) < min_cos_angle) return;
        const float r = s.normal.dot(p) - s.offset;
        if (!best || std::abs(r) < std::abs(*distance)) {
            best = &s;
            *distance = r;
        }
    };
    // The nearest half-axis's bin, and the second nearest when n is closer than 60 degrees to it
    // as well (a 45-degree wall fits planes in both).
    int bins[2] = {NormalBin(n), -1};
    Eigen::Vector3f a = n.cwiseAbs();
    a[bins[0] / 2] = -1;
    int second = 0;
    if (a.maxCoeff(&second) > 0.5f) bins[1] = 2 * second + (n[second] < 0 ? 1 : 0);
    // Most points lie on the plane of their own voxel: then the neighbours cannot be nearer.
    look(bins[0], kVoxelAndFaceNeighbours[0]);
    if (best && std::abs(*distance) < 0.1f / inv_size_) return best;
    for (const int bin : bins) {
        if (bin < 0) continue;
        for (size_t k = (bin == bins[0] ? 1 : 0); k < kVoxelAndFaceNeighbours.size(); ++k)
            look(bin, kVoxelAndFaceNeighbours[k]);
    }
    return best;
}

int SurfelMap::InVoxel(const Eigen::Vector3f& p, const Surfel* out[kNormalBins]) const {
    const uint64_t key = common::VoxelKey(p, inv_size_);
    int n = 0;
    for (int bin = 0; bin < kNormalBins; ++bin) {
        const uint32_t i = tables_[bin].Find(key);
        if (i != common::VoxelHash::kAbsent) out[n++] = &surfels_[size_t(i)];
    }
    return n;
}

}  // namespace bimslam::registration
