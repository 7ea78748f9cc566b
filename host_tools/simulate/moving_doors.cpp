// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/simulate/moving_doors.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <set>

#include "algorithms/common/status.hpp"
#include "algorithms/simulation/primitive_meshes.hpp"

namespace bimslam::simulate {
namespace {
constexpr double kRadiansPerDegree = M_PI / 180.0;
constexpr double kLeafThicknessM = 0.04;
constexpr double kHeadM = 0.005;  // the topmost vertices: the frame's head

MovingDoor DoorOf(const bim::BimModel& m, uint32_t e, const MovingDoorsSpec& spec, size_t k) {
    const bim::BimElement& el = m.elements[e];
    std::set<uint32_t> used;
    for (uint32_t t = el.first_triangle; t < el.first_triangle + el.triangle_count; ++t) {
        used.insert(m.mesh.triangles[t].begin(), m.mesh.triangles[t].end());
    }
    double z_lo = INFINITY, z_hi = -INFINITY;
    Eigen::Vector2d all = Eigen::Vector2d::Zero();
    for (const uint32_t v : used) {
        z_lo = std::min(z_lo, double(m.mesh.vertices[v].z()));
        z_hi = std::max(z_hi, double(m.mesh.vertices[v].z()));
        all += m.mesh.vertices[v].head<2>().cast<double>();
    }
    all /= double(std::max<size_t>(used.size(), 1));
    std::vector<Eigen::Vector2d> head;
    for (const uint32_t v : used) {
        if (m.mesh.vertices[v].z() >= z_hi - kHeadM) {
            head.push_back(m.mesh.vertices[v].head<2>().cast<double>());
        }
    }
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const auto& p : head) mean += p;
    mean /= double(std::max<size_t>(head.size(), 1));
    Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
    for (const auto& p : head) cov += (p - mean) * (p - mean).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver(cov);
    const Eigen::Vector2d along = solver.eigenvectors().col(1),
                          normal = solver.eigenvectors().col(0);
    double lo = INFINITY, hi = -INFINITY;
    for (const auto& p : head) {
        lo = std::min(lo, (p - mean).dot(along));
        hi = std::max(hi, (p - mean).dot(along));
    }
    MovingDoor d;
    d.global_id = el.global_id;
    d.element = e;
    d.width_m = head.size() >= 2 ? hi - lo : 0.0;
    d.hinge = mean + lo * along;
    d.closed = along;
    d.swing = (all - mean).dot(normal) < 0 ? Eigen::Vector2d(-normal) : normal;
    d.floor_z = z_lo;
    d.height_m = z_hi - z_lo - 0.05;  // under a 5 cm head
    d.period_s = spec.period_s;
    d.max_angle_deg = spec.max_angle_deg;
    d.phase = std::fmod(double(k) * 0.6180339887498949, 1.0);
    return d;
}

}  // namespace

double MovingDoor::AngleDeg(double t) const {
    return max_angle_deg * 0.5 * (1.0 - std::cos(2.0 * M_PI * (t / period_s + phase)));
}

std::vector<MovingDoor> FindMovingDoors(const bim::BimModel& model, const MovingDoorsSpec& spec,
                                        const std::vector<uint8_t>& removed) {
    std::vector<uint8_t> pick(model.elements.size(), 0);
    // Marks the elements whose GlobalId or class is in `wanted`; each must match one.
    auto mark = [&](const std::vector<std::string>& wanted, const std::string& key, bool by_class) {
        for (size_t k = 0; k < wanted.size(); ++k) {
            size_t matched = 0;
            for (size_t e = 0; e < model.elements.size(); ++e) {
                const bim::BimElement& el = model.elements[e];
                if ((by_class ? el.ifc_class : el.global_id) == wanted[k]) pick[e] = 1, ++matched;
            }
            if (matched == 0) {
                throw common::Error(common::StatusCode::kInvalidArgument,
                                    "edits.moving_doors." + key + "[" + std::to_string(k) +
                                        "] = '" + wanted[k] + "': no element of the model has " +
                                        (by_class ? "this class" : "this GlobalId"));
            }
        }
    };
    mark(spec.global_ids, "global_ids", false);
    mark(spec.classes, "classes", true);
    std::vector<MovingDoor> doors;
    for (size_t e = 0; e < model.elements.size(); ++e) {
        if (!pick[e] || (e < removed.size() && removed[e])) continue;
        MovingDoor d = DoorOf(model, uint32_t(e), spec, doors.size());
        if (d.width_m > 0.1 && d.height_m > 0.1) doors.push_back(d);
    }
    return doors;
}

namespace {
// The distance from p to the leaf at angle a_deg (a segment from the hinge, the door's width long).
double LeafDistance(const MovingDoor& d, double a_deg, const Eigen::Vector2d& p) {
    const double a = a_deg * kRadiansPerDegree;
    const Eigen::Vector2d dir = std::cos(a) * d.closed + std::sin(a) * d.swing;
    const double s = std::clamp((p - d.hinge).dot(dir), 0.0, d.width_m);
    return (d.hinge + s * dir - p).norm();
}
}  // namespace

double LeafAngleDeg(const MovingDoor& d, double t, const Eigen::Vector2d& walker_xy) {
    const double a = d.AngleDeg(t);
    double best = a, best_distance = LeafDistance(d, a, walker_xy);
    if (best_distance >= kWalkerClearanceM) return a;
    // Out from the swing's angle one degree at a time, both ways.
    for (double step = 1; step <= d.max_angle_deg; step += 1) {
        for (const double c : {a - step, a + step}) {
            if (c < 0 || c > d.max_angle_deg) continue;
            const double distance = LeafDistance(d, c, walker_xy);
            if (distance >= kWalkerClearanceM) return c;
            if (distance > best_distance) best = c, best_distance = distance;
        }
    }
    return best;
}

void AppendDoorLeaves(const std::vector<MovingDoor>& doors, double t,
                      const Eigen::Vector2d& walker_xy, common::TriangleMesh* mesh,
                      std::vector<uint32_t>* ids) {
    for (const MovingDoor& d : doors) {
        const double a = LeafAngleDeg(d, t, walker_xy) * kRadiansPerDegree;
        const Eigen::Vector2d dir = std::cos(a) * d.closed + std::sin(a) * d.swing;
        const Eigen::Vector2d c = d.hinge + 0.5 * d.width_m * dir;
        const common::TriangleMesh leaf = simulation::BoxMesh(
            {c.x(), c.y(), d.floor_z + 0.5 * d.height_m}, {d.width_m, kLeafThicknessM, d.height_m},
            std::atan2(dir.y(), dir.x()));
        const auto base = uint32_t(mesh->vertices.size());
        mesh->vertices.insert(mesh->vertices.end(), leaf.vertices.begin(), leaf.vertices.end());
        for (const auto& tri : leaf.triangles) {
            mesh->triangles.push_back({tri[0] + base, tri[1] + base, tri[2] + base});
        }
        ids->insert(ids->end(), leaf.triangles.size(), d.element);
    }
}

}  // namespace bimslam::simulate
