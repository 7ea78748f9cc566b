// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// bimslam live's page, embedded at build time (CMakeLists.txt of this folder generates
// live_assets.cpp from assets/).
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace bimslam::live {

// The file's bytes; throws common::Error (kNotFound) for a name that was not embedded.
std::string LiveAsset(std::string_view name);
// The names embedded, in order.
std::vector<std::string> LiveAssetNames();

}  // namespace bimslam::live
