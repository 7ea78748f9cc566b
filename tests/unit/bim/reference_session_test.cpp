// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/bim/reference_session.hpp"

#include <gtest/gtest.h>

#include "algorithms/common/se3.hpp"
#include "algorithms/common/status.hpp"
#include "tests/support/test_support.hpp"
#include "tests/unit/bim/synthetic_floor.hpp"

namespace bimslam::bim {
namespace {
namespace BIMSLAM_UNITY_ID {
using test_floor::Floor;

// The axis-aligned box of each element of the synthetic floor (all of them are boxes).
std::vector<Eigen::AlignedBox3d> ElementBoxes(const BimModel& m, bool structure_only) {
    std::vector<Eigen::AlignedBox3d> boxes;
    for (const BimElement& e : m.elements) {
        if (structure_only && e.role != ElementRole::kStructure) continue;
        Eigen::AlignedBox3d box;
        for (uint32_t t = e.first_triangle; t < e.first_triangle + e.triangle_count; ++t) {
            for (uint32_t v : m.mesh.triangles[t]) box.extend(m.mesh.vertices[v].cast<double>());
        }
        boxes.push_back(box);
    }
    return boxes;
}

// Distance from p to the surface of the nearest box that holds it (within tol), or infinity.
double DistanceToSurface(const std::vector<Eigen::AlignedBox3d>& boxes, const Eigen::Vector3d& p,
                         double tol) {
    double best = std::numeric_limits<double>::infinity();
    for (const auto& b : boxes) {
        const Eigen::AlignedBox3d grown(b.min().array() - tol, b.max().array() + tol);
        if (!grown.contains(p)) continue;
        const Eigen::Vector3d lo = (p - b.min()).cwiseAbs(), hi = (b.max() - p).cwiseAbs();
        best = std::min(best, std::min(lo.minCoeff(), hi.minCoeff()));
    }
    return best;
}

ReferenceSessionOptions SmallOptions() {
    ReferenceSessionOptions o;
    o.keyframe_gap_m = 2.0;
    o.lidar = simulation::LidarModel::DefaultOs1_32(512);
    return o;
}

TEST(ReferenceSession, GroundTruthScansOfTheStructure) {
    test::TempDir tmp;
    const BimModel model = Floor();
    ReferenceSessionOptions o = SmallOptions();
    o.plan_dir = tmp / "plan";
    const ReferenceSessionReport r = WriteReferenceSession(model, "ab12", tmp / "s", o);
    ASSERT_EQ(r.storeys.size(), 1u);
    EXPECT_EQ(r.storeys[0].rooms, 4);
    EXPECT_GT(r.keyframes, 10u);
    EXPECT_EQ(r.rays, r.keyframes * 32 * 512);
    EXPECT_TRUE(std::filesystem::exists(tmp / "plan" / "ground.pgm"));
    EXPECT_TRUE(std::filesystem::exists(tmp / "plan" / "ground_path.tum"));

    const io::Session s = io::ReadSession(tmp / "s");
    ASSERT_TRUE(s.complete);
    EXPECT_EQ(s.manifest.source, "bim");
    EXPECT_EQ(s.manifest.world_frame, "bim");
    ASSERT_TRUE(s.manifest.model.has_value());
    EXPECT_EQ(s.manifest.model->sha256, "ab12");
    EXPECT_EQ(s.manifest.model->storeys, std::vector<std::string>{"Ground"});
    EXPECT_EQ(s.manifest.sensor.columns, 512);
    ASSERT_EQ(s.keyframes.size(), r.keyframes);
    ASSERT_EQ(s.edges.size(), r.keyframes - 1);
    // Frames at 10 Hz over the walk.
    EXPECT_NEAR(double(s.trajectory.size()), r.walk_s * 10, 2.0);

    const auto structure = ElementBoxes(model, true);
    const auto desk = ElementBoxes(SelectElements(model, [](const BimElement& e) {
                                       return e.ifc_class == "IfcFurniture";
                                   }),
                                   false);
    size_t points = 0, off_surface = 0;
    for (size_t i = 0; i < s.keyframes.size(); ++i) {
        const io::SessionKeyframe& kf = s.keyframes[i];
        EXPECT_EQ(kf.descriptor.rows(), 20);
        EXPECT_EQ(kf.descriptor.cols(), 60);
        EXPECT_GT(kf.descriptor.maxCoeff(), 1.0f);  // walls span more than a metre
        EXPECT_NEAR(kf.T_world_lidar.translation().z(), 0.6, 1e-9);
        if (i > 0) {
            // A keyframe every 2 m of walk: never farther apart than that in a straight line.
            const double d = (kf.T_world_lidar.translation() -
                              s.keyframes[i - 1].T_world_lidar.translation()).norm();
            EXPECT_LT(d, 2.0 + 0.1);
            const Eigen::Isometry3d rel =
                common::Between(s.keyframes[i - 1].T_world_lidar, kf.T_world_lidar);
            EXPECT_LT(common::TranslationNorm(common::Between(rel, s.edges[i - 1].T_from_to)), 1e-6);
        }
        // Exact ranges: every point lies on the structure (1 mm steps, float coordinates), none
        // on the desk, which is not structure.
        for (const Eigen::Vector3f& p : kf.cloud.xyz) {
            const Eigen::Vector3d w = kf.T_world_lidar * p.cast<double>();
            ++points;
            if (DistanceToSurface(structure, w, 0.002) > 0.002) ++off_surface;
            EXPECT_FALSE(w.z() > 0.01 && desk[0].contains(w)) << w.transpose();  // floor under it
        }
    }
    EXPECT_EQ(points, r.points);
    EXPECT_GT(points, r.rays / 2);  // closed rooms: most rays return
    EXPECT_EQ(off_surface, 0u);
}

TEST(ReferenceSession, AllElementsSeeTheFurniture) {
    test::TempDir tmp;
    const BimModel model = Floor();
    ReferenceSessionOptions o = SmallOptions();
    o.all_elements = true;
    WriteReferenceSession(model, "", tmp / "s", o);
    const auto desk = ElementBoxes(SelectElements(model, [](const BimElement& e) {
                                       return e.ifc_class == "IfcFurniture";
                                   }),
                                   false);
    size_t on_desk = 0;
    for (const auto& kf : io::ReadSession(tmp / "s").keyframes) {
        for (const auto& p : kf.cloud.xyz) {
            on_desk += DistanceToSurface(desk, kf.T_world_lidar * p.cast<double>(), 0.002) < 0.002;
        }
    }
    EXPECT_GT(on_desk, 100u);
}

TEST(ReferenceSession, RefusesBadInput) {
    test::TempDir tmp;
    const BimModel model = Floor();
    ReferenceSessionOptions o = SmallOptions();
    o.storeys = {"Attic"};
    try {
        WriteReferenceSession(model, "", tmp / "s", o);
        FAIL() << "no error for an unknown storey";
    } catch (const common::Error& e) {
        EXPECT_NE(std::string(e.what()).find("'Ground'"), std::string::npos) << e.what();
    }
    o = SmallOptions();
    o.keyframe_gap_m = 0;
    EXPECT_THROW(WriteReferenceSession(model, "", tmp / "s", o), common::Error);
    // An existing session is not overwritten without the flag.
    o = SmallOptions();
    o.keyframe_gap_m = 5;
    WriteReferenceSession(model, "", tmp / "s", o);
    EXPECT_THROW(WriteReferenceSession(model, "", tmp / "s", o), common::Error);
    o.overwrite = true;
    EXPECT_NO_THROW(WriteReferenceSession(model, "", tmp / "s", o));
    EXPECT_EQ(StoreyFileStem("Level 1 (T/FDN)"), "level_1_t_fdn");
    EXPECT_EQ(StoreyFileStem("--"), "storey");
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::bim
