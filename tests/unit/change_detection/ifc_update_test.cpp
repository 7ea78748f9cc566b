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

namespace bimslam::change_detection {
namespace {

// A hand-written IFC2X3 file: project, site, building, one storey, one wall (4 x 0.2 x 3 m).
const char* const kTinyIfc2x3 = R"(ISO-10303-21;
HEADER;
FILE_DESCRIPTION(('ViewDefinition [CoordinationView]'),'2;1');
FILE_NAME('tiny.ifc','2024-01-01T00:00:00',('bimslam'),('bimslam'),'','bimslam test','');
FILE_SCHEMA(('IFC2X3'));
ENDSEC;
DATA;
#1=IFCPERSON($,$,'tester',$,$,$,$,$);
#2=IFCORGANIZATION($,'bimslam',$,$,$);
#3=IFCPERSONANDORGANIZATION(#1,#2,$);
#4=IFCAPPLICATION(#2,'1','bimslam test','test');
#5=IFCOWNERHISTORY(#3,#4,$,.ADDED.,$,$,$,0);
#6=IFCSIUNIT(*,.LENGTHUNIT.,$,.METRE.);
#7=IFCUNITASSIGNMENT((#6));
#8=IFCCARTESIANPOINT((0.,0.,0.));
#9=IFCAXIS2PLACEMENT3D(#8,$,$);
#10=IFCGEOMETRICREPRESENTATIONCONTEXT($,'Model',3,1.E-05,#9,$);
#11=IFCPROJECT('0YvctVUKr0kugbFTf53O9L',#5,'tiny; a name with a ; in it',$,$,$,$,(#10),#7);
#12=IFCLOCALPLACEMENT($,#9);
#13=IFCSITE('1YvctVUKr0kugbFTf53O9L',#5,'site',$,$,#12,$,$,.ELEMENT.,$,$,$,$,$);
#14=IFCLOCALPLACEMENT(#12,#9);
#15=IFCBUILDING('2YvctVUKr0kugbFTf53O9L',#5,'building',$,$,#14,$,$,.ELEMENT.,$,$,$);
#16=IFCLOCALPLACEMENT(#14,#9);
#17=IFCBUILDINGSTOREY('3YvctVUKr0kugbFTf53O9L',#5,'Ground',$,$,#16,$,$,.ELEMENT.,0.);
#18=IFCRELAGGREGATES('0AvctVUKr0kugbFTf53O9L',#5,$,$,#11,(#13));
#19=IFCRELAGGREGATES('0BvctVUKr0kugbFTf53O9L',#5,$,$,#13,(#15));
#20=IFCRELAGGREGATES('0CvctVUKr0kugbFTf53O9L',#5,$,$,#15,(#17));
#21=IFCCARTESIANPOINT((2.,0.));
#22=IFCAXIS2PLACEMENT2D(#21,$);
#23=IFCRECTANGLEPROFILEDEF(.AREA.,$,#22,4.,0.2);
#24=IFCDIRECTION((0.,0.,1.));
#25=IFCEXTRUDEDAREASOLID(#23,#9,#24,3.);
#26=IFCSHAPEREPRESENTATION(#10,'Body','SweptSolid',(#25));
#27=IFCPRODUCTDEFINITIONSHAPE($,$,(#26));
#28=IFCLOCALPLACEMENT(#16,#9);
/* a comment; with a semicolon */
#29=IFCWALLSTANDARDCASE('0EvctVUKr0kugbFTf53O9L',#5,'wall',$,$,#28,#27,$);
#30=IFCRELCONTAINEDINSPATIALSTRUCTURE('0DvctVUKr0kugbFTf53O9L',#5,$,$,(#29),#17);
ENDSEC;
END-ISO-10303-21;
)";

// A found object (a voxel block at `lo`) and a deviating or missing element.
SessionChanges Found(const bim::BimModel& model, const Eigen::Vector3f& lo, size_t element,
                     changes::Verdict verdict) {
    SessionChanges found;
    found.label = "test session";
    changes::NewObject obj;
    std::vector<Eigen::Vector3f> points;
    for (float x = 0.02f; x < 0.6f; x += 0.05f) {
        for (float y = 0.02f; y < 0.4f; y += 0.05f)
            points.push_back(lo + Eigen::Vector3f(x, y, 0.5f));
    }
    obj.solid = changes::MakeVoxelSolid(points, 0.1f, lo.z());
    obj.mesh = changes::VoxelSurface(obj.solid);
    obj.box_min = obj.solid.box_min();
    obj.box_max = obj.solid.box_max();
    obj.centroid = obj.solid.centroid();
    obj.volume_m3 = obj.solid.volume_m3();
    obj.points.assign(points.size(), 0);
    found.result.objects.push_back(obj);
    found.places.push_back({0, -1});
    found.object_global_ids.push_back(bim::IfcWriter::GlobalId(7, "object 0"));
    found.result.elements.resize(model.elements.size());
    found.result.elements[element].verdict = verdict;
    found.result.elements[element].offset = Eigen::Vector3d(0, 0.03, 0);
    return found;
}

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

TEST(StepIndex, RejectsFilesWithoutAClosedDataSection) {
    EXPECT_THROW(StepIndex("x.ifc", "ISO-10303-21;\nHEADER;\nENDSEC;\n"), common::FileError);
    EXPECT_THROW(StepIndex("x.ifc", "ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\n#1=IFCX('a');\n"),
                 common::FileError);
}

}  // namespace
}  // namespace bimslam::change_detection
