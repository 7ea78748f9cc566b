// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The walk of changes_cli_test.cpp (the sample building's ground-floor corridor past an added
// crate, a wall built 3 cm off and a person), its session placed on the ground truth and
// `bimslam changes --truth --json` of it: made once per build of bimslam and shared by the tests
// of the changes_cli_test program (changes_bcf_test.cpp reads its changes.bcf).
//   building.ifc, capture/, anchored/ (the session), out/ (the command's files), summary.json
#pragma once

#include <filesystem>

namespace bimslam::changes_test {

std::filesystem::path Walk();
// The walk's recording time, given to `bimslam changes --date` (changes.bcf's topics' date).
inline constexpr const char* kWalkDate = "2026-03-02T09:30:00Z";

}  // namespace bimslam::changes_test
