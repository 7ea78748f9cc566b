// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// `bimslam report`: one self-contained HTML page from a `bimslam map` output folder. The page's
// HTML, CSS and JavaScript are files in assets/, embedded at build time with three.js r111 and its
// OrbitControls from Debian's libjs-three (report_assets.hpp); the data is the JSON of
// CollectReportData. Nothing is fetched when the page is opened.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "host_tools/report/report_data.hpp"

namespace bimslam::report {

// The page for `data`: the template with every asset and the data inlined.
std::string BuildPage(const nlohmann::json& data);

// Collects the data of `out` and writes the page to `html` (atomically). Throws what
// CollectReportData throws, and common::FileError when `html` cannot be written.
void WriteReport(const std::filesystem::path& out, const std::filesystem::path& html,
                 const ReportProgress& progress = {}, const ReportConfig& config = {});

// A digest of the embedded assets: a new build with another page re-runs `bimslam map`'s report.
std::string PageVersion();

}  // namespace bimslam::report
