// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/anchor/rig_map_package.hpp"

#include <string>

#include "algorithms/common/status.hpp"
#include "algorithms/scancontext/config.hpp"
#include "algorithms/scancontext/session_descriptor.hpp"
#include "host_tools/anchor/anchor_session.hpp"
#include "host_tools/anchor/target.hpp"

namespace bimslam::anchor {

localization::RigMap MakeRigMap(const std::filesystem::path& reference,
                                const std::vector<localization::RigMapStorey>& storeys,
                                const AnchorConfig& config) {
    LoadOptions lo;
    lo.cloud = config.cloud;
    lo.descriptor = config.descriptor;
    lo.threads = config.threads;
    std::vector<AnchorSession> sessions;
    sessions.push_back(LoadAnchorSession(reference, lo));
    const AnchorSession& ref = sessions.front();
    const io::SessionManifest& manifest = ref.session.manifest;
    if (ref.foreign || manifest.world_frame != "bim" || !manifest.model) {
        throw common::FileError(
            common::StatusCode::kInvalidArgument, (reference / "session.json").string(), 0,
            "not a BIM reference session (world frame '" + manifest.world_frame +
                "', no model): make one with "
                "`bimslam bim2session` or give the model alone");
    }
    // The anchoring's target over the reference alone (anchoring.hpp, step 1).
    const Target target(sessions, {{0, ref.poses}}, config);
    localization::RigMap m;
    m.model_file = std::filesystem::path(manifest.model->file).filename().string();
    m.model_sha256 = manifest.model->sha256;
    m.frame = manifest.world_frame;
    m.reference = reference.string();
    m.sensor = manifest.sensor;
    // The descriptors are the session's when made as the anchoring makes them, else computed
    // again that way (LoadAnchorSession): either way, by config.descriptor.
    m.descriptor = scancontext::SessionDescriptor(config.descriptor);
    m.storeys = storeys;
    for (size_t k = 0; k < ref.keyframes(); ++k) {
        m.keyframes.push_back(ref.poses[k]);
        m.keyframe_storey.push_back(
            localization::StoreyAt(storeys, ref.poses[k].translation().z()));
        m.descriptors.push_back(ref.descriptors[k]);
    }
    for (size_t l = 0; l < target.map().levels(); ++l) m.levels.push_back(target.map().level(l));
    return m;
}

}  // namespace bimslam::anchor
