// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// How session.json and the rig's map package say the descriptors were made: the manifest's
// `descriptor` block (algorithms/io/session.hpp) from the Scan Context configuration that made
// them; localization::RigMap::DescriptorConfig reads it back. Header-only: included by the
// sources that write sessions or packages, which link io themselves (scancontext does not).
#pragma once

#include <string>

#include "algorithms/io/session.hpp"
#include "algorithms/scancontext/config.hpp"

namespace bimslam::scancontext {

inline io::SessionManifest::Descriptor SessionDescriptor(const ScanContextConfig& c) {
    io::SessionManifest::Descriptor d;
    d.kind = std::string(ToString(c.kind));
    d.rings = c.num_rings;
    d.sectors = c.num_sectors;
    d.max_radius_m = c.max_radius;
    d.min_points = c.indoor_min_points;
    d.min_z_span_m = c.indoor_min_z_span;
    d.cell_rule = std::string(ToString(c.indoor_rule));
    return d;
}

}  // namespace bimslam::scancontext
