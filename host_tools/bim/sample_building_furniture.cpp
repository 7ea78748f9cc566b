// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The sample buildings' furniture: desks, tables, cabinets and shelves placed by room kind, with
// the seed choosing which pieces stand, their sizes and small offsets. Every piece lies inside its
// room and keeps clear of the doors (1.4 m in front of each, both sides), the columns and the
// stairs, so the way into every room stays open. Rows stand along the wall opposite the room's
// door (RoomFrame), so a room opening to the east is furnished as one opening to the north.
#include <algorithm>
#include <cmath>

#include "host_tools/bim/sample_builder.hpp"

namespace bimslam::bim {
namespace {

using Eigen::AlignedBox2d;
using Eigen::Vector2d;
using Eigen::Vector3d;

// A reproducible stream of numbers from the seed (splitmix64: the same on every platform, unlike
// the standard library's distributions).
class Rng {
public:
    explicit Rng(uint64_t seed) : state_(seed ^ 0x6A09E667F3BCC909ull) {}
    uint64_t Next() {
        uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    double Uniform(double a, double b) { return a + (b - a) * double(Next() >> 11) * 0x1.0p-53; }
    bool Chance(double p) { return Uniform(0, 1) < p; }
    // Rounded to the centimetre: positions and sizes stay short numbers in the file.
    double Cm(double a, double b) { return std::round(Uniform(a, b) * 100.0) / 100.0; }

private:
    uint64_t state_;
};

AlignedBox2d Grow(const AlignedBox2d& b, double m) {
    return {b.min() - Vector2d(m, m), b.max() + Vector2d(m, m)};
}

class Placer {
public:
    Placer(SampleLayout& layout, uint64_t seed) : L_(layout), rng_(seed) {
        for (const SampleDoor& d : L_.doors) {
            const SampleWall& w = L_.walls[d.wall];
            const bool along_x = std::abs(w.Direction().x()) > 0.5;
            const double along = d.width_m / 2 + 0.4, across = w.thickness_m / 2 + 1.4;
            const Vector2d half = along_x ? Vector2d(along, across) : Vector2d(across, along);
            Block(d.storey, {d.centre - half, d.centre + half});
        }
        for (const SampleColumn& c : L_.columns) {
            const Vector2d half(c.size_m / 2, c.size_m / 2);
            Block(c.storey, Grow({c.centre - half, c.centre + half}, 0.5));
        }
        for (const SampleStair& s : L_.stairs) {
            Block(s.storey, Grow(s.Footprint(), 0.6));
            Block(s.storey + 1, Grow(s.Footprint(), 0.6));
        }
    }

    Rng& rng() { return rng_; }

    struct Piece {
        FurnitureKind kind;
        Vector2d centre;
        bool rotated;
        Vector3d size;
    };

    // Adds the pieces (of one room, touching each other if they like) when all of them fit:
    // inside the room (2 cm from the walls) and clear of everything blocked so far. Returns
    // whether they were added.
    bool Place(int room, const std::vector<Piece>& pieces) {
        std::vector<SampleFurniture> add;
        for (const Piece& piece : pieces) {
            SampleFurniture f;
            f.kind = piece.kind;
            f.storey = L_.rooms[room].storey;
            f.room = room;
            f.centre = piece.centre;
            f.rotated = piece.rotated;
            f.size = piece.size;
            if (!Fits(room, f.Footprint())) return false;
            add.push_back(std::move(f));
        }
        for (SampleFurniture& f : add) {
            Block(f.storey, Grow(f.Footprint(), 0.05));
            AddFurniture(L_, std::move(f));
        }
        return true;
    }
    bool Place(FurnitureKind kind, int room, Vector2d centre, bool rotated, Vector3d size) {
        return Place(room, {{kind, centre, rotated, size}});
    }

    bool Fits(int room, const AlignedBox2d& box) const {
        const SampleRoom& r = L_.rooms[room];
        const AlignedBox2d g = Grow(box, 0.02);
        for (const auto corner : {AlignedBox2d::BottomLeft, AlignedBox2d::BottomRight,
                                  AlignedBox2d::TopLeft, AlignedBox2d::TopRight}) {
            if (!r.Contains(g.corner(corner))) return false;  // the rooms are convex
        }
        for (const auto& [storey, b] : blocked_) {
            if (storey == r.storey && b.intersects(box)) return false;
        }
        return true;
    }

private:
    void Block(int storey, const AlignedBox2d& b) { blocked_.emplace_back(storey, b); }

    SampleLayout& L_;
    Rng rng_;
    std::vector<std::pair<int, AlignedBox2d>> blocked_;
};

// A room seen from its door: u runs along the wall opposite the door (the back wall), v across.
// In the office every room opens to the corridor in x, so u is x there and the back wall is the
// window wall; without a door the room is taken as opening towards the footprint's middle in y.
struct RoomFrame {
    bool along_x = true;      // u is the model's x
    bool back_at_min = true;  // the back wall is at the room's least v
    Vector2d At(double u, double v) const { return along_x ? Vector2d(u, v) : Vector2d(v, u); }
    double U(const Vector2d& p) const { return along_x ? p.x() : p.y(); }
    double V(const Vector2d& p) const { return along_x ? p.y() : p.x(); }
};

RoomFrame FrameOf(const SampleLayout& L, int room) {
    const AlignedBox2d b = L.rooms[room].Bounds();
    for (const SampleDoor& d : L.doors) {
        if (d.rooms[1] != room) continue;
        RoomFrame f;
        f.along_x = std::abs(L.walls[d.wall].Direction().x()) > 0.5;
        f.back_at_min = f.V(d.centre) > f.V(b.center());
        return f;
    }
    RoomFrame f;
    f.back_at_min = b.center().y() < L.footprint_m.y() / 2;
    return f;
}

// Desks in a row along the back wall (the window wall, away from the corridor), a cabinet against
// a side wall.
void Office(Placer& p, const SampleLayout& L, int room) {
    Rng& rng = p.rng();
    const AlignedBox2d b = L.rooms[room].Bounds();
    const RoomFrame f = FrameOf(L, room);
    const double u0 = f.U(b.min()), u1 = f.U(b.max());
    const double span = (u1 - u0) - 0.6;
    const int n = std::min(4, int(span / 1.8));
    const double gap = rng.Cm(0.1, 0.5);
    const double v = f.back_at_min ? f.V(b.min()) + gap + 0.4 : f.V(b.max()) - gap - 0.4;
    int placed = 0;
    for (int i = 0; i < n; ++i) {
        const bool keep = rng.Chance(0.85) || (i == n - 1 && placed == 0);
        const double u = u0 + 0.3 + (i + 0.5) * span / n + rng.Cm(-0.1, 0.1);
        if (keep) {
            placed += p.Place(FurnitureKind::kDesk, room, f.At(u, v), !f.along_x, {1.6, 0.8, 0.75});
        }
    }
    const bool west = rng.Chance(0.5);
    const Vector3d size(rng.Cm(0.8, 1.2), 0.45, rng.Chance(0.5) ? 1.2 : 1.9);
    const double u = west ? u0 + 0.25 : u1 - 0.25;
    p.Place(FurnitureKind::kCabinet, room, f.At(u, f.V(b.center()) + rng.Cm(-0.8, 0.8)), f.along_x,
            size);
}

// Islands of two desks face to face on a grid, around the columns.
void OpenOffice(Placer& p, const SampleLayout& L, int room) {
    Rng& rng = p.rng();
    const AlignedBox2d b = L.rooms[room].Bounds();
    for (double y = b.min().y() + 1.2; y <= b.max().y() - 1.2; y += 2.2) {
        for (double x = b.min().x() + 1.5; x <= b.max().x() - 1.5; x += 2.6) {
            if (!rng.Chance(0.8)) continue;
            const Vector2d c(x + rng.Cm(-0.2, 0.2), y);
            const Vector3d desk(1.6, 0.8, 0.75);
            p.Place(room, {{FurnitureKind::kDesk, c - Vector2d(0, 0.4), false, desk},
                           {FurnitureKind::kDesk, c + Vector2d(0, 0.4), false, desk}});
        }
    }
}

// A table in the middle along the room's longer side, shortened until it fits; a shelf against an
// end wall.
void Meeting(Placer& p, const SampleLayout& L, int room) {
    Rng& rng = p.rng();
    const AlignedBox2d b = L.rooms[room].Bounds();
    const bool along_x = b.sizes().x() >= b.sizes().y();
    double length = std::min((along_x ? b.sizes().x() : b.sizes().y()) - 3.0, rng.Cm(3.0, 4.4));
    const double width = rng.Cm(1.1, 1.4);
    const Vector2d c = b.center() + Vector2d(rng.Cm(-0.3, 0.3), rng.Cm(-0.2, 0.2));
    while (length >= 1.6 &&
           !p.Place(FurnitureKind::kTable, room, c, !along_x, {length, width, 0.75})) {
        length -= 0.4;
    }
    const Vector3d shelf(rng.Cm(1.6, 2.4), 0.4, 2.0);
    const Vector2d first =
        along_x ? Vector2d(b.min().x() + 0.22, c.y()) : Vector2d(c.x(), b.min().y() + 0.22);
    const Vector2d second =
        along_x ? Vector2d(b.max().x() - 0.22, c.y()) : Vector2d(c.x(), b.max().y() - 0.22);
    if (!p.Place(FurnitureKind::kShelf, room, first, along_x, shelf)) {
        p.Place(FurnitureKind::kShelf, room, second, along_x, shelf);
    }
}

// A counter along a side wall at the far end from the door, a small table.
void Kitchen(Placer& p, const SampleLayout& L, int room) {
    Rng& rng = p.rng();
    const AlignedBox2d b = L.rooms[room].Bounds();
    const RoomFrame f = FrameOf(L, room);
    const double length = rng.Cm(2.4, 3.6);
    const double v =
        f.back_at_min ? f.V(b.min()) + 0.1 + length / 2 : f.V(b.max()) - 0.1 - length / 2;
    p.Place(FurnitureKind::kCabinet, room, f.At(f.U(b.min()) + 0.32, v), f.along_x,
            {length, 0.6, 0.9});
    p.Place(FurnitureKind::kTable, room, b.center() + Vector2d(rng.Cm(0, 0.6), rng.Cm(-0.3, 0.3)),
            false, {1.2, 0.8, 0.75});
}

// Shelves along both side walls.
void Storage(Placer& p, const SampleLayout& L, int room) {
    Rng& rng = p.rng();
    const AlignedBox2d b = L.rooms[room].Bounds();
    const RoomFrame f = FrameOf(L, room);
    for (const double u : {f.U(b.min()) + 0.22, f.U(b.max()) - 0.22}) {
        const Vector3d size(rng.Cm(2.0, 3.0), 0.4, 2.0);
        p.Place(FurnitureKind::kShelf, room, f.At(u, f.V(b.center()) + rng.Cm(-0.5, 0.5)),
                f.along_x, size);
    }
}

// Rows of desks facing the back wall (the front, with the teacher's table), an aisle on the side
// of the door.
void Classroom(Placer& p, const SampleLayout& L, int room) {
    Rng& rng = p.rng();
    const AlignedBox2d b = L.rooms[room].Bounds();
    const RoomFrame f = FrameOf(L, room);
    const double u0 = f.U(b.min()), u1 = f.U(b.max());
    const double v0 = f.V(b.min()), v1 = f.V(b.max());
    const double dir = f.back_at_min ? 1.0 : -1.0;  // away from the front
    const double front = f.back_at_min ? v0 : v1;
    const double teacher = rng.Cm(-0.5, 0.5);
    p.Place(FurnitureKind::kTable, room, f.At(0.5 * (u0 + u1) + teacher, front + dir * 0.9),
            !f.along_x, {1.6, 0.7, 0.75});
    const double pitch = rng.Cm(1.4, 1.7);
    for (double d = 2.4; d <= (v1 - v0) - 1.8; d += pitch) {
        for (double u = u0 + 1.2; u <= u1 - 1.0; u += 1.8) {
            if (!rng.Chance(0.9)) continue;
            p.Place(FurnitureKind::kDesk, room, f.At(u, front + dir * d), !f.along_x,
                    {1.4, 0.6, 0.75});
        }
    }
}

// Rows of tall shelves across the room, reading tables near the door.
void Library(Placer& p, const SampleLayout& L, int room) {
    Rng& rng = p.rng();
    const AlignedBox2d b = L.rooms[room].Bounds();
    const RoomFrame f = FrameOf(L, room);
    const double u0 = f.U(b.min()), u1 = f.U(b.max());
    const double v0 = f.V(b.min()), v1 = f.V(b.max());
    const double dir = f.back_at_min ? 1.0 : -1.0;
    const double back = f.back_at_min ? v0 : v1;
    const double aisle = rng.Cm(1.5, 1.9);
    for (double d = 0.8; d <= (v1 - v0) - 3.0; d += aisle) {
        const double length = std::min(u1 - u0 - 2.4, rng.Cm(3.0, 5.0));
        const double u = u0 + 1.2 + length / 2 + rng.Cm(0, 0.6);
        p.Place(FurnitureKind::kShelf, room, f.At(u, back + dir * d), !f.along_x,
                {length, 0.5, 2.1});
    }
    p.Place(FurnitureKind::kTable, room,
            f.At(0.5 * (u0 + u1), (f.back_at_min ? v1 : v0) - dir * 1.6), !f.along_x,
            {2.0, 0.9, 0.75});
}

}  // namespace

void AddFurniture(SampleLayout& layout, SampleFurniture f) {
    const int n = 1 + int(std::count_if(layout.furniture.begin(), layout.furniture.end(),
                                        [&](const SampleFurniture& o) {
                                            return o.room == f.room && o.kind == f.kind;
                                        }));
    std::string name(ToString(f.kind));
    name[0] = char(name[0] - 'a' + 'A');
    f.name = name + " " + layout.rooms[f.room].number + "-" + std::to_string(n);
    layout.furniture.push_back(std::move(f));
}

void PlaceFurniture(SampleLayout& layout, uint64_t seed, const std::function<bool(int)>& furnish) {
    Placer placer(layout, seed);
    for (int r = 0; r < int(layout.rooms.size()); ++r) {
        if (furnish && !furnish(r)) continue;
        switch (layout.rooms[r].kind) {
            case RoomKind::kOffice:
                Office(placer, layout, r);
                break;
            case RoomKind::kOpenOffice:
                OpenOffice(placer, layout, r);
                break;
            case RoomKind::kMeeting:
                Meeting(placer, layout, r);
                break;
            case RoomKind::kKitchen:
                Kitchen(placer, layout, r);
                break;
            case RoomKind::kStorage:
                Storage(placer, layout, r);
                break;
            case RoomKind::kClassroom:
                Classroom(placer, layout, r);
                break;
            case RoomKind::kLibrary:
                Library(placer, layout, r);
                break;
            case RoomKind::kCorridor:
            case RoomKind::kStair:
            case RoomKind::kHall:
            case RoomKind::kToilets:
                break;
        }
    }
}

}  // namespace bimslam::bim
