// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The sample buildings through the whole of Step 1's planning: IFC text -> IFC++ -> grid -> walk.
// The walk must enter every room of every storey, through its doors, away from the walls.
#include <gtest/gtest.h>

#include <string>
#include <tuple>

#include "host_tools/bim/coverage_path.hpp"
#include "host_tools/bim/ifc_model.hpp"
#include "host_tools/bim/occupancy_grid.hpp"
#include "host_tools/bim/reference_session.hpp"
#include "host_tools/bim/sample_building.hpp"

namespace bimslam::bim {
namespace {
namespace BIMSLAM_UNITY_ID {

// Distance from p to the nearest edge of a closed polygon.
double DistanceToBoundary(const std::vector<Eigen::Vector2d>& polygon, const Eigen::Vector2d& p) {
    double best = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < polygon.size(); ++i) {
        const Eigen::Vector2d a = polygon[i], b = polygon[(i + 1) % polygon.size()];
        const double t = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
        best = std::min(best, (a + t * (b - a) - p).norm());
    }
    return best;
}

TEST(SampleBuildingCoverage, TheWalkEntersEveryRoomOfEveryStorey) {
    const SampleLayout layout = SampleBuildingLayout();
    const BimModel model = ParseIfc("sample.ifc", SampleBuildingIfc());
    ASSERT_EQ(model.storeys.size(), layout.storeys.size());
    const PathConfig config;
    for (int s = 0; s < int(layout.storeys.size()); ++s) {
        SCOPED_TRACE(layout.storeys[s].name);
        const OccupancyGrid grid =
            BuildOccupancyGrid(model, FindStorey(model, layout.storeys[s].name), {});
        const CoveragePath path = PlanCoveragePath(grid, config);
        EXPECT_EQ(path.unreachable_viewpoints, 0);
        EXPECT_GE(path.min_clearance_m, config.clearance_m - grid.resolution);
        int rooms = 0;
        for (const SampleRoom& room : layout.rooms) {
            if (room.storey != s) continue;
            ++rooms;
            // Entered: a point of the walk inside the room, at least 0.5 m from its walls.
            double deepest = 0;
            for (const Eigen::Vector2d& p : path.points) {
                if (room.Contains(p))
                    deepest = std::max(deepest, DistanceToBoundary(room.polygon, p));
            }
            EXPECT_GE(deepest, 0.5) << room.number << " " << room.name << " is not entered";
        }
        EXPECT_GE(rooms, 5);
        // The walk never crosses a wall: every point is free space with the clearance.
        for (const Eigen::Vector2d& p : path.points) {
            int x, y;
            ASSERT_TRUE(grid.ToCell(p, &x, &y));
            ASSERT_EQ(grid.At(x, y), Cell::kFree) << p.transpose();
        }
    }
}

// The other layouts, and every layout with its doors to the outside (which must leave each storey
// enclosed): the same walk through every room of every storey.
class EveryLayoutCoverage : public ::testing::TestWithParam<std::tuple<BuildingLayout, bool>> {};

TEST_P(EveryLayoutCoverage, TheWalkEntersEveryRoomOfEveryStorey) {
    SampleBuildingOptions options;
    options.layout = std::get<0>(GetParam());
    options.exterior_doors = std::get<1>(GetParam());
    const SampleLayout layout = SampleBuildingLayout(options);
    const BimModel model = ParseIfc("sample.ifc", SampleBuildingIfc(options));
    ASSERT_EQ(model.storeys.size(), layout.storeys.size());
    const PathConfig config;
    for (int s = 0; s < int(layout.storeys.size()); ++s) {
        SCOPED_TRACE(layout.storeys[s].name);
        const OccupancyGrid grid =
            BuildOccupancyGrid(model, FindStorey(model, layout.storeys[s].name), {});
        const CoveragePath path = PlanCoveragePath(grid, config);
        EXPECT_EQ(path.unreachable_viewpoints, 0);
        EXPECT_GE(path.min_clearance_m, config.clearance_m - grid.resolution);
        // The enclosed free space is the building's inside: no free cell outside the footprint
        // but in the reveal of an entrance (its cells a grid cell beyond the outer face).
        const Eigen::AlignedBox2d footprint(Eigen::Vector2d::Constant(-grid.resolution),
                                            layout.footprint_m.array() + grid.resolution);
        for (int y = 0; y < grid.height; ++y) {
            for (int x = 0; x < grid.width; ++x) {
                if (grid.At(x, y) != Cell::kFree) continue;
                ASSERT_TRUE(footprint.contains(grid.Center(x, y)))
                    << "free outside at " << grid.Center(x, y).transpose();
            }
        }
        int rooms = 0;
        for (const SampleRoom& room : layout.rooms) {
            if (room.storey != s) continue;
            ++rooms;
            double deepest = 0;
            for (const Eigen::Vector2d& p : path.points) {
                if (room.Contains(p))
                    deepest = std::max(deepest, DistanceToBoundary(room.polygon, p));
            }
            EXPECT_GE(deepest, 0.5) << room.number << " " << room.name << " is not entered";
        }
        EXPECT_GE(rooms, 5);
        for (const Eigen::Vector2d& p : path.points) {
            int x, y;
            ASSERT_TRUE(grid.ToCell(p, &x, &y));
            ASSERT_EQ(grid.At(x, y), Cell::kFree) << p.transpose();
        }
    }
}

INSTANTIATE_TEST_SUITE_P(Layouts, EveryLayoutCoverage,
                         // The office without its entrances is the test above.
                         ::testing::Values(std::make_tuple(BuildingLayout::kOffice, true),
                                           std::make_tuple(BuildingLayout::kHall, false),
                                           std::make_tuple(BuildingLayout::kHall, true),
                                           std::make_tuple(BuildingLayout::kSymmetric, false),
                                           std::make_tuple(BuildingLayout::kSymmetric, true),
                                           std::make_tuple(BuildingLayout::kWing, true)),
                         [](const auto& param_info) {
                             return std::string(ToString(std::get<0>(param_info.param))) +
                                    (std::get<1>(param_info.param) ? "_exterior_doors" : "");
                         });

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::bim
