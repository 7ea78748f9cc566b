// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// A walk split by storey for the report's floor plans and its 3D view's storey filter (issue 31,
// item 6): each pose is on a storey's floor when its height is the sensor's height above that
// floor, give or take a tolerance, and on a flight when it lies between two floors' heights. The
// sensor's height above its floor is not known to the report (a Go1's and a hand-held rig's
// differ, and a recording may come without its mount), so it is taken from the walk itself: the
// most common height above the storey below (a walk spends most of its time on floors).
#pragma once

#include <Eigen/Core>
#include <vector>

namespace bimslam::report {

struct StoreySplitConfig {
    double tolerance_m = 0.25;  // |z - (elevation + sensor height)| on a floor (gait, bumps)
    double bin_m = 0.05;        // of the heights' histogram
    double max_height_m = 2.5;  // a sensor higher above its floor than this is not on it
    void Validate() const;      // throws common::Error (kInvalidArgument) naming the field
};

// A stretch of the walk on one floor (lower == upper) or on a flight between two (lower + 1 ==
// upper). Each run after the first starts with the last point of the run before, so that the
// plans' lines join.
struct StoreyRun {
    int lower = 0, upper = 0;  // indices into the elevations
    std::vector<Eigen::Vector3d> points;
    bool OnFlight() const { return lower != upper; }
    bool On(int storey) const { return storey == lower || storey == upper; }
};

// The sensor's height above its floor: the centre of the fullest histogram bin of z minus the
// elevation of the storey below (heights in [0, max_height_m]); 0 for no point there.
double SensorHeightAboveFloor(const std::vector<Eigen::Vector3d>& points,
                              const std::vector<double>& elevations,
                              const StoreySplitConfig& config = {});

// The runs of `points` (a walk in time order) against the storeys' `elevations` (lowest first, the
// points' frame). Below the lowest floor counts as on it, above the highest as on that; a flight
// run that climbs less than the tolerance (a bump) belongs to the floor nearest its middle. Empty
// for no point or no storey.
std::vector<StoreyRun> SplitByStorey(const std::vector<Eigen::Vector3d>& points,
                                     const std::vector<double>& elevations,
                                     const StoreySplitConfig& config = {});

}  // namespace bimslam::report
