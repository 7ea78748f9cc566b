// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// IFC ingest of faceted-brep faces whose hole is listed before their outer boundary (issue 38):
// IFC++ takes the first bound as the outer one and dropped such faces; the ingest puts the outer
// one first. The file is the project's own (tests/support/ifc_frame.hpp): one IfcFacetedBrep, a
// square frame with a hole, measured here against its areas computed by hand.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "host_tools/bim/ifc_model.hpp"
#include "tests/support/ifc_frame.hpp"

namespace bimslam::bim {
namespace {
namespace BIMSLAM_UNITY_ID {

using test::FrameIfc;
using test::FrameTop;

Eigen::Vector3d Corner(const BimModel& m, const std::array<uint32_t, 3>& t, int k) {
    return m.mesh.vertices[t[size_t(k)]].cast<double>() + m.origin_m;
}

// Twice the triangle's vector area: its normal, as long as twice its area.
Eigen::Vector3d Normal(const BimModel& m, const std::array<uint32_t, 3>& t) {
    const Eigen::Vector3d a = Corner(m, t, 0);
    return (Corner(m, t, 1) - a).cross(Corner(m, t, 2) - a);
}

struct Surface {
    double total_m2 = 0;    // every triangle
    double top_m2 = 0;      // triangles at z = 0.1 facing up: the top face
    double volume_m3 = 0;   // sum of the signed tetrahedra to the origin (divergence theorem)
    size_t open_edges = 0;  // edges not met by exactly one triangle running each way
};

// Edges are keyed by their end points rounded to 1e-6 m, so that the check does not depend on
// how vertices are shared: a closed, consistently wound surface uses every directed edge a -> b
// exactly once and its reverse b -> a exactly once.
Surface Measure(const BimModel& m) {
    Surface s;
    using Key = std::tuple<long, long, long>;
    auto key = [](const Eigen::Vector3d& p) {
        return Key{std::lround(p.x() * 1e6), std::lround(p.y() * 1e6), std::lround(p.z() * 1e6)};
    };
    std::map<std::pair<Key, Key>, int> directed;
    for (const auto& t : m.mesh.triangles) {
        const Eigen::Vector3d n = Normal(m, t);
        s.total_m2 += 0.5 * n.norm();
        bool on_top = true;
        for (int k = 0; k < 3; ++k) on_top = on_top && std::abs(Corner(m, t, k).z() - 0.1) < 1e-6;
        if (on_top && n.z() > 0) s.top_m2 += 0.5 * n.norm();
        s.volume_m3 += Corner(m, t, 0).dot(Corner(m, t, 1).cross(Corner(m, t, 2))) / 6.0;
        for (int k = 0; k < 3; ++k) {
            ++directed[{key(Corner(m, t, k)), key(Corner(m, t, (k + 1) % 3))}];
        }
    }
    for (const auto& [edge, n] : directed) {
        const auto reverse = directed.find({edge.second, edge.first});
        if (n != 1 || reverse == directed.end() || reverse->second != 1) ++s.open_edges;
    }
    return s;
}

// By hand: top = outer square minus hole = 1 * 1 - 0.4 * 0.4 = 0.84 m2; bottom the same;
// outer sides 4 * (1 * 0.1) = 0.4 m2; hole sides 4 * (0.4 * 0.1) = 0.16 m2; in all
// 2 * 0.84 + 0.4 + 0.16 = 2.24 m2. Volume: 0.84 m2 * 0.1 m = 0.084 m3.
constexpr double kTopM2 = 1.0 * 1.0 - 0.4 * 0.4;
constexpr double kTotalM2 = 2 * kTopM2 + 4 * (1.0 * 0.1) + 4 * (0.4 * 0.1);
constexpr double kVolumeM3 = kTopM2 * 0.1;

class FaceBounds : public testing::TestWithParam<std::tuple<FrameTop, double>> {};

TEST_P(FaceBounds, TheFaceIsTheOuterLoopMinusTheHoleAndTheSolidStaysClosed) {
    const auto [top, units_per_metre] = GetParam();
    const BimModel m = ParseIfc("frame.ifc", FrameIfc(top, units_per_metre));
    ASSERT_EQ(m.elements.size(), 1u);
    EXPECT_EQ(m.faces_reordered, top == FrameTop::kOuterFirst ? 0u : 1u);
    EXPECT_EQ(m.faces_lost, 0u);
    EXPECT_TRUE(m.incomplete.empty());
    for (const auto& w : m.warnings) ADD_FAILURE() << w;  // e.g. "Meshset is not closed"

    const Surface s = Measure(m);
    EXPECT_NEAR(s.top_m2, kTopM2, 1e-6);
    EXPECT_NEAR(s.total_m2, kTotalM2, 1e-6);
    EXPECT_NEAR(s.volume_m3, kVolumeM3, 1e-7);  // closed and wound outwards
    EXPECT_EQ(s.open_edges, 0u) << "not watertight";
}

std::string OrderName(const testing::TestParamInfo<std::tuple<FrameTop, double>>& info) {
    static const std::map<FrameTop, std::string> kNames = {
        {FrameTop::kOuterFirst, "OuterFirst"},
        {FrameTop::kHoleFirst, "HoleFirst"},
        {FrameTop::kUnmarkedHoleFirst, "UnmarkedHoleFirst"}};
    return kNames.at(std::get<0>(info.param)) + (std::get<1>(info.param) == 1000.0 ? "_mm" : "_m");
}

INSTANTIATE_TEST_SUITE_P(Orders, FaceBounds,
                         testing::Combine(testing::Values(FrameTop::kOuterFirst,
                                                          FrameTop::kHoleFirst,
                                                          FrameTop::kUnmarkedHoleFirst),
                                          testing::Values(1.0, 1000.0)),
                         OrderName);

// A face no order can fix (its hole lies beside its outer loop, against ISO 10303-42) is not
// thinned away silently: it is counted as lost and its element listed, naming the face.
TEST(FaceBounds, AFaceIfcppCannotTriangulateIsReported) {
    const BimModel m = ParseIfc("frame.ifc", FrameIfc(FrameTop::kHoleOutsideOfOuter));
    ASSERT_EQ(m.elements.size(), 1u);
    EXPECT_EQ(m.faces_reordered, 0u);
    EXPECT_EQ(m.faces_lost, 1u);
    ASSERT_EQ(m.incomplete.size(), 1u);
    EXPECT_EQ(m.incomplete[0].global_id, "3vB2YO$MX4xv5uCqZZG05x");
    EXPECT_EQ(m.incomplete[0].ifc_class, "IfcFurniture");
    EXPECT_NE(m.incomplete[0].reason.find("faces IFC++ could not triangulate: #"),
              std::string::npos)
        << m.incomplete[0].reason;
    EXPECT_NEAR(Measure(m).top_m2, 0.0, 1e-9);  // the top face is missing
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::bim
