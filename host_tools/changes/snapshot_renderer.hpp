// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Pictures of the model for BCF viewpoints (issue 34): the model's triangle meshes seen through a
// perspective camera, greyed, with the change drawn in its colour, rendered off screen by Mesa's
// OSMesa (Debian's libosmesa6: Gallium llvmpipe, OpenGL in a buffer of ours, no display, no GPU,
// no EGL device to find). README.md of this folder, "changes.bcf", says why this renderer.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "algorithms/common/triangle_mesh.hpp"
#include "algorithms/io/image.hpp"
#include "host_tools/bim/bim_model.hpp"

namespace bimslam::change_detection {

using Rgb = std::array<uint8_t, 3>;

// In the frame of the model's mesh (bim::BimModel::origin_m subtracted), metres.
struct SnapshotCamera {
    Eigen::Vector3d eye = Eigen::Vector3d::Zero();
    Eigen::Vector3d direction = Eigen::Vector3d::UnitX();  // need not be unit
    Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
    double fov_deg = 60;  // vertical
};

// What a picture shows in colour: one element of the model (its index, -1 none) and meshes that
// are not in the model (a new object, where a moved element went), in the mesh's frame.
struct SnapshotHighlight {
    int element = -1;
    Rgb element_color{220, 30, 30};
    std::vector<std::pair<const common::TriangleMesh*, Rgb>> meshes;
};

class SnapshotRenderer {
public:
    // The model's physical elements (not spaces, openings, virtual elements, annotations); those
    // beams pass (bim::PassThrough: doors, windows) are drawn translucent. Throws common::Error
    // (kInternal) when OSMesa cannot make a context (with what it said).
    SnapshotRenderer(const bim::BimModel& model, int width, int height);
    ~SnapshotRenderer();
    SnapshotRenderer(const SnapshotRenderer&) = delete;
    SnapshotRenderer& operator=(const SnapshotRenderer&) = delete;

    // RGB, top row first. The highlighted things are drawn over the grey model and, where the
    // model hides them, again faintly through it (a change behind a column still shows).
    io::Image Render(const SnapshotCamera& camera, const SnapshotHighlight& highlight);

    int width() const { return width_; }
    int height() const { return height_; }

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    int width_, height_;
};

}  // namespace bimslam::change_detection
