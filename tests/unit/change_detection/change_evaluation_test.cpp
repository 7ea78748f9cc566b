#include "host_tools/changes/change_evaluation.hpp"

#include <gtest/gtest.h>

#include "algorithms/io/file_util.hpp"
#include "algorithms/io/ply.hpp"
#include "tests/support/test_support.hpp"
#include "tests/unit/changes/change_scene.hpp"

namespace bimslam::change_detection {
namespace {

Eigen::AlignedBox3d Box(double x, double y, double size) {
    return {Eigen::Vector3d(x, y, 0), Eigen::Vector3d(x + size, y + size, size)};
}

TruthChanges::Added Added(const std::string& name, const Eigen::AlignedBox3d& box) {
    return {name, "box", box, changes::test::SolidBox(box.min(), box.max())};
}

// Issue 31, item 8: what no beam hit cannot be found; the seen scores leave it out of recall
// and say how many were out of sight. Precision does not change.
TEST(ChangeEvaluation, SeenScoresCountOnlyWhatTheWalkSaw) {
    TruthChanges truth;
    truth.added = {Added("big", Box(0, 0, 0.5)), Added("unseen", Box(10, 0, 0.6)),
                   Added("glimpsed", Box(20, 0, 0.4))};
    truth.added[0].beam_hits = 5000;
    truth.added[1].beam_hits = 0;
    truth.added[2].beam_hits = 12;  // under min_seen_beam_hits (20)
    truth.removed = {"column", "hidden column"};
    truth.removed_beam_hits = {{"column", 900}, {"hidden column", 0}};
    FoundChanges found;
    found.objects = {{Box(0.02, 0.01, 0.5)}, {Box(30, 0, 0.5)}};  // big, and a false alarm
    found.elements["column"] = {"missing", 4.0, 0, {}, false, 0};
    found.elements["hidden column"] = {"not_observed", 0.0, 0, {}, false, 0};

    const ChangeEvaluation ev = EvaluateChanges(truth, found);
    EXPECT_NEAR(ev.added_large.recall(), 1.0 / 3, 1e-12);  // all three count
    EXPECT_EQ(ev.added_seen_large.truth, 1u);
    EXPECT_EQ(ev.added_seen_large.truth_matched, 1u);
    EXPECT_EQ(ev.added_large_out_of_sight, 2u);
    EXPECT_EQ(ev.added_out_of_sight, 2u);
    EXPECT_NEAR(ev.added_seen_large.recall(), 1.0, 1e-12);
    EXPECT_NEAR(ev.added_seen_large.precision(), ev.added_large.precision(), 1e-12);
    EXPECT_NEAR(ev.added_seen_large.precision(), 0.5, 1e-12);
    EXPECT_NEAR(ev.removed.recall(), 0.5, 1e-12);
    EXPECT_EQ(ev.removed_out_of_sight, 1u);
    EXPECT_NEAR(ev.removed_seen.recall(), 1.0, 1e-12);
    const nlohmann::json j = ev.ToJson();
    EXPECT_EQ(j["seen"]["out_of_sight"]["added_large"], 2);
    EXPECT_EQ(j["seen"]["removed"]["recall"], 1.0);

    // A truth file that does not say: everything counts as seen.
    for (auto& a : truth.added) a.beam_hits = -1;
    truth.removed_beam_hits.clear();
    const ChangeEvaluation all = EvaluateChanges(truth, found);
    EXPECT_EQ(all.added_out_of_sight, 0u);
    EXPECT_EQ(all.added_seen_large.truth, all.added_large.truth);
    EXPECT_EQ(all.removed_seen.truth, all.removed.truth);
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

}  // namespace
}  // namespace bimslam::change_detection
