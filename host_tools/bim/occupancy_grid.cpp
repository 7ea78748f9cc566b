// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/bim/occupancy_grid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "algorithms/common/status.hpp"
#include "algorithms/io/file_util.hpp"

namespace bimslam::bim {
namespace {
using common::StatusCode;

// Doors, windows and curtain walls close the building for telling inside from outside (their
// footprints up to this height above the floor), yet never block the walk.
constexpr double kClosureHeightM = 2.5;
bool Closure(const std::string& ifc_class) {
    for (const char* prefix : {"IfcDoor", "IfcWindow", "IfcCurtainWall"}) {
        if (ifc_class.rfind(prefix, 0) == 0) return true;
    }
    return false;
}

}  // namespace

std::vector<int> LabelRegions(const OccupancyGrid& g, const std::function<bool(size_t)>& in) {
    std::vector<int> label(g.cells.size(), -1);
    std::vector<size_t> stack;
    int next = 0;
    for (size_t start = 0; start < g.cells.size(); ++start) {
        if (label[start] >= 0 || !in(start)) continue;
        label[start] = next;
        stack.assign(1, start);
        while (!stack.empty()) {
            const size_t i = stack.back();
            stack.pop_back();
            const int x = int(i % g.width), y = int(i / g.width);
            const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};
            for (int k = 0; k < 4; ++k) {
                const int nx = x + dx[k], ny = y + dy[k];
                if (!g.Inside(nx, ny)) continue;
                const size_t j = size_t(ny) * g.width + nx;
                if (label[j] < 0 && in(j)) {
                    label[j] = next;
                    stack.push_back(j);
                }
            }
        }
        ++next;
    }
    return label;
}

namespace {

// Marks the cells a segment passes through (sampled at a quarter cell, so no cell is skipped).
void RasterizeSegment(const OccupancyGrid& g, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                      std::vector<uint8_t>& mask) {
    const double len = (b - a).norm();
    const int steps = std::max(1, int(std::ceil(len / (0.25 * g.resolution))));
    for (int i = 0; i <= steps; ++i) {
        int x, y;
        if (g.ToCell(a + (b - a) * (double(i) / steps), &x, &y)) {
            mask[size_t(y) * g.width + x] = 1;
        }
    }
}

}  // namespace

void MarkTrianglePlan(const OccupancyGrid& g, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                      const Eigen::Vector2d& c, std::vector<uint8_t>& mask) {
    RasterizeSegment(g, a, b, mask);
    RasterizeSegment(g, b, c, mask);
    RasterizeSegment(g, c, a, mask);
    const double area = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
    if (std::abs(area) < 1e-12) return;
    int x0, y0, x1, y1;
    const Eigen::Vector2d lo = a.cwiseMin(b).cwiseMin(c), hi = a.cwiseMax(b).cwiseMax(c);
    g.ToCell(lo.cwiseMax(g.origin), &x0, &y0);
    const Eigen::Vector2d top = g.origin + g.resolution * Eigen::Vector2d(g.width, g.height);
    g.ToCell(hi.cwiseMin(top - Eigen::Vector2d::Constant(1e-9)), &x1, &y1);
    for (int y = y0; y <= y1; ++y) {
        for (int x = x0; x <= x1; ++x) {
            const Eigen::Vector2d p = g.Center(x, y);
            const double w0 = ((b - p).x() * (c - p).y() - (b - p).y() * (c - p).x()) / area;
            const double w1 = ((c - p).x() * (a - p).y() - (c - p).y() * (a - p).x()) / area;
            if (w0 >= 0 && w1 >= 0 && w0 + w1 <= 1) mask[size_t(y) * g.width + x] = 1;
        }
    }
}

namespace {

// An object's triangle in plan, when it reaches between 2 cm above the floor and top_m above it:
// what a walker must go around (a rug or a shelf above the head is not in the way).
void RasterizeFootprint(const OccupancyGrid& g, const Eigen::Vector3f& a, const Eigen::Vector3f& b,
                        const Eigen::Vector3f& c, double top_m, std::vector<uint8_t>& mask) {
    const double zmin = std::min({a.z(), b.z(), c.z()}), zmax = std::max({a.z(), b.z(), c.z()});
    if (zmax < g.floor_z + 0.02 || zmin > g.floor_z + top_m) return;
    MarkTrianglePlan(g, a.head<2>().cast<double>(), b.head<2>().cast<double>(),
                     c.head<2>().cast<double>(), mask);
}

// The segment where a triangle crosses the plane z = h, if it does.
bool SliceTriangle(const Eigen::Vector3f& a, const Eigen::Vector3f& b, const Eigen::Vector3f& c,
                   double h, Eigen::Vector2d* p, Eigen::Vector2d* q) {
    const Eigen::Vector3d v[3] = {a.cast<double>(), b.cast<double>(), c.cast<double>()};
    double d[3];
    for (int i = 0; i < 3; ++i) {
        d[i] = v[i].z() - h;
        if (d[i] == 0) d[i] = 1e-9;  // a vertex on the plane counts as above it
    }
    Eigen::Vector2d pts[2];
    int n = 0;
    for (int i = 0; i < 3; ++i) {
        const int j = (i + 1) % 3;
        if ((d[i] < 0) != (d[j] < 0) && n < 2) {
            const double t = d[i] / (d[i] - d[j]);
            pts[n++] = (v[i] + t * (v[j] - v[i])).head<2>();
        }
    }
    if (n != 2) return false;
    *p = pts[0];
    *q = pts[1];
    return true;
}

// Fills the inside of an element's slice: its segments form closed loops when its mesh is closed
// (IFC solids are), so each cell row's crossings pair up as in/out (even-odd rule). A thick wall
// is then occupied through and through, not only its outline. Rows whose count is odd (an open
// mesh) keep the outline alone.
void FillSlice(const OccupancyGrid& g,
               const std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>>& segs,
               std::vector<double>& xs, std::vector<uint8_t>& mask) {
    if (segs.size() < 3) return;
    double ymin = segs[0].first.y(), ymax = ymin;
    for (const auto& [p, q] : segs) {
        ymin = std::min({ymin, p.y(), q.y()});
        ymax = std::max({ymax, p.y(), q.y()});
    }
    const int r0 = std::max(0, int(std::floor((ymin - g.origin.y()) / g.resolution)));
    const int r1 = std::min(g.height - 1, int(std::floor((ymax - g.origin.y()) / g.resolution)));
    for (int row = r0; row <= r1; ++row) {
        const double y = g.Center(0, row).y();
        xs.clear();
        for (const auto& [p, q] : segs) {
            if ((p.y() <= y) != (q.y() <= y))
                xs.push_back(p.x() + (y - p.y()) / (q.y() - p.y()) * (q.x() - p.x()));
        }
        if (xs.size() % 2 != 0) continue;
        std::sort(xs.begin(), xs.end());
        for (size_t k = 0; k + 1 < xs.size(); k += 2) {
            const int c0 = std::max(0, int(std::ceil((xs[k] - g.origin.x()) / g.resolution - 0.5)));
            const int c1 = std::min(
                g.width - 1, int(std::floor((xs[k + 1] - g.origin.x()) / g.resolution - 0.5)));
            for (int c = c0; c <= c1; ++c) mask[size_t(row) * g.width + c] = 1;
        }
    }
}

// Exact squared Euclidean distance transform of a 1-D sampled function (Felzenszwalb and
// Huttenlocher, "Distance Transforms of Sampled Functions", 2012).
void Edt1d(const std::vector<double>& f, std::vector<double>& d, std::vector<int>& v,
           std::vector<double>& z) {
    const int n = int(f.size());
    auto intersect = [&f](int q, int p) {  // where the parabolas from q and p meet
        return ((f[q] + double(q) * q) - (f[p] + double(p) * p)) / (2.0 * (q - p));
    };
    int k = 0;
    v[0] = 0;
    z[0] = -std::numeric_limits<double>::infinity();
    z[1] = std::numeric_limits<double>::infinity();
    for (int q = 1; q < n; ++q) {
        double s = intersect(q, v[k]);
        while (s <= z[k]) {  // z[0] = -inf stops this at k = 0
            --k;
            s = intersect(q, v[k]);
        }
        ++k;
        v[k] = q;
        z[k] = s;
        z[k + 1] = std::numeric_limits<double>::infinity();
    }
    k = 0;
    for (int q = 0; q < n; ++q) {
        while (z[k + 1] < q) ++k;
        d[q] = double(q - v[k]) * (q - v[k]) + f[v[k]];
    }
}

void Clearance(OccupancyGrid& g) {
    constexpr double kFar = 1e20;
    const int w = g.width, h = g.height;
    std::vector<double> grid(size_t(w) * h);
    for (size_t i = 0; i < grid.size(); ++i) grid[i] = g.cells[i] == Cell::kFree ? kFar : 0.0;
    const int n = std::max(w, h);
    std::vector<double> f(n), d(n), z(n + 1);
    std::vector<int> v(n);
    for (int x = 0; x < w; ++x) {  // columns
        f.resize(h);
        d.resize(h);
        for (int y = 0; y < h; ++y) f[y] = grid[size_t(y) * w + x];
        Edt1d(f, d, v, z);
        for (int y = 0; y < h; ++y) grid[size_t(y) * w + x] = d[y];
    }
    for (int y = 0; y < h; ++y) {  // rows
        f.resize(w);
        d.resize(w);
        for (int x = 0; x < w; ++x) f[x] = grid[size_t(y) * w + x];
        Edt1d(f, d, v, z);
        for (int x = 0; x < w; ++x) grid[size_t(y) * w + x] = d[x];
    }
    g.clearance.resize(grid.size());
    for (size_t i = 0; i < grid.size(); ++i) {
        g.clearance[i] = static_cast<float>(std::sqrt(grid[i]) * g.resolution);
    }
}
}  // namespace

void GridConfig::Validate() const {
    common::Require(resolution_m >= 0.005 && resolution_m <= 1.0, "GridConfig", "resolution_m",
                    resolution_m, "must be in [0.005, 1] m");
    common::Require(slice_height_m > 0 && slice_height_m < 10, "GridConfig", "slice_height_m",
                    slice_height_m, "must be in (0, 10) m");
    common::Require(margin_m >= 0 && margin_m < 100, "GridConfig", "margin_m", margin_m,
                    "must be in [0, 100) m");
    common::Require(object_height_m > 0 && object_height_m < 10, "GridConfig", "object_height_m",
                    object_height_m, "must be in (0, 10) m");
    common::Require(region >= 0 && region < 1000, "GridConfig", "region", double(region),
                    "must be in [0, 1000)");
    common::Require(headroom_m == 0 || (headroom_m > 0.3 && headroom_m < 10), "GridConfig",
                    "headroom_m", headroom_m, "must be 0 (none) or in (0.3, 10) m");
}

bool OccupancyGrid::ToCell(const Eigen::Vector2d& p, int* x, int* y) const {
    const Eigen::Vector2d c = (p - origin) / resolution;
    *x = int(std::floor(c.x()));
    *y = int(std::floor(c.y()));
    return Inside(*x, *y);
}

size_t OccupancyGrid::FreeCells() const {
    return size_t(std::count(cells.begin(), cells.end(), Cell::kFree));
}

namespace {

// The storey's grid over the structure's footprint and the margin, every cell unknown.
OccupancyGrid EmptyGrid(const BimModel& model, int storey, const GridConfig& config) {
    OccupancyGrid g;
    g.storey = model.storeys[storey].name;
    g.resolution = config.resolution_m;
    g.floor_z = model.storeys[storey].elevation_m;
    g.slice_z = g.floor_z + config.slice_height_m;
    // The footprint of the structure, plus a margin.
    Eigen::AlignedBox2d box;
    for (const BimElement& e : model.elements) {
        if (e.role != ElementRole::kStructure) continue;
        for (uint32_t t = e.first_triangle; t < e.first_triangle + e.triangle_count; ++t) {
            for (uint32_t k : model.mesh.triangles[t]) {
                box.extend(model.mesh.vertices[k].head<2>().cast<double>());
            }
        }
    }
    if (box.isEmpty()) {
        throw common::Error(StatusCode::kInvalidArgument, model.file + ": no structure geometry");
    }
    g.origin = box.min() - Eigen::Vector2d::Constant(config.margin_m);
    const Eigen::Vector2d size = box.sizes() + Eigen::Vector2d::Constant(2 * config.margin_m);
    g.width = int(std::ceil(size.x() / g.resolution));
    g.height = int(std::ceil(size.y() / g.resolution));
    g.cells.assign(size_t(g.width) * g.height, Cell::kUnknown);
    return g;
}

// blocked: the structure's slice (filled) and the footprints of objects. closed: doors, windows
// and curtain walls of this storey, which a robot passes (or not) but which close the building:
// without them an exterior door or a glass facade joins the inside to the outside. Blocked cells
// become occupied, and are not closed.
void Rasterize(const BimModel& model, const GridConfig& config, OccupancyGrid& g,
               std::vector<uint8_t>& blocked, std::vector<uint8_t>& closed) {
    blocked.assign(g.cells.size(), 0);
    closed.assign(g.cells.size(), 0);
    std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> segs;
    std::vector<double> xs;
    for (const BimElement& e : model.elements) {
        const bool structure = e.role == ElementRole::kStructure;
        const bool closure = !structure && Closure(e.ifc_class);
        if (!structure && !closure && (!config.object_footprints || PassThrough(e.ifc_class))) {
            continue;
        }
        segs.clear();
        for (uint32_t t = e.first_triangle; t < e.first_triangle + e.triangle_count; ++t) {
            const auto& tri = model.mesh.triangles[t];
            const Eigen::Vector3f& a = model.mesh.vertices[tri[0]];
            const Eigen::Vector3f& b = model.mesh.vertices[tri[1]];
            const Eigen::Vector3f& c = model.mesh.vertices[tri[2]];
            if (structure) {
                Eigen::Vector2d p, q;
                if (SliceTriangle(a, b, c, g.slice_z, &p, &q)) {
                    RasterizeSegment(g, p, q, blocked);
                    segs.emplace_back(p, q);
                }
                continue;
            }
            RasterizeFootprint(g, a, b, c, closure ? kClosureHeightM : config.object_height_m,
                               closure ? closed : blocked);
        }
        FillSlice(g, segs, xs, blocked);
    }
    for (size_t i = 0; i < g.cells.size(); ++i) {
        if (blocked[i]) g.cells[i] = Cell::kOccupied;
        if (blocked[i]) closed[i] = 0;
    }
}

// Per region label of `region`, whether it touches the grid's border (outdoors).
std::vector<uint8_t> Outdoors(const OccupancyGrid& g, const std::vector<int>& region) {
    std::vector<uint8_t> outdoors(g.cells.size() + 1, 0);  // by region
    const auto mark = [&](int x, int y) {
        if (region[size_t(y) * g.width + x] >= 0)
            outdoors[size_t(region[size_t(y) * g.width + x])] = 1;
    };
    for (int x = 0; x < g.width; ++x) {
        for (const int y : {0, g.height - 1}) mark(x, y);
    }
    for (int y = 0; y < g.height; ++y) {
        for (const int x : {0, g.width - 1}) mark(x, y);
    }
    return outdoors;
}

// The seed's cell (SIZE_MAX without a seed); throws where it is outside the grid or blocked.
size_t SeedCell(const BimModel& model, const GridConfig& config, const OccupancyGrid& g,
                const std::vector<uint8_t>& blocked) {
    if (!config.seed) return SIZE_MAX;
    int x, y;
    if (!g.ToCell(*config.seed, &x, &y) || blocked[size_t(y) * g.width + x]) {
        throw common::Error(StatusCode::kInvalidArgument,
                            model.file + ": the free-space seed (" +
                                std::to_string(config.seed->x()) + ", " +
                                std::to_string(config.seed->y()) + ") is outside the grid or " +
                                "inside a wall of storey '" + g.storey + "'");
    }
    return size_t(y) * g.width + x;
}

// Without a seed: the config.region-th enclosed region by size, counting open cells only (a run
// of closed cells alone is a facade), ties in label order so that the choice is the same on every
// run; every region's area into g.region_areas_m2. -1 when there is none.
int ChooseRegion(const BimModel& model, const GridConfig& config, OccupancyGrid& g,
                 const std::vector<int>& inside, const std::vector<uint8_t>& closed) {
    std::vector<size_t> sizes;
    for (size_t i = 0; i < g.cells.size(); ++i) {
        if (inside[i] < 0 || closed[i]) continue;
        if (size_t(inside[i]) >= sizes.size()) sizes.resize(size_t(inside[i]) + 1, 0);
        ++sizes[size_t(inside[i])];
    }
    std::vector<int> order;
    for (int id = 0; id < int(sizes.size()); ++id) {
        if (sizes[size_t(id)] > 0) order.push_back(id);
    }
    std::stable_sort(order.begin(), order.end(),
                     [&](int a, int b) { return sizes[size_t(a)] > sizes[size_t(b)]; });
    for (const int id : order)
        g.region_areas_m2.push_back(double(sizes[size_t(id)]) * g.resolution * g.resolution);
    if (!order.empty() && config.region >= int(order.size())) {
        throw common::Error(
            StatusCode::kInvalidArgument,
            model.file + ": storey '" + g.storey + "' has " + std::to_string(order.size()) +
                " enclosed free region(s), no region " + std::to_string(config.region + 1));
    }
    return order.empty() ? -1 : order[size_t(config.region)];
}

}  // namespace

namespace {
// Defined below, beside the overhead rule it shares with StandableCells.
void BlockOverhead(const BimModel& model, const OccupancyGrid& g, double headroom_m,
                   std::vector<uint8_t>& blocked, std::vector<uint8_t>& closed);
}  // namespace

OccupancyGrid BuildOccupancyGrid(const BimModel& model, int storey, const GridConfig& config) {
    config.Validate();
    if (storey < 0 || storey >= int(model.storeys.size())) {
        throw common::Error(StatusCode::kInvalidArgument,
                            model.file + ": no storey " + std::to_string(storey) + " (it has " +
                                std::to_string(model.storeys.size()) + ")");
    }
    OccupancyGrid g = EmptyGrid(model, storey, config);
    std::vector<uint8_t> blocked, closed;
    Rasterize(model, config, g, blocked, closed);
    if (config.headroom_m > 0) BlockOverhead(model, g, config.headroom_m, blocked, closed);

    // Regions of the open cells (neither blocked nor closed, 4-neighbourhood); the ones touching
    // the grid's border are outdoors. Closed doors make each room its own region.
    const std::vector<int> region =
        LabelRegions(g, [&](size_t i) { return !blocked[i] && !closed[i]; });
    const std::vector<uint8_t> outdoors = Outdoors(g, region);
    // The inside: the indoor regions joined through the doors (and windows) between them; with a
    // seed, whatever the seed's cell reaches, outdoors included.
    const size_t seed_cell = SeedCell(model, config, g, blocked);
    const std::vector<int> inside = LabelRegions(g, [&](size_t i) {
        if (blocked[i]) return false;
        if (closed[i] || seed_cell != SIZE_MAX) return true;
        return !outdoors[size_t(region[i])];
    });
    const int chosen =
        seed_cell != SIZE_MAX ? inside[seed_cell] : ChooseRegion(model, config, g, inside, closed);
    if (chosen < 0) {
        throw common::Error(
            StatusCode::kInvalidArgument,
            model.file + ": storey '" + g.storey + "' has no enclosed free space " + "at " +
                std::to_string(config.slice_height_m) +
                " m above its floor (no walls there, or a gap in its outer walls: " +
                "give a seed inside)");
    }
    for (size_t i = 0; i < g.cells.size(); ++i) {
        if (!blocked[i]) g.cells[i] = inside[i] == chosen ? Cell::kFree : Cell::kUnknown;
    }
    Clearance(g);
    return g;
}

size_t AddObstacle(OccupancyGrid& g, const common::TriangleMesh& mesh, double object_height_m) {
    std::vector<uint8_t> blocked(g.cells.size(), 0);
    for (const auto& t : mesh.triangles) {
        RasterizeFootprint(g, mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]],
                           object_height_m, blocked);
    }
    size_t taken = 0;
    for (size_t i = 0; i < g.cells.size(); ++i) {
        if (blocked[i] && g.cells[i] == Cell::kFree) g.cells[i] = Cell::kOccupied, ++taken;
    }
    if (taken > 0) Clearance(g);
    return taken;
}

namespace {
// The part of polygon `in` on one side of the plane z = h (Sutherland-Hodgman, one plane).
void ClipZ(const std::vector<Eigen::Vector3d>& in, double h, bool keep_above,
           std::vector<Eigen::Vector3d>* out) {
    out->clear();
    for (size_t i = 0; i < in.size(); ++i) {
        const Eigen::Vector3d& a = in[i];
        const Eigen::Vector3d& b = in[(i + 1) % in.size()];
        const bool a_in = keep_above ? a.z() >= h : a.z() <= h;
        const bool b_in = keep_above ? b.z() >= h : b.z() <= h;
        if (a_in) out->push_back(a);
        if (a_in != b_in) out->push_back(a + (h - a.z()) / (b.z() - a.z()) * (b - a));
    }
}
}  // namespace

namespace {
constexpr double kFloorBand = 0.3;   // m around the storey's elevation: the slab's faces
constexpr double kAboveFloor = 0.3;  // m: what is lower is the floor, a threshold, a step

// One structure triangle (in `poly`, which it overwrites): a horizontal face at the storey's
// elevation (the slab's top or underside) marks `floor`; its part between kAboveFloor and the
// headroom marks `overhead`, when asked for.
void MarkStanding(const OccupancyGrid& g, double headroom_m, std::vector<Eigen::Vector3d>& poly,
                  std::vector<Eigen::Vector3d>& clipped, std::vector<uint8_t>& floor,
                  std::vector<uint8_t>* overhead) {
    const Eigen::Vector3d n = (poly[1] - poly[0]).cross(poly[2] - poly[0]);
    const double zmin = std::min({poly[0].z(), poly[1].z(), poly[2].z()});
    const double zmax = std::max({poly[0].z(), poly[1].z(), poly[2].z()});
    if (std::abs(n.z()) > 0.7 * n.norm() && zmin > g.floor_z - kFloorBand &&
        zmax < g.floor_z + kFloorBand) {
        MarkTrianglePlan(g, poly[0].head<2>(), poly[1].head<2>(), poly[2].head<2>(), floor);
        return;
    }
    const double lo = g.floor_z + kAboveFloor, hi = g.floor_z + headroom_m;
    if (!overhead || zmax < lo || zmin > hi) return;
    ClipZ(poly, lo, true, &clipped);
    ClipZ(clipped, hi, false, &poly);
    for (size_t k = 1; k + 1 < poly.size(); ++k) {
        MarkTrianglePlan(g, poly[0].head<2>(), poly[k].head<2>(), poly[k + 1].head<2>(), *overhead);
    }
}

// MarkStanding over every triangle of the structure.
void MarkStructure(const BimModel& model, const OccupancyGrid& g, double headroom_m,
                   std::vector<uint8_t>& floor, std::vector<uint8_t>* overhead) {
    floor.assign(g.cells.size(), 0);
    if (overhead) overhead->assign(g.cells.size(), 0);
    std::vector<Eigen::Vector3d> poly, clipped;
    for (const BimElement& e : model.elements) {
        if (e.role != ElementRole::kStructure) continue;
        for (uint32_t t = e.first_triangle; t < e.first_triangle + e.triangle_count; ++t) {
            poly.clear();
            for (const uint32_t k : model.mesh.triangles[t]) {
                poly.push_back(model.mesh.vertices[k].cast<double>());
            }
            MarkStanding(g, headroom_m, poly, clipped, floor, overhead);
        }
    }
}

// Cells under structure between kAboveFloor and the headroom are blocked (and not closed), as
// Rasterize's slice blocks them.
void BlockOverhead(const BimModel& model, const OccupancyGrid& g, double headroom_m,
                   std::vector<uint8_t>& blocked, std::vector<uint8_t>& closed) {
    std::vector<uint8_t> floor, overhead;
    MarkStructure(model, g, headroom_m, floor, &overhead);
    for (size_t i = 0; i < g.cells.size(); ++i) {
        if (!overhead[i]) continue;
        blocked[i] = 1;
        closed[i] = 0;
    }
}
}  // namespace

std::vector<uint8_t> FloorFaceCells(const BimModel& model, const OccupancyGrid& g) {
    std::vector<uint8_t> floor;
    MarkStructure(model, g, 0.0, floor, nullptr);
    return floor;
}

bool FloorModelled(const OccupancyGrid& g, const std::vector<uint8_t>& floor) {
    size_t free_cells = 0, floored = 0;
    for (size_t i = 0; i < g.cells.size(); ++i) {
        free_cells += g.cells[i] == Cell::kFree;
        floored += g.cells[i] == Cell::kFree && floor[i];
    }
    return 2 * floored >= free_cells;
}

std::vector<uint8_t> StandableCells(const BimModel& model, const OccupancyGrid& g,
                                    double headroom_m) {
    std::vector<uint8_t> floor, overhead;
    MarkStructure(model, g, headroom_m, floor, &overhead);
    // A model read without assumed floors may have none (Office_A's storeys have only ceilings):
    // there the floor is not asked for.
    const bool floor_modelled = FloorModelled(g, floor);
    std::vector<uint8_t> standable(g.cells.size(), 0);
    for (size_t i = 0; i < g.cells.size(); ++i) {
        standable[i] = g.cells[i] == Cell::kFree && (floor[i] || !floor_modelled) && !overhead[i];
    }
    return standable;
}

std::vector<uint8_t> IndoorCells(const BimModel& model, const OccupancyGrid& grid) {
    GridConfig config;
    config.resolution_m = grid.resolution;
    config.slice_height_m = grid.slice_z - grid.floor_z;
    config.object_footprints = false;  // furniture outside is no building
    OccupancyGrid g = grid;
    g.cells.assign(g.cells.size(), Cell::kUnknown);
    std::vector<uint8_t> blocked, closed;
    Rasterize(model, config, g, blocked, closed);
    const std::vector<int> open =
        LabelRegions(g, [&](size_t i) { return !blocked[i] && !closed[i]; });
    const std::vector<uint8_t> outdoors = Outdoors(g, open);
    std::vector<uint8_t> indoor(g.cells.size(), 0);
    for (size_t i = 0; i < g.cells.size(); ++i) {
        indoor[i] = open[i] < 0 || !outdoors[size_t(open[i])];
    }
    return indoor;
}

io::Image GridImage(const OccupancyGrid& g) {
    io::Image img(g.width, g.height, 1, 205);
    for (int y = 0; y < g.height; ++y) {
        for (int x = 0; x < g.width; ++x) {
            const Cell c = g.At(x, y);
            img.At(x, g.height - 1 - y)[0] = c == Cell::kFree       ? 254
                                             : c == Cell::kOccupied ? 0
                                                                    : 205;
        }
    }
    return img;
}

void WriteGrid(const OccupancyGrid& g, const std::filesystem::path& stem) {
    const io::Image img = GridImage(g);
    std::filesystem::path pgm = stem, png = stem, yaml = stem;
    pgm += ".pgm";
    png += ".png";
    yaml += ".yaml";
    io::WritePgm(pgm, img);
    io::WritePng(png, img);
    // ROS map_server: origin is the pose of the lower-left pixel, thresholds as its defaults.
    const std::string text =
        "image: " + pgm.filename().string() + "\nresolution: " + io::FormatDouble(g.resolution) +
        "\norigin: [" + io::FormatDouble(g.origin.x()) + ", " + io::FormatDouble(g.origin.y()) +
        ", 0.0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n";
    io::WriteFileAtomic(yaml, text);
}

}  // namespace bimslam::bim
