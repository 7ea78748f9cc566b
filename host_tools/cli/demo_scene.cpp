#include "host_tools/cli/demo_scene.hpp"

#include <cmath>
#include <limits>

namespace bimslam::cli {
namespace {

void AddBox(DemoScene& s, double x0, double y0, double x1, double y1) {
    const Eigen::Vector2d p00(x0, y0), p10(x1, y0), p11(x1, y1), p01(x0, y1);
    s.walls.push_back({p00, p10});
    s.walls.push_back({p10, p11});
    s.walls.push_back({p11, p01});
    s.walls.push_back({p01, p00});
}

// Distance along the ray (o + t d) to segment ab in 2D, or +inf.
double HitSegment(const Eigen::Vector2d& o, const Eigen::Vector2d& d, const Eigen::Vector2d& a,
                  const Eigen::Vector2d& b) {
    const Eigen::Vector2d e = b - a;
    const double den = d.x() * e.y() - d.y() * e.x();
    if (std::abs(den) < 1e-12) return std::numeric_limits<double>::infinity();
    const Eigen::Vector2d w = a - o;
    const double t = (w.x() * e.y() - w.y() * e.x()) / den;
    const double u = (w.x() * d.y() - w.y() * d.x()) / den;
    if (t <= 0.0 || u < 0.0 || u > 1.0) return std::numeric_limits<double>::infinity();
    return t;
}
}  // namespace

DemoScene DemoScene::Office() {
    DemoScene s;
    // Outer shell 24 x 12 m with a corridor along y in [5, 7].
    AddBox(s, 0, 0, 24, 12);
    // South rooms (y 0..5) of widths 6, 8, 10 m; door gaps of 1 m in the corridor wall.
    const double south[] = {0, 6, 14, 24};
    for (int i = 0; i < 3; ++i) {
        const double x0 = south[i], x1 = south[i + 1], door = x0 + 1.5;
        s.walls.push_back({{x0, 5}, {door, 5}});
        s.walls.push_back({{door + 1.0, 5}, {x1, 5}});
        if (i > 0) s.walls.push_back({{x0, 0}, {x0, 5}});
    }
    // North rooms (y 7..12): 9 m and 15 m wide; the east one has a slanted wall.
    s.walls.push_back({{0, 7}, {3, 7}});
    s.walls.push_back({{4, 7}, {12, 7}});
    s.walls.push_back({{13, 7}, {24, 7}});
    s.walls.push_back({{9, 7}, {9, 12}});
    s.walls.push_back({{18, 12}, {24, 9.5}});
    // Pillars and a cabinet break the symmetry of the rooms.
    AddBox(s, 3.0, 2.0, 3.4, 2.4);
    AddBox(s, 19.0, 2.5, 19.5, 3.0);
    AddBox(s, 15.0, 9.0, 16.5, 9.6);
    AddBox(s, 5.0, 10.5, 7.0, 11.2);
    // The walk: east along the corridor with a detour through the middle south room, a loop
    // in the east room, back west through the north-east room and the north-west room. Door
    // passages keep 0.25 m from the jambs so that a second, offset lap still fits.
    s.loop = {{1.0, 6.0},  {8.0, 6.0},   {8.0, 3.0},   {11.0, 3.0},  {11.0, 4.0},   {8.1, 4.0},
              {8.1, 6.1},  {15.85, 6.1}, {15.85, 3.0}, {21.0, 2.0},  {21.5, 4.0},   {16.1, 4.0},
              {16.1, 6.2}, {12.35, 6.2}, {12.35, 9.0}, {14.0, 10.5}, {12.65, 10.5}, {12.65, 6.3},
              {3.35, 6.3}, {3.35, 9.0},  {6.0, 9.5},   {3.65, 9.3},  {3.65, 6.0},   {1.0, 6.0}};
    return s;
}

double DemoScene::LoopLength() const {
    double len = 0.0;
    for (size_t i = 1; i < loop.size(); ++i) len += (loop[i] - loop[i - 1]).norm();
    return len;
}

Eigen::Isometry3d DemoScene::PoseAt(double s, double lateral_offset, double z) const {
    const double total = LoopLength();
    s = std::fmod(std::fmod(s, total) + total, total);
    size_t i = 1;
    while (i + 1 < loop.size() && s > (loop[i] - loop[i - 1]).norm()) {
        s -= (loop[i] - loop[i - 1]).norm();
        ++i;
    }
    const Eigen::Vector2d dir = (loop[i] - loop[i - 1]).normalized();
    const Eigen::Vector2d left(-dir.y(), dir.x());
    const Eigen::Vector2d p = loop[i - 1] + s * dir + lateral_offset * left;
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(std::atan2(dir.y(), dir.x()), Eigen::Vector3d::UnitZ())
                     .toRotationMatrix();
    T.translation() = Eigen::Vector3d(p.x(), p.y(), z);
    return T;
}

double DemoScene::Cast(const Eigen::Vector3d& origin, const Eigen::Vector3d& d,
                       double* cos_incidence) const {
    double best = std::numeric_limits<double>::infinity();
    double cosine = std::abs(d.z());
    if (std::abs(d.z()) > 1e-9) {  // floor or ceiling
        best = ((d.z() > 0 ? ceiling_z : floor_z) - origin.z()) / d.z();
    }
    const double horiz = d.head<2>().norm();
    if (horiz > 1e-9) {
        const Eigen::Vector2d d2 = d.head<2>() / horiz;
        for (const auto& w : walls) {
            const double t2 = HitSegment(origin.head<2>(), d2, w.a, w.b);
            if (t2 / horiz < best) {
                best = t2 / horiz;
                const Eigen::Vector2d e = (w.b - w.a).normalized();
                cosine = std::abs(d2.x() * e.y() - d2.y() * e.x()) * horiz;
            }
        }
    }
    if (cos_incidence) *cos_incidence = cosine;
    return best > 0 ? best : std::numeric_limits<double>::infinity();
}

}  // namespace bimslam::cli
