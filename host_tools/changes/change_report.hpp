// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The files of `bimslam changes` for one session (their layout: README.md in this folder):
//   changes.json      new objects, missing and deviating elements, transient clusters, parameters
//   new_objects.ply   the new objects' voxel meshes, a colour and an object index per vertex
//   map_bim.ply       the merged map, with per-point distance, element, keyframes, class, object
//   map_bim.las       the same points as ASPRS LAS 1.4 (map_las.hpp)
//   elements.csv      one row per physical element: verdict, areas, rays, support, deviation
// Coordinates are the model's ("bim" frame, metres; BimModel::origin_m added back).
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "algorithms/changes/change_detector.hpp"
#include "host_tools/bim/bim_model.hpp"
#include "host_tools/changes/bim_change_model.hpp"
#include "host_tools/changes/session_input.hpp"

namespace bimslam::change_detection {

// What a run found for one session, with what the files need around it.
struct SessionChanges {
    std::string label;  // the session's name in the files (its folder's name)
    const SessionInput* input = nullptr;
    changes::ChangeResult result;
    std::vector<ObjectPlace> places;             // per new object
    std::vector<std::string> object_global_ids;  // per new object, as in the updated IFC
    // map_bim.las's point source id: the 1-based visit in a `bimslam map` project, 1 for a lone
    // `bimslam changes` run.
    uint16_t visit = 1;
};

struct ModelInfo {
    std::filesystem::path file;
    std::string sha256;
};

// changes.json as a JSON value (schema: README.md, "changes.json").
nlohmann::json ChangesJson(const bim::BimModel& model, const ModelInfo& info,
                           const SessionChanges& found,
                           const changes::ChangeDetectorConfig& config);

// The RGB colour of new object i (distinct hues by the golden angle).
std::array<uint8_t, 3> ObjectColor(size_t i);

// Writes changes.json, new_objects.ply, map_bim.ply, map_bim.las and elements.csv into `dir`
// (which exists).
// Throws common::FileError naming the file that cannot be written.
void WriteChangeFiles(const std::filesystem::path& dir, const bim::BimModel& model,
                      const ModelInfo& info, const SessionChanges& found,
                      const changes::ChangeDetectorConfig& config);

}  // namespace bimslam::change_detection
