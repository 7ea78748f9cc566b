// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// IFC ingest on the real models of ../shared/data/ifc (see its README.md): storeys, class counts
// (checked against the STEP text itself), plausible wall thicknesses and storey heights, extents
// in metres, openings that leave holes, and few failures.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <map>
#include <string>
#include <vector>

#include "algorithms/io/file_util.hpp"
#include "host_tools/bim/ifc_model.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::bim {
namespace {
namespace BIMSLAM_UNITY_ID {

struct Expected {
    std::string file;
    std::string schema;
    std::vector<std::pair<std::string, double>> storeys;  // name, elevation (m), lowest first
    // Instances per IFC class as the README lists them (and the STEP text holds).
    std::map<std::string, size_t> counts;
    size_t walls = 0;  // IfcWall + IfcWallStandardCase
    // Where the median wall thickness lies (m): FZK's walls are 0.24 .. 0.32 m; Duplex's mostly
    // 0.13 .. 0.17 m partitions and 0.42 m brick; Office_A's mostly 0.06 m furring (278 of 487)
    // and 0.14 m partitions, 0.30 m outside.
    double median_wall_min_m = 0, median_wall_max_m = 0;
    std::string walk_storey;  // where `bimslam simulate` walks when no storey is named
};

const std::vector<Expected>& Models() {
    static const std::vector<Expected> models = {
        {"AC20-FZK-Haus.ifc",
         "IFC4",
         {{"Erdgeschoss", 0.0}, {"Dachgeschoss", 2.7}},
         {{"IfcDoor", 5}, {"IfcWindow", 11}, {"IfcSpace", 7}, {"IfcSlab", 4}},
         13,
         0.2,
         0.4,
         "Erdgeschoss"},
        {"Duplex_A_20110907.ifc",
         "IFC2X3",
         {{"T/FDN", -1.25}, {"Level 1", 0.0}, {"Level 2", 3.1}, {"Roof", 6.0}},
         {{"IfcDoor", 14}, {"IfcWindow", 24}, {"IfcSpace", 21}, {"IfcSlab", 21}},
         57,
         0.1,
         0.3,
         "Level 1"},  // not 'T/FDN', the foundation 1.25 m under it
        {"Office_A_20110811.ifc",
         "IFC2X3",
         {{"Level 1", 0.0}, {"Level 2", 4.267}, {"Roof", 7.925}},
         {{"IfcDoor", 102},
          {"IfcWindow", 69},
          {"IfcSpace", 99},
          {"IfcSlab", 2},
          {"IfcCovering", 83}},
         487,
         0.04,
         0.1,
         "Level 1"},
    };
    return models;
}

// Instances of an entity in STEP text: "=IFCDOOR(" or "= IFCDOOR(" (what `grep -c` would count).
size_t CountInText(const std::string& text, std::string entity) {
    std::transform(entity.begin(), entity.end(), entity.begin(),
                   [](unsigned char c) { return char(std::toupper(c)); });
    const std::string needle = entity + "(";
    size_t n = 0;
    for (size_t at = text.find(needle); at != std::string::npos; at = text.find(needle, at + 1)) {
        size_t k = at;
        while (k > 0 && text[k - 1] == ' ') --k;
        if (k > 0 && text[k - 1] == '=') ++n;
    }
    return n;
}

Eigen::Vector3d Corner(const BimModel& m, uint32_t t, int k) {
    return m.mesh.vertices[m.mesh.triangles[t][k]].cast<double>() + m.origin_m;
}

// A wall's thickness: its vertices' extent across the wall, the minor horizontal axis of their
// spread. Right for straight walls; an L-shaped wall comes out thicker.
double Thickness(const BimModel& m, const BimElement& e) {
    std::vector<Eigen::Vector2d> points;
    for (uint32_t t = e.first_triangle; t < e.first_triangle + e.triangle_count; ++t) {
        for (int k = 0; k < 3; ++k) points.push_back(Corner(m, t, k).head<2>());
    }
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const auto& p : points) mean += p;
    mean /= double(points.size());
    Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
    for (const auto& p : points) cov += (p - mean) * (p - mean).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov);
    const Eigen::Vector2d across = eig.eigenvectors().col(0);  // smallest eigenvalue first
    double lo = 1e9, hi = -1e9;
    for (const auto& p : points) {
        lo = std::min(lo, p.dot(across));
        hi = std::max(hi, p.dot(across));
    }
    return hi - lo;
}

bool IsWall(const std::string& cls) { return cls == "IfcWall" || cls == "IfcWallStandardCase"; }

// Windows and doors whose centre, looked at across their thin side, has no structure within
// 0.4 m: the opening they fill was cut out of the wall.
double OpenFraction(const BimModel& m) {
    size_t openings = 0, open = 0;
    for (const auto& w : m.elements) {
        if (w.ifc_class != "IfcWindow" && w.ifc_class != "IfcDoor") continue;
        Eigen::AlignedBox3d box;
        for (uint32_t t = w.first_triangle; t < w.first_triangle + w.triangle_count; ++t) {
            for (int k = 0; k < 3; ++k) box.extend(Corner(m, t, k));
        }
        Eigen::Vector3d c = box.center();
        if (w.ifc_class == "IfcDoor") c.z() = box.min().z() + 1.0;  // leaves may be open
        const Eigen::Vector3d dir =
            Eigen::Vector3d::Unit(box.sizes().x() < box.sizes().y() ? 0 : 1);
        bool blocked = false;
        for (uint32_t t = 0; t < m.mesh.triangles.size() && !blocked; ++t) {
            if (m.elements[m.triangle_element[t]].role != ElementRole::kStructure) continue;
            const Eigen::Vector3d a = Corner(m, t, 0), e1 = Corner(m, t, 1) - a,
                                  e2 = Corner(m, t, 2) - a, h = dir.cross(e2);
            const double det = e1.dot(h);
            if (std::abs(det) < 1e-12) continue;
            const Eigen::Vector3d s = c - a, q = s.cross(e1);
            const double u = s.dot(h) / det, v = dir.dot(q) / det, d = e2.dot(q) / det;
            blocked = u >= 0 && v >= 0 && u + v <= 1 && std::abs(d) < 0.4;
        }
        ++openings;
        open += !blocked;
    }
    return openings == 0 ? 1.0 : double(open) / double(openings);
}

class IfcModelData : public testing::TestWithParam<size_t> {};

TEST_P(IfcModelData, StoreysCountsGeometryAndOpenings) {
    const Expected& x = Models()[GetParam()];
    BIMSLAM_REQUIRE_SHARED_DATA(path, "ifc/" + x.file);
    const BimModel m = LoadIfc(path);
    const std::string text = io::ReadFileToString(path);
    EXPECT_EQ(m.schema, x.schema);
    EXPECT_DOUBLE_EQ(m.length_unit_m, 1.0);  // all three are in metres

    ASSERT_EQ(m.storeys.size(), x.storeys.size());
    for (size_t i = 0; i < x.storeys.size(); ++i) {
        EXPECT_EQ(m.storeys[i].name, x.storeys[i].first);
        EXPECT_NEAR(m.storeys[i].elevation_m, x.storeys[i].second, 1e-3) << m.storeys[i].name;
        EXPECT_FALSE(m.storeys[i].global_id.empty());
    }
    EXPECT_EQ(m.storeys[size_t(DefaultWalkStorey(m))].name, x.walk_storey);
    // Storey heights above ground (the foundation level below it is shallower).
    for (size_t i = 1; i < m.storeys.size(); ++i) {
        if (m.storeys[i - 1].elevation_m < 0) continue;
        const double height = m.storeys[i].elevation_m - m.storeys[i - 1].elevation_m;
        EXPECT_GE(height, 2.2) << m.storeys[i].name;
        EXPECT_LE(height, 6.0) << m.storeys[i].name;
    }

    auto count = [&](const std::string& cls) {
        const auto it = m.class_counts.find(cls);
        return it == m.class_counts.end() ? size_t{0} : it->second;
    };
    for (const auto& [cls, n] : x.counts) {
        EXPECT_EQ(count(cls), n) << cls;
        EXPECT_EQ(count(cls), CountInText(text, cls)) << cls;
    }
    EXPECT_EQ(count("IfcWall") + count("IfcWallStandardCase"), x.walls);
    EXPECT_EQ(count("IfcWallStandardCase"), CountInText(text, "IfcWallStandardCase"));
    EXPECT_EQ(count("IfcOpeningElement"), CountInText(text, "IfcOpeningElement"));

    // Geometry: finite, in metres, every wall with its own triangles.
    ASSERT_TRUE(m.mesh.IndicesValid());
    for (const auto& v : m.mesh.vertices) ASSERT_TRUE(v.allFinite());
    const Eigen::AlignedBox3d box = m.Bounds();
    for (int k = 0; k < 3; ++k) {
        EXPECT_GE(box.sizes()[k], 5.0) << "axis " << k;
        EXPECT_LE(box.sizes()[k], 200.0) << "axis " << k << ": not metres?";
    }
    std::vector<double> thickness;
    size_t with_storey = 0;
    for (const auto& e : m.elements) {
        ASSERT_LT(e.storey, int(m.storeys.size()));
        with_storey += e.storey >= 0;
        if (IsWall(e.ifc_class)) {
            EXPECT_EQ(e.role, ElementRole::kStructure);
            thickness.push_back(Thickness(m, e));
        }
        if (e.ifc_class == "IfcDoor" || e.ifc_class == "IfcWindow") {
            EXPECT_EQ(e.role, ElementRole::kTransient);
        }
    }
    EXPECT_EQ(thickness.size(), x.walls) << "walls with geometry";
    std::sort(thickness.begin(), thickness.end());
    const double median = thickness[thickness.size() / 2];
    EXPECT_GE(median, x.median_wall_min_m);
    EXPECT_LE(median, x.median_wall_max_m);
    const auto plausible = std::count_if(thickness.begin(), thickness.end(),
                                         [](double t) { return t >= 0.02 && t <= 0.6; });
    EXPECT_GE(double(plausible), 0.9 * double(thickness.size()));
    EXPECT_LE(thickness.back(), 1.0);  // not millimetres, not a wall swallowing another
    // Everything but the site hangs below a storey.
    EXPECT_GE(with_storey + 1, m.elements.size());

    // Openings are holes: carve's CSG varies from run to run, so a small margin.
    const double open = OpenFraction(m);
    EXPECT_GE(open, 0.95);
    // Few failures, reported rather than fatal.
    EXPECT_LE(m.failed.size(), m.elements.size() / 50);
    std::cout << x.file << ": " << m.elements.size() << " elements with geometry, "
              << m.mesh.triangles.size() << " triangles, " << m.failed.size() << " failed, "
              << m.warning_count << " warnings, median wall " << median << " m, " << 100.0 * open
              << "% of windows and doors open\n";
}

INSTANTIATE_TEST_SUITE_P(SharedModels, IfcModelData, testing::Range<size_t>(0, 3),
                         [](const testing::TestParamInfo<size_t>& param) {
                             std::string name = Models()[param.param].file;
                             name = name.substr(0, name.find('_') == std::string::npos
                                                       ? name.find('.')
                                                       : name.find('_'));
                             std::replace(name.begin(), name.end(), '-', '_');
                             return name;
                         });

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::bim
