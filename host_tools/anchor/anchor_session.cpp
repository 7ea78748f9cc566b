// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/anchor/anchor_session.hpp"

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <memory>

#include "algorithms/common/status.hpp"
#include "algorithms/io/pcd.hpp"
#include "algorithms/io/trajectory.hpp"

namespace bimslam::anchor {
namespace fs = std::filesystem;
using common::FileError;
using common::StatusCode;

bool IsForeignSession(const fs::path& dir) {
    return fs::is_directory(dir / "Scans") && !fs::exists(dir / "session.json") &&
           !fs::exists(dir / "singlesession_posegraph.g2o") &&
           (fs::exists(dir / "optimized_poses.txt") || fs::exists(dir / "odom_poses.txt"));
}

std::vector<io::SessionEdge> EdgesFromPoses(const std::vector<Eigen::Isometry3d>& poses) {
    std::vector<io::SessionEdge> edges;
    for (size_t k = 1; k < poses.size(); ++k) {
        io::SessionEdge e;
        e.from = uint32_t(k - 1);
        e.to = uint32_t(k);
        e.T_from_to = poses[k - 1].inverse() * poses[k];
        const double d = e.T_from_to.translation().norm();
        const double st = std::max(kDefaultEdgeSigmaFloor, kDefaultEdgeSigmaPerMetre * d);
        const double sr =
            std::max(kDefaultEdgeSigmaFloor * 0.25, kDefaultEdgeSigmaDegPerMetre * d) * M_PI / 180;
        e.information = common::Matrix6d::Zero();
        e.information.diagonal() << 1 / (st * st), 1 / (st * st), 1 / (st * st), 1 / (sr * sr),
            1 / (sr * sr), 1 / (sr * sr);
        edges.push_back(e);
    }
    return edges;
}

namespace {

// The SC-A-LOAM / LT-mapper layout: poses (optimised ones when there, else the odometry's),
// times, and one cloud per keyframe; counts must agree.
void ReadForeign(const fs::path& dir, AnchorSession* s) {
    s->foreign = true;
    const bool optimized = fs::exists(dir / "optimized_poses.txt");
    const fs::path poses_file = dir / (optimized ? "optimized_poses.txt" : "odom_poses.txt");
    std::vector<Eigen::Isometry3d> poses = io::ReadKitti(poses_file);
    size_t scans = 0;
    while (fs::exists(io::KeyframeCloudPath(dir, scans))) ++scans;
    if (scans != poses.size()) {
        throw FileError(StatusCode::kDataLoss, poses_file.string(), 0,
                        "holds " + std::to_string(poses.size()) + " poses, but Scans/ holds " +
                            std::to_string(scans) + " clouds numbered from 000000.pcd");
    }
    std::vector<int64_t> times;
    if (fs::exists(dir / "times.txt")) {
        times = io::ReadTimes(dir / "times.txt");
        if (times.size() != poses.size()) {
            throw FileError(StatusCode::kDataLoss, (dir / "times.txt").string(), 0,
                            "holds " + std::to_string(times.size()) + " times for " +
                                std::to_string(poses.size()) + " poses in " +
                                poses_file.filename().string());
        }
    } else {
        s->notes.push_back("times.txt is missing: keyframes are numbered, not timed");
        for (size_t k = 0; k < poses.size(); ++k) times.push_back(int64_t(k) * 1'000'000'000);
    }
    s->session.complete = false;
    s->session.manifest.source = "rig";
    s->session.manifest.world_frame = "odom";
    s->session.manifest.counts.keyframes = poses.size();
    s->session.keyframes.resize(poses.size());
    for (size_t k = 0; k < poses.size(); ++k) {
        s->session.keyframes[k].stamp_ns = times[k];
        s->session.keyframes[k].T_world_lidar = poses[k];
        s->session.keyframes[k].T_odom_lidar = poses[k];
    }
    s->session.edges = EdgesFromPoses(poses);
    s->notes.push_back(
        "not a bimslam session (no session.json, no pose graph): read as the "
        "SC-A-LOAM/LT-mapper layout, " +
        std::to_string(poses.size()) + " keyframes with poses from " +
        poses_file.filename().string());
    char sigma[160];
    std::snprintf(sigma, sizeof sigma,
                  "odometry edges derived from the poses, covariance %.0f %% and %.1f deg per "
                  "metre travelled (at least %.0f cm)",
                  100 * kDefaultEdgeSigmaPerMetre, kDefaultEdgeSigmaDegPerMetre,
                  100 * kDefaultEdgeSigmaFloor);
    s->notes.push_back(sigma);
}

bool SameDescriptor(const io::SessionManifest::Descriptor& d,
                    const scancontext::ScanContextConfig& c) {
    return d.kind == scancontext::ToString(c.kind) && d.rings == c.num_rings &&
           d.sectors == c.num_sectors && std::abs(d.max_radius_m - c.max_radius) < 1e-9 &&
           (c.kind != scancontext::DescriptorKind::kIndoor ||
            (d.cell_rule == scancontext::ToString(c.indoor_rule) &&
             d.min_points == c.indoor_min_points &&
             std::abs(d.min_z_span_m - c.indoor_min_z_span) < 1e-9));
}

// The oriented clouds (options.load_clouds) and, when `compute`, the descriptors of the session's
// keyframes, read in parallel from their PCDs (by keyframe_ids once KeepKeyframes chose some).
void ReadClouds(AnchorSession* session, const LoadOptions& options, bool compute) {
    AnchorSession& s = *session;
    const size_t n = s.poses.size();
    s.clouds.resize(options.load_clouds ? n : 0);
    std::unique_ptr<tbb::global_control> limit;
    if (options.threads > 0) {
        limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                      size_t(options.threads));
    }
    // A worker's error (naming its file) is thrown here, the first keyframe's first.
    std::vector<std::exception_ptr> errors(n);
    tbb::parallel_for(size_t(0), n, [&](size_t k) {
        try {
            const size_t id = s.keyframe_ids.empty() ? k : s.keyframe_ids[k];
            common::PointCloud cloud = io::ReadPcd(io::KeyframeCloudPath(s.dir, id));
            if (compute) s.descriptors[k] = scancontext::MakeDescriptor(cloud, options.descriptor);
            if (options.load_clouds)
                s.clouds[k] = registration::MakeOrientedCloud(cloud, options.cloud);
        } catch (...) {
            errors[k] = std::current_exception();
        }
    });
    for (const std::exception_ptr& e : errors) {
        if (e) std::rethrow_exception(e);
    }
}

}  // namespace

AnchorSession LoadAnchorSession(const fs::path& dir, const LoadOptions& options) {
    AnchorSession s;
    s.dir = dir;
    fs::path norm = fs::absolute(dir).lexically_normal();
    if (norm.filename().empty()) norm = norm.parent_path();  // "a/b/"
    s.name = norm.filename().string();
    if (!fs::is_directory(dir)) {
        throw FileError(StatusCode::kNotFound, dir.string(), 0, "no such session folder");
    }
    if (IsForeignSession(dir)) {
        ReadForeign(dir, &s);
    } else {
        s.session = io::ReadSession(dir, {.load_clouds = false, .allow_recovery = true});
        for (const std::string& n : s.session.notes) s.notes.push_back(n);
    }
    s.odometry = ReadOdometryVerdict(dir);
    const size_t n = s.session.keyframes.size();
    if (n == 0) {
        throw FileError(
            StatusCode::kDataLoss, dir.string(), 0,
            "holds no keyframes (" +
                (s.notes.empty() ? std::string(io::kNoKeyframesHint) : s.notes.front()) + ")");
    }
    // Descriptors: the session's own when they are the kind the reference uses, else computed.
    const bool compute =
        options.compute_descriptors &&
        (s.foreign || !SameDescriptor(s.session.manifest.descriptor, options.descriptor));
    if (compute && !s.foreign) {
        const io::SessionManifest::Descriptor& d = s.session.manifest.descriptor;
        const bool indoor = options.descriptor.kind == scancontext::DescriptorKind::kIndoor;
        s.notes.push_back(
            "descriptors recomputed: the session's (" + d.kind +
            (d.kind == "indoor" ? ", " + d.cell_rule : std::string()) + ") are not the " +
            std::string(scancontext::ToString(options.descriptor.kind)) +
            (indoor ? ", " + std::string(scancontext::ToString(options.descriptor.indoor_rule))
                    : std::string()) +
            " Scan Context this run compares with");
    } else if (compute) {
        s.notes.push_back("Scan Context descriptors computed from the clouds (" +
                          std::string(scancontext::ToString(options.descriptor.kind)) + ")");
    }
    s.poses.resize(n);
    s.path_m.resize(n, 0.0);
    s.descriptors.resize(n);
    for (size_t k = 0; k < n; ++k) {
        s.poses[k] = s.session.keyframes[k].T_world_lidar;
        if (k > 0) {
            s.path_m[k] =
                s.path_m[k - 1] + (s.poses[k].translation() - s.poses[k - 1].translation()).norm();
        }
        if (!compute) s.descriptors[k] = s.session.keyframes[k].descriptor;
    }
    if (s.foreign && !compute) {
        s.notes.push_back("no SCDs/: bimslam anchor computes the Scan Context descriptors");
    }
    if (options.load_clouds || compute) ReadClouds(&s, options, compute);
    return s;
}

std::vector<std::vector<size_t>> EarlierTargets(const std::vector<AnchorSession>& sessions,
                                                const std::vector<size_t>& visit, double spacing) {
    std::vector<std::vector<size_t>> keep(sessions.size());
    std::vector<Eigen::Vector3d> newer;  // the kept keyframes of the visits after the one in hand
    for (size_t first = sessions.size(); first > 0;) {  // one visit's sessions at a time
        size_t begin = first - 1;
        while (begin > 0 && visit[begin - 1] == visit[first - 1]) --begin;
        std::vector<Eigen::Vector3d> mine;
        for (size_t s = begin; s < first; ++s) {
            for (size_t k = 0; k < sessions[s].poses.size(); ++k) {
                const Eigen::Vector3d p = sessions[s].poses[k].translation();
                const bool seen_since = std::any_of(newer.begin(), newer.end(), [&](const auto& q) {
                    return (q - p).squaredNorm() < spacing * spacing;
                });
                if (seen_since) continue;
                keep[s].push_back(k);
                mine.push_back(p);
            }
        }
        newer.insert(newer.end(), mine.begin(), mine.end());
        first = begin;
    }
    return keep;
}

void LoadClouds(AnchorSession* s, const LoadOptions& options) {
    LoadOptions o = options;
    o.load_clouds = true;
    ReadClouds(s, o, false);
}

void KeepKeyframes(AnchorSession* s, const std::vector<size_t>& keep) {
    if (s->keyframe_ids.empty()) {
        for (size_t k = 0; k < s->poses.size(); ++k) s->keyframe_ids.push_back(k);
    }
    std::vector<size_t> index(s->poses.size(), SIZE_MAX);  // old index -> new
    for (size_t i = 0; i < keep.size(); ++i) index.at(keep[i]) = i;
    const auto pick = [&](auto& v) {
        if (v.empty()) return;
        std::remove_reference_t<decltype(v)> kept;
        for (const size_t k : keep) kept.push_back(std::move(v[k]));
        v = std::move(kept);
    };
    pick(s->poses);
    pick(s->descriptors);
    pick(s->clouds);
    pick(s->path_m);
    pick(s->keyframe_ids);
    pick(s->session.keyframes);
    std::vector<io::SessionEdge> edges;
    for (io::SessionEdge e : s->session.edges) {
        if (index[e.from] == SIZE_MAX || index[e.to] == SIZE_MAX) continue;
        e.from = uint32_t(index[e.from]);
        e.to = uint32_t(index[e.to]);
        edges.push_back(e);
    }
    s->session.edges = std::move(edges);
    s->odometry = OdometryVerdict{};  // its stretches are by the old indices; an earlier
                                      // visit is never anchored in pieces
}

AnchorSession LoadEarlierSession(const fs::path& dir, const LoadOptions& options) {
    AnchorSession s = LoadAnchorSession(dir, options);
    const std::string& frame = s.session.manifest.world_frame;
    if (s.foreign || frame != "bim") {
        throw FileError(StatusCode::kInvalidArgument, (dir / "session.json").string(), 0,
                        "not an anchored session: its world frame is '" + frame +
                            "', not 'bim' (give a folder bimslam anchor wrote, OUT/<name>/)");
    }
    s.earlier = true;
    return s;
}

}  // namespace bimslam::anchor
