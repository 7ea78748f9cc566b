// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/changes/bim_change_model.hpp"

#include <algorithm>
#include <limits>
#include <map>

#include "algorithms/common/status.hpp"
#include "algorithms/simulation/scene.hpp"

namespace bimslam::change_detection {

bool Physical(const bim::BimElement& element) {
    for (const char* prefix :
         {"IfcSpace", "IfcOpeningElement", "IfcVirtualElement", "IfcAnnotation"}) {
        if (element.ifc_class.starts_with(prefix)) return false;
    }
    return true;
}

bool Listed(const bim::BimElement& element) { return Physical(element) && !element.assumed; }

changes::ChangeModel ToChangeModel(const bim::BimModel& model) {
    changes::ChangeModel out;
    out.element_opaque.assign(model.elements.size(), 0);
    out.element_judged.assign(model.elements.size(), 0);
    out.mesh.vertices = model.mesh.vertices;
    for (size_t e = 0; e < model.elements.size(); ++e) {
        const bim::BimElement& el = model.elements[e];
        if (!Physical(el)) continue;
        out.element_opaque[e] = !bim::PassThrough(el.ifc_class);
        out.element_judged[e] = Listed(el);
        for (uint32_t t = el.first_triangle; t < el.first_triangle + el.triangle_count; ++t) {
            out.mesh.triangles.push_back(model.mesh.triangles[t]);
            out.triangle_element.push_back(uint32_t(e));
        }
    }
    if (out.mesh.empty()) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            model.file + ": the model has no element with geometry to compare " +
                                "with (" + std::to_string(model.elements.size()) +
                                " elements with geometry, none of them built: spaces, openings)");
    }
    return out;
}

int StoreyUnder(const bim::BimModel& model, double bottom_z) {
    int storey = -1;
    for (size_t s = 0; s < model.storeys.size(); ++s) {
        if (model.storeys[s].elevation_m <= bottom_z + 0.3 || storey < 0) storey = int(s);
    }
    return storey;
}

int ElementStorey(const bim::BimModel& model, size_t element, bool* from_height) {
    const bim::BimElement& e = model.elements.at(element);
    if (from_height) *from_height = false;
    if (e.storey >= 0 || model.storeys.empty() || e.triangle_count == 0) return e.storey;
    float bottom = std::numeric_limits<float>::max();
    for (uint32_t t = e.first_triangle; t < e.first_triangle + e.triangle_count; ++t) {
        for (const uint32_t v : model.mesh.triangles[t]) {
            bottom = std::min(bottom, model.mesh.vertices[v].z());
        }
    }
    if (from_height) *from_height = true;
    return StoreyUnder(model, double(bottom) + model.origin_m.z());
}

std::vector<int> SpacesAt(const bim::BimModel& model, const std::vector<Eigen::Vector3f>& points) {
    // The spaces' meshes, ids = element index.
    common::TriangleMesh spaces;
    std::vector<uint32_t> ids;
    spaces.vertices = model.mesh.vertices;
    for (size_t e = 0; e < model.elements.size(); ++e) {
        const bim::BimElement& el = model.elements[e];
        if (!el.ifc_class.starts_with("IfcSpace")) continue;
        for (uint32_t t = el.first_triangle; t < el.first_triangle + el.triangle_count; ++t) {
            spaces.triangles.push_back(model.mesh.triangles[t]);
            ids.push_back(uint32_t(e));
        }
    }
    std::vector<int> out(points.size(), -1);
    if (spaces.empty()) return out;
    const simulation::Scene scene(spaces, ids);
    for (size_t i = 0; i < points.size(); ++i) {
        // Count the crossings of a ray going up, per space: odd means inside.
        std::map<uint32_t, int> crossings;
        float t = 0;
        for (int guard = 0; guard < 1000; ++guard) {
            const auto hit = scene.Intersect(points[i], Eigen::Vector3f::UnitZ(), t);
            if (!hit) break;
            ++crossings[hit->id];
            t = hit->t + 1e-4f;
        }
        for (const auto& [space, n] : crossings) {
            if (n % 2 == 1) {
                out[i] = int(space);
                break;
            }
        }
    }
    return out;
}

std::vector<ObjectPlace> PlaceObjects(const bim::BimModel& model,
                                      const std::vector<changes::NewObject>& objects) {
    std::vector<Eigen::Vector3f> bases;  // 0.1 m above the centre of each object's base
    for (const changes::NewObject& obj : objects) {
        bases.emplace_back(float(0.5 * (obj.box_min.x() + obj.box_max.x())),
                           float(0.5 * (obj.box_min.y() + obj.box_max.y())),
                           float(obj.box_min.z() + 0.1));
    }
    const std::vector<int> spaces = SpacesAt(model, bases);
    std::vector<ObjectPlace> out(objects.size());
    for (size_t o = 0; o < objects.size(); ++o) {
        out[o].storey = StoreyUnder(model, objects[o].box_min.z() + model.origin_m.z());
        out[o].space = spaces[o];
    }
    return out;
}

}  // namespace bimslam::change_detection
