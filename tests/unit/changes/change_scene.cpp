// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "tests/unit/changes/change_scene.hpp"

#include <cmath>

#include "algorithms/simulation/lidar_simulator.hpp"
#include "algorithms/simulation/scene.hpp"

namespace bimslam::changes::test {
namespace {
namespace BIMSLAM_UNITY_ID {

// A vertical cylinder (12 sides), closed.
common::TriangleMesh Cylinder(const Eigen::Vector2d& at, double radius, double height) {
    common::TriangleMesh m;
    constexpr int kSides = 12;
    for (int k = 0; k < kSides; ++k) {
        const double a = 2 * M_PI * k / kSides;
        const Eigen::Vector3d p(at.x() + radius * std::cos(a), at.y() + radius * std::sin(a), 0);
        m.vertices.push_back(p.cast<float>());
        m.vertices.push_back((p + Eigen::Vector3d(0, 0, height)).cast<float>());
    }
    const auto bottom = uint32_t(m.vertices.size());
    m.vertices.emplace_back(float(at.x()), float(at.y()), 0.0f);
    m.vertices.emplace_back(float(at.x()), float(at.y()), float(height));
    for (uint32_t k = 0; k < kSides; ++k) {
        const uint32_t a = 2 * k, b = 2 * ((k + 1) % kSides);
        m.triangles.push_back({a, b, b + 1});
        m.triangles.push_back({a, b + 1, a + 1});
        m.triangles.push_back({bottom, b, a});
        m.triangles.push_back({bottom + 1, a + 1, b + 1});
    }
    return m;
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace

// The decoded points of a simulated scan, in the sensor's (lidar) frame, as the driver gives them.
common::PointCloud ToCloud(const simulation::ScanImage& image,
                           const simulation::LidarModel& lidar) {
    common::PointCloud cloud;
    for (int u = 0; u < image.h; ++u) {
        for (int v = 0; v < image.w; ++v) {
            const uint32_t mm = image.range_mm[image.Index(u, v)];
            if (mm == 0) continue;
            const Eigen::Vector3d p = 1e-3 * mm * lidar.Direction(u, v) + lidar.Origin(u, v);
            cloud.PushBack(p.cast<float>(), 1.0f, uint16_t(u),
                           uint32_t(lidar.ColumnTimeOffsetNs(v)));
        }
    }
    return cloud;
}

namespace {
namespace BIMSLAM_UNITY_ID {

ChangeScene Build() {
    ChangeScene s;
    using V = Eigen::Vector3d;
    std::vector<common::TriangleMesh> elements(kElementCount);
    elements[kFloor] = SolidBox(V(-0.2, -0.2, -0.2), V(12.2, 6.2, 0));
    elements[kCeiling] = SolidBox(V(-0.2, -0.2, 3.0), V(12.2, 6.2, 3.2));
    elements[kWallSouth] = SolidBox(V(-0.2, -0.2, 0), V(12.2, 0, 3));
    elements[kWallNorthA] = SolidBox(V(-0.2, 6.0, 0), V(8.0, 6.2, 3));
    elements[kWallNorthB] = SolidBox(V(8.0, 6.0, 0), V(12.2, 6.2, 3));
    elements[kWallWest] = SolidBox(V(-0.2, 0, 0), V(0, 6.0, 3));
    elements[kWallEast] = SolidBox(V(12.0, 0, 0), V(12.2, 6.0, 3));
    elements[kWallDivider] = SolidBox(V(8.0, 0, 0), V(8.2, 6.0, 3));
    elements[kColumnA] = SolidBox(V(4.8, 3.3, 0), V(5.2, 3.7, 3));
    elements[kColumnC] = SolidBox(V(1.8, 4.3, 0), V(2.2, 4.7, 3));
    elements[kColumnB] = SolidBox(V(9.8, 2.8, 0), V(10.2, 3.2, 3));
    for (uint32_t e = 0; e < kElementCount; ++e) {
        Append(&s.model.mesh, elements[e]);
        s.model.triangle_element.insert(s.model.triangle_element.end(),
                                        elements[e].triangles.size(), e);
    }
    s.model.element_opaque.assign(kElementCount, 1);

    // As built.
    for (uint32_t e = 0; e < kElementCount; ++e) {
        if (e == kColumnA || e == kColumnB) continue;
        common::TriangleMesh m = elements[e];
        if (e == kWallNorthA) {
            for (auto& v : m.vertices) v.y() += float(s.wall_offset_m);
        }
        Append(&s.world, m);
    }
    s.added_box = Eigen::AlignedBox3d(V(2.6, 1.25, 0.0), V(3.4, 1.75, 0.6));
    Append(&s.world, SolidBox(s.added_box.min(), s.added_box.max()));
    const simulation::Scene world(s.world);

    // A loop around room A, the sensor 1 m above the floor, looking along the walk.
    const std::vector<Eigen::Vector2d> loop = {{1.0, 0.8}, {2.5, 0.6}, {4.0, 0.7}, {5.5, 0.8},
                                               {7.0, 1.0}, {7.2, 2.5}, {7.0, 4.0}, {6.8, 5.3},
                                               {5.3, 5.3}, {3.8, 5.2}, {2.3, 5.4}, {0.9, 5.2},
                                               {0.8, 3.8}, {1.0, 2.4}, {3.0, 3.0}, {6.0, 2.2}};
    const simulation::LidarModel lidar = simulation::LidarModel::DefaultOs1_32(1024);
    const simulation::NoiseModel noise;  // 1 cm range noise, dropouts
    for (size_t k = 0; k < loop.size(); ++k) {
        const Eigen::Vector2d next = loop[(k + 1) % loop.size()];
        const double yaw = std::atan2(next.y() - loop[k].y(), next.x() - loop[k].x());
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
        T.translation() = V(loop[k].x(), loop[k].y(), 1.0);
        T.linear() = Eigen::AngleAxisd(yaw, V::UnitZ()).toRotationMatrix();
        s.poses.push_back(T);
    }
    // The person crosses room A while keyframes 5 and 6 are taken, and is gone otherwise.
    for (size_t k = 0; k < s.poses.size(); ++k) {
        simulation::SimulatorOptions options;
        common::TriangleMesh person;
        if (k == 5 || k == 6) {
            const Eigen::Vector2d at(4.5, k == 5 ? 2.0 : 2.8);
            s.person_at.push_back(at);
            person = Cylinder(at, 0.25, 1.75);
        }
        const simulation::Scene overlay(person,
                                        std::vector<uint32_t>(person.triangles.size(), 999));
        options.overlay = &overlay;
        simulation::ScanImage image;
        simulation::SimulateScan(world, lidar, s.poses[k], noise, 1000 + k, &image, options);
        s.clouds.push_back(ToCloud(image, lidar));
    }
    for (size_t k = 0; k < s.clouds.size(); ++k) s.keyframes.push_back({&s.clouds[k], s.poses[k]});
    return s;
}

CorridorScene BuildCorridor() {
    CorridorScene s;
    using V = Eigen::Vector3d;
    const std::vector<common::TriangleMesh> elements = {
        SolidBox(V(-0.2, -0.2, -0.2), V(16.2, 2.2, 0)),   // floor
        SolidBox(V(-0.2, -0.2, 3.0), V(16.2, 2.2, 3.2)),  // ceiling
        SolidBox(V(-0.2, -0.2, 0), V(16.2, 0, 3)),        // south wall
        SolidBox(V(-0.2, 2.0, 0), V(16.2, 2.2, 3)),       // north wall
        SolidBox(V(-0.2, 0, 0), V(0, 2.0, 3)),            // west wall
        SolidBox(V(16.0, 0, 0), V(16.2, 2.0, 3)),         // east wall
    };
    for (uint32_t e = 0; e < elements.size(); ++e) {
        Append(&s.model.mesh, elements[e]);
        s.model.triangle_element.insert(s.model.triangle_element.end(),
                                        elements[e].triangles.size(), e);
    }
    s.model.element_opaque.assign(elements.size(), 1);
    const simulation::Scene world(s.model.mesh);

    s.person_from = {1.0, 0.6};
    s.person_to = {15.0, 0.6};
    // A triangle wave: the distance along a segment of `length` walked to and fro at `speed`.
    const auto along = [](double t, double speed, double length) {
        const double d = std::fmod(speed * t, 2 * length);
        return d <= length ? d : 2 * length - d;
    };
    const simulation::LidarModel lidar = simulation::LidarModel::DefaultOs1_32(1024);
    const simulation::NoiseModel noise;
    const double walk = 14.0;  // the Go1 from x = 1 to 15 and back along y = 1.5
    for (int k = 0; k < 56; ++k) {
        const double t = k;
        const double speed = 0.5;
        const bool back = std::fmod(speed * t, 2 * walk) > walk;
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
        T.translation() = V(1.0 + along(t, speed, walk), 1.5, 0.6);
        T.linear() = Eigen::AngleAxisd(back ? M_PI : 0.0, V::UnitZ()).toRotationMatrix();
        s.poses.push_back(T);
        const double length = (s.person_to - s.person_from).norm();
        const Eigen::Vector2d at =
            s.person_from + (s.person_to - s.person_from) * (along(t, 1.2, length) / length);
        const common::TriangleMesh person = Cylinder(at, s.person_radius_m, s.person_height_m);
        const simulation::Scene overlay(person,
                                        std::vector<uint32_t>(person.triangles.size(), 999));
        simulation::SimulatorOptions options;
        options.overlay = &overlay;
        simulation::ScanImage image;
        simulation::SimulateScan(world, lidar, T, noise, 2000 + uint64_t(k), &image, options);
        s.clouds.push_back(ToCloud(image, lidar));
    }
    for (size_t k = 0; k < s.clouds.size(); ++k) s.keyframes.push_back({&s.clouds[k], s.poses[k]});
    return s;
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace

common::TriangleMesh SolidBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    common::TriangleMesh m;
    for (int i = 0; i < 8; ++i) {
        m.vertices.emplace_back(float((i & 1) ? hi.x() : lo.x()), float((i & 2) ? hi.y() : lo.y()),
                                float((i & 4) ? hi.z() : lo.z()));
    }
    // Corner i has bits x = 1, y = 2, z = 4; faces counter-clockwise seen from outside.
    m.triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                   {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
    return m;
}

void Append(common::TriangleMesh* to, const common::TriangleMesh& m) {
    const auto base = uint32_t(to->vertices.size());
    to->vertices.insert(to->vertices.end(), m.vertices.begin(), m.vertices.end());
    for (const auto& t : m.triangles)
        to->triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
}

const ChangeScene& SharedChangeScene() {
    static const ChangeScene scene = BIMSLAM_UNITY_ID::Build();
    return scene;
}

const CorridorScene& SharedCorridorScene() {
    static const CorridorScene scene = BIMSLAM_UNITY_ID::BuildCorridor();
    return scene;
}

}  // namespace bimslam::changes::test
