// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/report/report_geometry.hpp"

#include <openssl/evp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>

#include "host_tools/bim/stairs.hpp"
#include "host_tools/report/storey_split.hpp"

namespace bimslam::report {
using nlohmann::json;

std::string Base64(const void* data, size_t bytes) {
    // OpenSSL's encoder (libcrypto), 1.8 times the speed of the loop it replaced, the same text.
    // It takes an int length: whole groups of 3 bytes at a time, so no '=' inside.
    constexpr size_t kPiece = size_t(3) << 28;
    const auto* p = static_cast<const unsigned char*>(data);
    std::string out(4 * ((bytes + 2) / 3), '\0');
    auto* o = reinterpret_cast<unsigned char*>(out.data());
    for (size_t at = 0; at < bytes; at += kPiece) {
        const size_t n = std::min(kPiece, bytes - at);
        o += EVP_EncodeBlock(o, p + at, int(n));
    }
    return out;
}

std::string PlanClass(const std::string& c) {
    if (c.starts_with("IfcWall") || c == "IfcCurtainWall") return "wall";
    if (c == "IfcDoor") return "door";
    if (c == "IfcWindow") return "window";
    if (c == "IfcColumn") return "column";
    return "other";
}

namespace {

bool Drawn(const bim::BimElement& e) {
    return e.ifc_class != "IfcSpace" && e.ifc_class != "IfcOpeningElement" &&
           e.ifc_class != "IfcVirtualElement" && e.triangle_count > 0;
}

// The storey whose elevation range [elevation, next elevation) holds z.
int StoreyOfHeight(const bim::BimModel& m, double z) {
    int s = m.storeys.empty() ? -1 : 0;
    for (size_t k = 0; k < m.storeys.size(); ++k) {
        if (m.storeys[k].elevation_m - m.origin_m.z() <= z) s = int(k);
    }
    return s;
}

}  // namespace

int StoreyAt(const bim::BimModel& model, double z) { return StoreyOfHeight(model, z - 0.1); }

int StoreyOfPoint(const bim::BimModel& model, double z) { return StoreyOfHeight(model, z + 0.05); }

std::vector<int> ElementStoreys(const bim::BimModel& m) {
    std::vector<int> out;
    for (const bim::BimElement& e : m.elements) {
        if (e.storey >= 0 || m.storeys.empty()) {
            out.push_back(e.storey);
            continue;
        }
        float bottom = std::numeric_limits<float>::max();
        for (uint32_t t = e.first_triangle; t < e.first_triangle + e.triangle_count; ++t) {
            for (const uint32_t v : m.mesh.triangles[t])
                bottom = std::min(bottom, m.mesh.vertices[v].z());
        }
        out.push_back(e.triangle_count ? StoreyOfPoint(m, bottom) : 0);
    }
    return out;
}

json PlanSections(const bim::BimModel& m, double cut_height_m) {
    json storeys = json::array();
    for (size_t s = 0; s < m.storeys.size(); ++s) {
        const double cut = m.storeys[s].elevation_m - m.origin_m.z() + cut_height_m;
        std::map<std::string, std::vector<float>> segments;
        std::map<std::string, std::vector<uint32_t>> runs;  // element, segments; per class
        for (size_t ei = 0; ei < m.elements.size(); ++ei) {
            const bim::BimElement& e = m.elements[ei];
            if (!Drawn(e)) continue;
            const int storey = e.storey >= 0 ? e.storey : StoreyOfHeight(m, cut);
            if (storey != int(s)) continue;
            std::vector<float>& out = segments[PlanClass(e.ifc_class)];
            const size_t before = out.size();
            for (uint32_t t = e.first_triangle; t < e.first_triangle + e.triangle_count; ++t) {
                // A triangle crossing the plane contributes the segment between its two crossing
                // edges (vertices exactly on the plane count as above).
                const auto& tri = m.mesh.triangles[t];
                float pts[4];
                int n = 0;
                for (int k = 0; k < 3 && n < 4; ++k) {
                    const Eigen::Vector3f& a = m.mesh.vertices[tri[k]];
                    const Eigen::Vector3f& b = m.mesh.vertices[tri[(k + 1) % 3]];
                    const bool a_above = a.z() >= cut, b_above = b.z() >= cut;
                    if (a_above == b_above) continue;
                    const float f = float((cut - a.z()) / (b.z() - a.z()));
                    const Eigen::Vector3f p = a + f * (b - a);
                    pts[n++] = p.x();
                    pts[n++] = p.y();
                }
                if (n == 4) out.insert(out.end(), pts, pts + 4);
            }
            if (out.size() > before) {
                auto& r = runs[PlanClass(e.ifc_class)];
                r.insert(r.end(), {uint32_t(ei), uint32_t((out.size() - before) / 4)});
            }
        }
        json seg = json::object(), seg_elements = json::object();
        for (auto& [cls, v] : segments) {
            if (v.empty()) continue;  // the class has elements on this storey, none cut
            for (float& x : v) x = std::round(x * 1000.0f) / 1000.0f;  // millimetres are enough
            seg[cls] = v;
            seg_elements[cls] = runs[cls];
        }
        storeys.push_back({{"name", m.storeys[s].name},
                           {"elevation", m.storeys[s].elevation_m - m.origin_m.z()},
                           {"cut_z", cut},
                           {"segments", seg},
                           {"segment_elements", seg_elements}});
    }
    return storeys;
}

json ModelBuffers(const bim::BimModel& m) {
    struct Buffers {
        std::vector<float> positions;
        std::vector<uint32_t> indices, element;
    };
    std::map<std::string, Buffers> by_class;
    json elements = json::array();
    for (const bim::BimElement& e : m.elements) {
        elements.push_back({{"g", e.global_id},
                            {"c", e.ifc_class},
                            {"n", e.name},
                            {"s", e.storey >= 0 ? m.storeys[size_t(e.storey)].name : ""}});
    }
    // Each class's triangles storey by storey, so that the 3D view's storey filter draws one
    // storey's as a range of its buffers (ranges: [first index, count] per storey).
    const std::vector<int> storey = ElementStoreys(m);
    std::vector<size_t> order(m.elements.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return storey[a] < storey[b]; });
    std::map<std::string, std::vector<std::array<size_t, 2>>> ranges;
    for (const size_t i : order) {
        const bim::BimElement& e = m.elements[i];
        if (!Drawn(e)) continue;
        Buffers& b = by_class[e.ifc_class];
        auto& r = ranges[e.ifc_class];
        while (r.size() <= size_t(std::max(storey[i], 0))) r.push_back({b.indices.size(), 0});
        // Elements share no vertices (BimModel): copy the element's vertex range once.
        std::map<uint32_t, uint32_t> local;
        for (uint32_t t = e.first_triangle; t < e.first_triangle + e.triangle_count; ++t) {
            for (uint32_t v : m.mesh.triangles[t]) {
                auto [it, fresh] = local.emplace(v, uint32_t(b.positions.size() / 3));
                if (fresh) {
                    const Eigen::Vector3f& p = m.mesh.vertices[v];
                    b.positions.insert(b.positions.end(), {p.x(), p.y(), p.z()});
                }
                b.indices.push_back(it->second);
            }
            b.element.push_back(uint32_t(i));
        }
        r.back()[1] = b.indices.size() - r.back()[0];
    }
    json classes = json::array();
    for (const auto& [name, b] : by_class) {
        auto& r = ranges[name];
        while (r.size() < m.storeys.size()) r.push_back({b.indices.size(), 0});
        classes.push_back({{"name", name},
                           {"storeys", r},
                           {"triangles", b.element.size()},
                           {"positions", Base64(b.positions)},
                           {"indices", Base64(b.indices)},
                           {"element", Base64(b.element)}});
    }
    return {{"classes", classes}, {"elements", elements}};
}

json ElementTriangles(const bim::BimModel& m, const std::vector<size_t>& elements) {
    const std::vector<int> storey = ElementStoreys(m);
    std::vector<size_t> order = elements;
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return storey.at(a) < storey.at(b); });
    std::vector<float> xyz;
    std::vector<std::array<size_t, 2>> ranges;  // [first vertex, vertices] per storey
    for (const size_t i : order) {
        while (ranges.size() <= size_t(std::max(storey[i], 0)))
            ranges.push_back({xyz.size() / 3, 0});
        const bim::BimElement& e = m.elements.at(i);
        for (uint32_t t = e.first_triangle; t < e.first_triangle + e.triangle_count; ++t) {
            for (uint32_t v : m.mesh.triangles[t]) {
                const Eigen::Vector3f& p = m.mesh.vertices[v];
                xyz.insert(xyz.end(), {p.x(), p.y(), p.z()});
            }
        }
        ranges.back()[1] = xyz.size() / 3 - ranges.back()[0];
    }
    while (ranges.size() < m.storeys.size()) ranges.push_back({xyz.size() / 3, 0});
    return {{"positions", Base64(xyz)}, {"storeys", ranges}};
}

}  // namespace bimslam::report

namespace bimslam::report {

json FlightOutlines(const bim::BimModel& m) {
    json out = json::array();
    for (const bim::StairFlight& f : bim::FindStairFlights(m)) {
        if (f.lower < 0 || f.upper < 0 || f.levels.empty()) continue;
        // Each level as a rectangle along the walking line there (from the level before to the
        // one after; the entry and the exit at the ends): its depth along, its width across.
        std::vector<Eigen::Vector2d> c{f.entry};
        for (const bim::StairLevel& l : f.levels) c.push_back(l.centre.head<2>());
        c.push_back(f.exit);
        std::vector<float> treads, line;
        for (size_t k = 1; k + 1 < c.size(); ++k) {
            const bim::StairLevel& l = f.levels[k - 1];
            Eigen::Vector2d u = c[k + 1] - c[k - 1];
            u = u.norm() > 1e-9 ? Eigen::Vector2d(u.normalized()) : Eigen::Vector2d::UnitX();
            const Eigen::Vector2d n(-u.y(), u.x());
            const Eigen::Vector2d a = 0.5 * l.depth_m * u, b = 0.5 * l.width_m * n;
            const std::array<Eigen::Vector2d, 4> corners{c[k] - a - b, c[k] + a - b, c[k] + a + b,
                                                         c[k] - a + b};
            for (const Eigen::Vector2d& p : corners) {
                treads.insert(treads.end(), {float(p.x()), float(p.y())});
            }
        }
        for (const Eigen::Vector2d& p : c) line.insert(line.end(), {float(p.x()), float(p.y())});
        out.push_back({{"name", f.name},
                       {"lower", f.lower},
                       {"upper", f.upper},
                       {"rise_m", f.rise_m},
                       {"risers", f.risers},
                       {"treads", treads},
                       {"line", line}});
    }
    return out;
}

}  // namespace bimslam::report

namespace bimslam::report {

Eigen::AlignedBox3d ElementBox(const bim::BimModel& m, size_t index) {
    const bim::BimElement& e = m.elements.at(index);
    Eigen::AlignedBox3d b;
    for (uint32_t t = e.first_triangle; t < e.first_triangle + e.triangle_count; ++t) {
        for (uint32_t v : m.mesh.triangles[t]) b.extend(m.mesh.vertices[v].cast<double>());
    }
    if (!b.isEmpty()) b.translate(m.origin_m);
    return b;
}

std::vector<float> ThinPoints(const std::vector<Eigen::Vector3d>& p, const Eigen::Vector3d& origin,
                              size_t max) {
    std::vector<float> out;
    const size_t step = std::max<size_t>(1, (p.size() + max - 1) / max);
    for (size_t i = 0; i < p.size(); ++i) {
        if (i % step != 0 && i + 1 != p.size()) continue;
        const Eigen::Vector3d q = p[i] - origin;
        for (int k = 0; k < 3; ++k) out.push_back(std::round(float(q[k]) * 1000.0f) / 1000.0f);
    }
    return out;
}

json StoreyRuns(const std::vector<Eigen::Vector3d>& positions, const bim::BimModel& model,
                size_t max_points) {
    const Eigen::Vector3d origin = model.origin_m;
    std::vector<Eigen::Vector3d> local;
    const size_t step = std::max<size_t>(1, (positions.size() + max_points - 1) / max_points);
    for (size_t i = 0; i < positions.size(); ++i) {
        if (i % step == 0 || i + 1 == positions.size()) local.push_back(positions[i] - origin);
    }
    std::vector<double> elevations;
    for (const bim::BimStorey& s : model.storeys) elevations.push_back(s.elevation_m - origin.z());
    json runs = json::array();
    for (const StoreyRun& r : SplitByStorey(local, elevations)) {
        runs.push_back({{"lower", r.lower},
                        {"upper", r.upper},
                        {"xyz", ThinPoints(r.points, Eigen::Vector3d::Zero(), r.points.size())}});
    }
    return runs;
}

}  // namespace bimslam::report
