// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The as-is model (host_tools/mapping/asis_model.hpp, issue 33 item 4) of a history made by hand
// on the sample office: an object present with its mesh from its visit's changes folder, an
// element missing as of the newest visit, one deviating; read back by IFC++.
#include "host_tools/mapping/asis_model.hpp"

#include <gtest/gtest.h>

#include "algorithms/io/file_util.hpp"
#include "algorithms/io/ply.hpp"
#include "host_tools/bim/ifc_model.hpp"
#include "host_tools/bim/sample_building.hpp"
#include "host_tools/mapping/map_project.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::mapping {
namespace {
namespace BIMSLAM_UNITY_ID {
using nlohmann::json;

// v2's changes of recording "walk": object 0, a 0.5 m cube at (5, 3) on the ground floor.
void WriteCube(const std::filesystem::path& out) {
    const std::filesystem::path dir = VisitDir(out, "v2") / "changes" / "walk";
    std::filesystem::create_directories(dir);
    io::PlyData cube;
    for (int k = 0; k < 8; ++k)
        cube.vertices.emplace_back(5.0f + 0.5f * (k & 1), 3.0f + 0.5f * ((k >> 1) & 1),
                                   0.5f * (k >> 2));
    cube.triangles = {{0, 1, 3}, {0, 3, 2}, {4, 7, 5}, {4, 6, 7}, {0, 5, 1}, {0, 4, 5},
                      {2, 3, 7}, {2, 7, 6}, {0, 2, 6}, {0, 6, 4}, {1, 5, 7}, {1, 7, 3}};
    io::WritePly(dir / "new_objects.ply", cube);
    const json mesh = {{"file", "new_objects.ply"},
                       {"first_vertex", 0},
                       {"vertices", 8},
                       {"first_triangle", 0},
                       {"triangles", 12}};
    io::WriteFileAtomic(dir / "changes.json",
                        json({{"new_objects", json::array({{{"id", 0}, {"mesh", mesh}}})}}).dump());
}

json HistoryElement(const std::string& id, const std::string& v1, const std::string& v2) {
    const bool built1 = v1 != "missing", built2 = v2 != "missing";
    json deviations = json::array();
    if (v2 == "deviating")
        deviations.push_back(
            {{"visit", "v2"}, {"offset_m", {0.03, 0, 0}}, {"offset_norm_m", 0.03}});
    return {{"global_id", id},
            {"class", "IfcWall"},
            {"verdicts", {v1, v2}},
            {"first_seen_built", built1 ? json("v1") : (built2 ? json("v2") : json(nullptr))},
            {"last_seen_built", built2 ? json("v2") : (built1 ? json("v1") : json(nullptr))},
            {"last_observed", "v2"},
            {"last_verdict", v2},
            {"deviations", deviations}};
}

TEST(AsIsModel, ProxiesHistoriesAndTheMissingGroupReadBackByIfcpp) {
    test::TempDir tmp;
    WriteCube(tmp.path());
    const std::string text = bim::SampleBuildingIfc();
    const bim::BimModel model = bim::ParseIfc("building.ifc", text);
    std::vector<std::string> walls;
    for (const auto& e : model.elements) {
        if (e.ifc_class == "IfcWall") walls.push_back(e.global_id);
    }
    ASSERT_GE(walls.size(), 3u);
    const json history = {
        {"visits", {{{"label", "v1"}}, {{"label", "v2"}}}},
        {"elements",
         {HistoryElement(walls[0], "confirmed", "missing"),
          HistoryElement(walls[1], "confirmed", "deviating"),
          HistoryElement(walls[2], "confirmed", "confirmed")}},
        {"objects",
         {{{"id", "O1"},
           {"state", "present"},
           {"storey", "Ground Floor"},
           {"first_seen", "v2"},
           {"last_seen", "v2"},
           {"sightings",
            {{{"visit", "v2"}, {"status", "new"}, {"recording", "walk"}, {"object", 0}}}}},
          {{"id", "O2"}, {"state", "gone"}, {"sightings", json::array()}}}}};
    const change_detection::IfcUpdate u =
        AsIsIfc(tmp.path(), "building.ifc", text, model, history, 42);
    EXPECT_EQ(u.proxies, 1u) << "the gone object is not in the model as is";
    EXPECT_EQ(u.element_property_sets, 3u);
    EXPECT_TRUE(u.notes.empty());
    EXPECT_EQ(u.text.compare(0, text.rfind("ENDSEC;"), text, 0, text.rfind("ENDSEC;")), 0);
    // The missing wall in the group, the deviation on the deviating one.
    const size_t group = u.text.find("IFCGROUP(");
    ASSERT_NE(group, std::string::npos);
    EXPECT_NE(u.text.find("'bimslam missing elements'", group), std::string::npos);
    EXPECT_NE(u.text.find("IFCRELASSIGNSTOGROUP("), std::string::npos);
    EXPECT_NE(u.text.find("'LastDeviation',$,IFCLENGTHMEASURE(0.03)"), std::string::npos);
    EXPECT_NE(u.text.find("'VerdictsByVisit',$,IFCTEXT('v1 confirmed; v2 missing')"),
              std::string::npos);

    const bim::BimModel back = bim::ParseIfc("model_asis.ifc", u.text);
    EXPECT_EQ(back.elements.size(), model.elements.size() + 1);
    EXPECT_EQ(back.class_counts.at("IfcBuildingElementProxy"), 1u);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::mapping
