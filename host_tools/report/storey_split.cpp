// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/report/storey_split.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "algorithms/common/status.hpp"

namespace bimslam::report {
namespace {

using Label = std::pair<int, int>;  // lower, upper storey

// The storey nearest a sensor at z (its floor at z - height).
int NearestFloor(double z, double height, const std::vector<double>& elevations) {
    int best = 0;
    for (size_t s = 1; s < elevations.size(); ++s) {
        if (std::abs(z - height - elevations[s]) < std::abs(z - height - elevations[size_t(best)]))
            best = int(s);
    }
    return best;
}

Label LabelOf(double z, double height, const std::vector<double>& elevations, double tolerance) {
    const int nearest = NearestFloor(z, height, elevations);
    if (std::abs(z - height - elevations[size_t(nearest)]) <= tolerance) return {nearest, nearest};
    int lower = -1;
    for (size_t s = 0; s < elevations.size(); ++s) {
        if (elevations[s] + height < z) lower = int(s);
    }
    if (lower < 0) return {0, 0};
    const int top = int(elevations.size()) - 1;
    if (lower == top) return {top, top};
    return {lower, lower + 1};
}

// [first, last) of each stretch of equal labels.
std::vector<std::pair<size_t, size_t>> Stretches(const std::vector<Label>& labels) {
    std::vector<std::pair<size_t, size_t>> out;
    for (size_t i = 0; i < labels.size(); ++i) {
        if (i == 0 || labels[i] != labels[i - 1]) out.push_back({i, i});
        out.back().second = i + 1;
    }
    return out;
}

}  // namespace

void StoreySplitConfig::Validate() const {
    const auto bad = [](const std::string& what) {
        throw common::Error(common::StatusCode::kInvalidArgument, "StoreySplitConfig: " + what);
    };
    if (!(tolerance_m > 0)) bad("tolerance_m must be > 0");
    if (!(bin_m > 0)) bad("bin_m must be > 0");
    if (!(max_height_m > bin_m)) bad("max_height_m must be > bin_m");
}

double SensorHeightAboveFloor(const std::vector<Eigen::Vector3d>& points,
                              const std::vector<double>& elevations,
                              const StoreySplitConfig& config) {
    config.Validate();
    std::vector<size_t> bins(size_t(std::ceil(config.max_height_m / config.bin_m)), 0);
    for (const Eigen::Vector3d& p : points) {
        double below = std::numeric_limits<double>::quiet_NaN();
        for (const double e : elevations) {
            if (e <= p.z()) below = e;
        }
        const double h = p.z() - below;  // NaN below the lowest floor: not counted
        if (h >= 0 && h < config.max_height_m)
            ++bins[std::min(bins.size() - 1, size_t(h / config.bin_m))];
    }
    const auto fullest = std::max_element(bins.begin(), bins.end());
    if (*fullest == 0) return 0;
    return (double(fullest - bins.begin()) + 0.5) * config.bin_m;
}

std::vector<StoreyRun> SplitByStorey(const std::vector<Eigen::Vector3d>& points,
                                     const std::vector<double>& elevations,
                                     const StoreySplitConfig& config) {
    config.Validate();
    if (points.empty() || elevations.empty()) return {};
    const double height = SensorHeightAboveFloor(points, elevations, config);
    std::vector<Label> labels;
    for (const Eigen::Vector3d& p : points) {
        labels.push_back(LabelOf(p.z(), height, elevations, config.tolerance_m));
    }
    // A "flight" that climbs less than the tolerance is a bump on a floor.
    for (const auto& [first, last] : Stretches(labels)) {
        if (labels[first].first == labels[first].second) continue;
        double lo = points[first].z(), hi = lo;
        for (size_t i = first; i < last; ++i) {
            lo = std::min(lo, points[i].z());
            hi = std::max(hi, points[i].z());
        }
        if (hi - lo >= config.tolerance_m) continue;
        const int floor = NearestFloor(0.5 * (lo + hi), height, elevations);
        for (size_t i = first; i < last; ++i) labels[i] = {floor, floor};
    }
    std::vector<StoreyRun> runs;
    for (const auto& [first, last] : Stretches(labels)) {
        StoreyRun run{labels[first].first, labels[first].second, {}};
        if (first > 0) run.points.push_back(points[first - 1]);
        run.points.insert(run.points.end(), points.begin() + long(first),
                          points.begin() + long(last));
        runs.push_back(std::move(run));
    }
    return runs;
}

}  // namespace bimslam::report
