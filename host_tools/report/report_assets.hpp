// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The report page's files, embedded at build time (CMakeLists.txt of this folder generates
// report_assets.cpp from assets/ and Debian's libjs-three).
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace bimslam::report {

// The file's bytes; throws common::Error (kNotFound) for a name that was not embedded.
std::string ReportAsset(std::string_view name);
// The names embedded, in order.
std::vector<std::string> ReportAssetNames();

}  // namespace bimslam::report
