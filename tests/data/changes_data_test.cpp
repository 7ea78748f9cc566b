// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The updated IFC of `bimslam changes` on the real models of ../shared/data/ifc (Revit IFC2X3,
// ArchiCAD IFC4 with CRLF line ends): a new object and a verdict appended to each, read back by
// IFC++ with the proxy where it was put (so an absolute placement means the same in these files'
// placement chains as in the project's), in its storey, nothing of the original lost; and by
// web-ifc where it is installed.
#include <gtest/gtest.h>

#include <cstdlib>
#include <nlohmann/json.hpp>

#include "algorithms/io/file_util.hpp"
#include "host_tools/bim/ifc_model.hpp"
#include "host_tools/changes/ifc_update.hpp"
#include "tests/support/test_support.hpp"
#include "tests/unit/change_detection/ifc_update_fixtures.hpp"

namespace bimslam::change_detection {
namespace {
namespace BIMSLAM_UNITY_ID {
namespace fs = std::filesystem;

class ChangesOnRealModels : public ::testing::TestWithParam<const char*> {};

TEST_P(ChangesOnRealModels, TheUpdatedIfcHoldsTheProxyWhereItWasFound) {
    BIMSLAM_REQUIRE_SHARED_DATA(file, std::string("ifc/") + GetParam());
    const bim::BimModel model = bim::LoadIfc(file);
    ASSERT_FALSE(model.storeys.empty());
    size_t wall = 0;
    while (wall < model.elements.size() && !model.elements[wall].ifc_class.starts_with("IfcWall")) {
        ++wall;
    }
    ASSERT_LT(wall, model.elements.size());
    // A block standing on the lowest storey's floor, in the middle of the building.
    const Eigen::Vector3d centre = model.Bounds().center() - model.origin_m;
    const Eigen::Vector3f lo(float(centre.x()), float(centre.y()),
                             float(model.storeys[0].elevation_m - model.origin_m.z()));
    const SessionChanges found = test::Found(model, lo, wall, changes::Verdict::kMissing);
    const std::string text = io::ReadFileToString(file);
    const IfcUpdate update = UpdateIfc(file.string(), text, model, found, 7);
    EXPECT_EQ(update.proxies, 1u);
    EXPECT_EQ(update.element_property_sets, 1u);
    EXPECT_TRUE(update.notes.empty()) << update.notes.front();

    const bim::BimModel updated = bim::ParseIfc("updated.ifc", update.text);
    EXPECT_EQ(updated.elements.size(), model.elements.size() + 1);
    EXPECT_EQ(updated.failed.size(), model.failed.size());
    size_t proxies = 0;
    for (const bim::BimElement& e : updated.elements) {
        if (e.global_id != found.object_global_ids[0]) continue;
        ++proxies;
        EXPECT_EQ(e.ifc_class, "IfcBuildingElementProxy");
        EXPECT_EQ(e.storey, 0);
        Eigen::AlignedBox3d box;
        for (uint32_t t = e.first_triangle; t < e.first_triangle + e.triangle_count; ++t) {
            for (const uint32_t v : updated.mesh.triangles[t]) {
                box.extend(updated.mesh.vertices[v].cast<double>() + updated.origin_m);
            }
        }
        const changes::NewObject& obj = found.result.objects[0];
        EXPECT_LT((box.min() - (obj.box_min + model.origin_m)).norm(), 1e-3)
            << box.min().transpose();
        EXPECT_LT((box.max() - (obj.box_max + model.origin_m)).norm(), 1e-3)
            << box.max().transpose();
    }
    EXPECT_EQ(proxies, 1u);

    const char* env = std::getenv("BIMSLAM_SOURCE_DIR");
    const fs::path tool = fs::path(env && *env ? env : BIMSLAM_SOURCE_ROOT) / "tests/tools/web_ifc";
    if (bimslam::test::RunCommand("node --version").exit_code != 0 ||
        !fs::exists(tool / "node_modules" / "web-ifc")) {
        GTEST_SKIP() << "web-ifc half skipped: node or tests/tools/web_ifc/node_modules missing "
                        "(toolchain/install-deps.sh --test)";
    }
    bimslam::test::TempDir tmp;
    io::WriteFileAtomic(tmp / "updated.ifc", update.text);
    const auto r = bimslam::test::RunCommand("node '" + (tool / "check.mjs").string() + "' '" +
                                             (tmp / "updated.ifc").string() + "'");
    // web-ifc may report problems of the original file; the proxy must be there either way.
    const nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["counts"]["IFCBUILDINGELEMENTPROXY"].get<size_t>(),
              model.class_counts.count("IfcBuildingElementProxy")
                  ? model.class_counts.at("IfcBuildingElementProxy") + 1
                  : 1u);
    EXPECT_GE(j["mesh_classes"]["IfcBuildingElementProxy"].get<size_t>(), 1u);
}

INSTANTIATE_TEST_SUITE_P(Models, ChangesOnRealModels,
                         ::testing::Values("AC20-FZK-Haus.ifc", "Duplex_A_20110907.ifc",
                                           "Office_A_20110811.ifc"),
                         [](const auto& param_info) {
                             return ::bimslam::test::Identifier(param_info.param);
                         });

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::change_detection
