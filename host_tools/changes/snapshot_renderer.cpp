// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/changes/snapshot_renderer.hpp"

// OSMesa's header declares the OpenGL 1.x entry points we use (fixed-function pipeline, client
// vertex arrays): nothing to load at run time, and llvmpipe runs them on the CPU's threads.
#include <GL/gl.h>
#include <GL/osmesa.h>

#include <Eigen/Geometry>
#include <cmath>

#include "algorithms/common/status.hpp"
#include "host_tools/changes/bim_change_model.hpp"

namespace bimslam::change_detection {
namespace {

[[noreturn]] void RenderFail(const std::string& what) {
    throw common::Error(common::StatusCode::kInternal, "snapshot renderer: " + what);
}

}  // namespace

// Named (not anonymous): SnapshotRenderer::Impl holds them.
namespace snapshot_detail {

// Triangles drawn with flat normals: three vertices and three copies of the face normal each.
struct Batch {
    std::vector<float> xyz, normal;
    size_t vertices() const { return xyz.size() / 3; }
    void Add(const Eigen::Vector3f& a, const Eigen::Vector3f& b, const Eigen::Vector3f& c) {
        Eigen::Vector3f n = (b - a).cross(c - a);
        if (n.squaredNorm() > 0) n.normalize();
        for (const Eigen::Vector3f* p : {&a, &b, &c}) {
            xyz.insert(xyz.end(), {p->x(), p->y(), p->z()});
            normal.insert(normal.end(), {n.x(), n.y(), n.z()});
        }
    }
    void AddMesh(const common::TriangleMesh& m) {
        for (const auto& t : m.triangles) Add(m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]);
    }
    // Vertices [first, first + count).
    void Draw(size_t first, size_t count) const {
        if (count == 0) return;
        glVertexPointer(3, GL_FLOAT, 0, xyz.data());
        glNormalPointer(GL_FLOAT, 0, normal.data());
        glDrawArrays(GL_TRIANGLES, GLint(first), GLsizei(count));
    }
    void DrawAll() const { Draw(0, vertices()); }
};

struct Range {
    bool glass = false;  // in the translucent batch
    size_t first = 0, count = 0;
};

}  // namespace snapshot_detail

using snapshot_detail::Batch;
using snapshot_detail::Range;

struct SnapshotRenderer::Impl {
    OSMesaContext context = nullptr;
    std::vector<uint8_t> rgba;
    Batch opaque, glass;
    std::vector<Range> element;  // per model element (count 0: not drawn)
    float far_m = 100;

    // Draws `batch` without the range `skip` (of this batch).
    void DrawWithout(const Batch& batch, const Range* skip) const {
        if (!skip) return batch.DrawAll();
        batch.Draw(0, skip->first);
        batch.Draw(skip->first + skip->count, batch.vertices() - skip->first - skip->count);
    }
};

SnapshotRenderer::SnapshotRenderer(const bim::BimModel& model, int width, int height)
    : impl_(std::make_unique<Impl>()), width_(width), height_(height) {
    if (width <= 0 || height <= 0)
        RenderFail("bad size " + std::to_string(width) + "x" + std::to_string(height));
    const int attributes[] = {OSMESA_FORMAT,
                              OSMESA_RGBA,
                              OSMESA_DEPTH_BITS,
                              24,
                              OSMESA_STENCIL_BITS,
                              0,
                              OSMESA_ACCUM_BITS,
                              0,
                              OSMESA_PROFILE,
                              OSMESA_COMPAT_PROFILE,
                              0};
    impl_->context = OSMesaCreateContextAttribs(attributes, nullptr);
    if (!impl_->context)
        RenderFail("OSMesaCreateContextAttribs failed (Mesa's libOSMesa, llvmpipe)");
    impl_->rgba.resize(size_t(width) * height * 4);

    impl_->element.resize(model.elements.size());
    for (size_t e = 0; e < model.elements.size(); ++e) {
        const bim::BimElement& el = model.elements[e];
        if (!Physical(el) || el.triangle_count == 0) continue;
        Range& r = impl_->element[e];
        r.glass = bim::PassThrough(el.ifc_class);
        Batch& b = r.glass ? impl_->glass : impl_->opaque;
        r.first = b.vertices();
        for (uint32_t t = el.first_triangle; t < el.first_triangle + el.triangle_count; ++t) {
            const auto& tri = model.mesh.triangles[t];
            b.Add(model.mesh.vertices[tri[0]], model.mesh.vertices[tri[1]],
                  model.mesh.vertices[tri[2]]);
        }
        r.count = b.vertices() - r.first;
    }
    const Eigen::AlignedBox3d box = model.Bounds();
    if (!box.isEmpty()) impl_->far_m = float(2 * box.diagonal().norm() + 10);
}

SnapshotRenderer::~SnapshotRenderer() {
    if (impl_->context) OSMesaDestroyContext(impl_->context);
}

namespace {

// Column-major, as glLoadMatrixd takes them.
Eigen::Matrix4d Perspective(double fov_deg, double aspect, double near, double far) {
    const double f = 1.0 / std::tan(0.5 * fov_deg * M_PI / 180.0);
    Eigen::Matrix4d p = Eigen::Matrix4d::Zero();
    p(0, 0) = f / aspect;
    p(1, 1) = f;
    p(2, 2) = (far + near) / (near - far);
    p(2, 3) = 2 * far * near / (near - far);
    p(3, 2) = -1;
    return p;
}

Eigen::Matrix4d LookAt(const SnapshotCamera& c) {
    const Eigen::Vector3d f = c.direction.normalized();
    Eigen::Vector3d s = f.cross(c.up);
    if (s.squaredNorm() < 1e-12) s = f.unitOrthogonal();
    s.normalize();
    const Eigen::Vector3d u = s.cross(f);
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    m.block<1, 3>(0, 0) = s.transpose();
    m.block<1, 3>(1, 0) = u.transpose();
    m.block<1, 3>(2, 0) = -f.transpose();
    m.block<3, 1>(0, 3) = -m.block<3, 3>(0, 0) * c.eye;
    return m;
}

void Color(const Rgb& c, float alpha) {
    glColor4f(c[0] / 255.f, c[1] / 255.f, c[2] / 255.f, alpha);
}

}  // namespace

io::Image SnapshotRenderer::Render(const SnapshotCamera& camera,
                                   const SnapshotHighlight& highlight) {
    Impl& m = *impl_;
    // Current on this thread, into our buffer (made so once: binding again costs a framebuffer).
    if (OSMesaGetCurrentContext() != m.context &&
        !OSMesaMakeCurrent(m.context, m.rgba.data(), GL_UNSIGNED_BYTE, width_, height_))
        RenderFail("OSMesaMakeCurrent failed");
    OSMesaPixelStore(OSMESA_Y_UP, 0);  // row 0 at the top, as io::Image
    glViewport(0, 0, width_, height_);
    glClearColor(0.96f, 0.96f, 0.97f, 1.f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);

    glMatrixMode(GL_PROJECTION);
    glLoadMatrixd(Perspective(camera.fov_deg, double(width_) / height_, 0.05, m.far_m).data());
    // A headlight: a directional light along the view, set while the modelview is the identity
    // (eye coordinates); two-sided, as IFC meshes do not all wind their faces outwards.
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    const float light_dir[] = {0.2f, 0.4f, 1.f, 0.f}, diffuse[] = {0.7f, 0.7f, 0.7f, 1.f},
                ambient[] = {0.35f, 0.35f, 0.35f, 1.f};
    glLightfv(GL_LIGHT0, GL_POSITION, light_dir);
    glLightfv(GL_LIGHT0, GL_DIFFUSE, diffuse);
    glLightModelfv(GL_LIGHT_MODEL_AMBIENT, ambient);
    glLightModeli(GL_LIGHT_MODEL_TWO_SIDE, GL_TRUE);
    glEnable(GL_LIGHTING);
    glEnable(GL_LIGHT0);
    glEnable(GL_COLOR_MATERIAL);
    glColorMaterial(GL_FRONT_AND_BACK, GL_AMBIENT_AND_DIFFUSE);
    glEnable(GL_NORMALIZE);
    glLoadMatrixd(LookAt(camera).data());
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LEQUAL);
    glEnableClientState(GL_VERTEX_ARRAY);
    glEnableClientState(GL_NORMAL_ARRAY);

    const Range* chosen = nullptr;
    if (highlight.element >= 0 && size_t(highlight.element) < m.element.size() &&
        m.element[size_t(highlight.element)].count > 0)
        chosen = &m.element[size_t(highlight.element)];
    // The highlighted things, in their colours.
    Batch extra;
    for (const auto& [mesh, color] : highlight.meshes) {
        (void)color;
        extra.AddMesh(*mesh);
    }
    auto draw_highlight = [&](float alpha) {
        if (chosen) {
            Color(highlight.element_color, alpha);
            (chosen->glass ? m.glass : m.opaque).Draw(chosen->first, chosen->count);
        }
        size_t first = 0;
        for (const auto& [mesh, color] : highlight.meshes) {
            Color(color, alpha);
            extra.Draw(first, 3 * mesh->triangles.size());
            first += 3 * mesh->triangles.size();
        }
    };

    // 1. The model, grey, without the highlighted element. 2. What of the highlight the model
    // hides, faintly through it (the depth buffer holds the model alone: the highlight's own back
    // faces do not show through its front). 3. The highlight.
    glColor4f(0.80f, 0.80f, 0.80f, 1.f);
    m.DrawWithout(m.opaque, chosen && !chosen->glass ? chosen : nullptr);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glDepthMask(GL_FALSE);
    glDepthFunc(GL_GREATER);
    draw_highlight(0.35f);
    glDepthFunc(GL_LEQUAL);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
    draw_highlight(1.f);
    // 4. Glass and doors, translucent, not hiding what is behind them.
    glEnable(GL_BLEND);
    glDepthMask(GL_FALSE);
    glColor4f(0.55f, 0.65f, 0.75f, 0.3f);
    m.DrawWithout(m.glass, chosen && chosen->glass ? chosen : nullptr);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
    glFinish();

    io::Image image(width_, height_, 3);
    for (size_t i = 0, n = size_t(width_) * height_; i < n; ++i) {
        for (int c = 0; c < 3; ++c) image.data[3 * i + c] = m.rgba[4 * i + c];
    }
    return image;
}

}  // namespace bimslam::change_detection
