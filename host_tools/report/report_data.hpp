// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Everything the report page shows, gathered from a `bimslam map` output folder into one JSON
// value (embedded in the page; its typed arrays as base64). README.md of this folder lists the
// files read and the fields.
#pragma once

#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>

namespace bimslam::report {

struct ReportConfig {
    // The map is decimated to at most this many points (a laptop's browser renders a few hundred
    // thousand smoothly); the page says how many it shows of how many.
    size_t max_map_points = 300000;
    double plan_cut_height_m = 1.0;       // floor plans cut the model this high above each storey
    size_t max_trajectory_points = 4000;  // per trajectory, evenly thinned
    void Validate() const;  // throws common::Error (kInvalidArgument) naming the field
};

using ReportProgress = std::function<void(const std::string&, double)>;

// Throws common::FileError naming the file when `out` is not a `bimslam map` output (no
// summary.json) or one of its files is damaged.
nlohmann::json CollectReportData(const std::filesystem::path& out, const ReportConfig& config,
                                 const ReportProgress& progress = {});

}  // namespace bimslam::report
