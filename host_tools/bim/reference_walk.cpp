// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/bim/reference_walk.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <optional>
#include <sstream>

#include "algorithms/common/se3.hpp"
#include "algorithms/common/status.hpp"
#include "host_tools/bim/building_graph.hpp"
#include "host_tools/bim/stairs.hpp"

namespace bimslam::bim {
namespace {

// Poses along a 3D way (x, y, floor height), every spacing_m of it and at its corners, after its
// first point (where the walk already stands): the sensor sensor_height_m above the floor, the yaw
// along the way in plan (kept over a riser, where the way rises in place), timed at speed_mps over
// the 3D length.
std::vector<io::StampedPose> PosesAlong(const std::vector<Eigen::Vector3d>& way,
                                        const PathConfig& c, int64_t start_ns, double yaw) {
    std::vector<Eigen::Vector3d> pts;
    for (size_t i = 1; i < way.size(); ++i) {
        const double len = (way[i] - way[i - 1]).norm();
        if (len < 1e-6) continue;  // where a route meets the flight: one place, one pose
        const int n = std::max(1, int(std::ceil(len / c.spacing_m)));
        for (int k = 1; k <= n; ++k) pts.push_back(way[i - 1] + (way[i] - way[i - 1]) * k / n);
    }
    std::vector<io::StampedPose> out;
    double t_s = 0;
    Eigen::Vector3d last = way.empty() ? Eigen::Vector3d::Zero() : way.front();
    for (size_t i = 0; i < pts.size(); ++i) {
        const Eigen::Vector2d ahead = (i + 1 < pts.size() ? pts[i + 1] : pts[i]).head<2>() -
                                      (i + 1 < pts.size() ? pts[i] : last).head<2>();
        if (ahead.norm() > 1e-3) yaw = std::atan2(ahead.y(), ahead.x());
        t_s += (pts[i] - last).norm() / c.speed_mps;
        last = pts[i];
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
        T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
        T.translation() = pts[i] + Eigen::Vector3d(0, 0, c.sensor_height_m);
        out.push_back(
            io::StampedPose::FromIsometry(start_ns + int64_t(std::llround(t_s * 1e9)), T));
    }
    return out;
}

double YawOf(const io::StampedPose& p) { return common::Heading(p.Pose().linear()); }

// The way from `from` on storey a to `to` on storey b by a walkable flight joining them: the route
// on a to the flight's end there, the flight, the route on b. Empty, with the reason in `why`, when
// no flight joins them or no route reaches one.
std::vector<Eigen::Vector3d> WayBetween(const BuildingGraph& g, const PathConfig& c, int a, int b,
                                        const Eigen::Vector2d& from, const Eigen::Vector2d& to,
                                        std::string* why) {
    for (const int fi : g.FlightsAt(a)) {
        const StairFlight& f = g.flights[size_t(fi)];
        const bool up = f.lower == a;
        if ((up ? f.upper : f.lower) != b) continue;
        try {
            std::vector<Eigen::Vector3d> way;
            const OccupancyGrid &ga = g.grids[size_t(a)], &gb = g.grids[size_t(b)];
            for (const Eigen::Vector2d& p : PlanRoute(ga, c, from, up ? f.entry : f.exit))
                way.emplace_back(p.x(), p.y(), ga.floor_z);
            std::vector<Eigen::Vector3d> line = f.Line();
            if (!up) std::reverse(line.begin(), line.end());
            way.insert(way.end(), line.begin(), line.end());
            for (const Eigen::Vector2d& p : PlanRoute(gb, c, up ? f.exit : f.entry, to))
                way.emplace_back(p.x(), p.y(), gb.floor_z);
            return way;
        } catch (const common::Error& e) {
            *why = f.name + ": " + e.what();
        }
    }
    if (why->empty()) why->assign("no walkable flight joins them");
    return {};
}

// The storeys' graph, or none when it cannot be built (a note says why).
std::optional<BuildingGraph> GraphFor(const BimModel& model, const std::vector<int>& storeys,
                                      const GridConfig& grid, const PathConfig& path,
                                      std::vector<std::string>* notes) {
    if (storeys.size() < 2) return std::nullopt;
    try {
        BuildingGraph g =
            BuildBuildingGraph(model, grid, StairLimits{}, path.clearance_m, storeys.front());
        for (const std::string& p : g.problems) notes->push_back(p);
        return g;
    } catch (const common::Error& e) {
        notes->push_back(std::string("the stairs are not walked: ") + e.what());
        return std::nullopt;
    }
}

void Shift(std::vector<io::StampedPose>& poses, int64_t to_first_ns) {
    const int64_t d = to_first_ns - poses.front().stamp_ns;
    for (io::StampedPose& p : poses) p.stamp_ns += d;
}

std::string Ordinal(int region) {
    static const char* const kNames[] = {"largest", "second", "third",   "fourth",
                                         "fifth",   "sixth",  "seventh", "eighth"};
    return region < 8 ? kNames[region] : std::to_string(region + 1) + "th";
}

// The storeys one pass walked, with their grids and coverage walks.
struct Pass {
    std::vector<int> storeys;
    std::vector<OccupancyGrid> grids;
    std::vector<CoveragePath> coverage;
};

// The walks of one pass: the grid.region-th enclosed region of each of `storeys` (by elevation),
// joined by the flights that stand in them, appended to w (pieces, segments, flights, notes) a
// second after its last pose. From the second region on, a storey whose region gives no walk is
// left out (said in a note); the largest must give one (throws).
Pass WalkRegions(const BimModel& model, const std::vector<int>& storeys, const GridConfig& grid,
                 const PathConfig& path, ReferenceWalk& w) {
    const bool first = grid.region == 0;
    std::vector<std::string> graph_notes;
    const std::optional<BuildingGraph> g = GraphFor(model, storeys, grid, path, &graph_notes);
    // From the second region on, the graph's problems name every storey without such a region.
    if (first) w.notes.insert(w.notes.end(), graph_notes.begin(), graph_notes.end());
    Pass pass;
    for (const int s : storeys) {
        try {
            // The graph's grid of a floor has the stairwell closed: no walk crosses the hole.
            const bool floor = g && g->grids[size_t(s)].width > 0;
            OccupancyGrid og = floor ? g->grids[size_t(s)] : BuildOccupancyGrid(model, s, grid);
            CoveragePath cp = PlanCoveragePath(og, path);
            pass.storeys.push_back(s);
            pass.grids.push_back(std::move(og));
            pass.coverage.push_back(std::move(cp));
        } catch (const common::Error& e) {
            if (first) throw;
            w.notes.push_back("storey '" + model.storeys[size_t(s)].name + "': its " +
                              Ordinal(grid.region) + " enclosed region is not walked: " + e.what());
        }
    }
    for (size_t k = 0; k < pass.storeys.size(); ++k) {
        std::vector<io::StampedPose> poses = pass.coverage[k].poses;
        const bool joined_before = k > 0;
        std::string why;
        std::vector<Eigen::Vector3d> way;
        if (joined_before && g) {
            way = WayBetween(*g, path, pass.storeys[k - 1], pass.storeys[k],
                             w.pieces.back().back().translation.head<2>(),
                             poses.front().translation.head<2>(), &why);
        }
        if (way.empty()) {
            if (joined_before) {
                w.notes.push_back("storeys '" + model.storeys[size_t(pass.storeys[k - 1])].name +
                                  "' and '" + model.storeys[size_t(pass.storeys[k])].name +
                                  "' are not joined in the reference" +
                                  (first ? "" : " in their " + Ordinal(grid.region) + " regions") +
                                  " (the stairs are not walked): " +
                                  (g ? why : "the graph of the building could not be built"));
            }
            if (!w.pieces.empty()) Shift(poses, w.pieces.back().back().stamp_ns + 1'000'000'000);
            w.segments.push_back(
                {pass.storeys[k], false, poses.front().stamp_ns, poses.back().stamp_ns});
            w.pieces.push_back(std::move(poses));
            continue;
        }
        const io::StampedPose here = w.pieces.back().back();
        way.front() = here.translation - Eigen::Vector3d(0, 0, path.sensor_height_m);
        std::vector<io::StampedPose> join = PosesAlong(way, path, here.stamp_ns, YawOf(here));
        join.pop_back();  // where the next storey's walk begins
        for (size_t i = 1; i < way.size(); ++i) w.flight_m += (way[i] - way[i - 1]).norm();
        ++w.flights_walked;
        w.segments.push_back(
            {pass.storeys[k - 1], true, join.front().stamp_ns, join.back().stamp_ns});
        Shift(poses,
              join.back().stamp_ns + int64_t(std::llround(path.spacing_m / path.speed_mps * 1e9)));
        w.segments.push_back(
            {pass.storeys[k], false, poses.front().stamp_ns, poses.back().stamp_ns});
        w.pieces.back().insert(w.pieces.back().end(), join.begin(), join.end());
        w.pieces.back().insert(w.pieces.back().end(), poses.begin(), poses.end());
    }
    return pass;
}
}  // namespace

const WalkSegment& ReferenceWalk::SegmentAt(int64_t stamp_ns) const {
    auto it = std::upper_bound(segments.begin(), segments.end(), stamp_ns,
                               [](int64_t t, const WalkSegment& s) { return t < s.start_ns; });
    return it == segments.begin() ? segments.front() : *(it - 1);
}

ReferenceWalk PlanReferenceWalk(const BimModel& model, std::vector<int> storeys,
                                const GridConfig& grid, const PathConfig& path) {
    std::stable_sort(storeys.begin(), storeys.end(), [&](int a, int b) {
        return model.storeys[size_t(a)].elevation_m < model.storeys[size_t(b)].elevation_m;
    });
    ReferenceWalk w;
    w.storeys = storeys;
    GridConfig largest = grid;
    largest.region = 0;
    Pass pass = WalkRegions(model, storeys, largest, path, w);
    w.grids = std::move(pass.grids);
    w.coverage = std::move(pass.coverage);
    // The other regions, second largest first; a seed makes one region of whatever it reaches.
    for (int r = 1; r < kMaxWalkedRegions && !grid.seed; ++r) {
        std::vector<int> at;
        for (size_t k = 0; k < storeys.size(); ++k) {
            const std::vector<double>& areas = w.grids[k].region_areas_m2;
            if (int(areas.size()) > r && areas[size_t(r)] >= kMinWalkedRegionM2)
                at.push_back(storeys[k]);
        }
        if (at.empty()) break;
        GridConfig other = grid;
        other.region = r;
        pass = WalkRegions(model, at, other, path, w);
        for (size_t k = 0; k < pass.storeys.size(); ++k) {
            const OccupancyGrid& og = pass.grids[k];
            std::ostringstream area;
            area << std::fixed << std::setprecision(1) << og.region_areas_m2[size_t(r)];
            w.notes.push_back("storey '" + og.storey + "': its " + Ordinal(r) +
                              " enclosed region (" + area.str() +
                              " m2, joined to the largest outside only) is walked too");
            w.more_regions.push_back(
                {pass.storeys[k], r, std::move(pass.grids[k]), std::move(pass.coverage[k])});
        }
    }
    return w;
}

}  // namespace bimslam::bim
