// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The building's history over its visits (issue 33, item 3; README.md of this folder, "History"):
// OUT/history.json, from each visit's changes (changes.json, elements.csv and map_bim.ply of its
// anchored recordings):
// - every element's verdict per visit (confirmed, missing, deviating with its offset, not
//   observed), the visits it was first and last seen as built, its last deviation;
// - the new objects followed from visit to visit by place and shape: the same object seen again,
//   moved (its offset), gone (its place seen empty), or not observed (its place not seen);
// - each visit's changes since the previous visit (new, gone, moved, newly missing, newly
//   deviating, reappeared) and since the model (what differs from it as of that visit);
// - the contradictions: an element that one visit found missing or deviating and the next visit
//   that saw it found in place (or built again), kept with both verdicts, never dropped.
// BuildHistory is pure (the visits' findings in, the JSON out); ReadVisitFindings reads a visit.
#pragma once

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "host_tools/changes/change_evaluation.hpp"

namespace bimslam::mapping {

struct HistoryConfig {
    // The same object in place: the change evaluation's match (change_evaluation.hpp): boxes of
    // 3D IoU at least this, or centres within this.
    double same_min_iou = 0.25;
    double same_max_centroid_m = 0.3;
    // A part of a known object: a visit that saw an object from one side only finds a box that
    // is a slice of the object's (the sample office's Go1 visit, walking past room 0.02's door,
    // found the bookcase's west face alone: 5 cm of its 1.2 m, its centre 0.6 m off). An object
    // with at least part_min_inside of its box's volume inside a known object's box grown by
    // part_margin_m (a voxel of the map: a face lies on the box's side) is that object seen in
    // part, not a new one; the known box stays as it was.
    double part_min_inside = 0.8;
    double part_margin_m = 0.05;
    // A moved object: one of the same shape (SameShape, object_tracks.hpp: its height within
    // shape_tolerance relative, or shape_tolerance_m, whichever is larger, and its volume; a box
    // of the map's 5 cm voxels measures an object to a few cm; a crate of 0.8 x 0.6 x 0.8 m and a
    // cabinet of 1.0 x 0.6 x 1.0 m are two objects) on the same storey, within moved_max_m, whose
    // old place the visit saw empty.
    double moved_max_m = 10.0;
    double shape_tolerance = 0.1;
    double shape_tolerance_m = 0.1;
    // The voxel solids' volumes (changes.json's volume_m3) agree within this share, where the
    // plans do not (older files' axis-aligned boxes, which a turn about z makes larger: a 0.6 m
    // crate turned 30 degrees measures 0.82 m).
    double volume_tolerance = 0.35;
    // An old place seen empty: of the cells (cell_m) wholly inside its footprint that no object
    // of the visit covers, at least min_floor_seen have a map point within floor_band_m of the
    // object's bottom: the floor it stood on, seen where it stood. An object still standing
    // hides that floor from every viewpoint, and a sparse sensor's rings sweep a seen floor's
    // cells only in part (a 16-beam OS1 carried by hand: a quarter to a half of 10 cm cells), so
    // a quarter is evidence. Fewer than min_cells such cells, or less seen: not observed.
    double cell_m = 0.1;
    double floor_band_m = 0.1;
    double min_floor_seen = 0.25;
    size_t min_cells = 4;
    nlohmann::json ToJson() const;
};

// What one visit found, merged over its anchored recordings (ReadVisitFindings's rules).
struct VisitFindings {
    std::string label;
    int64_t start_ns = 0;
    std::vector<std::string> recordings;  // those compared with the model (anchored)
    change_detection::FoundChanges found;
    std::vector<std::string> object_recordings;  // per found.objects: the recording that found it
};

// A visit's changes/<recording>/ folders, merged: an element's verdict is that of the recording
// that observed most of it (the largest expected visible area among those not "not_observed"); a
// new object that another recording of the visit found in the same place is counted once; the
// maps are joined. A visit with no changes folder (not anchored) has no findings: everything
// not observed. Throws common::FileError naming a damaged file.
VisitFindings ReadVisitFindings(const std::filesystem::path& visit_dir, const std::string& label,
                                int64_t start_ns);

// The history of the visits (in date order) as history.json (README.md, "History").
nlohmann::json BuildHistory(const std::vector<VisitFindings>& visits,
                            const HistoryConfig& config = {});

// The newest visit's changes since the previous one, counted, for the summaries.
nlohmann::json HistoryCounts(const nlohmann::json& history);

}  // namespace bimslam::mapping
