// The sample building's layout in metres (sample_building.hpp): storeys, rooms, walls, doors,
// windows, columns, slabs, the stair, railings and furniture. sample_building_ifc.cpp writes it as
// IFC4.
#include "host_tools/bim/sample_building.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "algorithms/common/status.hpp"

namespace bimslam::bim {
namespace {

using Eigen::AlignedBox2d;
using Eigen::Vector2d;

// The footprint and the fixed parts of every storey's plan (see the header's comment).
constexpr double kLength = 30.0, kWidth = 15.0;
constexpr double kExt = 0.3, kInt = 0.15, kSlab = 0.2;
constexpr double kFloorToFloor = 3.2;
constexpr double kWallHeight = kFloorToFloor - kSlab;  // up to the underside of the slab above
// Clear interior faces.
constexpr double kXMin = kExt, kXMax = kLength - kExt, kYMin = kExt, kYMax = kWidth - kExt;
// The corridor's walls: south one's faces at 6.0 / 6.15, north one's at 8.15 / 8.3.
constexpr double kCorridorSouthWall = 6.075, kCorridorNorthWall = 8.225;
constexpr double kSouthRoomsYMax = kCorridorSouthWall - kInt / 2;  // 6.0
constexpr double kCorridorYMin = kCorridorSouthWall + kInt / 2;    // 6.15
constexpr double kCorridorYMax = kCorridorNorthWall - kInt / 2;    // 8.15
constexpr double kNorthRoomsYMin = kCorridorNorthWall + kInt / 2;  // 8.3
constexpr double kCutCorner = 2.0;  // legs of the corner cut off by the slanted wall

// What differs between storeys: the partitions along the corridor and the rooms between them.
struct RoomSpec {
    RoomKind kind;
    const char* name;
};
struct StoreyPlan {
    const char* name;
    std::vector<double> south_partitions;  // centrelines, west to east
    std::vector<RoomSpec> south_rooms;     // one more than partitions
    std::vector<double> north_partitions;
    std::vector<RoomSpec> north_rooms;
    bool cut_east;  // the slanted wall cuts the north-east corner (else the north-west one) ...
    int cut_room;   // ... of this north room (index into north_rooms)
};

std::vector<StoreyPlan> Plans() {
    using K = RoomKind;
    return {
        {"Ground Floor",
         {6.0, 10.5, 22.5},
         {{K::kOffice, "Office"},
          {K::kOffice, "Office"},
          {K::kOpenOffice, "Open office"},
          {K::kStair, "Stair"}},
         {4.5, 11.0, 19.5},
         {{K::kToilets, "Toilets"},
          {K::kKitchen, "Kitchen"},
          {K::kOffice, "Office"},
          {K::kMeeting, "Meeting room"}},
         true,
         3},
        {"First Floor",
         {4.0, 10.5, 22.5},
         {{K::kStorage, "Print room"},
          {K::kOffice, "Office"},
          {K::kOpenOffice, "Open office"},
          {K::kStair, "Stair"}},
         {9.0, 14.5, 21.0},
         {{K::kMeeting, "Conference room"},
          {K::kOffice, "Office"},
          {K::kOffice, "Office"},
          {K::kOffice, "Office"}},
         false,
         0},
    };
}

// "6.0", "22.5": a partition's name.
std::string Metres(double v) {
    const long dm = std::lround(v * 10);
    return std::to_string(dm / 10) + "." + std::to_string(dm % 10);
}

std::string RoomNumber(int storey, int index) {
    return std::to_string(storey) + "." + (index < 10 ? "0" : "") + std::to_string(index);
}

class Builder {
public:
    SampleLayout out;

    int Wall(std::string name, int storey, Vector2d a, Vector2d b, double t, bool exterior) {
        out.walls.push_back({std::move(name), storey, a, b, t, kWallHeight, exterior});
        return int(out.walls.size()) - 1;
    }

    int Room(int storey, int index, RoomKind kind, std::string name, std::vector<Vector2d> poly) {
        out.rooms.push_back(
            {RoomNumber(storey, index), std::move(name), storey, kind, std::move(poly)});
        return int(out.rooms.size()) - 1;
    }

    void Door(int storey, int wall, Vector2d centre, double width, int leaves, int from, int into) {
        const SampleWall& w = out.walls[wall];
        SampleDoor d;
        // "Door 0.03-2": the second door into room 0.03; "Door 0.00-W": from outdoors.
        const auto n = std::count_if(out.doors.begin(), out.doors.end(),
                                     [&](const SampleDoor& o) { return o.rooms[1] == into; });
        d.name = "Door " + out.rooms[into].number + "-" +
                 (from >= 0 ? std::to_string(n + 1) : std::string(w.start.x() < 1 ? "W" : "E"));
        d.storey = storey;
        d.wall = wall;
        d.offset_m = (centre - w.start).dot(w.Direction());
        d.centre = centre;
        d.width_m = width;
        d.leaves = leaves;
        d.rooms = {from, into};
        out.doors.push_back(std::move(d));
    }

    // Windows along a room's edge that lies on the inner face of an exterior wall.
    void Windows(int room, int wall, Vector2d a, Vector2d b) {
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
};

std::vector<Vector2d> Rect(double x0, double y0, double x1, double y1) {
    return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

// Spans [a, b] of the rooms between partitions (centrelines) across the clear length.
std::vector<std::pair<double, double>> Spans(const std::vector<double>& partitions) {
    std::vector<std::pair<double, double>> spans;
    double a = kXMin;
    for (const double c : partitions) {
        spans.emplace_back(a, c - kInt / 2);
        a = c + kInt / 2;
    }
    spans.emplace_back(a, kXMax);
    return spans;
}

void AddStorey(Builder& b, int s, const StoreyPlan& plan, const SampleBuildingOptions& options) {
    SampleLayout& L = b.out;
    const std::string& sn = L.storeys[s].name;
    // Exterior walls: south and north over the full length, west and east between them.
    const int south =
        b.Wall(sn + " exterior wall south", s, {0, kExt / 2}, {kLength, kExt / 2}, kExt, true);
    const int north = b.Wall(sn + " exterior wall north", s, {0, kWidth - kExt / 2},
                             {kLength, kWidth - kExt / 2}, kExt, true);
    const int west =
        b.Wall(sn + " exterior wall west", s, {kExt / 2, kYMin}, {kExt / 2, kYMax}, kExt, true);
    const int east = b.Wall(sn + " exterior wall east", s, {kLength - kExt / 2, kYMin},
                            {kLength - kExt / 2, kYMax}, kExt, true);
    const int corridor_s = b.Wall(sn + " corridor wall south", s, {kXMin, kCorridorSouthWall},
                                  {kXMax, kCorridorSouthWall}, kInt, false);
    const int corridor_n = b.Wall(sn + " corridor wall north", s, {kXMin, kCorridorNorthWall},
                                  {kXMax, kCorridorNorthWall}, kInt, false);
    for (const double c : plan.south_partitions) {
        b.Wall(sn + " partition x=" + Metres(c), s, {c, kYMin}, {c, kSouthRoomsYMax}, kInt, false);
    }
    for (const double c : plan.north_partitions) {
        b.Wall(sn + " partition x=" + Metres(c), s, {c, kNorthRoomsYMin}, {c, kYMax}, kInt, false);
    }

    // Rooms: the corridor, then the south side west to east, then the north side.
    int number = 0;
    const int corridor = b.Room(s, number++, RoomKind::kCorridor, "Corridor",
                                Rect(kXMin, kCorridorYMin, kXMax, kCorridorYMax));
    std::vector<int> south_rooms, north_rooms;
    const auto south_spans = Spans(plan.south_partitions);
    for (size_t i = 0; i < south_spans.size(); ++i) {
        const auto [x0, x1] = south_spans[i];
        south_rooms.push_back(b.Room(s, number++, plan.south_rooms[i].kind,
                                     plan.south_rooms[i].name,
                                     Rect(x0, kYMin, x1, kSouthRoomsYMax)));
    }
    const auto north_spans = Spans(plan.north_partitions);
    for (size_t i = 0; i < north_spans.size(); ++i) {
        const auto [x0, x1] = north_spans[i];
        std::vector<Vector2d> poly = Rect(x0, kNorthRoomsYMin, x1, kYMax);
        if (int(i) == plan.cut_room) {
            // The slanted wall: its room-side face runs from p to q, cutting the corner off.
            const Vector2d corner = plan.cut_east ? Vector2d(x1, kYMax) : Vector2d(x0, kYMax);
            const double sx = plan.cut_east ? 1.0 : -1.0;
            const Vector2d p = corner - Vector2d(0, kCutCorner);
            const Vector2d q = corner - Vector2d(sx * kCutCorner, 0);
            if (plan.cut_east) {
                poly = {{x0, kNorthRoomsYMin}, {x1, kNorthRoomsYMin}, p, q, {x0, kYMax}};
            } else {
                poly = {{x0, kNorthRoomsYMin}, {x1, kNorthRoomsYMin}, {x1, kYMax}, q, p};
            }
            // Centreline half a thickness towards the corner, ends buried 0.2 m in the exterior
            // walls so the corner is closed (the triangle behind it is a closed shaft).
            const Vector2d n = Vector2d(sx, 1.0).normalized();
            const Vector2d d = (q - p).normalized();
            b.Wall(sn + " slanted wall", s, p + n * (kInt / 2) - 0.2 * d,
                   q + n * (kInt / 2) + 0.2 * d, kInt, false);
        }
        north_rooms.push_back(
            b.Room(s, number++, plan.north_rooms[i].kind, plan.north_rooms[i].name, poly));
    }

    // A door from the corridor into every room, 1 m from its west end; rooms longer than 8 m get
    // a second one 1 m from their east end; the stair room's door is at its east end, where the
    // flight arrives.
    const double door_w = 1.0;
    auto room_doors = [&](const std::vector<int>& rooms, int wall, double wall_y) {
        for (const int r : rooms) {
            const AlignedBox2d box = L.rooms[r].Bounds();
            const double x0 = box.min().x(), x1 = box.max().x();
            const bool stair = L.rooms[r].kind == RoomKind::kStair;
            if (!stair) b.Door(s, wall, {x0 + 1.0, wall_y}, door_w, 1, corridor, r);
            if (stair || x1 - x0 > 8.0) b.Door(s, wall, {x1 - 1.0, wall_y}, door_w, 1, corridor, r);
        }
    };
    room_doors(south_rooms, corridor_s, kCorridorSouthWall);
    room_doors(north_rooms, corridor_n, kCorridorNorthWall);
    const double corridor_y = 0.5 * (kCorridorYMin + kCorridorYMax);
    const bool entrances = options.exterior_doors && s == 0;
    if (entrances) {
        b.Door(s, west, {kExt / 2, corridor_y}, 1.6, 2, -1, corridor);  // the main entrance
        b.Door(s, east, {kLength - kExt / 2, corridor_y}, 1.0, 1, -1, corridor);
    }

    // Windows on every room edge lying on an exterior wall's inner face; the stair room only on
    // its east side (its flight runs along the south wall), the corridor's ends unless doors.
    for (int r = corridor; r < int(L.rooms.size()); ++r) {
        const auto& poly = L.rooms[r].polygon;
        for (size_t i = 0; i < poly.size(); ++i) {
            const Vector2d a = poly[i], c = poly[(i + 1) % poly.size()];
            const bool stair = L.rooms[r].kind == RoomKind::kStair;
            const bool corridor_end = r == corridor;
            if (corridor_end && entrances) continue;
            if (a.y() == kYMin && c.y() == kYMin && !stair) b.Windows(r, south, a, c);
            if (a.y() == kYMax && c.y() == kYMax && !stair) b.Windows(r, north, a, c);
            if (a.x() == kXMin && c.x() == kXMin && !stair) b.Windows(r, west, a, c);
            if (a.x() == kXMax && c.x() == kXMax) b.Windows(r, east, a, c);
        }
    }

    // Columns in the open office, one square and one round, on the same grid on both storeys.
    for (const int r : south_rooms) {
        if (L.rooms[r].kind != RoomKind::kOpenOffice) continue;
        const double y = 0.5 * (kYMin + kSouthRoomsYMax);
        L.columns.push_back(
            {"Column " + L.rooms[r].number + "-1", s, r, {14.5, y}, 0.4, false, kWallHeight});
        L.columns.push_back(
            {"Column " + L.rooms[r].number + "-2", s, r, {18.5, y}, 0.4, true, kWallHeight});
    }
}

}  // namespace

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
    if (length_unit_m != 1.0 && length_unit_m != 0.001) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            "sample building: length_unit_m must be 1 (metre) or 0.001 "
                            "(millimetre), not " +
                                std::to_string(length_unit_m));
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
        if (rooms[r].storey == storey && rooms[r].kind == RoomKind::kCorridor) return int(r);
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

void PlaceFurniture(SampleLayout& layout, uint64_t seed);  // sample_building_furniture.cpp

SampleLayout SampleBuildingLayout(const SampleBuildingOptions& options) {
    options.Validate();
    Builder b;
    SampleLayout& L = b.out;
    L.footprint_m = {kLength, kWidth};
    L.exterior_wall_m = kExt;
    L.interior_wall_m = kInt;
    L.slab_m = kSlab;
    const std::vector<StoreyPlan> plans = Plans();
    for (size_t s = 0; s < plans.size(); ++s) {
        L.storeys.push_back({plans[s].name, kFloorToFloor * double(s), kFloorToFloor});
    }
    for (size_t s = 0; s < plans.size(); ++s) AddStorey(b, int(s), plans[s], options);

    // The stair: a straight flight along the stair room's south wall, up towards the east; 16
    // risers of 0.2 m (the last one the upper slab's edge), treads of 0.28 m.
    auto stair_room = [&](int storey) {
        for (size_t r = 0; r < L.rooms.size(); ++r) {
            if (L.rooms[r].storey == storey && L.rooms[r].kind == RoomKind::kStair) return int(r);
        }
        return -1;
    };
    SampleStair stair;
    stair.name = "Stair";
    stair.storey = 0;
    stair.room_bottom = stair_room(0);
    stair.room_top = stair_room(1);
    stair.width_m = 1.2;
    stair.foot = {23.5, kYMin + stair.width_m / 2};
    stair.risers = int(std::lround(kFloorToFloor / stair.riser_m));
    L.stairs.push_back(stair);
    const AlignedBox2d flight = stair.Footprint();
    // The first floor's opening above the flight, 0.2 m longer at the bottom for headroom and 0.1
    // m wider; guarded by a railing on its open sides.
    const AlignedBox2d well(Vector2d(flight.min().x() - 0.2, flight.min().y()),
                            Vector2d(flight.max().x(), flight.max().y() + 0.1));

    const AlignedBox2d outline(Vector2d(0, 0), Vector2d(kLength, kWidth));
    L.slabs.push_back({"Ground Floor slab", 0, false, 0.0, kSlab, outline, {}});
    L.slabs.push_back({"First Floor slab", 1, false, 0.0, kSlab, outline, {well}});
    L.slabs.push_back({"Roof slab", 1, true, kFloorToFloor, kSlab, outline, {}});
    const double rail = 0.05;
    L.railings.push_back({"Stair well railing",
                          1,
                          {AlignedBox2d(Vector2d(well.min().x(), well.max().y()),
                                        Vector2d(well.max().x(), well.max().y() + rail)),
                           AlignedBox2d(Vector2d(well.min().x() - rail, well.min().y()),
                                        Vector2d(well.min().x(), well.max().y() + rail))},
                          1.0});

    if (options.furniture) PlaceFurniture(L, options.seed);
    return L;
}

}  // namespace bimslam::bim
