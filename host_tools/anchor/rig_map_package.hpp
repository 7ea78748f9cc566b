// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The rig's map package (algorithms/localization/rig_map.hpp) of a BIM reference session: the
// target the anchoring builds from it (the same surfel pyramid, descriptors and keyframe poses,
// with the same configuration), so that the rig relocalises against what `bimslam anchor` would.
#pragma once

#include <filesystem>
#include <vector>

#include "algorithms/localization/rig_map.hpp"
#include "host_tools/anchor/anchor_config.hpp"

namespace bimslam::anchor {

// `reference` is a reference session (`bimslam bim2session`, `bimslam map`'s OUT/reference):
// world frame "bim", with its model's file and SHA-256. `storeys` by elevation (the model's);
// each keyframe is placed on the storey at its height. Throws common::FileError naming
// session.json for a session that is not a BIM reference, and whatever reading it throws.
localization::RigMap MakeRigMap(const std::filesystem::path& reference,
                                const std::vector<localization::RigMapStorey>& storeys,
                                const AnchorConfig& config = {});

}  // namespace bimslam::anchor
