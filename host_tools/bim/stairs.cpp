// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/bim/stairs.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <sstream>

#include "algorithms/common/status.hpp"

namespace bimslam::bim {
namespace {

constexpr double kSampleM = 0.05;     // walking surfaces sampled on this grid
constexpr double kMinNormalZ = 0.9;   // horizontal enough to stand on (ramps up to 25 degrees)
constexpr double kUndersideM = 0.5;   // a face with its own stair this close above is an underside
constexpr double kLevelGapM = 0.02;   // heights further apart than this are different levels
constexpr double kRampBandM = 0.05;   // a sloped surface is cut into bands this high
constexpr double kMinLevelM2 = 0.03;  // smaller levels are slivers (nosings, stringer tops)
constexpr double kFloorM = 0.03;      // a surface this close to a storey's floor is that floor
constexpr double kTouchM = 0.1;       // elements of one stair touch within this
constexpr double kMaxLandingM2 = 20;  // a slab larger in plan is a floor, not a landing
constexpr double kRiserGapM = 0.001;  // the two points of a riser in Line()

bool IsStairClass(const std::string& c) { return IsStairOrRampClass(c); }

std::string Describe(const BimElement& e) {
    return e.ifc_class + " '" + e.name + "' (" + e.global_id + ")";
}

Eigen::AlignedBox3d ElementBox(const BimModel& m, const BimElement& e) {
    Eigen::AlignedBox3d box;
    for (uint32_t t = e.first_triangle; t < e.first_triangle + e.triangle_count; ++t) {
        for (const uint32_t v : m.mesh.triangles[t]) box.extend(m.mesh.vertices[v].cast<double>());
    }
    return box;
}

// A slab that may be a stair's landing: small, its top between storeys' floors. Exporters write
// landings as IfcSlab parts of the IfcStair (Office_A's half-turn stairs: two flights and a slab
// named as the stair); they join the stair they touch.
bool MaybeLanding(const BimModel& m, const BimElement& e, const Eigen::AlignedBox3d& box) {
    if (e.ifc_class != "IfcSlab") return false;
    const Eigen::Vector3d size = box.sizes();
    if (size.x() * size.y() > kMaxLandingM2) return false;
    return std::none_of(m.storeys.begin(), m.storeys.end(), [&](const BimStorey& s) {
        return std::abs(s.elevation_m - box.max().z()) < kFloorM;
    });
}

// The stair and ramp elements, and the landings touching them, grouped into stairs: those whose
// boxes touch (union-find). A group without a stair or ramp element is none.
std::vector<std::vector<size_t>> StairGroups(const BimModel& m) {
    std::vector<size_t> ids;
    std::vector<Eigen::AlignedBox3d> boxes;
    for (size_t i = 0; i < m.elements.size(); ++i) {
        const BimElement& e = m.elements[i];
        if (e.triangle_count == 0) continue;
        const Eigen::AlignedBox3d box = ElementBox(m, e);
        if (!IsStairClass(e.ifc_class) && !MaybeLanding(m, e, box)) continue;
        ids.push_back(i);
        boxes.push_back(box);
        boxes.back().min().array() -= kTouchM;
        boxes.back().max().array() += kTouchM;
    }
    std::vector<size_t> parent(ids.size());
    std::iota(parent.begin(), parent.end(), 0);
    auto root = [&](size_t i) {
        while (parent[i] != i) i = parent[i] = parent[parent[i]];
        return i;
    };
    for (size_t a = 0; a < ids.size(); ++a) {
        for (size_t b = a + 1; b < ids.size(); ++b) {
            if (boxes[a].intersects(boxes[b])) parent[root(a)] = root(b);
        }
    }
    std::map<size_t, std::vector<size_t>> groups;
    for (size_t a = 0; a < ids.size(); ++a) groups[root(a)].push_back(ids[a]);
    std::vector<std::vector<size_t>> out;
    for (auto& [r, g] : groups) {
        // The stair's elements first (it is named after the first).
        std::stable_partition(g.begin(), g.end(),
                              [&](size_t i) { return IsStairClass(m.elements[i].ifc_class); });
        if (IsStairClass(m.elements[g.front()].ifc_class)) out.push_back(std::move(g));
    }
    return out;
}

// The horizontal faces of the elements, sampled at the centres of the 5 cm grid's cells: per
// cell, the heights found there.
using CellHeights = std::map<std::pair<long, long>, std::vector<double>>;
CellHeights SampleHorizontalFaces(const BimModel& m, const std::vector<size_t>& elements) {
    CellHeights cells;
    for (const size_t e : elements) {
        const BimElement& el = m.elements[e];
        for (uint32_t t = el.first_triangle; t < el.first_triangle + el.triangle_count; ++t) {
            const auto& tri = m.mesh.triangles[t];
            const Eigen::Vector3d a = m.mesh.vertices[tri[0]].cast<double>();
            const Eigen::Vector3d b = m.mesh.vertices[tri[1]].cast<double>();
            const Eigen::Vector3d c = m.mesh.vertices[tri[2]].cast<double>();
            const Eigen::Vector3d n = (b - a).cross(c - a);
            if (n.norm() < 1e-12 || std::abs(n.z()) < kMinNormalZ * n.norm()) continue;
            const Eigen::Vector3d lo = a.cwiseMin(b).cwiseMin(c), hi = a.cwiseMax(b).cwiseMax(c);
            for (long ix = long(std::floor(lo.x() / kSampleM)); ix * kSampleM <= hi.x(); ++ix) {
                for (long iy = long(std::floor(lo.y() / kSampleM)); iy * kSampleM <= hi.y(); ++iy) {
                    const Eigen::Vector2d p((double(ix) + 0.5) * kSampleM,
                                            (double(iy) + 0.5) * kSampleM);
                    // Barycentric coordinates in plan (not vertical: n.z != 0).
                    const double d = n.z();
                    const Eigen::Vector2d ap = p - a.head<2>(), ab = (b - a).head<2>(),
                                          ac = (c - a).head<2>();
                    const double s1 = (ap.x() * ac.y() - ap.y() * ac.x()) / d;
                    const double s2 = (ab.x() * ap.y() - ab.y() * ap.x()) / d;
                    if (s1 < 0 || s2 < 0 || s1 + s2 > 1) continue;
                    cells[{ix, iy}].push_back(a.z() + s1 * (b.z() - a.z()) + s2 * (c.z() - a.z()));
                }
            }
        }
    }
    return cells;
}

// The tops among the sampled heights: nothing of the stair within kUndersideM above, and not a
// storey's floor.
std::vector<Eigen::Vector3d> TopSurfaces(const BimModel& m, CellHeights& cells) {
    std::vector<Eigen::Vector3d> tops;
    for (auto& [key, heights] : cells) {
        std::vector<double>& zs = heights;  // (a structured binding cannot be captured in C++20)
        std::sort(zs.begin(), zs.end());
        for (size_t i = 0; i < zs.size(); ++i) {
            if (i + 1 < zs.size() && zs[i + 1] - zs[i] < 1e-3) continue;  // a shared edge
            const double z0 = zs[i];
            const bool covered = std::any_of(zs.begin() + long(i) + 1, zs.end(), [z0](double z) {
                return z > z0 + 0.01 && z <= z0 + kUndersideM;
            });
            const bool floor = std::any_of(m.storeys.begin(), m.storeys.end(), [z0](const auto& s) {
                return std::abs(s.elevation_m - z0) < kFloorM;
            });
            if (covered || floor) continue;
            tops.emplace_back((double(key.first) + 0.5) * kSampleM,
                              (double(key.second) + 0.5) * kSampleM, zs[i]);
        }
    }
    return tops;
}

// The tops grouped by height into levels (a sloped surface into 5 cm bands), lowest first, with
// their centres; then each level's depth and width along and across the walking line.
std::vector<StairLevel> Levels(std::vector<Eigen::Vector3d> tops) {
    std::sort(tops.begin(), tops.end(),
              [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return a.z() < b.z(); });
    std::vector<std::vector<Eigen::Vector3d>> groups;
    for (size_t i = 0; i < tops.size(); ++i) {
        const bool step = i == 0 || tops[i].z() - tops[i - 1].z() > kLevelGapM ||
                          tops[i].z() - groups.back().front().z() > kRampBandM;
        if (step) groups.emplace_back();
        groups.back().push_back(tops[i]);
    }
    // Slivers are no levels: smaller than kMinLevelM2, or than 40 % of the median level (a newel
    // post's top on a spiral stair).
    std::vector<double> sizes;
    for (const auto& g : groups) sizes.push_back(double(g.size()));
    std::nth_element(sizes.begin(), sizes.begin() + long(sizes.size() / 2), sizes.end());
    const double median = sizes.empty() ? 0.0 : sizes[sizes.size() / 2];
    std::vector<StairLevel> levels;
    std::vector<std::vector<Eigen::Vector3d>> kept;
    for (auto& g : groups) {
        const double area = double(g.size()) * kSampleM * kSampleM;
        if (area < kMinLevelM2 || double(g.size()) < 0.4 * median) continue;
        StairLevel l;
        for (const Eigen::Vector3d& p : g) l.centre += p;
        l.centre /= double(g.size());
        l.area_m2 = area;
        levels.push_back(l);
        kept.push_back(std::move(g));
    }
    for (size_t k = 0; k < levels.size(); ++k) {
        const size_t a = k ? k - 1 : k, b = std::min(k + 1, levels.size() - 1);
        Eigen::Vector2d u = (levels[b].centre - levels[a].centre).head<2>();
        if (u.norm() < 1e-6) u = Eigen::Vector2d::UnitX();
        u.normalize();
        const Eigen::Vector2d v(-u.y(), u.x());
        double lo_u = 1e9, hi_u = -1e9, lo_v = 1e9, hi_v = -1e9;
        for (const Eigen::Vector3d& p : kept[k]) {
            lo_u = std::min(lo_u, p.head<2>().dot(u)), hi_u = std::max(hi_u, p.head<2>().dot(u));
            lo_v = std::min(lo_v, p.head<2>().dot(v)), hi_v = std::max(hi_v, p.head<2>().dot(v));
        }
        levels[k].depth_m = hi_u - lo_u + kSampleM;
        levels[k].width_m = hi_v - lo_v + kSampleM;
    }
    return levels;
}

double Median(std::vector<double> v) {
    if (v.empty()) return 0;
    std::nth_element(v.begin(), v.begin() + long(v.size() / 2), v.end());
    return v[v.size() / 2];
}

// The storey whose floor lies between z0 and z1 (z0 < z1), nearest to z; -1 when none does.
int StoreyBetween(const BimModel& m, double z0, double z1, double z) {
    int best = -1;
    for (size_t s = 0; s < m.storeys.size(); ++s) {
        const double e = m.storeys[s].elevation_m;
        if (e < z0 || e > z1) continue;
        if (best < 0 || std::abs(e - z) < std::abs(m.storeys[size_t(best)].elevation_m - z)) {
            best = int(s);
        }
    }
    return best;
}

std::string Fixed(double v, int digits) {
    std::ostringstream os;
    os.setf(std::ios::fixed);
    os.precision(digits);
    os << v;
    return os.str();
}

// Rise, run and width from the levels (medians over the treads: levels no larger than twice the
// median, so landings do not count), and the storeys the ends meet.
void MeasureFlight(const BimModel& m, StairFlight& f) {
    const std::vector<StairLevel>& l = f.levels;
    std::vector<double> areas, rises, runs, widths;
    for (const StairLevel& s : l) areas.push_back(s.area_m2);
    const double tread_area = Median(areas);
    for (StairLevel& level : f.levels) level.landing = level.area_m2 > 2 * tread_area;
    for (size_t k = 0; k < l.size(); ++k) {
        if (l[k].landing) continue;
        widths.push_back(l[k].width_m);
        if (k == 0) continue;
        rises.push_back(l[k].centre.z() - l[k - 1].centre.z());
        if (l[k - 1].area_m2 <= 2 * tread_area) {
            runs.push_back((l[k].centre - l[k - 1].centre).head<2>().norm());
        }
    }
    f.rise_m = rises.empty() ? 0.0 : Median(rises);
    f.run_m = runs.empty() ? l.front().depth_m : Median(runs);
    f.width_m = Median(widths);
    f.pitch_deg = std::atan2(f.rise_m, std::max(f.run_m, 1e-6)) * 180.0 / M_PI;
    if (l.size() == 1) f.rise_m = 0;  // one level: no riser between levels to measure
    const double rise = f.rise_m > 0 ? f.rise_m : 0.2;
    const double bottom = l.front().centre.z() - rise, top = l.back().centre.z() + rise;
    // An end meets the floor from a sliver above (below) its last (first) level up to one and a
    // half rises: exporters' last risers differ (FZK-Haus's top riser is 5 cm).
    const double z0 = l.front().centre.z(), z1 = l.back().centre.z();
    f.lower = StoreyBetween(m, z0 - 1.5 * rise, z0 - 0.02, bottom);
    f.upper = StoreyBetween(m, z1 + 0.02, z1 + 1.5 * rise, top);
    if (f.lower >= 0) f.lower_z = m.storeys[size_t(f.lower)].elevation_m;
    if (f.upper >= 0) f.upper_z = m.storeys[size_t(f.upper)].elevation_m;
    f.risers = int(l.size()) + 1;
    if (f.lower < 0 || f.upper < 0 || f.lower == f.upper) {
        f.problem = "its walking surfaces rise from " + Fixed(l.front().centre.z(), 2) + " to " +
                    Fixed(l.back().centre.z(), 2) + " m, and its " +
                    (f.lower < 0 ? "bottom (" + Fixed(bottom, 2) + " m)"
                                 : "top (" + Fixed(top, 2) + " m)") +
                    " meets no storey's floor: the storeys are not joined";
        return;
    }
    // Where the walk stands: half a level's depth before the first tread's centre is the first
    // riser, and so on beyond the last.
    const Eigen::Vector2d c0 = l.front().centre.head<2>(), c1 = l.back().centre.head<2>();
    const Eigen::Vector2d u0 = f.UpAtFoot(), u1 = f.UpAtHead();
    f.entry = c0 - u0 * (0.5 * l.front().depth_m);
    f.exit = c1 + u1 * (0.5 * l.back().depth_m);
}

// Declared over the group's IfcStairFlight elements (DeclaredFlight).
DeclaredFlight Declared(const BimModel& m, const std::vector<size_t>& group) {
    DeclaredFlight d;
    std::vector<double> rises, runs;
    for (const size_t e : group) {
        const DeclaredFlight& x = m.elements[e].declared_flight;
        d.risers += x.risers;
        d.treads += x.treads;
        if (x.riser_height_m > 0) rises.push_back(x.riser_height_m);
        if (x.tread_length_m > 0) runs.push_back(x.tread_length_m);
    }
    d.riser_height_m = Median(rises);
    d.tread_length_m = Median(runs);
    return d;
}

// The declared lengths against the measured ones, scaled by `scale` (1: as the file reads; feet);
// what differs, or nothing.
std::vector<std::string> LengthsDiffer(const StairFlight& f, double scale) {
    const DeclaredFlight& d = f.declared;
    std::vector<std::string> says;
    const double rise = d.riser_height_m * scale, run = d.tread_length_m * scale;
    if (rise > 0 && f.rise_m > 0 && std::abs(rise - f.rise_m) > kDeclaredRiseToleranceM) {
        says.push_back("risers of " + Fixed(f.rise_m, 3) + " m, " + Fixed(rise, 3) + " m declared");
    }
    if (run > 0 && f.run_m > 0 && std::abs(run - f.run_m) > kDeclaredRunToleranceM) {
        says.push_back("a run of " + Fixed(f.run_m, 3) + " m, treads of " + Fixed(run, 3) +
                       " m declared");
    }
    return says;
}

}  // namespace

DeclaredCheck CheckDeclared(const StairFlight& f) {
    const DeclaredFlight& d = f.declared;
    DeclaredCheck out;
    out.declared = d.Any();
    std::vector<std::string> says;
    const auto treads = std::count_if(f.levels.begin(), f.levels.end(),
                                      [](const StairLevel& l) { return !l.landing; });
    if (d.risers > 0 && !f.levels.empty() && d.risers != f.risers) {
        says.push_back(std::to_string(f.risers) + " risers in its geometry, " +
                       std::to_string(d.risers) + " declared");
    }
    if (d.treads > 0 && !f.levels.empty() && d.treads != int(treads)) {
        says.push_back(std::to_string(treads) + " treads in its geometry, " +
                       std::to_string(d.treads) + " declared");
    }
    std::vector<std::string> lengths = LengthsDiffer(f, 1.0);
    const bool lengths_declared = d.riser_height_m > 0 || d.tread_length_m > 0;
    const bool feet_unit = std::abs(d.length_unit_m - kFootM) < 1e-6;
    if (!lengths.empty() && lengths_declared && !feet_unit &&
        LengthsDiffer(f, kFootM / d.length_unit_m).empty()) {
        out.in_feet = true;
        lengths.clear();
    }
    says.insert(says.end(), lengths.begin(), lengths.end());
    for (const std::string& s : says) out.differs += (out.differs.empty() ? "" : "; ") + s;
    return out;
}

bool IsStairOrRampClass(std::string_view c) {
    return c == "IfcStair" || c == "IfcStairFlight" || c == "IfcRamp" || c == "IfcRampFlight";
}

void CheckStairLimits(const StairLimits& lim, StairFlight& f) {
    if (!f.problem.empty()) return;
    if (f.rise_m > lim.max_riser_m) {
        f.problem = "too steep: its risers are " + Fixed(f.rise_m, 3) + " m (at most " +
                    Fixed(lim.max_riser_m, 3) + " m)";
    } else if (f.pitch_deg > lim.max_pitch_deg) {
        f.problem = "too steep: it climbs at " + Fixed(f.pitch_deg, 1) + " degrees (at most " +
                    Fixed(lim.max_pitch_deg, 1) + ")";
    } else if (f.width_m < lim.min_width_m) {
        f.problem = "too narrow: " + Fixed(f.width_m, 2) + " m wide (at least " +
                    Fixed(lim.min_width_m, 2) + " m)";
    }
}

StairLimits StairLimits::Go1() {
    StairLimits l;
    l.max_riser_m = 0.21;
    l.max_pitch_deg = 40.0;
    l.min_width_m = 0.6;
    return l;
}

void StairLimits::Validate() const {
    common::Require(max_riser_m > 0 && max_riser_m < 0.5, "StairLimits", "max_riser_m", max_riser_m,
                    "must be in (0, 0.5) m");
    common::Require(max_pitch_deg > 0 && max_pitch_deg < 90, "StairLimits", "max_pitch_deg",
                    max_pitch_deg, "must be in (0, 90) deg");
    common::Require(min_width_m > 0, "StairLimits", "min_width_m", min_width_m, "must be > 0");
    common::Require(standing_m >= 0, "StairLimits", "standing_m", standing_m, "must be >= 0");
}

std::vector<Eigen::Vector3d> StairFlight::Line() const {
    // The centres of the levels, with the standing points at the ends. Between two treads the
    // riser lies half way (a spiral's wedges reach further along the line than their centres are
    // apart); next to a landing or a floor, at the landing's or first or last tread's edge.
    std::vector<Eigen::Vector2d> c{entry};
    std::vector<double> depth{0.0}, z{lower_z};
    std::vector<bool> tread{false};
    for (const StairLevel& l : levels) {
        c.push_back(l.centre.head<2>());
        depth.push_back(l.depth_m);
        z.push_back(l.centre.z());
        tread.push_back(!l.landing);
    }
    c.push_back(exit);
    depth.push_back(0.0);
    z.push_back(upper_z);
    tread.push_back(false);
    std::vector<Eigen::Vector3d> out{{entry.x(), entry.y(), lower_z}};
    for (size_t k = 1; k < c.size(); ++k) {
        const Eigen::Vector2d d = c[k] - c[k - 1];
        const double len = d.norm();
        const Eigen::Vector2d u = len > 1e-9 ? Eigen::Vector2d(d / len) : Eigen::Vector2d::UnitX();
        const bool from_floor = k == 1, to_floor = k + 1 == c.size();
        double at = 0.5 * len;  // between treads
        if (from_floor || (!to_floor && tread[k - 1] && !tread[k])) {
            at = len - 0.5 * depth[k];  // the near edge of the first level or of a landing
        } else if (to_floor || (!tread[k - 1] && tread[k])) {
            at = 0.5 * depth[k - 1];  // the far edge of the last level or of a landing
        }
        at = std::clamp(at, 0.0, std::max(0.0, len - kRiserGapM));
        const Eigen::Vector2d riser = c[k - 1] + at * u, up = riser + kRiserGapM * u;
        out.emplace_back(riser.x(), riser.y(), z[k - 1]);
        out.emplace_back(up.x(), up.y(), z[k]);
        out.emplace_back(c[k].x(), c[k].y(), z[k]);
    }
    return out;
}

Eigen::Vector2d StairFlight::UpAtFoot() const {
    if (levels.size() < 2) return Eigen::Vector2d::UnitX();
    return (levels[1].centre - levels[0].centre).head<2>().normalized();
}

Eigen::Vector2d StairFlight::UpAtHead() const {
    if (levels.size() < 2) return UpAtFoot();
    return (levels.back().centre - levels[levels.size() - 2].centre).head<2>().normalized();
}

double StairFlight::LengthM() const {
    const std::vector<Eigen::Vector3d> line = Line();
    double len = 0;
    for (size_t k = 1; k < line.size(); ++k) len += (line[k] - line[k - 1]).head<2>().norm();
    return len;
}

std::vector<StairFlight> FindStairFlights(const BimModel& m) {
    std::vector<StairFlight> out;
    for (const std::vector<size_t>& group : StairGroups(m)) {
        StairFlight f;
        f.name = Describe(m.elements[group.front()]);
        for (const size_t e : group) {
            f.global_ids.push_back(m.elements[e].global_id);
            f.ramp = f.ramp || m.elements[e].ifc_class.starts_with("IfcRamp");
        }
        f.declared = Declared(m, group);
        CellHeights cells = SampleHorizontalFaces(m, group);
        f.levels = Levels(TopSurfaces(m, cells));
        if (f.levels.empty()) {
            f.problem = "no walking surface in its geometry (no tread or landing)";
        } else {
            MeasureFlight(m, f);
        }
        out.push_back(std::move(f));
    }
    return out;
}

}  // namespace bimslam::bim
