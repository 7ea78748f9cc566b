// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/simulate/rig_body.hpp"

#include <initializer_list>

#include "algorithms/simulation/primitive_meshes.hpp"

namespace bimslam::simulate {
namespace {

struct Box {
    Eigen::Vector3d center, size;
};

common::TriangleMesh Boxes(std::initializer_list<Box> boxes) {
    common::TriangleMesh m;
    for (const Box& b : boxes) {
        const common::TriangleMesh part = simulation::BoxMesh(b.center, b.size, 0.0);
        const auto base = uint32_t(m.vertices.size());
        m.vertices.insert(m.vertices.end(), part.vertices.begin(), part.vertices.end());
        for (const auto& t : part.triangles)
            m.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    }
    return m;
}

}  // namespace

common::TriangleMesh RigBody(Platform platform) {
    switch (platform) {
        case Platform::kGo1:
            // The trunk, and four legs from the hips to the floor (0.32 m below the centre).
            return Boxes({{{0, 0, 0}, {0.65, 0.28, 0.12}},
                          {{0.19, 0.13, -0.16}, {0.06, 0.06, 0.32}},
                          {{0.19, -0.13, -0.16}, {0.06, 0.06, 0.32}},
                          {{-0.19, 0.13, -0.16}, {0.06, 0.06, 0.32}},
                          {{-0.19, -0.13, -0.16}, {0.06, 0.06, 0.32}}});
        case Platform::kHandheld:
            // The person: legs to the floor (1.2 m below the base), torso, head; and the
            // forearms from the elbows forward to the handle under the sensor.
            return Boxes({{{-0.35, 0, -0.925}, {0.2, 0.35, 0.55}},
                          {{-0.35, 0, -0.275}, {0.25, 0.45, 0.75}},
                          {{-0.35, 0, 0.225}, {0.2, 0.18, 0.25}},
                          {{-0.15, 0.1, -0.08}, {0.3, 0.07, 0.07}},
                          {{-0.15, -0.1, -0.08}, {0.3, 0.07, 0.07}}});
        case Platform::kVehicle:
            // The roof (its top is the base) and the body below it.
            return Boxes({{{0, 0, -0.05}, {2.4, 1.6, 0.1}}, {{0, 0, -0.95}, {4.4, 1.8, 0.7}}});
    }
    return {};
}

}  // namespace bimslam::simulate
