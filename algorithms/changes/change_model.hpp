// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The building model as change detection sees it: one triangle mesh in the model's frame (metres)
// with the element of every triangle, and per element whether a LiDAR beam stops at it. Neutral
// (no IFC): host_tools/changes fills it from a bim::BimModel, tests from synthetic rooms.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "algorithms/common/triangle_mesh.hpp"

namespace bimslam::changes {

inline constexpr uint32_t kNoElement = 0xFFFFFFFFu;

struct ChangeModel {
    // Every physical element (walls, slabs, columns, doors, windows, furniture, ...; not spaces or
    // openings): what "in the model" means for the signed distance.
    common::TriangleMesh mesh;
    std::vector<uint32_t> triangle_element;  // per triangle: element index
    // Per element: 1 when beams stop at it (structure, furniture, closed doors' frames...), 0 when
    // they pass (doors taken as open, glass). Opaque elements are what the rays of the element
    // check are cast against, and the only ones it judges.
    std::vector<uint8_t> element_opaque;
    // Per element: 0 for one that is cast against but never judged (a floor the model's reader
    // assumed where the file has none); empty when every opaque element is judged.
    std::vector<uint8_t> element_judged;

    size_t element_count() const { return element_opaque.size(); }
    bool Judged(size_t e) const {
        return element_opaque[e] && (element_judged.empty() || element_judged[e]);
    }
    // Throws common::Error (kInvalidArgument) naming what is inconsistent: a triangle without an
    // element or with an element out of range, invalid indices, non-finite vertices.
    void Validate() const;
};

}  // namespace bimslam::changes
