// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// `bimslam rig-map` (issue 35, item 1): the package of the sample office from the reference
// `bimslam map` made, read back with every keyframe, descriptor and storey of that reference; made
// from the model alone; refused for a reference of another model or over an existing file.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>
#include <vector>

#include "algorithms/io/sha256.hpp"
#include "algorithms/localization/rig_map.hpp"
#include "tests/integration/map_test_support.hpp"

namespace bimslam {
namespace {
namespace BIMSLAM_UNITY_ID {
namespace fs = std::filesystem;
using namespace map_test;

TEST(RigMapCli, ThePackageOfAMapsReferenceHoldsItsKeyframesDescriptorsAndStoreys) {
    const fs::path model = Building() / "building.ifc";
    const fs::path reference = Mapped() / "out" / "reference";
    test::TempDir tmp;
    const fs::path package = tmp / "office.rigmap";
    const auto r = Cli("rig-map " + model.string() + " --reference " + reference.string() + " -o " +
                       package.string() + " --json");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("rig map  " + package.string()), std::string::npos) << r.out;

    const localization::RigMap map = localization::ReadRigMap(package);
    const io::Session ref = io::ReadSession(reference, {.load_clouds = false});
    EXPECT_EQ(map.model_file, "building.ifc");
    EXPECT_EQ(map.model_sha256, io::Sha256File(model));
    EXPECT_EQ(map.reference, reference.string());
    ASSERT_EQ(map.keyframes.size(), ref.keyframes.size());
    ASSERT_EQ(map.storeys.size(), 2u);  // the office's ground and first floor
    EXPECT_LT(map.storeys[0].elevation_m, map.storeys[1].elevation_m);
    size_t on[2] = {0, 0};
    for (size_t k = 0; k < map.keyframes.size(); ++k) {
        EXPECT_TRUE(map.keyframes[k].isApprox(ref.keyframes[k].T_world_lidar, 1e-12)) << k;
        // The reference's own descriptors: the anchoring's kind and shape.
        EXPECT_TRUE(map.descriptors[k] == ref.keyframes[k].descriptor) << k;
        ASSERT_GE(map.keyframe_storey[k], 0) << k;
        ++on[map.keyframe_storey[k]];
    }
    EXPECT_GT(on[0], 20u);
    EXPECT_GT(on[1], 20u);
    ASSERT_EQ(map.levels.size(), 3u);
    for (const auto& level : map.levels) EXPECT_GT(level.size(), 1000u);
    // The office's spaces, named; the reference walks through them: most keyframes (the sensor
    // 0.5 m over the floor) stand in one, and the corridor is among them.
    EXPECT_GE(map.spaces.size(), 10u);
    size_t in_space = 0;
    std::set<std::string> names;
    for (const Eigen::Isometry3d& T : map.keyframes) {
        const int s = localization::SpaceAt(map, T.translation());
        in_space += s >= 0;
        if (s >= 0) names.insert(map.spaces[size_t(s)].name);
    }
    EXPECT_GT(in_space, map.keyframes.size() * 8 / 10);
    EXPECT_TRUE(names.count("Corridor")) << names.size();

    // The free-space level carries the surfels the reference's own rays pass through (porous:
    // the stair's railings, algorithms/registration/README.md), a few; --json counts them.
    std::vector<size_t> porous;
    for (const auto& level : map.levels) {
        porous.push_back(size_t(std::count_if(level.surfels().begin(), level.surfels().end(),
                                              [](const auto& s) { return s.porous; })));
    }
    EXPECT_EQ(porous[0], 0u);
    EXPECT_GT(porous[1], 0u);
    EXPECT_LT(porous[1], map.levels[1].size() / 50);
    EXPECT_EQ(porous[2], 0u);
    const size_t brace = r.out.find('{');
    ASSERT_NE(brace, std::string::npos) << r.out;
    EXPECT_EQ(nlohmann::json::parse(r.out.substr(brace)).at("porous_surfels"), porous) << r.out;

    // Over an existing package: refused, the package untouched.
    const auto again = Cli("rig-map " + model.string() + " --reference " + reference.string() +
                           " -o " + package.string());
    EXPECT_EQ(again.exit_code, 2);
    EXPECT_NE(again.err.find("exists (--overwrite replaces it)"), std::string::npos) << again.err;
}

TEST(RigMapCli, AReferenceOfAnotherModelIsRefusedAndTheModelAloneMakesItsOwn) {
    test::TempDir tmp;
    const fs::path hall = tmp / "hall.ifc";
    MustRun("bim sample --layout hall -o " + hall.string());
    const fs::path office_reference = Mapped() / "out" / "reference";
    const auto r = Cli("rig-map " + hall.string() + " --reference " + office_reference.string() +
                       " -o " + (tmp / "hall.rigmap").string());
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find((office_reference / "session.json").string()), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("made from another model"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(tmp / "hall.rigmap"));

    // The model alone: its reference simulated, used and removed.
    const fs::path office = Building() / "building.ifc";
    const auto made = Cli("rig-map " + office.string() + " -o " + (tmp / "office.rigmap").string());
    ASSERT_EQ(made.exit_code, 0) << made.err;
    const localization::RigMap map = localization::ReadRigMap(tmp / "office.rigmap");
    EXPECT_GT(map.keyframes.size(), 100u);
    EXPECT_EQ(map.reference, "made from the model by bimslam rig-map");
    EXPECT_EQ(map.model_sha256, io::Sha256File(office));
    size_t files = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(tmp.path())) ++files;
    EXPECT_EQ(files, 2u);  // hall.ifc, office.rigmap and nothing left of the reference
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam
