// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The sample buildings as another IFC engine reads them: web-ifc (That Open Company, independent of
// IFC++) opens the metre and the millimetre file of each layout through
// tests/tools/web_ifc/check.mjs, finds the classes the layout says, builds geometry without errors,
// and puts it in the same box in metres.
// Skips, saying why, when node or the tool's node_modules is missing (toolchain/install-deps.sh
// --test installs both).
#include "host_tools/bim/sample_building.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/integration/web_ifc_support.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::bim {
namespace {
namespace BIMSLAM_UNITY_ID {
namespace fs = std::filesystem;

void ExpectLayoutCounts(const nlohmann::json& j, const SampleLayout& L) {
    const auto& c = j.at("counts");
    EXPECT_EQ(c.at("IFCBUILDINGSTOREY").get<size_t>(), L.storeys.size());
    EXPECT_EQ(c.at("IFCSPACE").get<size_t>(), L.rooms.size());
    EXPECT_EQ(c.at("IFCWALL").get<size_t>() + c.at("IFCWALLSTANDARDCASE").get<size_t>(),
              L.walls.size());
    EXPECT_EQ(c.at("IFCDOOR").get<size_t>(), L.doors.size());
    EXPECT_EQ(c.at("IFCWINDOW").get<size_t>(), L.windows.size());
    EXPECT_EQ(c.at("IFCCOLUMN").get<size_t>(), L.columns.size());
    EXPECT_EQ(c.at("IFCSLAB").get<size_t>(), L.slabs.size());
    EXPECT_EQ(c.at("IFCSTAIR").get<size_t>(), L.stairs.size());
    EXPECT_EQ(c.at("IFCSTAIRFLIGHT").get<size_t>(), L.stairs.size());
    EXPECT_EQ(c.at("IFCRAILING").get<size_t>(), L.railings.size());
    EXPECT_EQ(c.at("IFCFURNITURE").get<size_t>(), L.furniture.size());
    EXPECT_GE(c.at("IFCFURNITURE").get<size_t>(), 1u);
    // A mesh for every element with a body (web-ifc leaves spaces and openings out).
    const auto& meshes = j.at("mesh_classes");
    EXPECT_EQ(meshes.value("IfcWall", 0u), L.walls.size());
    EXPECT_EQ(meshes.value("IfcDoor", 0u), L.doors.size());
    EXPECT_EQ(meshes.value("IfcWindow", 0u), L.windows.size());
    EXPECT_EQ(meshes.value("IfcColumn", 0u), L.columns.size());
    EXPECT_EQ(meshes.value("IfcSlab", 0u), L.slabs.size());
    EXPECT_EQ(meshes.value("IfcStairFlight", 0u), L.stairs.size());
    EXPECT_EQ(meshes.value("IfcFurniture", 0u), L.furniture.size());
}

TEST(SampleBuildingWebIfc, OpensTheMetreAndMillimetreFilesAsTheSameBuilding) {
    test::TempDir tmp;
    SampleBuildingOptions m, mm;
    mm.length_unit_m = 0.001;
    WriteSampleBuilding(tmp / "sample_m.ifc", m);
    WriteSampleBuilding(tmp / "sample_mm.ifc", mm);
    const SampleLayout L = SampleBuildingLayout(m);
    const Eigen::AlignedBox3d box = L.Bounds();

    if (const std::string why = web_ifc::Missing(); !why.empty()) GTEST_SKIP() << why;
    const nlohmann::json jm = web_ifc::Read(tmp / "sample_m.ifc");
    const nlohmann::json jmm = web_ifc::Read(tmp / "sample_mm.ifc");
    ASSERT_FALSE(jm.is_null() || jmm.is_null());
    for (const nlohmann::json* j : {&jm, &jmm}) {
        SCOPED_TRACE(j->at("file").get<std::string>());
        EXPECT_EQ(j->at("schema"), "IFC4");
        EXPECT_EQ(j->at("error_count").get<int>(), 0) << j->at("errors").dump();
        ExpectLayoutCounts(*j, L);
        EXPECT_GT(j->at("triangles").get<int>(), 1000);
        EXPECT_GT(j->at("vertices").get<int>(), 1000);
        // web-ifc applies the length unit: both files come out in metres, 30 x 15 x 6.6 m
        // (the ground slab's underside at -0.2 to the roof at 6.4), in the model's axes.
        const auto& b = j->at("bbox_ifc_m");
        for (int k = 0; k < 3; ++k) {
            EXPECT_NEAR(b.at("min")[k].get<double>(), box.min()[k], 1e-4) << "axis " << k;
            EXPECT_NEAR(b.at("max")[k].get<double>(), box.max()[k], 1e-4) << "axis " << k;
        }
    }
    // The same meshes in both units (web-ifc triangulates deterministically).
    EXPECT_EQ(jm.at("meshes"), jmm.at("meshes"));
    EXPECT_EQ(jm.at("geometries"), jmm.at("geometries"));
    EXPECT_EQ(jm.at("vertices"), jmm.at("vertices"));
    EXPECT_EQ(jm.at("triangles"), jmm.at("triangles"));
}

TEST(SampleBuildingWebIfc, OpensTheVariants) {
    // Other seeds, no furniture, exterior doors: each still a valid model to web-ifc.
    test::TempDir tmp;
    SampleBuildingOptions o;
    o.seed = 42;
    o.furniture = false;
    o.exterior_doors = true;
    WriteSampleBuilding(tmp / "bare.ifc", o);
    if (const std::string why = web_ifc::Missing(); !why.empty()) GTEST_SKIP() << why;
    const nlohmann::json j = web_ifc::Read(tmp / "bare.ifc");
    ASSERT_FALSE(j.is_null());
    EXPECT_EQ(j.at("error_count").get<int>(), 0) << j.at("errors").dump();
    const SampleLayout L = SampleBuildingLayout(o);
    EXPECT_EQ(j.at("counts").at("IFCFURNITURE").get<size_t>(), 0u);
    EXPECT_EQ(j.at("counts").at("IFCDOOR").get<size_t>(), L.doors.size());
    EXPECT_GT(j.at("triangles").get<int>(), 1000);
}

// A layout with its entrances, in both units: the same classes, box and meshes.
void ExpectOpensInMetresAndMillimetres(BuildingLayout layout) {
    test::TempDir tmp;
    if (const std::string why = web_ifc::Missing(); !why.empty()) GTEST_SKIP() << why;
    SampleBuildingOptions o;
    o.layout = layout;
    o.exterior_doors = true;
    const SampleLayout L = SampleBuildingLayout(o);
    const Eigen::AlignedBox3d box = L.Bounds();
    nlohmann::json meshes;
    for (const double unit : {1.0, 0.001}) {
        o.length_unit_m = unit;
        const fs::path file =
            tmp / (std::string(ToString(layout)) + (unit == 1.0 ? "_m.ifc" : "_mm.ifc"));
        WriteSampleBuilding(file, o);
        SCOPED_TRACE(file.string());
        const nlohmann::json j = web_ifc::Read(file);
        ASSERT_FALSE(j.is_null());
        EXPECT_EQ(j.at("schema"), "IFC4");
        EXPECT_EQ(j.at("error_count").get<int>(), 0) << j.at("errors").dump();
        ExpectLayoutCounts(j, L);
        const auto& b = j.at("bbox_ifc_m");
        for (int k = 0; k < 3; ++k) {
            EXPECT_NEAR(b.at("min")[k].get<double>(), box.min()[k], 1e-4) << "axis " << k;
            EXPECT_NEAR(b.at("max")[k].get<double>(), box.max()[k], 1e-4) << "axis " << k;
        }
        if (unit == 1.0) {
            meshes = j.at("meshes");
        } else {
            EXPECT_EQ(j.at("meshes"), meshes);
        }
    }
}

TEST(SampleBuildingWebIfc, OpensTheHall) {
    ExpectOpensInMetresAndMillimetres(BuildingLayout::kHall);
}

TEST(SampleBuildingWebIfc, OpensTheSymmetricBuilding) {
    ExpectOpensInMetresAndMillimetres(BuildingLayout::kSymmetric);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::bim
