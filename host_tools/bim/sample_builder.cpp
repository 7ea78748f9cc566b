// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The parts every sample layout is assembled from (sample_builder.hpp).
#include "host_tools/bim/sample_builder.hpp"

#include <algorithm>
#include <cmath>

#include "algorithms/common/status.hpp"

namespace bimslam::bim {
namespace {

using Eigen::AlignedBox2d;
using Eigen::Vector2d;

// The strip of thickness t just outside the side of b that faces `side` (a unit axis), as long as
// that side.
AlignedBox2d Outside(const AlignedBox2d& b, const Vector2d& side, double t) {
    AlignedBox2d s = b;
    if (side.x() > 0.5) {
        s.min().x() = b.max().x();
        s.max().x() = b.max().x() + t;
    } else if (side.x() < -0.5) {
        s.min().x() = b.min().x() - t;
        s.max().x() = b.min().x();
    } else if (side.y() > 0.5) {
        s.min().y() = b.max().y();
        s.max().y() = b.max().y() + t;
    } else {
        s.min().y() = b.min().y() - t;
        s.max().y() = b.min().y();
    }
    return s;
}

// b with its side facing `side` (a unit axis) moved out by m.
AlignedBox2d Extend(AlignedBox2d b, const Vector2d& side, double m) {
    if (side.x() > 0.5) {
        b.max().x() += m;
    } else if (side.x() < -0.5) {
        b.min().x() -= m;
    } else if (side.y() > 0.5) {
        b.max().y() += m;
    } else {
        b.min().y() -= m;
    }
    return b;
}

}  // namespace

std::vector<Vector2d> Rect(double x0, double y0, double x1, double y1) {
    return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

std::string Metres(double v) {
    const long dm = std::lround(v * 10);
    return std::to_string(dm / 10) + "." + std::to_string(dm % 10);
}

std::string RoomNumber(int storey, int index) {
    return std::to_string(storey) + "." + (index < 10 ? "0" : "") + std::to_string(index);
}

int SampleBuilder::Wall(std::string name, int storey, Vector2d a, Vector2d b, double thickness,
                        bool exterior) {
    const double height = out.storeys[storey].height_m - out.slab_m;  // to the slab above
    out.walls.push_back({std::move(name), storey, a, b, thickness, height, exterior});
    return int(out.walls.size()) - 1;
}

int SampleBuilder::Room(int storey, int index, RoomKind kind, std::string name,
                        std::vector<Vector2d> polygon) {
    out.rooms.push_back(
        {RoomNumber(storey, index), std::move(name), storey, kind, std::move(polygon)});
    return int(out.rooms.size()) - 1;
}

void SampleBuilder::Door(int storey, int wall, Vector2d centre, double width, int leaves, int from,
                         int into) {
    const SampleWall& w = out.walls[wall];
    SampleDoor d;
    std::string suffix;
    if (from >= 0) {
        const auto n = std::count_if(out.doors.begin(), out.doors.end(),
                                     [&](const SampleDoor& o) { return o.rooms[1] == into; });
        suffix = std::to_string(n + 1);
    } else {
        // The side of the footprint the exterior wall is on.
        const Vector2d half = out.footprint_m / 2;
        if (std::abs(w.Direction().y()) > 0.5) {
            suffix = w.start.x() < half.x() ? "W" : "E";
        } else {
            suffix = w.start.y() < half.y() ? "S" : "N";
        }
    }
    d.name = "Door " + out.rooms[into].number + "-" + suffix;
    d.storey = storey;
    d.wall = wall;
    d.offset_m = (centre - w.start).dot(w.Direction());
    d.centre = centre;
    d.width_m = width;
    d.leaves = leaves;
    d.rooms = {from, into};
    out.doors.push_back(std::move(d));
}

void SampleBuilder::Windows(int room, int wall, Vector2d a, Vector2d b) {
    const double length = (b - a).norm();
    if (length < 1.5) return;
    const int n = std::max(1, int(length / 2.7));
    const SampleWall& w = out.walls[wall];
    for (int i = 0; i < n; ++i) {
        SampleWindow win;
        const auto k = std::count_if(out.windows.begin(), out.windows.end(),
                                     [&](const SampleWindow& o) { return o.room == room; });
        win.name = "Window " + out.rooms[room].number + "-" + std::to_string(k + 1);
        win.storey = w.storey;
        win.wall = wall;
        // On the wall's centreline, opposite the point along the room's edge.
        const Vector2d on_edge = a + (b - a) * ((i + 0.5) / n);
        win.offset_m = (on_edge - w.start).dot(w.Direction());
        win.centre = w.start + win.offset_m * w.Direction();
        win.width_m = length >= 2.5 ? 1.5 : 1.0;
        win.room = room;
        out.windows.push_back(std::move(win));
    }
}

void SampleBuilder::WindowsOnExteriorEdges(int room, const std::vector<int>& walls) {
    const std::vector<Vector2d> poly = out.rooms[room].polygon;  // a copy: Windows() appends
    for (size_t i = 0; i < poly.size(); ++i) {
        const Vector2d a = poly[i], c = poly[(i + 1) % poly.size()];
        for (const int k : walls) {
            const SampleWall& w = out.walls[k];
            const Vector2d d = w.Direction(), n(-d.y(), d.x());
            // Both ends half the wall's thickness from its centreline, within its length.
            auto on_face = [&](const Vector2d& p) {
                const double along = (p - w.start).dot(d);
                return std::abs(std::abs((p - w.start).dot(n)) - w.thickness_m / 2) < 1e-9 &&
                       along > -1e-9 && along < w.Length() + 1e-9;
            };
            if (on_face(a) && on_face(c)) {
                Windows(room, k, a, c);
                break;
            }
        }
    }
}

void SampleBuilder::Column(int room, Vector2d centre, double size, bool round) {
    const int storey = out.rooms[room].storey;
    const auto n = std::count_if(out.columns.begin(), out.columns.end(),
                                 [&](const SampleColumn& c) { return c.room == room; });
    out.columns.push_back({"Column " + out.rooms[room].number + "-" + std::to_string(n + 1), storey,
                           room, centre, size, round, out.storeys[storey].height_m - out.slab_m});
}

int StairRoom(const SampleLayout& layout, int storey) {
    for (size_t r = 0; r < layout.rooms.size(); ++r) {
        if (layout.rooms[r].storey == storey && layout.rooms[r].kind == RoomKind::kStair) {
            return int(r);
        }
    }
    return -1;
}

AlignedBox2d SampleBuilder::Stair(const StairSpec& spec) {
    SampleStair stair;
    stair.name = spec.name;
    stair.storey = spec.storey;
    stair.room_bottom = spec.room_bottom;
    stair.room_top = spec.room_top;
    stair.width_m = spec.width_m;
    stair.foot = spec.foot;
    stair.direction = spec.direction;
    stair.riser_m = spec.riser_m;
    stair.tread_m = spec.tread_m;
    const double rise = out.storeys[spec.storey].height_m;
    stair.risers = int(std::lround(rise / spec.riser_m));
    if (std::abs(stair.risers * spec.riser_m - rise) > 1e-9) {
        throw common::Error(common::StatusCode::kInternal,
                            spec.name + ": risers of " + std::to_string(spec.riser_m) +
                                " m do not divide the storey height " + std::to_string(rise));
    }
    out.stairs.push_back(stair);

    const Vector2d up = spec.direction, left(-up.y(), up.x());
    AlignedBox2d well = Extend(stair.Footprint(), -up, 0.2);
    if (!spec.wall_left) well = Extend(well, left, 0.1);
    if (!spec.wall_right) well = Extend(well, -left, 0.1);
    const double rail = 0.05;
    SampleRailing railing{spec.name + " well railing", spec.storey + 1, {}, 1.0};
    if (!spec.wall_left) railing.parts.push_back(Outside(well, left, rail));
    if (!spec.wall_right) railing.parts.push_back(Outside(well, -left, rail));
    AlignedBox2d bottom = Outside(well, -up, rail);  // with the corners of the open sides
    if (!spec.wall_left) bottom = Extend(bottom, left, rail);
    if (!spec.wall_right) bottom = Extend(bottom, -left, rail);
    railing.parts.push_back(bottom);
    out.railings.push_back(std::move(railing));
    return well;
}

void SampleBuilder::Slabs(const std::vector<std::vector<AlignedBox2d>>& openings_per_storey) {
    const AlignedBox2d outline(Vector2d(0, 0), out.footprint_m);
    for (size_t s = 0; s < out.storeys.size(); ++s) {
        out.slabs.push_back({out.storeys[s].name + " slab", int(s), false, 0.0, out.slab_m, outline,
                             s < openings_per_storey.size() ? openings_per_storey[s]
                                                            : std::vector<AlignedBox2d>{}});
    }
    const int top = int(out.storeys.size()) - 1;
    out.slabs.push_back(
        {"Roof slab", top, true, out.storeys[top].height_m, out.slab_m, outline, {}});
}

}  // namespace bimslam::bim
