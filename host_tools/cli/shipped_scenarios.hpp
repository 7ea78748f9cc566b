// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The example scenarios of host_tools/simulate/scenarios/, embedded at build time
// (bimslam_embed_files in this folder's CMakeLists.txt), so that `bimslam demo` builds its changed
// building from the same files a user reads and edits, without the source tree at run time.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace bimslam::cli {

// The text of scenarios/<name> (e.g. "changed_building.yaml"); common::Error for another name.
std::string ShippedScenario(std::string_view name);
std::vector<std::string> ShippedScenarioNames();

}  // namespace bimslam::cli
