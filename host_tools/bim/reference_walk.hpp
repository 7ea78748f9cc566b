// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The walk of the reference session over its storeys (paper, Step 1; issue 31 item 3): each
// storey's coverage walk (coverage_path.hpp), and between two storeys that a walkable flight joins
// (building_graph.hpp), the way to the flight, the flight itself and the way from its other end to
// the next storey's walk. The reference is then one connected walk with keyframes on the stairs,
// so that anchoring can follow a session from floor to floor. Storeys that no flight joins are
// walked one after the other as before (a second apart, "the stairs are not walked"), with a note
// naming the storeys and the reason.
//
// A storey may have several enclosed regions joined outside only (Duplex_A's two dwellings, each
// with its own stair): the largest of each storey is walked first, as above; then the second
// largest of each storey that has one of kMinWalkedRegionM2 or more, joined by the flights that
// stand in them, and so on. A session walked in any of them then finds reference keyframes there.
//
// The flights are walked with a person's limits (StairLimits{}): the reference is cast from the
// model, no platform climbs it; what matters is that its keyframes lie where a walk can pass.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "algorithms/io/trajectory.hpp"
#include "host_tools/bim/bim_model.hpp"
#include "host_tools/bim/coverage_path.hpp"
#include "host_tools/bim/occupancy_grid.hpp"

namespace bimslam::bim {

// A stretch of the walk in time: on a storey's floor, or on a flight.
struct WalkSegment {
    int storey = -1;       // the model storey walked on (on a flight: the one it left)
    bool flight = false;   // on a flight, or on the way to or from one
    int64_t start_ns = 0;  // the stretch's first and last pose
    int64_t end_ns = 0;
};

// Enclosed regions smaller than this get no walk of their own: a shaft, a duct, a closet whose
// door the model lacks. At most kMaxWalkedRegions regions of a storey are walked.
inline constexpr double kMinWalkedRegionM2 = 10.0;
inline constexpr int kMaxWalkedRegions = 8;

// A walk over a storey's enclosed region other than its largest.
struct RegionWalk {
    int storey = -1;  // model storey
    int region = 1;   // GridConfig::region: 1 the second largest, ...
    OccupancyGrid grid;
    CoveragePath coverage;
};

struct ReferenceWalk {
    std::vector<int> storeys;              // in the order walked (by elevation)
    std::vector<OccupancyGrid> grids;      // one per walked storey, same order: its largest region
    std::vector<CoveragePath> coverage;    // one per walked storey, same order
    std::vector<RegionWalk> more_regions;  // the storeys' other regions walked, after those
    // The walk in connected pieces (a new piece where storeys are not joined), one clock.
    std::vector<std::vector<io::StampedPose>> pieces;
    std::vector<WalkSegment> segments;  // in time order
    size_t flights_walked = 0;
    double flight_m = 0;             // along the flights and the ways to and from them
    std::vector<std::string> notes;  // storeys not joined, and why

    // The segment a time falls in (the last whose start is at or before it).
    const WalkSegment& SegmentAt(int64_t stamp_ns) const;
};

// Plans the walk over `storeys` (model indices; walked by elevation). Throws common::Error as
// BuildOccupancyGrid and PlanCoveragePath do for a storey without enclosed free space.
ReferenceWalk PlanReferenceWalk(const BimModel& model, std::vector<int> storeys,
                                const GridConfig& grid, const PathConfig& path);

}  // namespace bimslam::bim
