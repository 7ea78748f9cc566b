// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/registration/oriented_cloud.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>

#include "algorithms/common/status.hpp"
#include "algorithms/common/voxel_hash.hpp"

namespace bimslam::registration {
using common::Require;

void OrientedCloudConfig::Validate() const {
    const char* c = "OrientedCloudConfig";
    Require(min_range >= 0 && min_range < max_range, c, "min_range", min_range,
            "must be in [0, max_range)");
    Require(normal_voxel_size > 0.05, c, "normal_voxel_size", normal_voxel_size,
            "must be over 0.05 m");
    Require(coarse_normal_voxel_size >= normal_voxel_size, c, "coarse_normal_voxel_size",
            coarse_normal_voxel_size, "must be at least normal_voxel_size");
    Require(min_plane_points >= 3, c, "min_plane_points", min_plane_points, "must be at least 3");
    Require(max_thickness > 0 && max_thickness < 0.5 * normal_voxel_size, c, "max_thickness",
            max_thickness, "must be in (0, normal_voxel_size / 2) m");
    Require(sample_voxel_size > 0.01, c, "sample_voxel_size", sample_voxel_size,
            "must be over 0.01 m");
    Require(thin_voxel_size > 0 && thin_voxel_size <= sample_voxel_size, c, "thin_voxel_size",
            thin_voxel_size, "must be in (0, sample_voxel_size] m");
}

namespace {

// The last voxel key looked up and its value. A scan's points come in sensor order, so about
// half of them fall in the voxel of the point before (MakeOrientedCloud's thinning keeps about
// half of a 32-beam scan): those skip the hash table, with the same result.
struct RunOfKeys {
    uint64_t key = common::VoxelHash::kEmpty;
    uint32_t value = 0;
    bool Same(uint64_t k) const { return k == key; }
    uint32_t Remember(uint64_t k, uint32_t v) {
        key = k;
        value = v;
        return v;
    }
};

// The plane of each voxel of one size over the points: the normal (oriented towards the
// origin, where the sensor is) per point, zero where its voxel holds no plane.
void VoxelNormals(const std::vector<Eigen::Vector3f>& pts, double voxel, int min_points,
                  double max_thickness, std::vector<Eigen::Vector3f>* normals) {
    struct Sums {
        int n = 0;
        Eigen::Vector3d origin, sum = Eigen::Vector3d::Zero();
        Eigen::Matrix3d sq = Eigen::Matrix3d::Zero();
        Eigen::Vector3f normal = Eigen::Vector3f::Zero();
        Eigen::Vector3f centroid = Eigen::Vector3f::Zero();
    };
    const float inv = static_cast<float>(1.0 / voxel);
    common::VoxelHash table(pts.size() / 4 + 16);
    std::vector<Sums> sums;
    std::vector<uint32_t> voxel_of(pts.size());
    RunOfKeys run;
    for (size_t k = 0; k < pts.size(); ++k) {
        const uint64_t key = common::VoxelKey(pts[k], inv);
        bool fresh = false;
        const uint32_t i =
            run.Same(key)
                ? run.value
                : run.Remember(key, table.FindOrInsert(key, uint32_t(sums.size()), &fresh));
        if (fresh) sums.push_back({0, pts[k].cast<double>()});
        Sums& s = sums[size_t(i)];
        const Eigen::Vector3d q = pts[k].cast<double>() - s.origin;
        ++s.n;
        s.sum += q;
        s.sq += q * q.transpose();
        voxel_of[k] = i;
    }
    const double max_sd = max_thickness;
    for (Sums& s : sums) {
        if (s.n < min_points) continue;
        const Eigen::Vector3d mean = s.sum / s.n;
        const Eigen::Matrix3d cov = s.sq / s.n - mean * mean.transpose();
        const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
        const Eigen::Vector3d l = eig.eigenvalues().cwiseMax(0.0);
        // Spread within the plane in both directions, by more than noise: a single ring crossing
        // a voxel is a line whose noise along the rays would tilt the fitted plane towards them.
        const double min_spread = 0.1 * voxel;
        if (l(0) > max_sd * max_sd || l(1) < std::max(9.0 * l(0), min_spread * min_spread))
            continue;
        Eigen::Vector3d n = eig.eigenvectors().col(0);
        // The sensor (the origin) is on the side the surface was seen from.
        if (n.dot(s.origin + mean) > 0) n = -n;
        s.normal = n.cast<float>();
        s.centroid = (s.origin + mean).cast<float>();
    }
    // A plane fitted to a floor and the foot of a wall can be thin on average and tilted: every
    // point must lie within three thicknesses of it, or the voxel offers no normal.
    const float max_residual = float(3 * max_thickness);
    for (size_t k = 0; k < pts.size(); ++k) {
        Sums& s = sums[size_t(voxel_of[k])];
        if (s.normal.squaredNorm() > 0 &&
            std::abs(s.normal.dot(pts[k] - s.centroid)) > max_residual) {
            s.normal.setZero();
        }
    }
    normals->resize(pts.size());
    for (size_t k = 0; k < pts.size(); ++k) (*normals)[k] = sums[size_t(voxel_of[k])].normal;
}

}  // namespace

OrientedCloud MakeOrientedCloud(const std::vector<Eigen::Vector3f>& points,
                                const OrientedCloudConfig& config) {
    config.Validate();
    OrientedCloud out;
    out.input_points = points.size();
    std::vector<Eigen::Vector3f> pts;
    pts.reserve(points.size());
    const float min2 = float(config.min_range * config.min_range);
    const float max2 = float(config.max_range * config.max_range);
    // First point per thin_voxel_size voxel: a 32 x 1024 scan has 30 000 points, several per
    // few centimetres near the sensor, which add nothing to a plane fitted over 0.4 m.
    const float inv_thin = static_cast<float>(1.0 / config.thin_voxel_size);
    // Sized for every point: about half of them are kept, and growing the table on the way
    // costs more than the larger table.
    common::VoxelHash thin(points.size() + 16);
    RunOfKeys run;
    for (const Eigen::Vector3f& p : points) {
        const float r2 = p.squaredNorm();
        if (!p.allFinite() || r2 < min2 || r2 > max2) continue;
        const uint64_t key = common::VoxelKey(p, inv_thin);
        if (run.Same(key)) continue;
        bool fresh = false;
        run.Remember(key, thin.FindOrInsert(key, 0, &fresh));
        if (fresh) pts.push_back(p);
    }
    std::vector<Eigen::Vector3f> fine, coarse;
    VoxelNormals(pts, config.normal_voxel_size, config.min_plane_points, config.max_thickness,
                 &fine);
    VoxelNormals(pts, config.coarse_normal_voxel_size, config.min_plane_points,
                 config.max_thickness, &coarse);

    // One point per sample voxel: the first one on a plane.
    const float inv = static_cast<float>(1.0 / config.sample_voxel_size);
    common::VoxelHash taken(pts.size() / 4 + 16);
    run = {};
    for (size_t k = 0; k < pts.size(); ++k) {
        const Eigen::Vector3f& n = fine[k].squaredNorm() > 0 ? fine[k] : coarse[k];
        if (n.squaredNorm() == 0) continue;
        const uint64_t key = common::VoxelKey(pts[k], inv);
        if (run.Same(key)) continue;
        bool fresh = false;
        run.Remember(key, taken.FindOrInsert(key, 0, &fresh));
        if (!fresh) continue;
        out.points.push_back(pts[k]);
        out.normals.push_back(n);
    }
    if (config.max_points > 0 && out.points.size() > config.max_points) {
        const double step = double(out.points.size()) / double(config.max_points);
        for (size_t k = 0; k < config.max_points; ++k) {
            out.points[k] = out.points[size_t(k * step)];
            out.normals[k] = out.normals[size_t(k * step)];
        }
        out.points.resize(config.max_points);
        out.normals.resize(config.max_points);
    }
    return out;
}

OrientedCloud MakeOrientedCloud(const common::PointCloud& cloud,
                                const OrientedCloudConfig& config) {
    return MakeOrientedCloud(cloud.xyz, config);
}

OrientedCloud MergeOriented(const std::vector<const OrientedCloud*>& clouds,
                            const std::vector<Eigen::Isometry3d>& T_first_k) {
    if (clouds.size() != T_first_k.size()) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            "MergeOriented: one transform per cloud");
    }
    OrientedCloud out;
    for (size_t c = 0; c < clouds.size(); ++c) {
        const Eigen::Matrix3f R = T_first_k[c].linear().cast<float>();
        const Eigen::Vector3f t = T_first_k[c].translation().cast<float>();
        out.input_points += clouds[c]->input_points;
        for (size_t k = 0; k < clouds[c]->size(); ++k) {
            out.points.push_back(R * clouds[c]->points[k] + t);
            out.normals.push_back(R * clouds[c]->normals[k]);
        }
    }
    return out;
}

}  // namespace bimslam::registration
