// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The updated IFC read back with IFC++ (through host_tools/bim, the project's ingest): the new
// objects as proxies with their voxel meshes where they were found, in their storey, and the
// verdicts as property sets on the elements; IFC4 (the sample building, tessellated) and IFC2X3
// (a small hand-written file, faceted B-rep). web-ifc, the second reader, is in
// tests/integration/changes_cli_test.cpp.
#include "host_tools/changes/ifc_update.hpp"

#include <gtest/gtest.h>

#include "algorithms/common/status.hpp"
#include "host_tools/bim/ifc_model.hpp"
#include "host_tools/bim/ifc_writer.hpp"
#include "host_tools/bim/sample_building.hpp"
#include "host_tools/changes/step_index.hpp"
#include "tests/support/test_support.hpp"
#include "tests/unit/change_detection/ifc_update_fixtures.hpp"

namespace bimslam::change_detection {
namespace {
namespace BIMSLAM_UNITY_ID {
using test::Found;
using test::kTinyIfc2x3;

// The proxies IFC++ reads from `text`, with their triangles' box.
std::vector<std::pair<bim::BimElement, Eigen::AlignedBox3d>> Proxies(const std::string& text) {
    const bim::BimModel m = bim::ParseIfc("updated.ifc", text);
    std::vector<std::pair<bim::BimElement, Eigen::AlignedBox3d>> out;
    for (const bim::BimElement& e : m.elements) {
        if (e.ifc_class != "IfcBuildingElementProxy") continue;
        Eigen::AlignedBox3d box;
        for (uint32_t t = e.first_triangle; t < e.first_triangle + e.triangle_count; ++t) {
            for (const uint32_t v : m.mesh.triangles[t])
                box.extend(m.mesh.vertices[v].cast<double>());
        }
        out.emplace_back(e, box);
    }
    return out;
}

// The verdict property set on entity `id`: its Verdict value, or "".
std::string VerdictOn(const std::string& text, int id) {
    const StepIndex index("updated.ifc", text);
    for (const StepEntity* rel : index.OfType("IFCRELDEFINESBYPROPERTIES")) {
        const auto args = StepIndex::SplitArgs(rel->args);
        if (args.size() != 6 || args[4] != "(#" + std::to_string(id) + ")") continue;
        const int set = std::stoi(std::string(args[5].substr(1)));
        for (const StepEntity& e : index.entities()) {
            if (e.id != set) continue;
            const auto set_args = StepIndex::SplitArgs(e.args);
            EXPECT_EQ(set_args[2], "'bimslam_ChangeDetection'");
            for (const StepEntity& p : index.entities()) {
                if (p.type == "IFCPROPERTYSINGLEVALUE" && p.args.starts_with("'Verdict'") &&
                    set_args[4].find("#" + std::to_string(p.id) + ",") != std::string_view::npos) {
                    return std::string(StepIndex::SplitArgs(p.args)[2]);
                }
            }
        }
    }
    return "";
}

TEST(IfcUpdate, Ifc4ProxiesWithTessellatedMeshesInTheirStoreyAndVerdictsAsPropertySets) {
    const std::string text = bim::SampleBuildingIfc(bim::SampleBuildingOptions{});
    const bim::BimModel model = bim::ParseIfc("building.ifc", text);
    size_t column = 0;
    while (model.elements[column].ifc_class != "IfcColumn") ++column;
    const SessionChanges found =
        Found(model, Eigen::Vector3f(3.0f, 2.0f, 0.0f), column, changes::Verdict::kMissing);
    const IfcUpdate update = UpdateIfc("building.ifc", text, model, found, 7);
    EXPECT_EQ(update.proxies, 1u);
    EXPECT_EQ(update.element_property_sets, 1u);
    EXPECT_TRUE(update.notes.empty());
    EXPECT_NE(update.text.find("IFCTRIANGULATEDFACESET("), std::string::npos);
    // The original is kept byte for byte up to where the new entities start.
    const StepIndex original("building.ifc", text);
    EXPECT_EQ(update.text.substr(0, original.data_end()), text.substr(0, original.data_end()));

    const auto proxies = Proxies(update.text);
    ASSERT_EQ(proxies.size(), 1u);
    const auto& [proxy, box] = proxies[0];
    EXPECT_EQ(proxy.global_id, found.object_global_ids[0]);
    EXPECT_EQ(proxy.storey, 0);
    const changes::NewObject& obj = found.result.objects[0];
    EXPECT_LT((box.min() - obj.box_min).norm(), 1e-4) << box.min().transpose();
    EXPECT_LT((box.max() - obj.box_max).norm(), 1e-4) << box.max().transpose();
    // Nothing of the original was lost.
    const bim::BimModel updated = bim::ParseIfc("updated.ifc", update.text);
    EXPECT_EQ(updated.elements.size(), model.elements.size() + 1);
    const StepIndex index("updated.ifc", update.text);
    EXPECT_EQ(VerdictOn(update.text, index.FindGlobalId(model.elements[column].global_id)->id),
              "IFCLABEL('missing')");
}

TEST(IfcUpdate, Ifc2x3ProxiesAsFacetedBrepsReadBackWhereTheyWereFound) {
    const bim::BimModel model = bim::ParseIfc("tiny.ifc", kTinyIfc2x3);
    ASSERT_EQ(model.schema, "IFC2X3");
    ASSERT_EQ(model.elements.size(), 1u);
    const SessionChanges found =
        Found(model, Eigen::Vector3f(1.0f, 1.0f, 0.0f), 0, changes::Verdict::kDeviating);
    const IfcUpdate update = UpdateIfc("tiny.ifc", kTinyIfc2x3, model, found, 7);
    EXPECT_NE(update.text.find("IFCFACETEDBREP("), std::string::npos);
    EXPECT_EQ(update.text.find("IFCTRIANGULATEDFACESET("), std::string::npos);
    // The owner history of the file is reused (IFC2X3 requires one).
    EXPECT_NE(update.text.find("IFCBUILDINGELEMENTPROXY('" + found.object_global_ids[0] + "',#5,"),
              std::string::npos);
    const auto proxies = Proxies(update.text);
    ASSERT_EQ(proxies.size(), 1u);
    EXPECT_EQ(proxies[0].first.storey, 0);
    EXPECT_LT((proxies[0].second.min() - found.result.objects[0].box_min).norm(), 1e-4);
    EXPECT_LT((proxies[0].second.max() - found.result.objects[0].box_max).norm(), 1e-4);
    EXPECT_EQ(VerdictOn(update.text, 29), "IFCLABEL('deviating')");
    EXPECT_NE(update.text.find("IFCPROPERTYSINGLEVALUE('Offset',$,IFCLENGTHMEASURE(0.03),$)"),
              std::string::npos);
}

TEST(IfcUpdate, MillimetreFilesGetTheirCoordinatesInMillimetres) {
    bim::SampleBuildingOptions options;
    options.length_unit_m = 0.001;
    const std::string text = bim::SampleBuildingIfc(options);
    const bim::BimModel model = bim::ParseIfc("building_mm.ifc", text);
    const SessionChanges found =
        Found(model, Eigen::Vector3f(3.0f, 2.0f, 0.0f), 0, changes::Verdict::kMissing);
    const IfcUpdate update = UpdateIfc("building_mm.ifc", text, model, found, 7);
    EXPECT_NE(update.text.find("(3000.,2000.,0.)"), std::string::npos);
    const auto proxies = Proxies(update.text);
    ASSERT_EQ(proxies.size(), 1u);
    EXPECT_LT((proxies[0].second.min() - found.result.objects[0].box_min).norm(), 1e-4);
}

TEST(StepIndex, SkipsStringsAndCommentsAndFindsTheEndOfData) {
    const StepIndex index("tiny.ifc", kTinyIfc2x3);
    EXPECT_EQ(index.max_id(), 30);
    EXPECT_EQ(index.entities().size(), 30u);
    ASSERT_NE(index.FindGlobalId("0EvctVUKr0kugbFTf53O9L"), nullptr);
    EXPECT_EQ(index.FindGlobalId("0EvctVUKr0kugbFTf53O9L")->type, "IFCWALLSTANDARDCASE");
    EXPECT_EQ(std::string_view(kTinyIfc2x3).substr(index.data_end(), 7), "ENDSEC;");
    EXPECT_EQ(index.OfType("IFCRELAGGREGATES").size(), 3u);
    const auto args = StepIndex::SplitArgs("'a,b',(1,2),#3,'it''s'");
    ASSERT_EQ(args.size(), 4u);
    EXPECT_EQ(args[1], "(1,2)");
    EXPECT_EQ(args[3], "'it''s'");
    std::string crlf;
    for (const char c : std::string(kTinyIfc2x3))
        crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
    EXPECT_EQ(StepIndex("crlf.ifc", crlf).newline(), "\r\n");
}

// Mutants of a real file: the index either reads them or throws FileError naming the file, never
// anything else (what UpdateIfc sees has passed IFC++, but the index must not trust it).
TEST(StepIndex, SurvivesMutatedFiles) {
    const std::string sample = bim::SampleBuildingIfc(bim::SampleBuildingOptions{});
    const auto counts = bimslam::test::FuzzReader(
        "m.ifc", {{std::string(kTinyIfc2x3), 2048}, {sample.substr(0, 6000) + "ENDSEC;\n", 2048}},
        1500, 17, "';()#=*/\n\r,$.ENDSECDATA", [](const std::string& text) {
            const StepIndex index("m.ifc", text);
            for (const StepEntity& e : index.entities()) StepIndex::SplitArgs(e.args);
        });
    EXPECT_GT(counts.accepted, 0u);
    EXPECT_GT(counts.rejected, 0u);
}

TEST(StepIndex, RejectsFilesWithoutAClosedDataSection) {
    EXPECT_THROW(StepIndex("x.ifc", "ISO-10303-21;\nHEADER;\nENDSEC;\n"), common::FileError);
    EXPECT_THROW(StepIndex("x.ifc", "ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\n#1=IFCX('a');\n"),
                 common::FileError);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::change_detection
