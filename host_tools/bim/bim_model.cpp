// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/bim/bim_model.hpp"

#include <limits>

#include "algorithms/common/status.hpp"

namespace bimslam::bim {

std::string_view ToString(ElementRole role) {
    switch (role) {
        case ElementRole::kStructure:
            return "structure";
        case ElementRole::kTransient:
            return "transient";
    }
    return "unknown";
}

Eigen::AlignedBox3d BimModel::Bounds() const {
    Eigen::AlignedBox3d box;  // empty
    for (const auto& t : mesh.triangles) {
        for (const uint32_t v : t) {
            if (v < mesh.vertices.size()) box.extend(mesh.vertices[v].cast<double>() + origin_m);
        }
    }
    return box;
}

bool PassThrough(std::string_view ifc_class) {
    for (const char* prefix : {"IfcDoor", "IfcWindow", "IfcSpace", "IfcOpeningElement",
                               "IfcCurtainWall", "IfcVirtualElement", "IfcAnnotation"}) {
        if (ifc_class.starts_with(prefix)) return true;
    }
    return false;
}

int FindStorey(const BimModel& model, const std::string& name) {
    std::string known;
    for (size_t i = 0; i < model.storeys.size(); ++i) {
        if (model.storeys[i].name == name) return int(i);
        known += (i ? ", '" : "'") + model.storeys[i].name + "'";
    }
    throw common::Error(common::StatusCode::kInvalidArgument,
                        model.file + ": no storey '" + name + "' (it has " +
                            (known.empty() ? std::string("none") : known) + ")");
}

int DefaultWalkStorey(const BimModel& model) {
    for (size_t i = 0; i < model.storeys.size(); ++i) {
        if (i + 1 == model.storeys.size() ||
            model.storeys[i + 1].elevation_m - model.storeys[i].elevation_m >=
                kMinWalkStoreyHeight) {
            return int(i);
        }
    }
    return 0;
}

std::vector<int> StoreyIndices(const BimModel& model, const std::vector<std::string>& names) {
    std::vector<int> out;
    for (const std::string& name : names) out.push_back(FindStorey(model, name));
    if (names.empty()) {
        for (int i = 0; i < int(model.storeys.size()); ++i) out.push_back(i);
    }
    return out;
}

BimModel SelectElements(const BimModel& model, const std::function<bool(const BimElement&)>& keep) {
    BimModel out;
    out.file = model.file;
    out.schema = model.schema;
    out.length_unit_m = model.length_unit_m;
    out.storeys = model.storeys;
    out.class_counts = model.class_counts;
    out.failed = model.failed;
    out.faces_reordered = model.faces_reordered;
    out.faces_lost = model.faces_lost;
    out.incomplete = model.incomplete;
    out.warnings = model.warnings;
    out.warning_count = model.warning_count;
    out.assumed_floors = model.assumed_floors;
    out.origin_m = model.origin_m;
    constexpr uint32_t kUnused = std::numeric_limits<uint32_t>::max();
    std::vector<uint32_t> new_index(model.mesh.vertices.size(), kUnused);
    for (const BimElement& e : model.elements) {
        if (!keep(e)) continue;
        BimElement copy = e;
        copy.first_triangle = static_cast<uint32_t>(out.mesh.triangles.size());
        const auto element_index = static_cast<uint32_t>(out.elements.size());
        const size_t end = std::min<size_t>(size_t{e.first_triangle} + e.triangle_count,
                                            model.mesh.triangles.size());
        for (size_t t = e.first_triangle; t < end; ++t) {
            std::array<uint32_t, 3> tri{};
            for (int k = 0; k < 3; ++k) {
                const uint32_t v = model.mesh.triangles[t][k];
                if (new_index[v] == kUnused) {
                    new_index[v] = static_cast<uint32_t>(out.mesh.vertices.size());
                    out.mesh.vertices.push_back(model.mesh.vertices[v]);
                }
                tri[k] = new_index[v];
            }
            out.mesh.triangles.push_back(tri);
            out.triangle_element.push_back(element_index);
        }
        copy.triangle_count =
            static_cast<uint32_t>(out.mesh.triangles.size()) - copy.first_triangle;
        out.elements.push_back(std::move(copy));
    }
    return out;
}

}  // namespace bimslam::bim
