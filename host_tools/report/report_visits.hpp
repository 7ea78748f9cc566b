// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The project's visits as the report shows them (issue 33 item 6): each visit's walks in BIM
// coordinates for the timeline's plans, and the building's history (OUT/history.json,
// host_tools/mapping/README.md "History") with each element's box for the change list, the plans
// and the 3D view.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>

#include "host_tools/bim/bim_model.hpp"

namespace bimslam::report {

// The visits of summary.json (`visits`, in date order): [{label, start, recordings: [{name,
// anchor_verdict}], walks: [{name, runs}]}], a walk per recording anchored (or anchored in parts)
// from OUT/<visit dir>/anchor/<name>/trajectory_bim.tum, split by storey and thinned to at most
// max_points (StoreyRuns). Null for a summary without visits (an older bimslam).
nlohmann::json VisitWalks(const std::filesystem::path& out, const nlohmann::json& summary,
                          const bim::BimModel& model, size_t max_points);

// OUT/history.json with each element's box in the model's frame (`min`, `max`; elements the model
// no longer has none), or null when there is none (an older bimslam). Throws common::FileError
// naming the file when it is damaged.
nlohmann::json HistoryForPage(const std::filesystem::path& out, const bim::BimModel& model);

}  // namespace bimslam::report
