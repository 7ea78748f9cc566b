// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The ground around the building, for the points off the model's footprint (issue 33: "an
// extension that the model lacks", the paper's map extension). Off the footprint a map holds the
// ground, which no model holds, and what stands on it: an annex or a shed the model lacks, seen
// through the windows or walked into. Change detection compares the second and not the first
// (ChangeDetectorConfig::extension_margin_m), telling them apart by the height over the lowest of
// those points around each one: no ground model, no slope assumed, a kerb under the clearance.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <vector>

namespace bimslam::changes {

// For each of `points` (indices into xyz): 1 where it stands more than clearance_m above the
// lowest of `points` in its cell of cell_m in plan or the eight around it (the ground within
// 1.5 cells), else 0.
std::vector<uint8_t> AboveLocalGround(std::span<const Eigen::Vector3f> xyz,
                                      std::span<const uint32_t> points, float cell_m,
                                      float clearance_m);

}  // namespace bimslam::changes
