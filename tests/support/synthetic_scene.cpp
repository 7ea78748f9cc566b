// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "tests/support/synthetic_scene.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

namespace bimslam::test {
namespace {

constexpr double kEps = 1e-12;

// Slab test; the entry distance when the ray enters the box in front of the origin.
std::optional<double> HitBox(const SceneBox& b, const Eigen::Vector3d& o,
                             const Eigen::Vector3d& d) {
    double t_near = -std::numeric_limits<double>::infinity();
    double t_far = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k) {
        if (std::abs(d[k]) < kEps) {
            if (o[k] < b.lo[k] || o[k] > b.hi[k]) return std::nullopt;
            continue;
        }
        double t0 = (b.lo[k] - o[k]) / d[k], t1 = (b.hi[k] - o[k]) / d[k];
        if (t0 > t1) std::swap(t0, t1);
        t_near = std::max(t_near, t0);
        t_far = std::min(t_far, t1);
    }
    if (t_near > t_far || t_near <= 0.0) return std::nullopt;
    return t_near;
}

// The wall, floor or ceiling of a room the origin is inside of.
std::optional<double> HitRoom(const SceneBox& b, const Eigen::Vector3d& o,
                              const Eigen::Vector3d& d) {
    double best = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k) {
        if (std::abs(d[k]) < kEps) continue;
        const double t = ((d[k] > 0 ? b.hi[k] : b.lo[k]) - o[k]) / d[k];
        if (t > 0.0) best = std::min(best, t);
    }
    if (!std::isfinite(best)) return std::nullopt;
    return best;
}

std::optional<double> HitCylinder(const SceneCylinder& c, const Eigen::Vector3d& o,
                                  const Eigen::Vector3d& d) {
    double best = std::numeric_limits<double>::infinity();
    const Eigen::Vector2d oc = o.head<2>() - c.centre, d2 = d.head<2>();
    const double a = d2.squaredNorm();
    if (a > kEps) {
        const double b = 2.0 * d2.dot(oc), cc = oc.squaredNorm() - c.radius * c.radius;
        const double disc = b * b - 4.0 * a * cc;
        if (disc >= 0.0) {
            const double t = (-b - std::sqrt(disc)) / (2.0 * a);
            const double z = o.z() + t * d.z();
            if (t > 0.0 && z >= c.z_lo && z <= c.z_hi) best = t;
        }
    }
    if (std::abs(d.z()) > kEps) {
        for (double zc : {c.z_lo, c.z_hi}) {
            const double t = (zc - o.z()) / d.z();
            if (t > 0.0 && t < best &&
                (o.head<2>() + t * d2 - c.centre).squaredNorm() <= c.radius * c.radius) {
                best = t;
            }
        }
    }
    if (!std::isfinite(best)) return std::nullopt;
    return best;
}

// Horizontal distance from p to the footprint of a box.
double FootprintDistance(const SceneBox& b, const Eigen::Vector2d& p) {
    const double dx = std::max({b.lo.x() - p.x(), 0.0, p.x() - b.hi.x()});
    const double dy = std::max({b.lo.y() - p.y(), 0.0, p.y() - b.hi.y()});
    return std::hypot(dx, dy);
}

double CylinderDistance(const SceneCylinder& c, const Eigen::Vector2d& p) {
    return std::max(0.0, (p - c.centre).norm() - c.radius);
}

}  // namespace

std::optional<double> Scene::Cast(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
                                  double max_range) const {
    double best = std::numeric_limits<double>::infinity();
    auto take = [&best](std::optional<double> t) {
        if (t && *t < best) best = *t;
    };
    if (room) take(HitRoom(*room, origin, dir));
    if (ground_z && dir.z() < -kEps) take((*ground_z - origin.z()) / dir.z());
    for (const SceneBox& b : boxes) take(HitBox(b, origin, dir));
    for (const SceneCylinder& c : cylinders) take(HitCylinder(c, origin, dir));
    if (!(best <= max_range)) return std::nullopt;
    return best;
}

common::PointCloud ScanScene(const Scene& scene, const Eigen::Isometry3d& T_world_lidar,
                             const LidarModel& lidar, uint32_t seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> noise(0.0, 1.0);
    const Eigen::Matrix3d R = T_world_lidar.linear();
    const Eigen::Vector3d origin = T_world_lidar.translation();
    // Beam elevations (cos, sin), computed once.
    std::vector<Eigen::Vector2d> beam(static_cast<size_t>(std::max(lidar.beams, 0)));
    for (int r = 0; r < lidar.beams; ++r) {
        const double frac = lidar.beams > 1 ? static_cast<double>(r) / (lidar.beams - 1) : 0.5;
        const double el_deg = lidar.highest_elevation_deg -
                              frac * (lidar.highest_elevation_deg - lidar.lowest_elevation_deg);
        const double el = el_deg * std::numbers::pi / 180.0;
        beam[static_cast<size_t>(r)] = Eigen::Vector2d(std::cos(el), std::sin(el));
    }
    common::PointCloud cloud;
    cloud.Reserve(static_cast<size_t>(lidar.beams) * static_cast<size_t>(lidar.columns));
    for (int c = 0; c < lidar.columns; ++c) {
        const double az = lidar.azimuth_offset_rad + 2.0 * std::numbers::pi * c / lidar.columns;
        const double ca = std::cos(az), sa = std::sin(az);
        const auto t_ns = static_cast<uint32_t>(100'000'000.0 * c / lidar.columns);
        for (int r = 0; r < lidar.beams; ++r) {
            const Eigen::Vector2d& e = beam[static_cast<size_t>(r)];
            const Eigen::Vector3d d_lidar(e.x() * ca, e.x() * sa, e.y());
            const std::optional<double> t = scene.Cast(origin, R * d_lidar, lidar.max_range);
            Eigen::Vector3f p = Eigen::Vector3f::Zero();
            if (t) {
                const double range =
                    lidar.range_noise_sigma > 0.0 ? *t + lidar.range_noise_sigma * noise(rng) : *t;
                p = (range * d_lidar).cast<float>();
            } else if (!lidar.misses_as_origin) {
                continue;
            }
            cloud.PushBack(p, 100.0f, static_cast<uint16_t>(r), t_ns);
        }
    }
    return cloud;
}

Place MakeRandomRoom(uint32_t seed) {
    std::mt19937 rng(seed);
    auto uniform = [&rng](double lo, double hi) {
        return std::uniform_real_distribution<double>(lo, hi)(rng);
    };
    auto count = [&rng](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };

    Place place;
    place.clearance = 0.6;
    const double sx = uniform(4.0, 14.0), sy = uniform(3.0, 10.0), h = uniform(2.4, 4.0);
    place.scene.room = SceneBox{Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(sx, sy, h)};
    place.sensor =
        Eigen::Vector3d(uniform(1.0, sx - 1.0), uniform(1.0, sy - 1.0), uniform(0.4, 1.2));
    const Eigen::Vector2d s2 = place.sensor.head<2>();

    // Furniture: boxes standing on the floor, none closer than the clearance to the sensor.
    const int n_boxes = count(2, 6);
    for (int i = 0, tries = 0; i < n_boxes && tries < 200; ++tries) {
        const double w = uniform(0.3, 2.0), d = uniform(0.3, 2.0), bh = uniform(0.4, 2.2);
        const double x = uniform(0.0, sx - w), y = uniform(0.0, sy - d);
        const SceneBox b{Eigen::Vector3d(x, y, 0.0),
                         Eigen::Vector3d(x + w, y + d, std::min(bh, h))};
        if (FootprintDistance(b, s2) < place.clearance) continue;
        place.scene.boxes.push_back(b);
        ++i;
    }
    // Pillars, floor to ceiling.
    const int n_pillars = count(0, 3);
    for (int i = 0, tries = 0; i < n_pillars && tries < 200; ++tries) {
        const SceneCylinder c{Eigen::Vector2d(uniform(0.5, sx - 0.5), uniform(0.5, sy - 0.5)),
                              uniform(0.1, 0.4), 0.0, h};
        if (CylinderDistance(c, s2) < place.clearance) continue;
        place.scene.cylinders.push_back(c);
        ++i;
    }
    // Sometimes a partition wall (0.15 m thick, floor to ceiling) part-way across the room.
    if (uniform(0.0, 1.0) < 0.3) {
        for (int tries = 0; tries < 50; ++tries) {
            SceneBox wall;
            if (uniform(0.0, 1.0) < 0.5) {
                const double x = uniform(0.5, sx - 0.5), len = uniform(0.3, 0.7) * sy;
                const double y0 = uniform(0.0, 1.0) < 0.5 ? 0.0 : sy - len;
                wall = SceneBox{Eigen::Vector3d(x, y0, 0), Eigen::Vector3d(x + 0.15, y0 + len, h)};
            } else {
                const double y = uniform(0.5, sy - 0.5), len = uniform(0.3, 0.7) * sx;
                const double x0 = uniform(0.0, 1.0) < 0.5 ? 0.0 : sx - len;
                wall = SceneBox{Eigen::Vector3d(x0, y, 0), Eigen::Vector3d(x0 + len, y + 0.15, h)};
            }
            if (FootprintDistance(wall, s2) < place.clearance) continue;
            place.scene.boxes.push_back(wall);
            break;
        }
    }
    return place;
}

Place MakeRandomTown(uint32_t seed) {
    std::mt19937 rng(seed);
    auto uniform = [&rng](double lo, double hi) {
        return std::uniform_real_distribution<double>(lo, hi)(rng);
    };
    auto count = [&rng](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };

    Place place;
    place.clearance = 2.0;
    place.scene.ground_z = 0.0;
    place.sensor = Eigen::Vector3d(0.0, 0.0, 1.8);
    const Eigen::Vector2d s2 = place.sensor.head<2>();
    const int n_buildings = count(8, 20);
    for (int i = 0, tries = 0; i < n_buildings && tries < 500; ++tries) {
        const double w = uniform(5.0, 30.0), d = uniform(5.0, 30.0), bh = uniform(3.0, 25.0);
        const double x = uniform(-70.0, 70.0 - w), y = uniform(-70.0, 70.0 - d);
        const SceneBox b{Eigen::Vector3d(x, y, 0.0), Eigen::Vector3d(x + w, y + d, bh)};
        if (FootprintDistance(b, s2) < 4.0) continue;
        place.scene.boxes.push_back(b);
        ++i;
    }
    const int n_trees = count(0, 15);
    for (int i = 0, tries = 0; i < n_trees && tries < 500; ++tries) {
        const SceneCylinder c{Eigen::Vector2d(uniform(-60.0, 60.0), uniform(-60.0, 60.0)),
                              uniform(0.2, 0.5), 0.0, uniform(3.0, 8.0)};
        if (CylinderDistance(c, s2) < place.clearance) continue;
        place.scene.cylinders.push_back(c);
        ++i;
    }
    return place;
}

}  // namespace bimslam::test
