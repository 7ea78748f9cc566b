// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Scan Context configuration (Kim & Kim, "Scan Context: Egocentric Spatial Descriptor for Place
// Recognition within 3D Point Cloud Map", IROS 2018; referred to below as [SC]).
//
// Two cell rules share one descriptor layout (rings x sectors, see descriptor.hpp):
//   Outdoor  [SC] eq. (1)-(2): a cell holds the maximum height of its points, lifted by
//            lidar_height so that the values of ordinary scenes are positive (the reference
//            implementation adds 2 m for the same reason).
//   Indoor   our variant: a cell holds the vertical extent (max z - min z) of its points when it
//            holds at least indoor_min_points points spanning at least indoor_min_z_span metres,
//            and 0 otherwise. Indoors, the highest point of almost every cell near a wall or under
//            a ceiling is the ceiling, so max height says little about the place; the vertical
//            extent tells walls, pillars and furniture (tall spans) from floor and ceiling (flat,
//            near-zero spans), which is what makes one room look different from another.
//            Two rules measure the extent (IndoorCellRule): z_span, max z - min z of all the
//            cell's points (stops 1-71), and z_stack (since stop 72, the default): the tallest
//            stack of them whose heights leave no gap over indoor_min_z_span, and a cell seen
//            (indoor_min_points points) with no such stack holds indoor_min_z_span, the least an
//            occupied cell holds. In an open room with a floor and a ceiling every cell from about
//            4 m out holds both: z_span fills such cells with the room's height, so open space
//            weighs as much as a wall and what fills the descriptor depends on the sensor's
//            height; z_stack keeps walls, pillars and furniture (which stand on the floor) at
//            their height and open floor or ceiling at the floor value, which still marks where
//            the scan saw space (without that mark a corridor looks alike walked either way: the
//            mirror-symmetric building's walk turned 180 degrees about its start verified as a
//            rival). On Office_A, whose floors the ingest assumes, z_span found one right place
//            among 93 candidates of a hand-held walk in its open office
//            (algorithms/localization/README.md "Office_A with floors").
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

namespace bimslam::scancontext {

enum class DescriptorKind : uint8_t {
    kOutdoor,  // max height per cell ([SC])
    kIndoor,   // vertical extent of occupied cells (see above)
};

// "outdoor" / "indoor", the names session.json uses (shared/specs/session-data.md).
std::string_view ToString(DescriptorKind kind);
std::optional<DescriptorKind> ParseDescriptorKind(std::string_view name);

// How an indoor cell's vertical extent is measured (above).
enum class IndoorCellRule : uint8_t {
    kZSpan,   // max z - min z of the cell's points
    kZStack,  // the tallest stack with no gap over indoor_min_z_span; a seen cell at least that
};
// "z_span" / "z_stack", the names session.json and the rig's map package use; a file that names
// none was made with z_span.
std::string_view ToString(IndoorCellRule rule);
std::optional<IndoorCellRule> ParseIndoorCellRule(std::string_view name);

// Upper bounds on the descriptor's shape: the distance keeps its per-column scratch on the stack
// (no allocation on the hot path), and nothing sensible needs more than 0.5 degree sectors.
inline constexpr int kMaxRings = 500;
inline constexpr int kMaxSectors = 720;

struct ScanContextConfig {
    DescriptorKind kind = DescriptorKind::kOutdoor;

    // [SC] Sec. III-A: N_r = 20 rings of equal width up to L_max, N_s = 60 sectors of 6 degrees.
    int num_rings = 20;
    int num_sectors = 60;
    // L_max, metres: 80 m outdoors as in [SC]; 10 m indoors (rooms and corridors of the buildings
    // we map are rarely wider, and 0.5 m rings resolve furniture).
    double max_radius = 80.0;

    // Outdoor only: added to every z before taking the maximum (metres). The reference
    // implementation uses 2 m so that max heights of a ground vehicle's scan are positive; a cell
    // whose highest point is still below zero keeps its negative value.
    double lidar_height = 2.0;

    // Indoor only: a cell counts as occupied when it holds at least indoor_min_points points whose
    // z values span at least indoor_min_z_span metres (z_stack: a stack of them; a cell of
    // indoor_min_points flat points holds indoor_min_z_span, the mark of space seen). Three points:
    // one or two returns in a cell are often a mixed pixel on an edge or a single beam grazing a
    // surface; three need at least two beams (or one beam crossing a vertical surface). 0.3 m: well
    // above the noise of an OS1-32 (~3 cm) and the slope of floors and ceilings across a 0.5 m
    // ring, so flat floor and ceiling cells hold no more than the mark, while door frames, table
    // tops over their legs, cabinets and pillars register; it also ignores low clutter such as
    // cables and door sills.
    int indoor_min_points = 3;
    double indoor_min_z_span = 0.3;
    IndoorCellRule indoor_rule = IndoorCellRule::kZStack;

    // Number of ring-key nearest neighbours whose full distance is computed ([SC] Sec. IV-A uses
    // 10; the reference implementation's NUM_CANDIDATES_FROM_TREE).
    int num_candidates = 10;

    // Width of the column-shift search window around the sector-key pre-alignment, as a fraction
    // of num_sectors: the window is the pre-aligned shift +/- round(0.5 * search_ratio *
    // num_sectors), exactly as the reference implementation's SEARCH_RATIO (0.1 -> +/-3 columns of
    // 60). 1.0 searches every shift (the exhaustive minimum of [SC] eq. (6)); 0.0 trusts the
    // pre-alignment alone.
    double search_ratio = 0.1;

    // The defaults above (outdoor) and the indoor variant (10 m, z-span cells, no height offset).
    static ScanContextConfig Outdoor();
    static ScanContextConfig Indoor();

    // Throws common::Error (kInvalidArgument) naming the first bad field and its value.
    void Validate() const;

    // Angular width of one sector and radial width of one ring.
    double SectorAngle() const;
    double RingWidth() const { return max_radius / num_rings; }
};

}  // namespace bimslam::scancontext
