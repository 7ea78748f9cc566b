// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The report's deviation views (issue 34 item 3): each compared element's measured deviation and
// its verdict against the QA tolerance (elements.csv, `bimslam changes --tolerance`), which the
// plans and the 3D view colour elements by, and per storey the histogram of the map's
// point-to-model distances (map_bim.ply's scalar_distance: the signed distances change detection
// measured (algorithms/changes/model_distance.hpp), read back, not measured again).
#pragma once

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "host_tools/bim/bim_model.hpp"

namespace bimslam::report {

// The tolerance verdicts of elements.csv, as the page codes them.
enum DeviationCode : int { kWithin = 0, kBeyond = 1, kNotObserved = 2 };

// The elements of the visit's recordings' change folders (each with changes.json and
// elements.csv): {tolerance_m, elements: [[GlobalId, code, offset_m], ...]}. By GlobalId: the
// changes step reads the model with its spaces, the report without, so indices differ. An
// element several recordings compared takes the verdict of the one that measured it (within or
// beyond before not observed), then of the one with the most support points. Null when no folder
// has an elements.csv with tolerance verdicts (an output of an older bimslam).
nlohmann::json ElementDeviations(const std::vector<std::filesystem::path>& change_dirs);

// Per storey the distances to the model of the map's points on it (class "model": within the
// new-object threshold of an element), counted in bins of bin_m over [-range_m, range_m].
class DistanceHistogram {
public:
    DistanceHistogram(size_t storeys, double range_m, double bin_m);
    // A map point of `storey` (StoreyOfPoint) at signed distance d (m); points of other classes
    // are not counted.
    void Add(int storey, float distance_m, int point_class);
    // {bin_cm, range_cm, storeys: [{name, counts: [...], points, mean_cm, rms_cm}]}.
    nlohmann::json ToJson(const bim::BimModel& model) const;

private:
    double range_m_, bin_m_;
    std::vector<std::vector<uint64_t>> counts_;
    std::vector<double> sum_, sum2_;
};

}  // namespace bimslam::report
