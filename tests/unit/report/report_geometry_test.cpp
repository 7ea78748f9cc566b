// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The report's geometry: base64 as RFC 4648 gives it, and floor-plan sections: a wall crossing the
// cut plane gives its outline, one below it gives nothing, and each storey is cut at its own
// elevation.
#include "host_tools/report/report_geometry.hpp"

#include <gtest/gtest.h>

#include <string>

namespace bimslam::report {
namespace {
namespace BIMSLAM_UNITY_ID {

TEST(ReportGeometry, Base64IsRfc4648) {
    auto b = [](const std::string& s) { return Base64(s.data(), s.size()); };
    EXPECT_EQ(b(""), "");
    EXPECT_EQ(b("f"), "Zg==");
    EXPECT_EQ(b("fo"), "Zm8=");
    EXPECT_EQ(b("foo"), "Zm9v");
    EXPECT_EQ(b("foobar"), "Zm9vYmFy");
    const std::vector<float> one{1.0f};  // 0x3f800000, little endian
    EXPECT_EQ(Base64(one), "AACAPw==");
}

// A box element (12 triangles) from (x0, y0, z0) to (x1, y1, z1).
void AddBox(bim::BimModel& m, const std::string& cls, int storey, Eigen::Vector3f lo,
            Eigen::Vector3f hi) {
    bim::BimElement e;
    e.ifc_class = cls;
    e.storey = storey;
    e.first_triangle = uint32_t(m.mesh.triangles.size());
    const uint32_t v0 = uint32_t(m.mesh.vertices.size());
    for (int i = 0; i < 8; ++i) {
        m.mesh.vertices.emplace_back(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(),
                                     i & 4 ? hi.z() : lo.z());
    }
    const uint32_t f[12][3] = {{0, 1, 3}, {0, 3, 2}, {4, 6, 7}, {4, 7, 5}, {0, 4, 5}, {0, 5, 1},
                               {2, 3, 7}, {2, 7, 6}, {0, 2, 6}, {0, 6, 4}, {1, 5, 7}, {1, 7, 3}};
    for (const auto& t : f) m.mesh.triangles.push_back({v0 + t[0], v0 + t[1], v0 + t[2]});
    e.triangle_count = 12;
    m.elements.push_back(e);
}

TEST(ReportGeometry, PlanSectionsCutEachStoreyAtItsElevation) {
    bim::BimModel m;
    m.storeys = {{"Ground", "g0", 0.0}, {"First", "g1", 3.0}};
    AddBox(m, "IfcWall", 0, {0, 0, 0}, {4, 0.2f, 2.8f});            // crosses z = 1
    AddBox(m, "IfcFurnishingElement", 0, {1, 1, 0}, {2, 2, 0.7f});  // below the cut
    AddBox(m, "IfcDoor", 1, {0, 0, 3}, {1, 0.2f, 5.1f});            // crosses z = 4
    const nlohmann::json plans = PlanSections(m, 1.0);
    ASSERT_EQ(plans.size(), 2u);
    EXPECT_DOUBLE_EQ(plans[0]["cut_z"].get<double>(), 1.0);
    EXPECT_DOUBLE_EQ(plans[1]["cut_z"].get<double>(), 4.0);
    const auto& wall = plans[0]["segments"]["wall"];
    // The four side faces are cut (two triangles each): 8 segments of 4 numbers.
    ASSERT_EQ(wall.size(), 32u);
    for (size_t i = 0; i < wall.size(); i += 2) {
        EXPECT_GE(wall[i].get<float>(), 0.0f);
        EXPECT_LE(wall[i].get<float>(), 4.0f);
    }
    // One run of 8 segments, of the wall (element 0).
    EXPECT_EQ(plans[0]["segment_elements"]["wall"], nlohmann::json::array({0, 8}));
    EXPECT_FALSE(plans[0]["segments"].contains("other")) << "furniture below the cut";
    EXPECT_EQ(plans[1]["segments"]["door"].size(), 32u);
    EXPECT_FALSE(plans[1]["segments"].contains("wall"));
    EXPECT_EQ(StoreyAt(m, 1.5), 0);
    EXPECT_EQ(StoreyAt(m, 3.5), 1);
    EXPECT_EQ(StoreyAt(m, -2.0), 0);
}

TEST(ReportGeometry, ModelBuffersGroupByClassWithTheElementOfEachTriangle) {
    bim::BimModel m;
    AddBox(m, "IfcWall", -1, {0, 0, 0}, {1, 1, 1});
    AddBox(m, "IfcSpace", -1, {0, 0, 0}, {1, 1, 1});  // not drawn
    AddBox(m, "IfcWall", -1, {2, 0, 0}, {3, 1, 1});
    const nlohmann::json b = ModelBuffers(m);
    ASSERT_EQ(b["classes"].size(), 1u);
    EXPECT_EQ(b["classes"][0]["name"], "IfcWall");
    EXPECT_EQ(b["classes"][0]["triangles"], 24);
    EXPECT_EQ(b["elements"].size(), 3u);
    // 24 triangles' element indices (uint32): 12 x 0 then 12 x 2.
    std::vector<uint32_t> expected(12, 0);
    expected.resize(24, 2);
    EXPECT_EQ(b["classes"][0]["element"], Base64(expected));
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::report
