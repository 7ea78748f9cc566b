#include "host_tools/changes/change_evaluation.hpp"

#include <gtest/gtest.h>

#include "algorithms/io/file_util.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::change_detection {
namespace {

Eigen::AlignedBox3d Box(double x, double y, double size) {
    return {Eigen::Vector3d(x, y, 0), Eigen::Vector3d(x + size, y + size, size)};
}

TEST(ChangeEvaluation, ScoresObjectsElementsWallsAndPeople) {
    TruthChanges truth;
    truth.added = {{"big", "box", Box(0, 0, 0.5)},
                   {"small", "clutter", Box(5, 0, 0.2)},
                   {"unseen", "box", Box(10, 0, 0.6)}};
    truth.removed = {"column", "far column"};
    truth.moved = {{"desk", "IfcFurniture", "Desk", "moved", {0.5, -0.3, 0}, 15},
                   {"wall", "IfcWall", "Wall", "as_built", {0, 0.03, 0}, 0},
                   {"far wall", "IfcWall", "Wall", "as_built", {0.02, 0, 0}, 0}};
    truth.people = {{{20, 0}, {30, 0}, 0.25, 1.75, 0}};

    FoundChanges found;
    found.objects = {{Box(0.02, 0.01, 0.5)},  // big: IoU ~0.9
                     {Box(5.05, 0.05, 0.2)},  // small: centre 7 cm off
                     {Box(25, -0.2, 0.4)}};   // on the person's line: a person as an object
    found.transients = {{22, 0.1, 1}};
    found.elements["column"] = {"missing", 4.0, 0, {}, false, 0};
    found.elements["far column"] = {"not_observed", 0.0, 0, {}, false, 0};
    found.elements["cabinet"] = {"missing", 2.0, 0, {}, false, 0};  // not removed: a false alarm
    found.elements["desk"] = {"deviating", 2.0, 200, {0.48, -0.29, 0.0}, true, 15.5};
    found.elements["wall"] = {"deviating", 9.0, 500, {0, 0.035, 0}, false, 0};
    found.elements["far wall"] = {"not_observed", 0.0, 0, {}, false, 0};

    const ChangeEvaluation ev = EvaluateChanges(truth, found);
    EXPECT_EQ(ev.added.truth, 3u);
    EXPECT_EQ(ev.added.truth_matched, 2u);
    EXPECT_EQ(ev.added.found_matched, 2u);
    EXPECT_NEAR(ev.added.precision(), 2.0 / 3, 1e-12);
    // Large: "big" and "unseen" are true, "big" and the person are found large.
    EXPECT_EQ(ev.added_large.truth, 2u);
    EXPECT_EQ(ev.added_large.truth_matched, 1u);
    EXPECT_EQ(ev.added_large.found, 2u);
    EXPECT_EQ(ev.added_large.found_matched, 1u);
    EXPECT_NEAR(ev.added_large.f1(), 0.5, 1e-12);
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
    test::TempDir tmp;
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
