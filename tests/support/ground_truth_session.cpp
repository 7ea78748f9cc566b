// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "tests/support/ground_truth_session.hpp"

#include <algorithm>

#include "algorithms/common/status.hpp"
#include "algorithms/io/session.hpp"
#include "algorithms/io/text_reader.hpp"
#include "algorithms/io/trajectory.hpp"

namespace bimslam::test {

GroundTruthPlacement PlaceSessionOnGroundTruth(const std::filesystem::path& session_dir,
                                               const std::filesystem::path& ground_truth_tum,
                                               const std::filesystem::path& out) {
    const io::Session session = io::ReadSession(session_dir);
    const std::vector<io::StampedPose> truth = io::ReadTum(ground_truth_tum);
    const auto at = [&](int64_t stamp_ns) {
        const auto it =
            std::lower_bound(truth.begin(), truth.end(), stamp_ns,
                             [](const io::StampedPose& p, int64_t t) { return p.stamp_ns < t; });
        if (it == truth.end() || it->stamp_ns != stamp_ns) {
            throw common::Error(common::StatusCode::kInvalidArgument,
                                ground_truth_tum.string() + ": no pose at " +
                                    io::FormatNsAsSeconds(stamp_ns) + " s (a scan of " +
                                    session_dir.string() + "); the lookup must be exact");
        }
        return it->Pose();
    };
    io::SessionManifest manifest = session.manifest;
    manifest.world_frame = "bim";
    manifest.created.clear();
    io::SessionWriterOptions options;
    options.flush_every = 100;
    options.sync_each_file = false;
    io::SessionWriter writer(out, manifest, options);
    for (const io::SessionKeyframe& k : session.keyframes) {
        io::SessionKeyframe placed = k;
        placed.T_odom_lidar = k.T_odom_lidar.value_or(k.T_world_lidar);
        placed.T_world_lidar = at(k.stamp_ns);
        writer.AddKeyframe(placed);
    }
    for (const io::SessionEdge& e : session.edges) writer.AddEdge(e);
    for (const io::StampedPose& p : session.trajectory) {
        writer.AddScanPose(io::StampedPose::FromIsometry(p.stamp_ns, at(p.stamp_ns)));
    }
    writer.Finish();
    return {session.keyframes.size(), session.trajectory.size()};
}

}  // namespace bimslam::test
