// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The as-is model of a project (issue 33, item 4; README.md of this folder, "The as-is model"):
// OUT/model_asis.ifc is the model file, byte for byte, with the project's history appended
// (change_detection::IfcAppender, as `bimslam changes` updates a model):
// - every new object present after the newest visit (history.json's objects not gone) as an
//   IfcBuildingElementProxy, its mesh as the visit that last saw it found it (that recording's
//   new_objects.ply), in its storey, with a property set bimslam_History;
// - every element some visit observed: a property set bimslam_History (its verdict per visit,
//   first and last seen as built, its last deviation, its state as is);
// - the elements missing as of the newest visit in an IfcGroup "bimslam missing elements".
#pragma once

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "host_tools/bim/bim_model.hpp"
#include "host_tools/changes/ifc_update.hpp"

namespace bimslam::mapping {

// `out` is the project's folder (its visits' changes hold the objects' meshes), `text` the model
// file's (`name` in errors), `model` what bim::LoadIfc made of it, `history` history.json's value,
// `seed` the seed of the new GlobalIds. Throws common::FileError naming a damaged mesh file.
change_detection::IfcUpdate AsIsIfc(const std::filesystem::path& out, const std::string& name,
                                    const std::string& text, const bim::BimModel& model,
                                    const nlohmann::json& history, uint64_t seed);

}  // namespace bimslam::mapping
