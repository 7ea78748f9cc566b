// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// A storey's occupancy grid from the BIM (paper, Step 1): a horizontal slice of the permanent
// structure at sensor height, the footprints of furniture and other objects a walking robot must
// go around, and the free space reachable from a seed (the rest is outside or walled off).
// Exported as the ROS map_server convention (PGM + YAML) and as PNG.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "algorithms/io/image.hpp"
#include "host_tools/bim/bim_model.hpp"

namespace bimslam::bim {

struct GridConfig {
    double resolution_m = 0.05;
    // Height of the slice above the storey's floor: the sensor height (an OS1 on a Go1 is at
    // about 0.6 m). Below window sills, so windows stay walls and the free space stays inside.
    double slice_height_m = 0.6;
    double margin_m = 1.0;  // around the building's footprint
    // Objects that are not structure (furniture, proxies) block the way below this height above
    // the floor: their footprints are occupied. Doors, windows and spaces never are.
    bool object_footprints = true;
    double object_height_m = 1.0;
    // The platform's top above the floor (its sensor and what carries it), or 0: structure
    // between 0.3 m and this height blocks the cells under it too (StandableCells' overhead
    // rule), so a walk keeps its sensor out of a roof that comes down and from under the low end
    // of a flight. The slice alone does not see either: a hand-held walk through FZK-Haus' attic
    // carried its sensor 8 s inside the roof, every scan empty (host_tools/simulate/README.md).
    double headroom_m = 0;
    // Free space is what is reachable from this point (metres, model x y); without it, the
    // largest enclosed free region (one not touching the grid's border, i.e. not outdoors).
    std::optional<Eigen::Vector2d> seed;
    // Without a seed: which enclosed region, by open area, largest first (0). A building of two
    // dwellings (Duplex_A) has one per dwelling and storey, joined outside only.
    int region = 0;

    void Validate() const;  // throws common::Error naming the field and value
};

enum class Cell : uint8_t { kUnknown = 0, kFree = 1, kOccupied = 2 };

struct OccupancyGrid {
    std::string storey;
    double resolution = 0.05;
    Eigen::Vector2d origin = Eigen::Vector2d::Zero();  // model x y of the corner of cell (0, 0)
    int width = 0, height = 0;                         // cells; row 0 is the lowest y
    double floor_z = 0;                                // the storey's elevation (m)
    double slice_z = 0;                                // height of the slice (m, model z)
    std::vector<Cell> cells;
    std::vector<float> clearance;  // metres from each free cell to the nearest non-free cell
    // Built without a seed: the open area of every enclosed region of the storey, largest first
    // (the grid's own is region_areas_m2[GridConfig::region]); with a seed, empty.
    std::vector<double> region_areas_m2;

    Cell At(int x, int y) const { return cells[size_t(y) * width + x]; }
    bool Inside(int x, int y) const { return x >= 0 && y >= 0 && x < width && y < height; }
    Eigen::Vector2d Center(int x, int y) const {
        return origin + resolution * Eigen::Vector2d(x + 0.5, y + 0.5);
    }
    // The cell holding point p, or false when p is outside the grid.
    bool ToCell(const Eigen::Vector2d& p, int* x, int* y) const;
    size_t FreeCells() const;
};

// Throws common::Error when the storey index is out of range, or when no enclosed free space is
// found (a storey with no walls at the slice height, a seed inside a wall, or fewer enclosed
// regions than GridConfig::region asks for).
OccupancyGrid BuildOccupancyGrid(const BimModel& model, int storey, const GridConfig& config);

// An object that is not in the model (a scenario's added cabinet, a desk it moved): the cells
// under every triangle of `mesh` (model coordinates) that reaches between the floor and
// object_height_m above it become occupied, as BuildOccupancyGrid does for the model's furniture,
// and the clearance is recomputed. Returns how many free cells it took.
size_t AddObstacle(OccupancyGrid& grid, const common::TriangleMesh& mesh,
                   double object_height_m = GridConfig{}.object_height_m);

// Per cell of `grid` (of `model`'s storey), 1 where the building stands at the slice: the cells no
// path from the grid's border reaches without crossing the structure or a door, window or curtain
// wall. Every enclosed room, not only the grid's region, with its walls, doors and windows.
std::vector<uint8_t> IndoorCells(const BimModel& model, const OccupancyGrid& grid);

// Per cell of `grid`, 1 under a horizontal face of the structure within 0.3 m of the storey's
// elevation (a slab's top or underside, a landing at floor height).
std::vector<uint8_t> FloorFaceCells(const BimModel& model, const OccupancyGrid& grid);
// Whether the storey's floor is modelled: floor faces under at least half of the grid's free
// space. Office_A's storeys are not: the file has no floor slabs, only ceilings.
bool FloorModelled(const OccupancyGrid& grid, const std::vector<uint8_t>& floor_face_cells);

// Marks in `mask` the cells whose centres lie in triangle abc's plan, and those its edges cross.
void MarkTrianglePlan(const OccupancyGrid& grid, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                      const Eigen::Vector2d& c, std::vector<uint8_t>& mask);

// Per cell of `grid` (of `model`'s storey), 1 where a robot or a person can stand: a free cell
// with the storey's floor under it (a horizontal face of the structure within 0.3 m of the
// storey's elevation) and no structure between 0.3 m and headroom_m above the floor. A storey
// whose floor is not modelled (FloorModelled: a file read without assumed floors, ifc_model.hpp)
// is not asked for it. The grid's one slice sees neither a void in
// the floor (an attic floor that stops short of the eaves, a stairwell) nor a roof that comes
// down below a person's head: a hand-held walk of the storeys benchmark once started over
// FZK-Haus' ground floor at attic height, its sensor inside the roof (issue 31).
std::vector<uint8_t> StandableCells(const BimModel& model, const OccupancyGrid& grid,
                                    double headroom_m);

// 4-connected components of the cells `in` accepts (by index y * width + x): per cell its
// component, numbered from 0, or -1.
std::vector<int> LabelRegions(const OccupancyGrid& grid, const std::function<bool(size_t)>& in);

// Grey image as ROS map_server draws it: free 254, occupied 0, unknown 205; top row = max y.
io::Image GridImage(const OccupancyGrid& grid);
// stem.pgm + stem.yaml (map_server: image, resolution, origin, negate, thresholds) + stem.png.
void WriteGrid(const OccupancyGrid& grid, const std::filesystem::path& stem);

}  // namespace bimslam::bim
