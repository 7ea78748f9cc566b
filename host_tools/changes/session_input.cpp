#include "host_tools/changes/session_input.hpp"

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
    if (in.session.keyframes.empty()) fail("the session has no keyframes: nothing to compare");
    Eigen::Isometry3d shift = Eigen::Isometry3d::Identity();
    shift.translation() = -origin_m;
    for (const io::SessionKeyframe& k : in.session.keyframes) {
        in.keyframes.push_back({&k.cloud, shift * k.T_world_lidar});
        in.points += k.cloud.size();
    }
    if (load_clouds && in.points == 0) {
        fail("the session's keyframes hold no points: nothing to compare");
    }
    return in;
}

}  // namespace bimslam::change_detection
