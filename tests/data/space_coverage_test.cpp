// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The rooms the reference walks, against the model's own rooms (an outside yardstick: the
// author's IfcSpaces): each IfcSpace of a floor, its footprint (its volume's faces seen from
// above) on the storey's grid, and how much of it is free space of an enclosed region the
// reference session's walk covers (PlanReferenceWalk: the largest region, and every other of
// kMinWalkedRegionM2 or more). A room the reference never walks is a room where a visit cannot be
// anchored: with the largest region alone (before stop 68), Duplex_A's second dwelling fails
// here. Each model skips, saying so, when absent.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "host_tools/bim/building_graph.hpp"
#include "host_tools/bim/ifc_model.hpp"
#include "host_tools/bim/occupancy_grid.hpp"
#include "host_tools/bim/reference_walk.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::bim {
namespace {
namespace BIMSLAM_UNITY_ID {

// The cells of `g` whose centre lies under one of the element's triangles (in plan).
std::vector<size_t> Footprint(const BimModel& m, const BimElement& e, const OccupancyGrid& g) {
    std::vector<uint8_t> in(g.cells.size(), 0);
    for (uint32_t t = e.first_triangle; t < e.first_triangle + e.triangle_count; ++t) {
        const auto& tri = m.mesh.triangles[t];
        Eigen::Vector2d p[3];
        for (int k = 0; k < 3; ++k) p[k] = m.mesh.vertices[tri[size_t(k)]].head<2>().cast<double>();
        const double area2 =
            (p[1] - p[0]).x() * (p[2] - p[0]).y() - (p[1] - p[0]).y() * (p[2] - p[0]).x();
        if (std::abs(area2) < 1e-9) continue;  // a wall of the volume, seen edge-on
        Eigen::AlignedBox2d box;
        for (const auto& q : p) box.extend(q);
        int x0, y0, x1, y1;
        if (!g.ToCell(box.min().cwiseMax(g.origin), &x0, &y0)) continue;
        g.ToCell(box.max(), &x1, &y1);
        x1 = x1 < 0 ? g.width - 1 : x1;
        y1 = y1 < 0 ? g.height - 1 : y1;
        for (int y = y0; y <= std::min(y1, g.height - 1); ++y) {
            for (int x = x0; x <= std::min(x1, g.width - 1); ++x) {
                const Eigen::Vector2d c = g.Center(x, y);
                double s[3];
                for (int k = 0; k < 3; ++k) {
                    const Eigen::Vector2d a = p[k], b = p[(k + 1) % 3];
                    s[k] = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
                }
                const bool inside =
                    (s[0] >= 0 && s[1] >= 0 && s[2] >= 0) || (s[0] <= 0 && s[1] <= 0 && s[2] <= 0);
                if (inside) in[size_t(y) * size_t(g.width) + size_t(x)] = 1;
            }
        }
    }
    std::vector<size_t> out;
    for (size_t i = 0; i < in.size(); ++i) {
        if (in[i]) out.push_back(i);
    }
    return out;
}

class SpaceCoverage : public ::testing::TestWithParam<std::string> {};

// The walked grids of storey s: its largest region's and every other region's the walk covers.
std::vector<const OccupancyGrid*> WalkedGrids(const ReferenceWalk& walk, int s) {
    std::vector<const OccupancyGrid*> out;
    for (size_t k = 0; k < walk.storeys.size(); ++k) {
        if (walk.storeys[k] == s) out.push_back(&walk.grids[k]);
    }
    for (const RegionWalk& r : walk.more_regions) {
        if (r.storey == s) out.push_back(&r.grid);
    }
    return out;
}

TEST_P(SpaceCoverage, EveryRoomIsWalkedByTheReference) {
    BIMSLAM_REQUIRE_SHARED_DATA(path, "ifc/" + GetParam());
    IfcLoadOptions options;
    options.space_geometry = true;
    const BimModel model = LoadIfc(path, options);
    // The reference session's own walk (reference_session.cpp: every storey, the defaults).
    const ReferenceWalk walk =
        PlanReferenceWalk(model, StoreyIndices(model, {}), GridConfig{}, PathConfig{});
    const BuildingGraph graph =
        BuildBuildingGraph(model, GridConfig{}, StairLimits{}, 0.35, DefaultWalkStorey(model));
    size_t spaces = 0;
    for (const int s : graph.floors) {
        const std::vector<const OccupancyGrid*> walked = WalkedGrids(walk, s);
        ASSERT_FALSE(walked.empty()) << model.storeys[size_t(s)].name << " is not walked";
        const OccupancyGrid& grid = *walked.front();
        for (const OccupancyGrid* g : walked) {  // one extent: a cell index means one place
            ASSERT_EQ(g->origin, grid.origin);
            ASSERT_EQ(g->width, grid.width);
            ASSERT_EQ(g->height, grid.height);
        }
        for (const BimElement& e : model.elements) {
            if (e.ifc_class != "IfcSpace" || e.storey != s) continue;
            const std::vector<size_t> cells = Footprint(model, e, grid);
            size_t free = 0;
            for (const size_t i : cells) {
                free += std::any_of(walked.begin(), walked.end(), [&](const OccupancyGrid* g) {
                    return g->cells[i] == Cell::kFree;
                });
            }
            const double area = double(cells.size()) * grid.resolution * grid.resolution;
            const double share = cells.empty() ? 0.0 : double(free) / double(cells.size());
            std::printf("%-12s %-6s %-26s %7.2f m2  %5.1f %% free in a walked region\n",
                        model.storeys[size_t(s)].name.c_str(), e.name.c_str(), e.long_name.c_str(),
                        area, 100.0 * share);
            ++spaces;
            // A room of a walked region's size: at least half its floor free and walked (a
            // kitchen's counters take 40 %; a room the reference missed would show none). A
            // smaller one (a shaft, an elevator car) may be a region of its own, not walked.
            if (area >= kMinWalkedRegionM2) {
                EXPECT_GE(share, 0.5)
                    << e.name << " '" << e.long_name << "' on " << model.storeys[size_t(s)].name;
            }
        }
    }
    EXPECT_GT(spaces, 0u) << "no IfcSpace with geometry on a floor";
}

INSTANTIATE_TEST_SUITE_P(Models, SpaceCoverage,
                         ::testing::Values("Duplex_A_20110907.ifc", "Office_A_20110811.ifc",
                                           "AC20-FZK-Haus.ifc"),
                         [](const auto& p) {
                             return p.param.substr(0, 4) == "AC20" ? std::string("FZK")
                                                                   : p.param.substr(0, 6);
                         });

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::bim
