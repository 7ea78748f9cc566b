// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// A session as anchoring uses it: its keyframes' poses in its own frame, their oriented clouds
// for registration, their Scan Context descriptors, its odometry edges, the scan poses of
// trajectory.tum and the odometry's verdict on it (pieces.hpp); read from a bimslam session, or
// from the layout SC-A-LOAM, LT-mapper and FAST-LIO-SC write (Scans/*.pcd, odom_poses.txt,
// optimized_poses.txt, times.txt), whose missing parts are derived and said:
//   - no SCDs/: the descriptors are computed from the clouds (indoor Scan Context, the rig's);
//   - no g2o: odometry edges between consecutive keyframes from the poses, with the stated
//     default covariance (kDefaultEdgeSigma*), since those tools do not write theirs;
//   - no session.json: counts and the descriptor's shape come from the files.
#pragma once

#include <Eigen/Geometry>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "algorithms/io/session.hpp"
#include "algorithms/localization/loop_rules.hpp"
#include "algorithms/registration/oriented_cloud.hpp"
#include "algorithms/scancontext/config.hpp"
#include "algorithms/scancontext/descriptor.hpp"
#include "host_tools/anchor/pieces.hpp"

namespace bimslam::anchor {

// The covariance of an odometry edge derived from poses alone: per metre travelled (plus a floor
// for short edges). A LiDAR odometry drifts about 1 % (this project's: 0.1-1.4 %, its README);
// 2 % and 0.5 deg per metre leave room for other tools' odometry without letting a wrong loop
// bend the path freely.
inline constexpr double kDefaultEdgeSigmaPerMetre = 0.02;    // m per m
inline constexpr double kDefaultEdgeSigmaDegPerMetre = 0.5;  // deg per m
inline constexpr double kDefaultEdgeSigmaFloor = 0.01;       // m (and 0.25 deg)

// Where a walk starts, when the user knows (localization::StartHint, shared with the rig's
// relocaliser).
using localization::StartHint;

struct AnchorSession {
    std::string name;  // the folder's name
    std::filesystem::path dir;
    io::Session session;   // without clouds; manifest filled in for foreign sessions
    bool foreign = false;  // SC-A-LOAM/LT-mapper layout, not a bimslam session
    std::vector<Eigen::Isometry3d> poses;  // T_local_lidar per keyframe
    std::vector<scancontext::Descriptor> descriptors;
    std::vector<registration::OrientedCloud> clouds;
    std::vector<double> path_m;  // distance along the keyframes from the first
    // The odometry's own verdict (odometry_verdict.json, pieces.hpp): where it failed, the
    // session is anchored in pieces.
    OdometryVerdict odometry;
    // What was missing and what was derived, for the user.
    std::vector<std::string> notes;
    // An earlier visit's anchored session (`bimslam anchor` wrote it with world frame "bim", so
    // `poses` are world poses): never a query; a target beside the reference, free in the joint
    // optimisation but held at its poses by priors (anchoring.hpp, step 7).
    bool earlier = false;
    // The keyframes' indices in the session's folder, once KeepKeyframes chose some (empty: all,
    // in order): for their clouds' files and the loops' target_index.
    std::vector<size_t> keyframe_ids;
    // A query's start, when given; a split session's pieces have it widened by the way from the
    // start to their first keyframe (anchor_pieces.cpp).
    std::optional<StartHint> start;
    size_t keyframes() const { return poses.size(); }
    size_t KeyframeId(size_t k) const { return keyframe_ids.empty() ? k : keyframe_ids[k]; }
};

struct LoadOptions {
    registration::OrientedCloudConfig cloud;
    scancontext::ScanContextConfig descriptor = scancontext::ScanContextConfig::Indoor();
    bool load_clouds = true;
    // Descriptors missing or of another kind are computed from the clouds (reads every cloud).
    bool compute_descriptors = true;
    int threads = 0;  // 0: all cores
};

// Reads a session for anchoring. Throws common::FileError naming the file on a damaged or
// unreadable session (exit 2), and on a folder that is neither layout.
AnchorSession LoadAnchorSession(const std::filesystem::path& dir, const LoadOptions& options);

// An earlier visit's anchored session (AnchorSession::earlier): a bimslam session whose world
// frame is "bim", as `bimslam anchor` writes OUT/<name>/. Throws common::FileError naming
// session.json for a session in another frame (an odometry session, another tool's layout).
AnchorSession LoadEarlierSession(const std::filesystem::path& dir, const LoadOptions& options);

// Which keyframes of earlier visits' sessions stand for them as a new visit's targets
// (AnchorConfig::earlier_spacing_m): the newest visit's all, an older visit's those farther than
// `spacing` from every kept keyframe of the visits after it (by their world poses). `visit`
// numbers each session's visit, in date order (sessions of one visit adjacent). Returns the kept
// indices per session, ascending.
std::vector<std::vector<size_t>> EarlierTargets(const std::vector<AnchorSession>& sessions,
                                                const std::vector<size_t>& visit, double spacing);

// Keeps the keyframes `keep` (indices, ascending) of a session and the odometry edges between
// kept ones, dropping its odometry verdict: for an earlier visit's session, whose keyframes are
// each held by a prior (AnchorSession::earlier), so that a few of them may stand for it.
void KeepKeyframes(AnchorSession* s, const std::vector<size_t>& keep);

// Reads the oriented clouds of a session loaded without them (LoadOptions::load_clouds false),
// of its kept keyframes only. Throws common::FileError naming a damaged cloud.
void LoadClouds(AnchorSession* s, const LoadOptions& options);

// True when `dir` holds the SC-A-LOAM/LT-mapper layout without session.json and SCDs/.
bool IsForeignSession(const std::filesystem::path& dir);

// The odometry edges of a foreign session: consecutive keyframes, default covariance.
std::vector<io::SessionEdge> EdgesFromPoses(const std::vector<Eigen::Isometry3d>& poses);

}  // namespace bimslam::anchor
