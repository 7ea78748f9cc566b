#include "algorithms/changes/moved_elements.hpp"

#include <gtest/gtest.h>

#include <random>

#include "tests/unit/changes/change_scene.hpp"

namespace bimslam::changes {
namespace {

// A desk: a top and four legs, element 0 of a model.
ChangeModel Desk() {
    ChangeModel m;
    test::Append(&m.mesh, test::SolidBox({0, 0, 0.72}, {1.6, 0.8, 0.75}));
    for (const auto& [x, y] : {std::pair{0.0, 0.0}, {1.55, 0.0}, {0.0, 0.75}, {1.55, 0.75}}) {
        test::Append(&m.mesh, test::SolidBox({x, y, 0}, {x + 0.05, y + 0.05, 0.72}));
    }
    m.triangle_element.assign(m.mesh.triangles.size(), 0);
    m.element_opaque = {1};
    return m;
}

TEST(MovedElements, FitsTheMotionOfADeskFromPointsOnItsNewPlace) {
    const ChangeModel desk = Desk();
    const Eigen::Vector3d c(0.8, 0.4, 0.375);  // the desk's box centre
    const double yaw = 15 * M_PI / 180;
    const Eigen::Vector3d t(0.5, -0.3, 0.0);
    const Eigen::Isometry3d M = Eigen::Translation3d(c + t) *
                                Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                                Eigen::Translation3d(-c);
    // Points on the moved desk's top and legs, 5 mm noise.
    std::mt19937 rng(2);
    std::normal_distribution<float> noise(0, 0.005f);
    std::vector<Eigen::Vector3f> points;
    for (double x = 0.02; x < 1.6; x += 0.04) {
        for (double y = 0.02; y < 0.8; y += 0.04) {
            const Eigen::Vector3d p = M * Eigen::Vector3d(x, y, 0.75);
            points.push_back(p.cast<float>() + Eigen::Vector3f(noise(rng), noise(rng), noise(rng)));
        }
    }
    for (double z = 0.05; z < 0.7; z += 0.05) {
        for (const auto& [x, y] : {std::pair{0.0, 0.025}, {1.6, 0.025}, {0.0, 0.775}}) {
            points.push_back((M * Eigen::Vector3d(x, y, z)).cast<float>());
        }
    }
    const MotionFit fit = FitElementMotion(desk, 0, points, MovedConfig{});
    EXPECT_GT(fit.inlier_fraction, 0.9);
    EXPECT_NEAR((fit.translation - t).norm(), 0.0, 0.02) << fit.translation.transpose();
    EXPECT_NEAR(fit.yaw_rad, yaw, 0.5 * M_PI / 180);
}

}  // namespace
}  // namespace bimslam::changes
