// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The sample buildings' types (sample_building.hpp) and the choice of layout; each layout's plan is
// in its own file (sample_office.cpp, sample_hall.cpp, sample_symmetric.cpp), assembled from the
// parts of sample_builder.hpp. sample_building_ifc.cpp writes a layout as IFC4.
#include "host_tools/bim/sample_building.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "algorithms/common/status.hpp"
#include "host_tools/bim/sample_builder.hpp"

namespace bimslam::bim {
namespace {
using Eigen::AlignedBox2d;
using Eigen::Vector2d;
}  // namespace

std::string_view ToString(BuildingLayout layout) {
    switch (layout) {
        case BuildingLayout::kOffice:
            return "office";
        case BuildingLayout::kHall:
            return "hall";
        case BuildingLayout::kSymmetric:
            return "symmetric";
        case BuildingLayout::kWing:
            return "wing";
    }
    return "unknown";
}

std::optional<BuildingLayout> ParseBuildingLayout(std::string_view name) {
    for (const BuildingLayout l : {BuildingLayout::kOffice, BuildingLayout::kHall,
                                   BuildingLayout::kSymmetric, BuildingLayout::kWing}) {
        if (ToString(l) == name) return l;
    }
    return std::nullopt;
}

std::string_view ToString(RoomKind kind) {
    switch (kind) {
        case RoomKind::kCorridor:
            return "corridor";
        case RoomKind::kStair:
            return "stair";
        case RoomKind::kOffice:
            return "office";
        case RoomKind::kOpenOffice:
            return "open office";
        case RoomKind::kMeeting:
            return "meeting";
        case RoomKind::kKitchen:
            return "kitchen";
        case RoomKind::kToilets:
            return "toilets";
        case RoomKind::kStorage:
            return "storage";
        case RoomKind::kHall:
            return "hall";
        case RoomKind::kClassroom:
            return "classroom";
        case RoomKind::kLibrary:
            return "library";
    }
    return "unknown";
}

std::string_view ToString(FurnitureKind kind) {
    switch (kind) {
        case FurnitureKind::kDesk:
            return "desk";
        case FurnitureKind::kTable:
            return "table";
        case FurnitureKind::kCabinet:
            return "cabinet";
        case FurnitureKind::kShelf:
            return "shelf";
    }
    return "unknown";
}

void SampleBuildingOptions::Validate() const {
    if (!ParseBuildingLayout(ToString(layout))) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            "sample building: layout " + std::to_string(int(layout)) +
                                " is none of office, hall, symmetric, wing");
    }
    if (length_unit_m != 1.0 && length_unit_m != 0.001) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            "sample building: length_unit_m must be 1 (metre) or 0.001 "
                            "(millimetre), not " +
                                std::to_string(length_unit_m));
    }
    if (storeys != 0 && (layout != BuildingLayout::kHall || storeys < 2 || storeys > 8)) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            "sample building: storeys " + std::to_string(storeys) +
                                (layout == BuildingLayout::kHall
                                     ? " is not 2 to 8"
                                     : ": only the hall layout takes another number of storeys"));
    }
}

AlignedBox2d SampleRoom::Bounds() const {
    AlignedBox2d box;
    for (const Vector2d& p : polygon) box.extend(p);
    return box;
}

double SampleRoom::Area() const {
    double twice = 0;
    for (size_t i = 0; i < polygon.size(); ++i) {
        const Vector2d& a = polygon[i];
        const Vector2d& b = polygon[(i + 1) % polygon.size()];
        twice += a.x() * b.y() - b.x() * a.y();
    }
    return 0.5 * twice;
}

bool SampleRoom::Contains(const Vector2d& p) const {
    // Convex and counter-clockwise: p is on the left of (or on) every edge.
    for (size_t i = 0; i < polygon.size(); ++i) {
        const Vector2d e = polygon[(i + 1) % polygon.size()] - polygon[i];
        const Vector2d v = p - polygon[i];
        if (e.x() * v.y() - e.y() * v.x() < -1e-9) return false;
    }
    return !polygon.empty();
}

bool SampleWall::Slanted() const {
    const Vector2d d = end - start;
    return std::abs(d.x()) > 1e-9 && std::abs(d.y()) > 1e-9;
}

AlignedBox2d SampleStair::Footprint() const {
    const Vector2d left(-direction.y(), direction.x());
    AlignedBox2d box;
    for (const double s : {-0.5, 0.5}) {
        box.extend(foot + s * width_m * left);
        box.extend(foot + s * width_m * left + RunLength() * direction);
    }
    return box;
}

AlignedBox2d SampleFurniture::Footprint() const {
    const Vector2d half =
        rotated ? Vector2d(size.y(), size.x()) / 2 : Vector2d(size.x(), size.y()) / 2;
    return {centre - half, centre + half};
}

int SampleLayout::Corridor(int storey) const {
    for (size_t r = 0; r < rooms.size(); ++r) {
        if (rooms[r].storey == storey &&
            (rooms[r].kind == RoomKind::kCorridor || rooms[r].kind == RoomKind::kHall)) {
            return int(r);
        }
    }
    return -1;
}

Eigen::AlignedBox3d SampleLayout::Bounds() const {
    Eigen::AlignedBox3d box;
    for (const SampleSlab& s : slabs) {
        const double top = storeys[s.storey].elevation_m + s.top_m;
        box.extend(Eigen::Vector3d(s.outline.min().x(), s.outline.min().y(), top - s.thickness_m));
        box.extend(Eigen::Vector3d(s.outline.max().x(), s.outline.max().y(), top));
    }
    for (const SampleWall& w : walls) {
        const double z = storeys[w.storey].elevation_m;
        const Vector2d n = Vector2d(-w.Direction().y(), w.Direction().x()) * (w.thickness_m / 2);
        const std::array<Vector2d, 4> corners{w.start + n, w.start - n, w.end + n, w.end - n};
        for (const Vector2d& p : corners) {
            box.extend(Eigen::Vector3d(p.x(), p.y(), z));
            box.extend(Eigen::Vector3d(p.x(), p.y(), z + w.height_m));
        }
    }
    return box;
}

SampleLayout SampleBuildingLayout(const SampleBuildingOptions& options) {
    options.Validate();
    switch (options.layout) {
        case BuildingLayout::kHall:
            return HallLayout(options);
        case BuildingLayout::kSymmetric:
            return SymmetricLayout(options);
        case BuildingLayout::kWing:
            return WingLayout(options);
        case BuildingLayout::kOffice:
            break;
    }
    return OfficeLayout(options);
}

}  // namespace bimslam::bim
