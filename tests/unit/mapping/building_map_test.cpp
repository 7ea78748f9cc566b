// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The building's map over the visits (host_tools/mapping/building_map.hpp, issue 33 item 5), on
// visits made by hand: a floor and a wall sampled by each visit at other spots (as a sparse
// sensor's rings fall), a crate that is gone in the second visit, a transient.
#include "host_tools/mapping/building_map.hpp"

#include <gtest/gtest.h>

#include <random>
#include <set>

#include "algorithms/io/file_util.hpp"
#include "algorithms/io/las.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::mapping {
namespace {
namespace BIMSLAM_UNITY_ID {
using nlohmann::json;

// A visit's map: the floor z = 0 over [0, 4] x [0, 4] and the wall x = 4 up to 2.5 m, one point
// per 5 cm cell at a random spot in it (the seed), and what `extra` adds.
VisitFindings Sampled(const std::string& label, unsigned seed,
                      const std::vector<Eigen::Vector3f>& extra = {}, uint8_t extra_class = 0) {
    VisitFindings v;
    v.label = label;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 0.05f);
    for (int i = 0; i < 80; ++i) {
        for (int k = 0; k < 80; ++k)
            v.found.map.push_back({Eigen::Vector3f(0.05f * i + u(rng), 0.05f * k + u(rng), 0.0f)});
        for (int k = 0; k < 50; ++k)
            v.found.map.push_back({Eigen::Vector3f(4.0f, 0.05f * i + u(rng), 0.05f * k + u(rng))});
    }
    for (const Eigen::Vector3f& p : extra) {
        v.found.map.push_back({p});
        v.found.map.back().cls = extra_class;
    }
    return v;
}

// The points of a 0.6 m crate's faces at (1, 1) on the floor, every 5 cm.
std::vector<Eigen::Vector3f> Crate() {
    std::vector<Eigen::Vector3f> pts;
    for (int i = 0; i <= 12; ++i) {
        for (int k = 0; k <= 12; ++k) {
            const float a = 0.7f + 0.05f * i, b = 0.05f * k;
            pts.emplace_back(a, 0.7f, b);
            pts.emplace_back(a, 1.3f, b);
            pts.emplace_back(0.7f, a, b);
            pts.emplace_back(1.3f, a, b);
            pts.emplace_back(a, 0.7f + 0.05f * k, 0.6f);
        }
    }
    return pts;
}

json History(const std::vector<std::string>& labels, bool crate_gone_in_second) {
    json changes = json::array(), objects = json::array();
    for (size_t v = 0; v < labels.size(); ++v)
        changes.push_back({{"visit", labels[v]},
                           {"since_previous",
                            v ? json::object({{"newly_missing", json::array()}}) : json(nullptr)}});
    if (crate_gone_in_second) {
        objects.push_back({{"id", "O1"},
                           {"sightings",
                            {{{"visit", labels[0]},
                              {"status", "new"},
                              {"centroid", {1.0, 1.0, 0.3}},
                              {"size_m", {0.6, 0.6, 0.6}}},
                             {{"visit", labels[1]}, {"status", "gone"}}}}});
    }
    return {{"changes", changes}, {"objects", objects}};
}

TEST(BuildingMap, VisitsOfAnUnchangedPlaceRefreshItsVoxelsInsteadOfAddingThem) {
    BuildingMap map;
    const json h = History({"v1", "v2", "v3"}, false);
    const size_t first = map.Add(0, Sampled("v1", 1), h).at("voxels");
    const json second = map.Add(1, Sampled("v2", 2), h);
    const json third = map.Add(2, Sampled("v3", 3), h);
    EXPECT_LT(second.at("growth").get<double>(), 0.10) << second.dump();
    EXPECT_LT(third.at("growth").get<double>(), 0.10) << third.dump();
    EXPECT_GT(second.at("dropped").at("seen_again").get<size_t>(), first / 2) << second.dump();
    // A 5 cm grid alone would hold every visit's points: about twice the first after two.
    for (const auto& v : map.Voxels()) EXPECT_EQ(v.first, 0) << "seen since the first visit";
}

TEST(BuildingMap, AnObjectGoneAndTransientsLeaveNoPointsAndUnseenPlacesStay) {
    BuildingMap map;
    const json h = History({"v1", "v2"}, true);
    // A person's points on the first visit: transient, never in the map.
    const json first = map.Add(0, Sampled("v1", 1, Crate()), h);
    map.Add(0, Sampled("v1", 1, {{2.0f, 2.0f, 1.5f}}, 2), h);  // same visit: a transient
    const json second = map.Add(1, Sampled("v2", 2), h);
    EXPECT_EQ(second.at("transient_points"), 0);
    EXPECT_GT(second.at("dropped").at("superseded_objects").get<size_t>(), 100u) << second.dump();
    size_t above_floor_near_crate = 0;
    for (const auto& v : map.Voxels()) {
        const bool at_crate =
            (v.xyz - Eigen::Vector3f(1.0f, 1.0f, 0.3f)).cwiseAbs().maxCoeff() < 0.35f;
        if (at_crate && v.xyz.z() > 0.1f) ++above_floor_near_crate;
        EXPECT_FALSE((v.xyz - Eigen::Vector3f(2.0f, 2.0f, 1.5f)).norm() < 0.01f) << "a transient";
    }
    EXPECT_EQ(above_floor_near_crate, 0u);
    // A place the second visit did not see keeps its points, as of the first visit.
    BuildingMap partial;
    partial.Add(0, Sampled("v1", 1, {{2.0f, 2.0f, 2.0f}}), History({"v1", "v2"}, false));
    partial.Add(1, Sampled("v2", 2), History({"v1", "v2"}, false));
    size_t kept = 0;
    for (const auto& v : partial.Voxels())
        kept += (v.xyz - Eigen::Vector3f(2.0f, 2.0f, 2.0f)).norm() < 0.01f && v.last == 0;
    EXPECT_EQ(kept, 1u);
}

// A visit added to a project folds that visit alone into the map on disk, and the files equal a
// fold of every visit at once; a visit whose findings were made again (another digest) makes the
// map again from the first visit.
TEST(BuildingMap, AVisitAddedFoldsItAloneAndEqualsAFoldOfThemAll) {
    const json h = History({"v1", "v2", "v3"}, true);
    const std::vector<VisitFindings> visits = {Sampled("v1", 1, Crate()), Sampled("v2", 2),
                                               Sampled("v3", 3)};
    const std::vector<std::string> made = {"a", "b", "c"};
    test::TempDir all, added;
    const json once = WriteBuildingMap(all.path(), visits, h, made);
    // Two visits, then the third: the history of the first two is the same (it looks back only).
    WriteBuildingMap(added.path(), {visits[0], visits[1]}, h, {made[0], made[1]});
    const json step = WriteBuildingMap(added.path(), visits, h, made);
    EXPECT_EQ(step, once);
    EXPECT_EQ(io::ReadFileToString(added / "building_map.ply"),
              io::ReadFileToString(all / "building_map.ply"));
    // The kept folds were read back, not made again: a map on disk that differs from the fold
    // (here: emptied of its points) shows through when the digests hold...
    BuildingMap empty;
    empty.Write(added / "building_map.ply");
    const json reused = WriteBuildingMap(added.path(), visits, h, made);
    EXPECT_EQ(reused.at("voxels"), 0u) << "every visit's digest held: nothing folded again";
    // ...and not when a visit's findings were made again: every visit is folded anew.
    const json redone = WriteBuildingMap(added.path(), visits, h, {"a", "b2", "c"});
    EXPECT_EQ(redone.at("voxels"), once.at("voxels"));
    EXPECT_NE(redone.at("visits").at(1).at("fold_sha256"),
              once.at("visits").at(1).at("fold_sha256"));
}

// building_map.las: every voxel, its visits 1-based (point source = the last, extra bytes
// first_visit), the time of the last visit's start, the class as map_bim.las's.
TEST(BuildingMap, LasHoldsEveryVoxelWithItsVisits) {
    BuildingMap map;
    const json h = History({"v1", "v2"}, false);
    map.Add(0, Sampled("v1", 1, {{2.0f, 2.0f, 2.0f}}, 1), h);  // a new object's point
    map.Add(1, Sampled("v2", 2), h);
    test::TempDir dir;
    const std::vector<int64_t> starts = {1796083200'000'000'000, 1798761600'000'000'000};
    map.WriteLas(dir / "m.las", starts);
    const io::LasData las = io::ReadLas(dir / "m.las");
    const std::vector<BuildingMap::Voxel> voxels = map.Voxels();
    ASSERT_EQ(las.size(), voxels.size());
    const io::LasExtraField* first = las.Find("first_visit");
    ASSERT_NE(first, nullptr);
    std::set<int> sources;
    for (size_t i = 0; i < las.size(); ++i) {
        ASSERT_LT((las.xyz[i] - voxels[i].xyz.cast<double>()).norm(), 1e-4);
        EXPECT_EQ(las.point_source_id[i], voxels[i].last + 1);
        EXPECT_EQ(first->values[i], voxels[i].first + 1);
        EXPECT_EQ(las.gps_time[i], io::UnixNsToAdjustedGpsSeconds(starts[voxels[i].last]));
        EXPECT_EQ(las.user_data[i], voxels[i].cls);
        // A new object's point is 64; these hand-made points have no class (255): 1 unclassified.
        EXPECT_EQ(las.classification[i], voxels[i].cls == 1 ? 64 : voxels[i].cls == 0 ? 6 : 1);
        sources.insert(las.point_source_id[i]);
    }
    EXPECT_EQ(sources, (std::set<int>{1, 2}));
    EXPECT_TRUE(las.adjusted_standard_gps_time);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::mapping
