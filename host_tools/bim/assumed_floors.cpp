// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/bim/assumed_floors.hpp"

#include <algorithm>
#include <map>
#include <optional>
#include <set>

#include "algorithms/common/status.hpp"
#include "host_tools/bim/occupancy_grid.hpp"
#include "host_tools/bim/stairs.hpp"

namespace bimslam::bim {
namespace {

// What of a stair lies lower than this under the floor's top is cut out of the floor: the last
// tread, one riser (0.15-0.2 m) under it, is (Office_A's floor had first covered it); what is
// nearer is the floor's own edge.
constexpr double kUnderFloorM = 0.05;

// Whether a storey is one people stand on: as DefaultWalkStorey, kMinWalkStoreyHeight to the next
// one, the last one counting as high enough.
bool WalkedStorey(const BimModel& model, size_t s) {
    return s + 1 == model.storeys.size() ||
           model.storeys[s + 1].elevation_m - model.storeys[s].elevation_m >= kMinWalkStoreyHeight;
}

// The storey's grid, or nothing when it finds no enclosed space (no walls at its slice height).
std::optional<OccupancyGrid> GridOf(const BimModel& model, int storey) {
    try {
        return BuildOccupancyGrid(model, storey, GridConfig{});
    } catch (const common::Error&) {
        return std::nullopt;
    }
}

// The cells over every stair and ramp that climbs to `storey` from below: the plan of its
// elements' triangles lower than kUnderFloorM under the storey's floor, up to its last riser.
// Beyond that riser the floor stays: Office_A's concrete pans run on under where the floor is, at
// the last tread's height, and the walk steps off the flight there.
std::vector<uint8_t> StairOpenings(const BimModel& model, const std::vector<StairFlight>& flights,
                                   int storey, const OccupancyGrid& g) {
    std::vector<uint8_t> open(g.cells.size(), 0), flight(g.cells.size(), 0);
    const float below = float(g.floor_z - model.origin_m.z() - kUnderFloorM);
    for (const StairFlight& f : flights) {
        if (f.upper != storey || f.levels.empty()) continue;
        const std::set<std::string> ids(f.global_ids.begin(), f.global_ids.end());
        std::fill(flight.begin(), flight.end(), 0);
        for (const BimElement& e : model.elements) {
            if (!ids.contains(e.global_id)) continue;
            for (uint32_t t = e.first_triangle; t < e.first_triangle + e.triangle_count; ++t) {
                const auto& tri = model.mesh.triangles[t];
                const Eigen::Vector3f& a = model.mesh.vertices[tri[0]];
                const Eigen::Vector3f& b = model.mesh.vertices[tri[1]];
                const Eigen::Vector3f& c = model.mesh.vertices[tri[2]];
                if (std::min({a.z(), b.z(), c.z()}) >= below) continue;
                MarkTrianglePlan(g, a.head<2>().cast<double>(), b.head<2>().cast<double>(),
                                 c.head<2>().cast<double>(), flight);
            }
        }
        const Eigen::Vector2d up = f.UpAtHead();
        const StairLevel& top = f.levels.back();
        const Eigen::Vector2d last_riser = top.centre.head<2>() + 0.5 * top.depth_m * up;
        for (int y = 0; y < g.height; ++y) {
            for (int x = 0; x < g.width; ++x) {
                const size_t i = size_t(y) * g.width + x;
                if (flight[i] && (g.Center(x, y) - last_riser).dot(up) <= 0) open[i] = 1;
            }
        }
    }
    return open;
}

// A slab over the cells of `in`: its top at z_top, its underside kAssumedFloorThicknessM lower,
// rectangles merged greedily (row runs extended while the next row has the same run), and its
// edges where a cell of `in` meets one that is not. Faces point out of the slab.
class SlabMesher {
public:
    SlabMesher(const OccupancyGrid& g, const std::vector<uint8_t>& in, double z_top,
               common::TriangleMesh& mesh)
        : g_(g),
          in_(in),
          top_(float(z_top)),
          bottom_(float(z_top - kAssumedFloorThicknessM)),
          mesh_(mesh) {}

    void Run() {
        Faces();
        Edges();
    }

private:
    bool In(int x, int y) const { return g_.Inside(x, y) && in_[size_t(y) * g_.width + x]; }
    Eigen::Vector2f Corner(int x, int y) const {
        return (g_.origin + g_.resolution * Eigen::Vector2d(x, y)).cast<float>();
    }
    // Two triangles a b c, a c d.
    void Quad(const Eigen::Vector3f& a, const Eigen::Vector3f& b, const Eigen::Vector3f& c,
              const Eigen::Vector3f& d) {
        const auto v = uint32_t(mesh_.vertices.size());
        mesh_.vertices.insert(mesh_.vertices.end(), {a, b, c, d});
        mesh_.triangles.push_back({v, v + 1, v + 2});
        mesh_.triangles.push_back({v, v + 2, v + 3});
    }
    // The top (up) and underside (down) of the cells [x0, x1) x [y0, y1).
    void Rectangle(int x0, int x1, int y0, int y1) {
        const Eigen::Vector2f p = Corner(x0, y0), q = Corner(x1, y1);
        Quad({p.x(), p.y(), top_}, {q.x(), p.y(), top_}, {q.x(), q.y(), top_},
             {p.x(), q.y(), top_});
        Quad({p.x(), p.y(), bottom_}, {p.x(), q.y(), bottom_}, {q.x(), q.y(), bottom_},
             {q.x(), p.y(), bottom_});
    }
    void Faces() {
        // Open rectangles by their run [x0, x1): the row they started in.
        std::map<std::pair<int, int>, int> open, next;
        for (int y = 0; y <= g_.height; ++y) {
            next.clear();
            for (int x = 0; y < g_.height && x < g_.width;) {
                if (!In(x, y)) {
                    ++x;
                    continue;
                }
                int x1 = x;
                while (x1 < g_.width && In(x1, y)) ++x1;
                const auto it = open.find({x, x1});
                next[{x, x1}] = it == open.end() ? y : it->second;
                if (it != open.end()) open.erase(it);
                x = x1;
            }
            for (const auto& [run, y0] : open) Rectangle(run.first, run.second, y0, y);
            open.swap(next);
        }
    }
    // A vertical face from a to b (plan), outward to the right of a -> b seen from above.
    void Edge(const Eigen::Vector2f& a, const Eigen::Vector2f& b) {
        Quad({a.x(), a.y(), bottom_}, {b.x(), b.y(), bottom_}, {b.x(), b.y(), top_},
             {a.x(), a.y(), top_});
    }
    void Edges() {
        // Along rows: the south and north sides of runs whose neighbour row is not in the slab.
        for (int y = 0; y < g_.height; ++y) {
            for (const int dy : {-1, 1}) {
                for (int x = 0; x < g_.width;) {
                    if (!In(x, y) || In(x, y + dy)) {
                        ++x;
                        continue;
                    }
                    int x1 = x;
                    while (x1 < g_.width && In(x1, y) && !In(x1, y + dy)) ++x1;
                    const int yy = dy < 0 ? y : y + 1;
                    if (dy < 0) Edge(Corner(x, yy), Corner(x1, yy));
                    if (dy > 0) Edge(Corner(x1, yy), Corner(x, yy));
                    x = x1;
                }
            }
        }
        // Along columns: the west and east sides.
        for (int x = 0; x < g_.width; ++x) {
            for (const int dx : {-1, 1}) {
                for (int y = 0; y < g_.height;) {
                    if (!In(x, y) || In(x + dx, y)) {
                        ++y;
                        continue;
                    }
                    int y1 = y;
                    while (y1 < g_.height && In(x, y1) && !In(x + dx, y1)) ++y1;
                    const int xx = dx < 0 ? x : x + 1;
                    if (dx < 0) Edge(Corner(xx, y1), Corner(xx, y));
                    if (dx > 0) Edge(Corner(xx, y), Corner(xx, y1));
                    y = y1;
                }
            }
        }
    }

    const OccupancyGrid& g_;
    const std::vector<uint8_t>& in_;
    const float top_, bottom_;
    common::TriangleMesh& mesh_;
};

// The floor's cells on one storey's grid: indoors, not over a stair from below (cells where a face
// is modelled at floor height stay: the walls' tops under a storey are). Its area and the
// openings' into `floor`.
std::vector<uint8_t> FloorCells(const BimModel& model, const std::vector<StairFlight>& flights,
                                int storey, const OccupancyGrid& g, AssumedFloor& floor) {
    std::vector<uint8_t> cells = IndoorCells(model, g);
    const std::vector<uint8_t> open = StairOpenings(model, flights, storey, g);
    const double cell_m2 = g.resolution * g.resolution;
    for (size_t i = 0; i < cells.size(); ++i) {
        if (cells[i] && open[i]) floor.opening_m2 += cell_m2;
        cells[i] = cells[i] && !open[i];
        if (cells[i]) floor.area_m2 += cell_m2;
    }
    return cells;
}

}  // namespace

std::string AssumedFloorId(int storey) { return "assumed-floor-" + std::to_string(storey); }

void AddAssumedFloors(BimModel& model) {
    std::optional<std::vector<StairFlight>> flights;  // found once, when a floor is missing
    const size_t storeys = model.storeys.size();
    for (size_t s = 0; s < storeys; ++s) {
        if (!WalkedStorey(model, s)) continue;
        const std::optional<OccupancyGrid> g = GridOf(model, int(s));
        if (!g) continue;
        if (FloorModelled(*g, FloorFaceCells(model, *g))) continue;
        if (!flights) flights = FindStairFlights(model);
        AssumedFloor floor{int(s)};
        const std::vector<uint8_t> cells = FloorCells(model, *flights, int(s), *g, floor);
        if (floor.area_m2 <= 0) continue;

        BimElement e;
        e.global_id = AssumedFloorId(int(s));
        e.ifc_class = "IfcSlab";
        e.name = "assumed floor of '" + model.storeys[s].name + "' (the file models none)";
        e.storey = int(s);
        e.role = ElementRole::kStructure;
        e.assumed = true;
        e.first_triangle = uint32_t(model.mesh.triangles.size());
        SlabMesher(*g, cells, g->floor_z - model.origin_m.z(), model.mesh).Run();
        e.triangle_count = uint32_t(model.mesh.triangles.size()) - e.first_triangle;
        model.triangle_element.resize(model.mesh.triangles.size(), uint32_t(model.elements.size()));
        model.elements.push_back(std::move(e));
        model.assumed_floors.push_back(floor);
    }
}

}  // namespace bimslam::bim
