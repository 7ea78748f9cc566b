// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Planar polylines: resampling at a fixed spacing along their length (walks, coverage paths).
#pragma once

#include <Eigen/Core>
#include <vector>

namespace bimslam::common {

// Points every `spacing` metres along the polyline, starting at its first point. Open: the last
// point is appended when the spacing does not land on it. Closed: the segment from the last
// point back to the first is walked too, and nothing is appended. `points` must not be empty;
// `spacing` must be > 0.
std::vector<Eigen::Vector2d> ResamplePolyline(const std::vector<Eigen::Vector2d>& points,
                                              double spacing, bool closed);

}  // namespace bimslam::common
