// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/changes/session_input.hpp"

#include <string>

#include "algorithms/common/status.hpp"

namespace bimslam::change_detection {

SessionInput LoadAnchoredSession(const std::filesystem::path& dir, const Eigen::Vector3d& origin_m,
                                 bool load_clouds) {
    SessionInput in;
    in.dir = dir;
    io::SessionReadOptions options;
    options.load_clouds = load_clouds;
    in.session = io::ReadSession(dir, options);
    const auto fail = [&](const std::string& what) {
        throw common::FileError(common::StatusCode::kInvalidArgument, dir.string(), 0, what);
    };
    if (!in.session.complete && in.session.keyframes.empty()) {
        fail("not a session: no session.json and no keyframe in it");
    }
    const std::string& frame = in.session.manifest.world_frame;
    if (frame != "bim") {
        fail("its poses are in the '" + frame +
             "' frame, not the model's ('bim'): anchor it to the BIM reference session first "
             "(bimslam anchor), then compare the anchored session");
    }
    if (in.session.keyframes.empty()) {
        fail(std::string("the session has no keyframes: nothing to compare (") +
             io::kNoKeyframesHint + ")");
    }
    Eigen::Isometry3d shift = Eigen::Isometry3d::Identity();
    shift.translation() = -origin_m;
    for (const io::SessionKeyframe& k : in.session.keyframes) {
        in.keyframes.push_back({&k.cloud, shift * k.T_world_lidar});
        in.points += k.cloud.size();
    }
    // The session's own graph, for the refinement (algorithms/changes/pose_refinement.hpp). A
    // recovered session (no session.json) may name keyframes it lost: those edges are dropped.
    for (const io::SessionEdge& e : in.session.edges) {
        const size_t n = in.keyframes.size();
        if (e.from >= n || e.to >= n || e.from == e.to) {
            if (!in.session.complete) continue;
            fail("singlesession_posegraph.g2o: the edge " + std::to_string(e.from) + " -> " +
                 std::to_string(e.to) + " joins keyframes that do not exist (" + std::to_string(n) +
                 " keyframes)");
        }
        in.edges.push_back({e.from, e.to, e.T_from_to, e.information});
    }
    if (load_clouds && in.points == 0) {
        fail("the session's keyframes hold no points: nothing to compare");
    }
    return in;
}

}  // namespace bimslam::change_detection
