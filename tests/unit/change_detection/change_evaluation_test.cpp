// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/changes/change_evaluation.hpp"

#include <gtest/gtest.h>

#include "algorithms/io/file_util.hpp"
#include "algorithms/io/ply.hpp"
#include "tests/support/test_support.hpp"
#include "tests/unit/changes/change_scene.hpp"

namespace bimslam::change_detection {
namespace {
namespace BIMSLAM_UNITY_ID {

Eigen::AlignedBox3d Box(double x, double y, double size) {
    return {Eigen::Vector3d(x, y, 0), Eigen::Vector3d(x + size, y + size, size)};
}

TruthChanges::Added Added(const std::string& name, const Eigen::AlignedBox3d& box) {
    return {name, "box", box, changes::test::SolidBox(box.min(), box.max())};
}

// Map points on the face x = x0 of an object (just outside it), `n` of them, 1 cm from it, 0.2 m
// from the model (as if its floor were 0.2 m and more below), each seen by `keyframes` keyframes.
void AddFace(FoundChanges* found, double x0, double y0, int n, uint32_t keyframes) {
    for (int k = 0; k < n; ++k) {
        const Eigen::Vector3f p(float(x0 + 0.01), float(y0 + 0.05 * (k % 8)),
                                0.2f + 0.04f * float(k / 8));
        found->map.push_back({p, 0.2f, keyframes});
    }
}

// Issue 31, item 8: the seen scores count in recall only what the walk's keyframes put enough
// points on for the detector to call an object (the map points on it and off the model by more
// than band_threshold_m: at least min_object_points, a quarter of them seen by two keyframes or
// more), and removed elements whose place their beams reached over min_judged_area_m2; they say
// how many were out of view, and of those how many no beam hit at all. Precision does not change.
TEST(ChangeEvaluation, SeenScoresCountOnlyWhatTheKeyframesPutEnoughPointsOn) {
    TruthChanges truth;
    truth.added = {Added("big", Box(0, 0, 0.5)), Added("unseen", Box(10, 0, 0.6)),
                   Added("glimpsed", Box(20, 0, 0.4)), Added("seen once", Box(30, 0, 0.4)),
                   Added("in the floor", Box(40, 0, 0.4))};
    truth.added[0].beam_hits = 5000;
    truth.added[1].beam_hits = 0;     // no beam of any scan
    truth.added[2].beam_hits = 2000;  // many scans, but the keyframes put 20 points on it
    truth.added[3].beam_hits = 3000;  // one keyframe alone saw most of it
    truth.added[4].beam_hits = 900;
    truth.removed = {"column", "hidden column", "far column"};
    truth.removed_beam_hits = {{"column", 900}, {"hidden column", 0}, {"far column", 4000}};
    FoundChanges found;
    found.has_map = true;
    AddFace(&found, 0.5, 0.0, 40, 3);   // big: 40 points, all seen twice or more
    AddFace(&found, 20.4, 0.0, 20, 3);  // glimpsed: fewer than min_object_points (30)
    AddFace(&found, 30.4, 0.0, 32, 1);  // seen once: 32 points, 8 of them (< 25 %) seen twice
    for (int k = 0; k < 7; ++k) found.map[size_t(60 + k)].keyframes = 2;
    for (int k = 0; k < 40; ++k) {  // 1 cm from the object, but nearer to the model (0.5 cm)
        found.map.push_back({Eigen::Vector3f(40.41f, 0.01f * float(k), 0.005f), 0.005f, 4});
    }
    for (int k = 0; k < 40; ++k) {  // 1 cm from it and 4 cm from the model: taken for the model
        found.map.push_back({Eigen::Vector3f(40.41f, 0.01f * float(k), 0.2f), 0.04f, 4});
    }
    found.objects = {{Box(0.02, 0.01, 0.5)}, {Box(50, 0, 0.5)}};  // big, and a false alarm
    found.elements["column"] = {"missing", 4.0, 0, {}, false, 0};
    found.elements["hidden column"] = {"not_observed", 0.1, 0, {}, false, 0};
    found.elements["far column"] = {"not_observed", 0.0, 0, {}, false, 0};

    const ChangeEvaluation ev = EvaluateChanges(truth, found);
    EXPECT_NEAR(ev.added_large.recall(), 1.0 / 5, 1e-12);  // all five count
    ASSERT_EQ(ev.added_view.size(), 5u);
    EXPECT_EQ(ev.added_view[0].map_points, 40u);
    EXPECT_EQ(ev.added_view[0].multi_view_points, 40u);
    EXPECT_EQ(ev.added_view[2].map_points, 20u);
    EXPECT_EQ(ev.added_view[3].map_points, 32u);
    EXPECT_EQ(ev.added_view[3].multi_view_points, 7u);
    EXPECT_EQ(ev.added_view[4].map_points, 0u) << "points nearer to the model are not on it";
    for (size_t k = 0; k < 5; ++k) EXPECT_EQ(ev.added_view[k].in_view, k == 0) << k;
    EXPECT_EQ(ev.added_seen_large.truth, 1u);
    EXPECT_EQ(ev.added_seen_large.truth_matched, 1u);
    EXPECT_EQ(ev.added_large_out_of_view, 4u);
    EXPECT_EQ(ev.added_out_of_view, 4u);
    EXPECT_EQ(ev.added_no_beam, 1u);
    EXPECT_NEAR(ev.added_seen_large.recall(), 1.0, 1e-12);
    EXPECT_NEAR(ev.added_seen_large.precision(), ev.added_large.precision(), 1e-12);
    EXPECT_NEAR(ev.added_seen_large.precision(), 0.5, 1e-12);
    EXPECT_NEAR(ev.removed.recall(), 1.0 / 3, 1e-12);
    EXPECT_EQ(ev.removed_out_of_view, 2u);
    EXPECT_EQ(ev.removed_no_beam, 1u);
    EXPECT_NEAR(ev.removed_seen.recall(), 1.0, 1e-12);
    const nlohmann::json j = ev.ToJson();
    EXPECT_EQ(j["seen"]["out_of_view"]["added_large"], 4);
    EXPECT_EQ(j["seen"]["no_beam"]["removed"], 1);
    EXPECT_EQ(j["seen"]["removed"]["recall"], 1.0);
    EXPECT_EQ(j["seen"]["rule"]["min_map_points"], 30);
    EXPECT_EQ(j["seen"]["objects"][2]["beam_hits"], 2000);
    EXPECT_EQ(j["seen"]["objects"][2]["in_view"], false);

    // The run's own thresholds: a detector run with min_object_points 20 sees "glimpsed".
    found.min_object_points = 20;
    EXPECT_EQ(EvaluateChanges(truth, found).added_seen_large.truth, 2u);

    // A run without a map: everything counts as in view.
    found.has_map = false;
    found.map.clear();
    const ChangeEvaluation all = EvaluateChanges(truth, found);
    EXPECT_EQ(all.added_out_of_view, 0u);
    EXPECT_EQ(all.added_seen_large.truth, all.added_large.truth);
    EXPECT_EQ(all.removed_seen.truth, all.removed.truth);
}

// Issue 33: a found object is matched by the part of a true object the walk saw. Shelving 3 m long
// seen at one end only is found as that end, 1.4 m from the shelving's centre: it matches the
// box of the map points on the shelving, and is no false alarm. Without the map nothing says
// what was seen, and the whole box alone decides.
TEST(ChangeEvaluation, AFoundObjectMatchesThePartOfATrueOneTheWalkSaw) {
    TruthChanges truth;
    truth.added = {Added("shelving", {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.4, 3, 2)}),
                   Added("crate", Box(10, 0, 0.5))};
    FoundChanges found;
    found.has_map = true;
    AddFace(&found, 0.4, 0.0, 40, 3);  // x = 0.41, y 0-0.35, z 0.2-0.36: the shelving's end
    const Eigen::AlignedBox3d end(Eigen::Vector3d(0.39, 0, 0.2), Eigen::Vector3d(0.43, 0.35, 0.36));
    found.objects = {{end}, {Box(12, 0, 0.5)}};  // the end, and a false alarm 2 m from the crate

    const ChangeEvaluation ev = EvaluateChanges(truth, found);
    ASSERT_EQ(ev.added_view.size(), 2u);
    EXPECT_TRUE(ev.added_view[0].in_view);
    EXPECT_FALSE(ev.added_view[1].in_view) << "no map point on the crate";
    EXPECT_TRUE(ev.added_view[0].found);
    EXPECT_NEAR(ev.added_view[0].seen_box.min().y(), 0.0, 1e-6);
    EXPECT_NEAR(ev.added_view[0].seen_box.max().y(), 0.35, 1e-6);
    EXPECT_TRUE(ev.added_view[1].seen_box.isEmpty());
    EXPECT_EQ(ev.added.found_matched, 1u);
    EXPECT_EQ(ev.added.truth_matched, 1u);
    EXPECT_NEAR(ev.added_seen.recall(), 1.0, 1e-12);
    EXPECT_NEAR(ev.added_seen.precision(), 0.5, 1e-12) << "the crate's false alarm stays one";
    const nlohmann::json j = ev.ToJson();
    EXPECT_NEAR(j["seen"]["objects"][0]["seen_box_max"][1].get<double>(), 0.35, 1e-6);
    EXPECT_FALSE(j["seen"]["objects"][1].contains("seen_box_min"));

    found.has_map = false;
    found.map.clear();
    const ChangeEvaluation whole = EvaluateChanges(truth, found);
    EXPECT_EQ(whole.added.truth_matched, 0u) << "1.4 m from the whole shelving's centre";
}

TEST(ChangeEvaluation, ScoresObjectsElementsWallsAndPeople) {
    TruthChanges truth;
    truth.added = {Added("big", Box(0, 0, 0.5)), Added("small", Box(5, 0, 0.2)),
                   Added("unseen", Box(10, 0, 0.6)),
                   // Two boxes 2 cm apart: one lump in a 5 cm map.
                   Added("pair a", Box(40, 0, 0.4)), Added("pair b", Box(40.42, 0, 0.4))};
    truth.removed = {"column", "far column"};
    truth.moved = {{"desk", "IfcFurniture", "Desk", "moved", {0.5, -0.3, 0}, 15},
                   {"wall", "IfcWall", "Wall", "as_built", {0, 0.03, 0}, 0},
                   {"far wall", "IfcWall", "Wall", "as_built", {0.02, 0, 0}, 0}};
    truth.people = {{{20, 0}, {30, 0}, 0.25, 1.75, 0}};

    FoundChanges found;
    found.objects = {
        {Box(0.02, 0.01, 0.5)},  // big: IoU ~0.9
        {Box(5.05, 0.05, 0.2)},  // small: centre 7 cm off
        {Box(25, -0.2, 0.4)},    // on the person's line: a person as an object
        {Eigen::AlignedBox3d(
            Eigen::Vector3d(40, 0, 0),
            Eigen::Vector3d(40.82, 0.4,
                            0.4))}};  // the pair   // on the person's line: a person as an object
    found.transients = {{22, 0.1, 1}};
    found.elements["column"] = {"missing", 4.0, 0, {}, false, 0};
    found.elements["far column"] = {"not_observed", 0.0, 0, {}, false, 0};
    found.elements["cabinet"] = {"missing", 2.0, 0, {}, false, 0};  // not removed: a false alarm
    found.elements["desk"] = {"deviating", 2.0, 200, {0.48, -0.29, 0.0}, true, 15.5};
    found.elements["wall"] = {"deviating", 9.0, 500, {0, 0.035, 0}, false, 0};
    found.elements["far wall"] = {"not_observed", 0.0, 0, {}, false, 0};

    const ChangeEvaluation ev = EvaluateChanges(truth, found);
    EXPECT_EQ(ev.added.truth, 5u);
    EXPECT_EQ(ev.added.truth_matched, 3u);  // big, small, one of the pair
    EXPECT_EQ(ev.added.found_matched, 3u);
    EXPECT_NEAR(ev.added.precision(), 3.0 / 4, 1e-12);
    // Large: "big", "unseen" and the pair are true, "big", the person and the lump found large.
    EXPECT_EQ(ev.added_large.truth, 4u);
    EXPECT_EQ(ev.added_large.truth_matched, 2u);
    EXPECT_EQ(ev.added_large.found, 3u);
    EXPECT_EQ(ev.added_large.found_matched, 2u);
    // Separable: the pair is one true object, found.
    EXPECT_EQ(ev.touching_groups, 1u);
    EXPECT_EQ(ev.added_separable_large.truth, 3u);
    EXPECT_EQ(ev.added_separable_large.truth_matched, 2u);
    EXPECT_EQ(ev.added_separable_large.found_matched, 2u);
    // Removed: "column" found; "far column" was never in view (not large); "cabinet" a false alarm.
    EXPECT_EQ(ev.removed.truth, 2u);
    EXPECT_EQ(ev.removed.truth_matched, 1u);
    EXPECT_EQ(ev.removed_large.truth, 1u);
    EXPECT_EQ(ev.removed_large.truth_matched, 1u);
    EXPECT_EQ(ev.removed_large.found, 2u);
    EXPECT_NEAR(ev.removed_large.precision(), 0.5, 1e-12);
    ASSERT_EQ(ev.moved.size(), 1u);
    EXPECT_TRUE(ev.moved[0].found);
    EXPECT_NEAR(ev.moved[0].translation_error_m, std::hypot(0.02, 0.01), 1e-9);
    EXPECT_NEAR(ev.moved[0].yaw_error_deg, 0.5, 1e-9);
    ASSERT_EQ(ev.walls.size(), 1u);
    EXPECT_EQ(ev.walls_unobserved, 1u);
    EXPECT_NEAR(ev.walls[0].error_m, 0.005, 1e-9);
    EXPECT_NEAR(ev.walls[0].measured_offset_m, 0.035, 1e-9);
    EXPECT_EQ(ev.people_as_objects, 1u);
    EXPECT_EQ(ev.people_with_transients, 1u);
    EXPECT_EQ(ev.ToJson()["as_built"]["within_1cm"], 1);
}

TEST(ChangeEvaluation, ReadsTheSimulatorsTruthAndNamesTheFileWhenItIsBad) {
    bimslam::test::TempDir tmp;
    std::filesystem::create_directories(tmp / "changes");
    io::WritePly(tmp / "changes" / "000_crate.ply",
                 io::ToPly(changes::test::SolidBox({1, 2, 0}, {1.5, 2.5, 0.6})));
    io::WriteFileAtomic(tmp / "changes.json", R"({"frame": "bim",
        "added": [{"name": "crate", "kind": "box", "mesh": "changes/000_crate.ply",
                   "box_min": [1, 2, 0], "box_max": [1.5, 2.5, 0.6]}],
        "removed": [{"global_id": "abc", "class": "IfcColumn", "name": "c"}],
        "moved": [{"global_id": "w", "class": "IfcWall", "name": "w", "reason": "as_built",
                   "translation": [0, 0.03, 0], "yaw_deg": 0}],
        "people": [{"from": [0, 1], "to": [5, 1], "speed_mps": 1.2, "radius_m": 0.25,
                    "height_m": 1.75, "floor_z": 0}]})");
    const TruthChanges t = ReadTruthChanges(tmp / "changes.json");
    ASSERT_EQ(t.added.size(), 1u);
    EXPECT_NEAR(t.added[0].box.sizes().z(), 0.6, 1e-12);
    EXPECT_EQ(t.added[0].mesh.triangles.size(), 12u);
    EXPECT_EQ(t.removed, std::vector<std::string>{"abc"});
    EXPECT_EQ(t.moved[0].reason, "as_built");
    EXPECT_NEAR(t.people[0].to.x(), 5, 1e-12);
    io::WriteFileAtomic(tmp / "bad.json", R"({"added": [{"name": "x"}]})");
    EXPECT_FILE_ERROR(ReadTruthChanges(tmp / "bad.json"), (tmp / "bad.json").string(), 0);
    io::WriteFileAtomic(tmp / "garbage.json", "not json");
    EXPECT_FILE_ERROR(ReadTruthChanges(tmp / "garbage.json"), (tmp / "garbage.json").string(), 0);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::change_detection
