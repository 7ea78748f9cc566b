// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The project's own sample buildings, written as IFC4 STEP files, so that the demo and the default
// tests need no third-party model. Four layouts (SampleBuildingOptions::layout):
//  - "office" (the default): a small two-storey office, 30 m x 15 m, 3.2 m floor to floor. Every
//    storey has a corridor along x (clear y 6.15..8.15) with rooms of different sizes on both
//    sides, a door from the corridor into every room, windows in the exterior walls, and a stair
//    room whose straight flight connects the ground floor with the first floor through an opening
//    in the first floor's slab. One room per storey has a corner cut off by a slanted wall.
//  - "hall": a second, different building, 24 m x 20 m, three storeys 3.5 m apart, thicker walls.
//    The ground floor is a central hall along y with round columns, rooms on both sides and a stair
//    hall to the north; the upper floors have a corridor along y, open offices with columns, and
//    rooms opening from the stair hall. Two straight flights, one per storey, climb the stair
//    hall. The entrance (--exterior-doors) is in the south wall, into the hall.
//  - "symmetric": one storey, 20 m x 12 m, exactly invariant under the mirror about each centre
//    line (and so under a half turn about the vertical through the centre): identical rooms on
//    both sides of a central corridor, double doors in their middles, windows at mirrored places,
//    no slanted wall, no stair, furniture placed in one quarter and mirrored into the others, and
//    (--exterior-doors) the same entrance at both ends. A rig in it cannot tell where it is up to
//    the symmetry: the case anchoring must report as ambiguous.
//  - "wing": a long two-storey office wing, 90 m x 15 m, 3.2 m floor to floor: the office's
//    corridor plan with rooms of 3.5-10 m on both sides and one straight stair at the east end. A
//    walk along it keeps entering space it has not seen, as in a large real office: what the
//    odometry's drift is tuned on without the held-out Office_A (sample_wing.cpp).
// SampleBuildingLayout() is the building in plain numbers (metres), the generator's own truth that
// tests compare a reader's output with; SampleBuildingIfc() writes the same building as IFC4 text
// (plain text generation through ifc_writer.hpp: no IFC library is involved). The office's file is
// the same, byte for byte, as before the other layouts existed (sample_layouts_test.cpp).
//
// The model's frame ("bim" frame): x east along the building's length, y north, z up, metres,
// origin at the south-west outer corner of the footprint at ground-floor level.
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace bimslam::bim {

// Which building (see the comment at the top).
enum class BuildingLayout : uint8_t { kOffice, kHall, kSymmetric, kWing };
std::string_view ToString(BuildingLayout layout);  // "office", "hall", "symmetric", "wing"
std::optional<BuildingLayout> ParseBuildingLayout(std::string_view name);

struct SampleBuildingOptions {
    BuildingLayout layout = BuildingLayout::kOffice;
    // The file's length unit in metres: 1 (METRE) or 0.001 (MILLI METRE). Every length, coordinate
    // and elevation in the file is written in it; the building is the same.
    double length_unit_m = 1.0;
    // Varies the furniture (which pieces, where, their sizes) and the GlobalIds. The same seed
    // gives the same file, byte for byte.
    uint64_t seed = 1;
    bool furniture = true;
    // Doors to the outside on the ground floor: the office's at both ends of its corridor, the
    // hall's main entrance into the hall, the symmetric building's at both ends. Off by default.
    // Their frames close the building for the occupancy grid (occupancy_grid.hpp, closures), so
    // every storey's free space stays enclosed with them too (sample_coverage_test.cpp).
    bool exterior_doors = false;
    // The hall's number of storeys, 2 to 8 (its two upper plans take turns above the first
    // floor, joined by flights that take turns too); 0: the layout's own (the hall's three). The
    // other layouts have theirs only.
    int storeys = 0;

    // Throws common::Error (kInvalidArgument) naming the field and value.
    void Validate() const;
};

// "Ground Floor" at elevation 0, then "First Floor" (3.2 m in the office), ...
struct SampleStorey {
    std::string name;
    double elevation_m = 0.0;  // of the finished floor (the top of its slab)
    double height_m = 0.0;     // floor to floor (to the top of the roof slab for the top storey)
};

enum class RoomKind : uint8_t {
    kCorridor,
    kStair,
    kOffice,
    kOpenOffice,
    kMeeting,
    kKitchen,
    kToilets,
    kStorage,
    kHall,  // a wide circulation room (the hall layout's ground floor)
    kClassroom,
    kLibrary
};
std::string_view ToString(RoomKind kind);

// One IfcSpace.
struct SampleRoom {
    std::string number;  // IfcSpace.Name, e.g. "0.03" (storey.index)
    std::string name;    // IfcSpace.LongName, e.g. "Open office"
    int storey = 0;
    RoomKind kind = RoomKind::kOffice;
    // The clear floor area between the faces of its walls, counter-clockwise, metres (model x y).
    // Convex: rectangles (in the office one per storey has a corner cut off).
    std::vector<Eigen::Vector2d> polygon;

    bool Circulation() const {
        return kind == RoomKind::kCorridor || kind == RoomKind::kStair || kind == RoomKind::kHall;
    }
    Eigen::AlignedBox2d Bounds() const;
    double Area() const;
    bool Contains(const Eigen::Vector2d& p) const;  // inside or on the boundary
};

// One IfcWall: a straight box along its centreline, standing on its storey's floor.
struct SampleWall {
    std::string name;
    int storey = 0;
    Eigen::Vector2d start = Eigen::Vector2d::Zero(), end = Eigen::Vector2d::Zero();  // centreline
    double thickness_m = 0.0;
    double height_m = 0.0;  // up to the underside of the slab above
    bool exterior = false;

    double Length() const { return (end - start).norm(); }
    Eigen::Vector2d Direction() const { return (end - start).normalized(); }
    // Neither along x nor along y.
    bool Slanted() const;
};

// One IfcDoor in an IfcOpeningElement of a wall. The leaves stand open at 90 degrees into
// rooms[1], so the opening is passable.
struct SampleDoor {
    std::string name;
    int storey = 0;
    int wall = 0;           // index into SampleLayout::walls
    double offset_m = 0.0;  // of its centre along the wall from the wall's start
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();  // on the wall's centreline
    double width_m = 1.0;                              // clear opening
    double height_m = 2.1;
    int leaves = 1;
    // The rooms it connects (indices into SampleLayout::rooms; -1 outdoors); it swings into
    // rooms[1]. For room doors rooms[0] is the circulation (corridor, hall or stair hall).
    std::array<int, 2> rooms{-1, -1};
};

// One IfcWindow in an IfcOpeningElement of an exterior wall.
struct SampleWindow {
    std::string name;
    int storey = 0;
    int wall = 0;
    double offset_m = 0.0;
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    double width_m = 1.5;
    double sill_m = 0.9;  // above the storey's floor
    double height_m = 1.2;
    int room = -1;
};

// One IfcColumn from floor to the underside of the slab above.
struct SampleColumn {
    std::string name;
    int storey = 0;
    int room = -1;
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    double size_m = 0.4;  // side of the square, or diameter
    bool round = false;
    double height_m = 0.0;
};

// One IfcSlab: a box over the whole footprint, with rectangular openings (IfcOpeningElement).
struct SampleSlab {
    std::string name;
    int storey = 0;  // the storey it is contained in
    bool roof = false;
    double top_m = 0.0;  // height of its top face above its storey's elevation
    double thickness_m = 0.2;
    Eigen::AlignedBox2d outline;
    std::vector<Eigen::AlignedBox2d> openings;
};

// The IfcStair with its one IfcStairFlight: a straight run from the floor of `storey` to the floor
// of the storey above. Its last riser is the edge of the upper slab (`risers` rises, `risers - 1`
// treads on the flight).
struct SampleStair {
    std::string name;
    int storey = 0;
    int room_bottom = -1, room_top = -1;
    Eigen::Vector2d foot = Eigen::Vector2d::Zero();        // the middle of the first riser
    Eigen::Vector2d direction = Eigen::Vector2d::UnitX();  // up the flight, unit, along x or y
    double width_m = 1.2;
    int risers = 16;
    double riser_m = 0.2;
    double tread_m = 0.28;

    double RunLength() const { return (risers - 1) * tread_m; }
    Eigen::AlignedBox2d Footprint() const;
};

// One IfcRailing: upright boxes (plan rectangles) from the floor up to height_m.
struct SampleRailing {
    std::string name;
    int storey = 0;
    std::vector<Eigen::AlignedBox2d> parts;
    double height_m = 1.0;
};

enum class FurnitureKind : uint8_t { kDesk, kTable, kCabinet, kShelf };
std::string_view ToString(FurnitureKind kind);

// One IfcFurniture standing on its storey's floor.
struct SampleFurniture {
    std::string name;
    FurnitureKind kind = FurnitureKind::kDesk;
    int storey = 0;
    int room = -1;
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    bool rotated = false;  // its local x along the model's y (a quarter turn)
    Eigen::Vector3d size = Eigen::Vector3d::Zero();  // along its local x, y, and height
    Eigen::AlignedBox2d Footprint() const;
};

struct SampleLayout {
    BuildingLayout layout = BuildingLayout::kOffice;
    std::string building_name;  // IfcBuilding.Name, e.g. "Sample office"
    std::string summary;        // IfcProject.LongName, e.g. "A small two-storey office ..."
    Eigen::Vector2d footprint_m{30.0, 15.0};  // outer faces at x = 0 and length, y = 0 and width
    double exterior_wall_m = 0.3;
    double interior_wall_m = 0.15;
    double slab_m = 0.2;
    std::vector<SampleStorey> storeys;
    std::vector<SampleRoom> rooms;
    std::vector<SampleWall> walls;
    std::vector<SampleDoor> doors;
    std::vector<SampleWindow> windows;
    std::vector<SampleColumn> columns;
    std::vector<SampleSlab> slabs;
    std::vector<SampleStair> stairs;
    std::vector<SampleRailing> railings;
    std::vector<SampleFurniture> furniture;

    // The room index of the storey's main circulation room (its corridor or hall), or -1.
    int Corridor(int storey) const;
    // Of all element geometry (model coordinates, metres): the ground slab's underside to the roof.
    Eigen::AlignedBox3d Bounds() const;
};

// The building of options.layout (furniture per options.seed and options.furniture; the unit does
// not matter).
SampleLayout SampleBuildingLayout(const SampleBuildingOptions& options = {});

// The building as IFC4 STEP text (ISO 10303-21). Throws common::Error (kInvalidArgument) for
// invalid options.
std::string SampleBuildingIfc(const SampleBuildingOptions& options = {});

// Writes it atomically (io::WriteFileAtomic). Throws common::FileError naming the file.
void WriteSampleBuilding(const std::filesystem::path& path,
                         const SampleBuildingOptions& options = {});

}  // namespace bimslam::bim
