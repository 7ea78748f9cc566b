// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/scancontext/config.hpp"

#include <cmath>
#include <numbers>
#include <sstream>
#include <string>

#include "algorithms/common/status.hpp"

namespace bimslam::scancontext {
namespace {

template <typename T>
[[noreturn]] void Fail(const char* field, T value, const char* requirement) {
    std::ostringstream os;
    os << "ScanContextConfig." << field << " = " << value << ": " << requirement;
    throw common::Error(common::StatusCode::kInvalidArgument, os.str());
}

}  // namespace

std::string_view ToString(DescriptorKind kind) {
    switch (kind) {
        case DescriptorKind::kOutdoor:
            return "outdoor";
        case DescriptorKind::kIndoor:
            return "indoor";
    }
    return "unknown";
}

std::optional<DescriptorKind> ParseDescriptorKind(std::string_view name) {
    if (name == "outdoor") return DescriptorKind::kOutdoor;
    if (name == "indoor") return DescriptorKind::kIndoor;
    return std::nullopt;
}

ScanContextConfig ScanContextConfig::Outdoor() { return ScanContextConfig{}; }

std::string_view ToString(IndoorCellRule rule) {
    return rule == IndoorCellRule::kZSpan ? "z_span" : "z_stack";
}

std::optional<IndoorCellRule> ParseIndoorCellRule(std::string_view name) {
    if (name == "z_span") return IndoorCellRule::kZSpan;
    if (name == "z_stack") return IndoorCellRule::kZStack;
    return std::nullopt;
}

ScanContextConfig ScanContextConfig::Indoor() {
    ScanContextConfig c;
    c.kind = DescriptorKind::kIndoor;
    c.max_radius = 10.0;
    // The z-span does not depend on an offset; zero keeps the field honest.
    c.lidar_height = 0.0;
    return c;
}

double ScanContextConfig::SectorAngle() const {
    return 2.0 * std::numbers::pi / static_cast<double>(num_sectors);
}

void ScanContextConfig::Validate() const {
    if (kind != DescriptorKind::kOutdoor && kind != DescriptorKind::kIndoor) {
        Fail("kind", static_cast<int>(kind), "must be Outdoor or Indoor");
    }
    if (num_rings < 1 || num_rings > kMaxRings) {
        Fail("num_rings", num_rings, "must be in [1, 500]");
    }
    if (num_sectors < 2 || num_sectors > kMaxSectors) {
        Fail("num_sectors", num_sectors, "must be in [2, 720]");
    }
    if (!std::isfinite(max_radius) || max_radius <= 0.0) {
        Fail("max_radius", max_radius, "must be a finite number of metres > 0");
    }
    if (!std::isfinite(lidar_height)) {
        Fail("lidar_height", lidar_height, "must be finite (metres)");
    }
    if (indoor_min_points < 1) {
        Fail("indoor_min_points", indoor_min_points, "must be >= 1");
    }
    if (!std::isfinite(indoor_min_z_span) || indoor_min_z_span < 0.0) {
        Fail("indoor_min_z_span", indoor_min_z_span, "must be a finite number of metres >= 0");
    }
    if (num_candidates < 1) {
        Fail("num_candidates", num_candidates, "must be >= 1");
    }
    if (!std::isfinite(search_ratio) || search_ratio < 0.0 || search_ratio > 1.0) {
        Fail("search_ratio", search_ratio, "must be in [0, 1]");
    }
}

}  // namespace bimslam::scancontext
