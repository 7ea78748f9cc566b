// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Issue 38 on real models: every element's surface area against what main gave before the face
// bounds were reordered (tests/data/ifc_element_areas.json, which says how it was measured). The
// elements main got wrong (faces whose hole is listed first, dropped by IFC++) must now have their
// faceted breps' exact area; every other element must keep its area.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "algorithms/io/file_util.hpp"
#include "host_tools/bim/ifc_model.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::bim {
namespace {
namespace BIMSLAM_UNITY_ID {

// The targets: a repaired element within 0.1 % of its exact area, any other element
// within 0.01 % of main's (measured: 1e-15 from run to run, carve's order notwithstanding).
constexpr double kRepairedTolerance = 1e-3;
constexpr double kUnchangedTolerance = 1e-4;

const nlohmann::json& Reference() {
    static const nlohmann::json reference = nlohmann::json::parse(io::ReadFileToString(
        std::filesystem::path(BIMSLAM_SOURCE_ROOT) / "tests/data/ifc_element_areas.json"));
    return reference;
}

// The three models of ../shared/data/ifc and xBIM's IFC4 sample house, whose windows and chairs
// have faces with their hole listed first (not in ../shared/data today: that case skips, saying
// so, until it is added under this name).
const std::vector<std::string>& Files() {
    static const std::vector<std::string> files = {"AC20-FZK-Haus.ifc", "Duplex_A_20110907.ifc",
                                                   "Office_A_20110811.ifc", "SampleHouse4.ifc"};
    return files;
}

// Each element's area (m2): the sum of its triangles' areas, in double from the float vertices.
std::map<std::string, double> ElementAreas(const BimModel& m) {
    std::map<std::string, double> out;
    for (const BimElement& e : m.elements) {
        double area = 0;
        for (uint32_t t = e.first_triangle; t < e.first_triangle + e.triangle_count; ++t) {
            const auto& tri = m.mesh.triangles[t];
            const Eigen::Vector3d a = m.mesh.vertices[tri[0]].cast<double>();
            const Eigen::Vector3d b = m.mesh.vertices[tri[1]].cast<double>();
            const Eigen::Vector3d c = m.mesh.vertices[tri[2]].cast<double>();
            area += 0.5 * (b - a).cross(c - a).norm();
        }
        out[e.global_id] += area;
    }
    return out;
}

class IfcAreaData : public testing::TestWithParam<size_t> {};

TEST_P(IfcAreaData, RepairedElementsGetTheirExactAreaAndNoOtherChanges) {
    const std::string& file = Files()[GetParam()];
    if (const auto root = test::SharedDataDir();
        root && !std::filesystem::exists(*root / "ifc" / file)) {
        GTEST_SKIP() << "../shared/data/ifc/" << file << " is absent ("
                     << Reference().at("models").at(file).value("source", "")
                     << "): its elements are not checked";
    }
    BIMSLAM_REQUIRE_SHARED_DATA(path, "ifc/" + file);
    const nlohmann::json& ref = Reference().at("models").at(file);
    // The file's own elements: the floors the ingest assumes (Office_A's) are not in it.
    IfcLoadOptions as_written;
    as_written.assume_floors = false;
    const BimModel m = LoadIfc(path, as_written);
    EXPECT_EQ(m.faces_reordered, ref.at("faces_reordered").get<size_t>());
    EXPECT_EQ(m.faces_lost, 0u);
    EXPECT_TRUE(m.incomplete.empty());

    const std::map<std::string, double> areas = ElementAreas(m);
    const nlohmann::json& main_m2 = ref.at("main_m2");
    const nlohmann::json exact_m2 = ref.value("exact_m2", nlohmann::json::object());
    EXPECT_EQ(areas.size(), main_m2.size()) << "elements with geometry";
    double unchanged_worst = 0, repaired_worst = 0, main_worst = 0;
    for (const auto& [id, main_value] : main_m2.items()) {
        const auto it = areas.find(id);
        if (it == areas.end()) {
            ADD_FAILURE() << file << ": " << id << " has no geometry any more";
            continue;
        }
        const double before = main_value.get<double>(), now = it->second;
        if (exact_m2.contains(id)) {
            const double exact = exact_m2.at(id).get<double>();
            EXPECT_NEAR(now, exact, kRepairedTolerance * exact) << file << " " << id;
            repaired_worst = std::max(repaired_worst, std::abs(now - exact) / exact);
            main_worst = std::max(main_worst, std::abs(before - exact) / exact);
        } else {
            EXPECT_NEAR(now, before, kUnchangedTolerance * before) << file << " " << id;
            unchanged_worst = std::max(unchanged_worst, std::abs(now - before) / before);
        }
    }
    std::cout << file << ": " << areas.size() << " elements, " << m.faces_reordered
              << " faces reordered; largest change of the others from main "
              << 100 * unchanged_worst << " %";
    if (!exact_m2.empty()) {
        std::cout << "; " << exact_m2.size() << " repaired, within " << 100 * repaired_worst
                  << " % of their exact area (main: " << 100 * main_worst << " % off)";
    }
    std::cout << "\n";
}

INSTANTIATE_TEST_SUITE_P(SharedModels, IfcAreaData, testing::Range<size_t>(0, Files().size()),
                         [](const testing::TestParamInfo<size_t>& param) {
                             std::string name = Files()[param.param];
                             name = name.substr(0, std::min(name.find('_'), name.find('.')));
                             std::replace(name.begin(), name.end(), '-', '_');
                             return name;
                         });

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::bim
