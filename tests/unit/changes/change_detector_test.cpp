// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Change detection end to end on a simulated two-room building (change_scene.hpp): the cases the
// issue names, each checked against the scene's own truth.
#include "algorithms/changes/change_detector.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "algorithms/common/status.hpp"
#include "tests/unit/changes/change_scene.hpp"

namespace bimslam::changes {
namespace {
namespace BIMSLAM_UNITY_ID {
using test::SharedChangeScene;

// These tests are about the detection on the poses given (the simulator's, exact), so without
// the refinement of the poses (pose_refinement_test.cpp has its own). With it, this scene could
// not keep the 3 cm of its north wall: room A has two walls across y and one column, and a
// refinement whose prior says every element may be off cannot tell the off wall from the other
// (it splits the offset: 1.1 and 1.3 cm; algorithms/changes/README.md, "Pose refinement").
ChangeDetectorConfig GivenPoses() {
    ChangeDetectorConfig c;
    c.refinement.enabled = false;
    return c;
}

const ChangeResult& SharedResult() {
    static const ChangeResult result = [] {
        const test::ChangeScene& s = SharedChangeScene();
        return DetectChanges(s.model, s.keyframes, GivenPoses());
    }();
    return result;
}

std::string Describe(const ChangeResult& r) {
    std::string text;
    for (size_t o = 0; o < r.objects.size(); ++o) {
        const NewObject& obj = r.objects[o];
        text += "object " + std::to_string(o) + ": " + std::to_string(obj.points.size()) +
                " points, box (" + std::to_string(obj.box_min.x()) + " " +
                std::to_string(obj.box_min.y()) + " " + std::to_string(obj.box_min.z()) + ") (" +
                std::to_string(obj.box_max.x()) + " " + std::to_string(obj.box_max.y()) + " " +
                std::to_string(obj.box_max.z()) + ")\n";
    }
    for (const TransientCluster& t : r.transients) {
        text += "transient: " + std::to_string(t.points.size()) + " points at (" +
                std::to_string(t.centroid.x()) + " " + std::to_string(t.centroid.y()) + ")\n";
    }
    for (size_t e = 0; e < r.elements.size(); ++e) {
        const ElementReport& el = r.elements[e];
        text += "element " + std::to_string(e) + ": " + std::string(ToString(el.verdict)) +
                " expected " + std::to_string(el.evidence.expected_area_m2) + " seen " +
                std::to_string(el.evidence.seen_area_m2) + " support " +
                std::to_string(el.support_points) + " offset " + std::to_string(el.offset.norm()) +
                "\n";
    }
    return text;
}

TEST(ChangeDetector, ABoxAddedToARoomIsFoundWithItsSizeWithinOneVoxel) {
    const test::ChangeScene& s = SharedChangeScene();
    const ChangeResult& r = SharedResult();
    const double voxel = ChangeDetectorConfig{}.map.voxel_m;
    int found = -1;
    for (size_t o = 0; o < r.objects.size(); ++o) {
        const Eigen::AlignedBox3d box(r.objects[o].box_min, r.objects[o].box_max);
        if (box.intersects(s.added_box)) {
            EXPECT_EQ(found, -1) << "two objects on the box\n" << Describe(r);
            found = int(o);
        }
    }
    ASSERT_GE(found, 0) << Describe(r);
    const NewObject& obj = r.objects[size_t(found)];
    const Eigen::Vector3d size = obj.box_max - obj.box_min;
    const Eigen::Vector3d truth = s.added_box.sizes();
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(size[k], truth[k], voxel) << "axis " << k << "\n" << Describe(r);
    }
    EXPECT_TRUE(obj.on_floor);
    EXPECT_NEAR(obj.centroid.x(), s.added_box.center().x(), voxel);
    EXPECT_NEAR(obj.centroid.y(), s.added_box.center().y(), voxel);
    // The solid fills the box (2.5D), the voxels overlapping its faces by up to a voxel.
    EXPECT_GE(obj.volume_m3, 0.9 * truth.prod());
    EXPECT_LE(obj.volume_m3, (truth.array() + 2 * voxel).prod());
    EXPECT_EQ(obj.moved_element, kNoElement);
    // Nothing else in room A is a new object: the people are transient, the walls in the model.
    EXPECT_EQ(r.objects.size(), 1u) << Describe(r);
}

TEST(ChangeDetector, ARemovedColumnIsMissing) {
    const ChangeResult& r = SharedResult();
    EXPECT_EQ(r.elements[test::kColumnA].verdict, Verdict::kMissing) << Describe(r);
    EXPECT_GT(r.elements[test::kColumnA].evidence.expected_area_m2, 1.0);
    EXPECT_GT(r.elements[test::kColumnA].evidence.rays_through, 100u);
}

TEST(ChangeDetector, AColumnOutOfViewIsNotObservedNotMissing) {
    const ChangeResult& r = SharedResult();
    EXPECT_EQ(r.elements[test::kColumnB].verdict, Verdict::kNotObserved) << Describe(r);
    EXPECT_EQ(r.elements[test::kColumnB].evidence.rays_agree +
                  r.elements[test::kColumnB].evidence.rays_through,
              0u);
    // And the one in view that is there is confirmed.
    EXPECT_EQ(r.elements[test::kColumnC].verdict, Verdict::kConfirmed) << Describe(r);
}

TEST(ChangeDetector, AWallOffsetBy3cmIsDeviatingBy3Plus1cm) {
    const test::ChangeScene& s = SharedChangeScene();
    const ChangeResult& r = SharedResult();
    const ElementReport& wall = r.elements[test::kWallNorthA];
    EXPECT_EQ(wall.verdict, Verdict::kDeviating) << Describe(r);
    EXPECT_NEAR(wall.offset.y(), s.wall_offset_m, 0.01) << Describe(r);
    EXPECT_NEAR(wall.offset.norm(), s.wall_offset_m, 0.01);
    // Scan-vs-BIM numbers: seen from the room only, its points lie 3 cm behind its face.
    EXPECT_NEAR(wall.mean_signed_m, -s.wall_offset_m, 0.01);
    EXPECT_GT(wall.support_points, 1000u);
    // The walls built where the model has them are confirmed.
    for (const auto e :
         {test::kWallSouth, test::kWallWest, test::kWallDivider, test::kFloor, test::kCeiling}) {
        EXPECT_EQ(r.elements[e].verdict, Verdict::kConfirmed) << "element " << e << "\n"
                                                              << Describe(r);
        EXPECT_LT(r.elements[e].offset.norm(), 0.01);
    }
}

// The QA verdicts against a tolerance (issue 34, elements.csv tolerance_verdict): the wall built
// 3 cm off is beyond 1 cm and within 5 cm; the walls where the model has them are within 1 cm;
// the removed column is beyond whatever the tolerance, the one out of view not observed.
TEST(ChangeDetector, ToleranceVerdictsFollowTheMeasuredDeviations) {
    const ChangeResult& r = SharedResult();
    ElementCheckConfig tight, loose;
    tight.tolerance_m = 0.01;
    loose.tolerance_m = 0.05;
    const ElementReport& wall = r.elements[test::kWallNorthA];
    EXPECT_EQ(JudgeTolerance(wall, tight), ToleranceVerdict::kBeyond) << Describe(r);
    EXPECT_EQ(JudgeTolerance(wall, loose), ToleranceVerdict::kWithin) << Describe(r);
    for (const auto e : {test::kWallSouth, test::kWallWest, test::kWallDivider, test::kFloor}) {
        EXPECT_EQ(JudgeTolerance(r.elements[e], tight), ToleranceVerdict::kWithin)
            << "element " << e << "\n"
            << Describe(r);
    }
    EXPECT_EQ(JudgeTolerance(r.elements[test::kColumnA], loose), ToleranceVerdict::kBeyond);
    EXPECT_EQ(JudgeTolerance(r.elements[test::kColumnB], loose), ToleranceVerdict::kNotObserved);
    EXPECT_EQ(ToString(ToleranceVerdict::kNotObserved), "not_observed");
    // Seen and confirmed, but with too little support to measure a deviation: not observed.
    ElementReport thin = r.elements[test::kWallSouth];
    thin.support_points = tight.min_support_points - 1;
    EXPECT_EQ(JudgeTolerance(thin, tight), ToleranceVerdict::kNotObserved);
    // A moved element is beyond even when only turned in place.
    ElementReport turned = r.elements[test::kColumnC];
    turned.moved = true;
    turned.verdict = Verdict::kDeviating;
    turned.offset.setZero();
    EXPECT_EQ(JudgeTolerance(turned, loose), ToleranceVerdict::kBeyond);
}

TEST(ChangeDetector, APersonCrossingTheRoomIsTransientNotANewObject) {
    const test::ChangeScene& s = SharedChangeScene();
    const ChangeResult& r = SharedResult();
    for (const Eigen::Vector2d& at : s.person_at) {
        for (const NewObject& obj : r.objects) {
            const Eigen::Vector2d c = 0.5 * (obj.box_min + obj.box_max).head<2>();
            EXPECT_GT((c - at).norm(), 0.6) << "a new object where the person stood\n"
                                            << Describe(r);
        }
        bool reported = false;
        for (const TransientCluster& t : r.transients) {
            reported |= (t.centroid.head<2>() - at).norm() < 0.4 && t.points.size() > 20;
        }
        EXPECT_TRUE(reported) << "no transient cluster at " << at.transpose() << "\n"
                              << Describe(r);
    }
    EXPECT_GT(r.counts.transient_points, 50u);
}

// The changed-building benchmark's remaining false object (issue 13): a person walking to and fro
// along a corridor, seen from a Go1 at the same heights again and again. Merged, those rings make
// horizontal sheets whose normal is vertical; every beam grazes them, so no keyframe votes on
// them, and they made a new object a person's width, 0.2-0.95 m high, on the person's line. The
// corridor is built as modelled: nothing in it is a new object.
TEST(ChangeDetector, APersonWalkingToAndFroAlongTheCorridorIsTransientNotANewObject) {
    const test::CorridorScene& s = test::SharedCorridorScene();
    const ChangeResult r = DetectChanges(s.model, s.keyframes, GivenPoses());
    EXPECT_TRUE(r.objects.empty()) << Describe(r);
    // The case is the one above: points no keyframe could judge, judged by the person around them.
    EXPECT_GT(r.counts.unjudged_points, 20u);
    EXPECT_GT(r.counts.transient_by_neighbours, 20u);
    // The person is transient all along the line walked.
    const Eigen::Vector2d dir = (s.person_to - s.person_from).normalized();
    const double length = (s.person_to - s.person_from).norm();
    std::vector<int> covered(size_t(length), 0);  // 1 m stretches of the line
    for (const TransientCluster& t : r.transients) {
        const Eigen::Vector2d c = t.centroid.head<2>() - s.person_from;
        const double along = c.dot(dir);
        const double across = std::abs(c.x() * dir.y() - c.y() * dir.x());
        if (across < s.person_radius_m + 0.2 && along >= 0 && along < length) {
            covered[size_t(along)] = 1;
        }
    }
    int stretches = 0;
    for (const int c : covered) stretches += c;
    EXPECT_GE(stretches, int(covered.size()) - 2) << Describe(r);
}

// The scene's keyframes and one more at `sensor` (unrotated) that saw `cloud` (its lidar frame).
std::vector<MapKeyframe> WithOneMoreView(const test::ChangeScene& s,
                                         const common::PointCloud& cloud,
                                         const Eigen::Vector3f& sensor) {
    std::vector<MapKeyframe> keyframes = s.keyframes;
    MapKeyframe view;
    view.cloud = &cloud;
    view.T_world_lidar =
        Eigen::Translation3d(sensor.cast<double>()) * Eigen::Isometry3d::Identity();
    keyframes.push_back(view);
    return keyframes;
}

// A 0.6 m crate on the ground outside the west wall, within the compared box (the model's box
// plus 0.5 m), and the ground around it, seen by one more keyframe standing outside: no element is
// below them. The ground is outside; the crate is an object outside the footprint (an annex or a
// shed the model lacks is found the same way), or outside too with the extension's margin at 0.
TEST(ChangeDetector, AThingBesideTheBuildingIsAnObjectOutsideItsFootprintAndTheGroundIsNot) {
    const test::ChangeScene& s = SharedChangeScene();
    const Eigen::Vector3f sensor(-2.0f, 2.15f, 0.5f);
    common::PointCloud seen;
    for (float a = 0; a <= 0.3f; a += 0.025f) {
        for (float b = 0; b <= 0.6f; b += 0.025f) {
            seen.xyz.push_back(Eigen::Vector3f(-0.6f, 2.0f + a, b) - sensor);  // facing it
        }
        for (float b = 0; b <= 0.3f; b += 0.025f) {
            seen.xyz.push_back(Eigen::Vector3f(-0.6f + a, 2.0f + b, 0.6f) - sensor);  // top
        }
    }
    for (float x = -2.4f; x <= -0.65f; x += 0.05f) {  // the ground before it and around
        for (float y = 1.0f; y <= 3.3f; y += 0.05f) {
            seen.xyz.push_back(Eigen::Vector3f(x, y, 0.0f) - sensor);
        }
    }
    const std::vector<MapKeyframe> keyframes = WithOneMoreView(s, seen, sensor);
    const auto objects_outside = [](const ChangeResult& r) {
        std::vector<const NewObject*> found;
        for (const NewObject& obj : r.objects) {
            if (obj.box_max.x() < -0.2) found.push_back(&obj);
        }
        return found;
    };
    // One keyframe sees the crate: with the multi-view rule on, it would be dropped as seen
    // once, and this test would not tell whether the footprint check works.
    ChangeDetectorConfig beside = GivenPoses();
    beside.min_multi_view_fraction = 0;
    const ChangeResult r = DetectChanges(s.model, keyframes, beside);
    const auto found = objects_outside(r);
    ASSERT_EQ(found.size(), 1u) << "the crate, not the ground: " << Describe(r);
    EXPECT_TRUE(found[0]->outside_footprint);
    EXPECT_LT(found[0]->box_max.x() - found[0]->box_min.x(), 0.5) << "no ground in it";
    EXPECT_GT(found[0]->box_max.z(), 0.55);
    EXPECT_GT(r.counts.extension_points, 20u);
    EXPECT_GT(r.counts.outside_footprint, r.counts.extension_points) << "the ground";
    for (const NewObject& obj : r.objects) {
        EXPECT_EQ(obj.outside_footprint, &obj == found[0]) << "the objects inside are inside";
    }
    // The objects inside are unchanged by the check: the added box is still found.
    EXPECT_EQ(r.objects.size(), SharedResult().objects.size() + 1) << Describe(r);

    ChangeDetectorConfig footprint = beside;
    footprint.extension_margin_m = 0;
    const ChangeResult cropped = DetectChanges(s.model, keyframes, footprint);
    EXPECT_TRUE(objects_outside(cropped).empty()) << Describe(cropped);
    EXPECT_GT(cropped.counts.outside_footprint, 50u);  // 5 cm voxels of the crate and the ground
    EXPECT_EQ(cropped.counts.extension_points, 0u);
    EXPECT_EQ(cropped.objects.size(), SharedResult().objects.size()) << Describe(cropped);

    ChangeDetectorConfig keep = footprint;
    keep.crop_to_footprint = false;
    const ChangeResult kept = DetectChanges(s.model, keyframes, keep);
    EXPECT_GE(objects_outside(kept).size(), 1u) << Describe(kept);
    EXPECT_EQ(kept.counts.outside_footprint, 0u);
}

// A cabinet's face seen with a gap at its lower corner (the sample hall's: its face and two
// slivers of its lower corners, three objects): the strip left in the gap, more than DBSCAN's eps
// from the rest, is a cluster of its own, inside the face's box, and joins it. The same strip
// 0.3 m beyond the face's end stays an object of its own.
TEST(ChangeDetector, APartInsideAnObjectsBoxIsThatObject) {
    const test::ChangeScene& s = SharedChangeScene();
    const Eigen::Vector3f sensor(1.5f, 0.8f, 1.0f);  // away from the person's path
    const auto cloud = [&](float strip_x) {
        common::PointCloud c;
        for (float x = 1.0f; x <= 2.0f; x += 0.025f) {
            for (float z = 0.05f; z <= 2.0f; z += 0.025f) {
                if (x < 1.4f && z < 0.95f) continue;  // the gap at its lower corner
                c.xyz.push_back(Eigen::Vector3f(x, 2.0f, z) - sensor);
            }
        }
        for (float x = strip_x; x <= strip_x + 0.15f; x += 0.025f) {
            for (float z = 0.05f; z <= 0.75f; z += 0.025f) {
                c.xyz.push_back(Eigen::Vector3f(x, 2.0f, z) - sensor);
            }
        }
        return c;
    };
    // One keyframe sees it, which the walk's beams cross where it stands: the multi-view rule
    // and the transients would drop it, and this test would not tell whether the parts join.
    ChangeDetectorConfig config = GivenPoses();
    config.min_multi_view_fraction = 0;
    config.detect_transients = false;
    const size_t before = DetectChanges(s.model, s.keyframes, config).objects.size();
    const auto detect = [&](const common::PointCloud& c) {
        return DetectChanges(s.model, WithOneMoreView(s, c, sensor), config);
    };
    const common::PointCloud inside = cloud(1.0f), beyond = cloud(0.5f);
    const ChangeResult joined = detect(inside);
    ASSERT_EQ(joined.objects.size(), before + 1) << Describe(joined);
    const auto face =
        std::find_if(joined.objects.begin(), joined.objects.end(), [](const NewObject& o) {
            return std::abs(o.centroid.y() - 2.0) < 0.1 && o.centroid.x() < 2.2;
        });
    ASSERT_NE(face, joined.objects.end());
    const auto in_strip = [&](const NewObject& o) {
        return std::count_if(o.points.begin(), o.points.end(), [&](uint32_t i) {
            const Eigen::Vector3f& p = joined.map.xyz[i];
            return p.x() < 1.25f && p.z() > 0.1f && p.z() < 0.8f;
        });
    };
    EXPECT_GE(in_strip(*face), 30) << "the strip is in it";
    EXPECT_NEAR(face->box_min.z(), 0.0, 0.03) << "on the floor";
    const ChangeResult apart = detect(beyond);
    EXPECT_EQ(apart.objects.size(), before + 2) << Describe(apart);
}

// Surfaces of room B (which the scene's walk of room A never sees, behind the divider) that one
// more keyframe at `sensor` saw: each is a rectangle upright along x (at y) or along y (at x),
// sampled every 2.5 cm. The multi-view rule and the transients would drop what one keyframe saw.
struct Upright {
    bool along_x;
    float at, from, to, z_from, z_to;
};
ChangeResult DetectInRoomB(const std::vector<Upright>& surfaces, const Eigen::Vector3f& sensor,
                           const ChangeDetectorConfig& base = GivenPoses()) {
    const test::ChangeScene& s = SharedChangeScene();
    common::PointCloud c;
    for (const Upright& u : surfaces) {
        for (float a = u.from; a <= u.to; a += 0.025f) {
            for (float z = u.z_from; z <= u.z_to; z += 0.025f) {
                const Eigen::Vector3f p =
                    u.along_x ? Eigen::Vector3f(a, u.at, z) : Eigen::Vector3f(u.at, a, z);
                c.xyz.push_back(p - sensor);
            }
        }
    }
    ChangeDetectorConfig config = base;
    config.min_multi_view_fraction = 0;
    config.detect_transients = false;
    return DetectChanges(s.model, WithOneMoreView(s, c, sensor), config);
}

std::vector<const NewObject*> ObjectsInRoomB(const ChangeResult& r) {
    std::vector<const NewObject*> found;
    for (const NewObject& obj : r.objects) {
        if (obj.box_min.x() > 8.3) found.push_back(&obj);
    }
    return found;
}

// New walls meeting at corners (the visits' annex: its south and east walls were one object, which
// matched neither; the held-out Office_A's shed, three walls in a U, one object) are an object
// each; a cabinet seen from two sides stays one.
TEST(ChangeDetector, WallsMeetingAtCornersAreAnObjectEachAndACabinetIsOne) {
    const Eigen::Vector3f sensor(9.0f, 1.0f, 1.0f);
    const ChangeResult walls = DetectInRoomB(
        {{true, 4.5f, 9.0f, 11.5f, 0.05f, 2.2f}, {false, 11.5f, 2.0f, 4.5f, 0.05f, 2.2f}}, sensor);
    const auto found = ObjectsInRoomB(walls);
    ASSERT_EQ(found.size(), 2u) << Describe(walls);
    for (const NewObject* wall : found) {
        const Eigen::Vector3d size = wall->box_max - wall->box_min;
        EXPECT_LT(std::min(size.x(), size.y()), 0.15) << "one wall each: " << Describe(walls);
        EXPECT_GT(std::max(size.x(), size.y()), 2.3) << Describe(walls);
    }
    const ChangeResult u = DetectInRoomB({{true, 4.8f, 8.8f, 11.3f, 0.05f, 2.2f},
                                          {false, 8.8f, 2.3f, 4.8f, 0.05f, 2.2f},
                                          {false, 11.3f, 2.3f, 4.8f, 0.05f, 2.2f}},
                                         Eigen::Vector3f(10.05f, 1.0f, 1.0f));
    EXPECT_EQ(ObjectsInRoomB(u).size(), 3u) << "a U of three walls: " << Describe(u);
    const ChangeResult cabinet = DetectInRoomB(
        {{true, 4.5f, 10.0f, 11.0f, 0.05f, 2.0f}, {false, 10.0f, 4.5f, 5.0f, 0.05f, 2.0f}}, sensor);
    EXPECT_EQ(ObjectsInRoomB(cabinet).size(), 1u) << Describe(cabinet);
    ChangeDetectorConfig off = GivenPoses();
    off.walls.split_corners = false;
    const ChangeResult unsplit = DetectInRoomB(
        {{true, 4.5f, 9.0f, 11.5f, 0.05f, 2.2f}, {false, 11.5f, 2.0f, 4.5f, 0.05f, 2.2f}}, sensor,
        off);
    EXPECT_EQ(ObjectsInRoomB(unsplit).size(), 1u) << "the rule is what splits them";
}

// One new wall seen in two pieces (the visits' shed, seen through two windows of the hall, its
// middle hidden by the wall between them): when no beam went through the gap between the pieces
// (here nothing returned from it) they are one object; when the beams looked through it to the
// north wall behind, they are two things side by side.
TEST(ChangeDetector, PiecesOfOneWallAreJoinedWhereNoBeamWentThroughTheGap) {
    const Eigen::Vector3f sensor(10.0f, 2.0f, 1.2f);
    const Upright west{true, 5.0f, 8.6f, 9.3f, 0.6f, 2.2f},
        east{true, 5.0f, 10.7f, 11.4f, 0.6f, 2.2f};
    const ChangeResult hidden = DetectInRoomB({west, east}, sensor);
    const auto joined = ObjectsInRoomB(hidden);
    ASSERT_EQ(joined.size(), 1u) << Describe(hidden);
    EXPECT_NEAR(joined[0]->box_min.x(), 8.6, 0.05);
    EXPECT_NEAR(joined[0]->box_max.x(), 11.4, 0.05);
    const Upright behind{true, 6.0f, 9.3f, 10.7f, 0.6f, 2.2f};  // the north wall, as modelled
    const ChangeResult through = DetectInRoomB({west, east, behind}, sensor);
    EXPECT_EQ(ObjectsInRoomB(through).size(), 2u) << Describe(through);
    ChangeDetectorConfig off = GivenPoses();
    off.walls.join_hidden_gaps = false;
    EXPECT_EQ(ObjectsInRoomB(DetectInRoomB({west, east}, sensor, off)).size(), 2u)
        << "the rule is what joins them";
}

// A keyframe anchored 15 cm off (the benchmark's anchoring outliers are 13-21 cm) sees the
// surfaces of room A where they are not. What no other keyframe's beam crosses (behind a wall,
// under a column's foot) is not transient and, without the multi-view rule, becomes an object
// that only that keyframe saw; with it, the only object is still the box.
TEST(ChangeDetector, WhatOneKeyframeAloneSawIsNotANewObject) {
    const test::ChangeScene& s = SharedChangeScene();
    std::vector<MapKeyframe> keyframes = s.keyframes;
    const size_t off = keyframes.size() / 2;
    keyframes[off].T_world_lidar.pretranslate(Eigen::Vector3d(0.15, -0.10, 0.0));
    const auto only_off = [&](const ChangeResult& r) {
        size_t n = 0;
        for (const NewObject& obj : r.objects) {
            n += std::all_of(obj.points.begin(), obj.points.end(), [&](uint32_t i) {
                return r.map.keyframes[i] == 1 && r.map.first_keyframe[i] == off;
            });
        }
        return n;
    };
    ChangeDetectorConfig any_view = GivenPoses();
    any_view.min_multi_view_fraction = 0;
    const ChangeResult before = DetectChanges(s.model, keyframes, any_view);
    EXPECT_GE(only_off(before), 1u) << Describe(before);
    EXPECT_EQ(before.counts.single_view_clusters, 0u);

    const ChangeResult after = DetectChanges(s.model, keyframes, GivenPoses());
    EXPECT_EQ(only_off(after), 0u) << Describe(after);
    EXPECT_GE(after.counts.single_view_clusters, 1u);
    ASSERT_EQ(after.objects.size(), 1u) << Describe(after);
    EXPECT_TRUE(Eigen::AlignedBox3d(after.objects[0].box_min, after.objects[0].box_max)
                    .intersects(s.added_box));
}

// Issue 31 (Duplex_A, hand-held, seed 3): a clutter box 0.56 m high seen from above only (its
// top; its sides hidden) came out as a slab floating at 0.55-0.58 m, 3 cm high, whose centre was
// 0.32 m from the true box's: a miss and a false alarm. The floor under it is what the box hid
// from every keyframe, so the object stands on it; a table's top, with the floor seen under it,
// still floats. Two keyframes 1.5 m up in room A see a 0.4 m square top at 0.55 m and the floor
// around it (and, for the table, under it). Issue 33 (Duplex_A, seed 1, v3): the same top
// turned 30 deg about z stands on the floor too, though its axis-aligned box holds floor in view.
TEST(ChangeDetector, AnObjectSeenFromAboveOnlyStandsOnTheFloorItHidesAndATableTopDoesNot) {
    const test::ChangeScene& s = SharedChangeScene();
    const auto walk = [&](bool floor_under, double max_drop_m, float yaw_deg = 0) {
        const std::vector<Eigen::Vector3f> sensors = {{5.5f, 1.0f, 1.5f}, {7.0f, 1.8f, 1.5f}};
        const Eigen::Rotation2Df turn(-yaw_deg * float(M_PI) / 180);  // world to the top's axes
        std::vector<common::PointCloud> clouds(sensors.size());
        for (size_t k = 0; k < sensors.size(); ++k) {
            for (float x = 5.8f; x <= 7.2f; x += 0.025f) {
                for (float y = 0.8f; y <= 2.2f; y += 0.025f) {
                    const Eigen::Vector2f d = turn * Eigen::Vector2f(x - 6.5f, y - 1.5f);
                    const bool under = std::abs(d.x()) <= 0.2f && std::abs(d.y()) <= 0.2f;
                    if (under) clouds[k].xyz.push_back(Eigen::Vector3f(x, y, 0.55f) - sensors[k]);
                    if (!under || floor_under) {
                        clouds[k].xyz.push_back(Eigen::Vector3f(x, y, 0.0f) - sensors[k]);
                    }
                }
            }
        }
        std::vector<MapKeyframe> keyframes(sensors.size());
        for (size_t k = 0; k < sensors.size(); ++k) {
            keyframes[k].cloud = &clouds[k];
            keyframes[k].T_world_lidar =
                Eigen::Isometry3d(Eigen::Translation3d(sensors[k].cast<double>()));
        }
        ChangeDetectorConfig config = GivenPoses();
        config.detect_transients = false;  // no ring channel, and nothing here walks
        config.max_unseen_support_drop_m = max_drop_m;
        return DetectChanges(s.model, keyframes, config);
    };
    const ChangeResult before = walk(false, 0.0);  // the rule off: the box floats, as before
    ASSERT_EQ(before.objects.size(), 1u) << Describe(before);
    EXPECT_FALSE(before.objects[0].on_floor);
    EXPECT_GT(before.objects[0].box_min.z(), 0.5) << Describe(before);

    const ChangeResult box = walk(false, 3.0);
    ASSERT_EQ(box.objects.size(), 1u) << Describe(box);
    EXPECT_TRUE(box.objects[0].on_floor);
    EXPECT_NEAR(box.objects[0].box_min.z(), 0.0, 0.01) << Describe(box);
    EXPECT_NEAR(box.objects[0].box_max.z(), 0.55, 0.03) << Describe(box);

    const ChangeResult turned = walk(false, 3.0, 30);
    ASSERT_EQ(turned.objects.size(), 1u) << Describe(turned);
    EXPECT_TRUE(turned.objects[0].on_floor);
    EXPECT_NEAR(turned.objects[0].box_min.z(), 0.0, 0.01) << Describe(turned);
    EXPECT_NEAR(std::fmod(turned.objects[0].plan.yaw_deg, 90.0), 30, 2)
        << Describe(turned);  // a square

    const ChangeResult table = walk(true, 3.0);
    ASSERT_EQ(table.objects.size(), 1u) << Describe(table);
    EXPECT_FALSE(table.objects[0].on_floor);
    EXPECT_GT(table.objects[0].box_min.z(), 0.5) << Describe(table);

    ChangeDetectorConfig bad = GivenPoses();
    bad.max_unseen_support_drop_m = -1;
    EXPECT_THROW(bad.Validate(), common::Error);
}

TEST(ChangeDetector, RejectsAModelWithoutGeometryAndASessionWithoutKeyframes) {
    const test::ChangeScene& s = SharedChangeScene();
    try {
        DetectChanges(ChangeModel{}, s.keyframes, ChangeDetectorConfig{});
        ADD_FAILURE() << "no error";
    } catch (const common::Error& e) {
        EXPECT_EQ(e.code(), common::StatusCode::kInvalidArgument);
        EXPECT_NE(std::string(e.what()).find("no geometry"), std::string::npos) << e.what();
    }
    try {
        DetectChanges(s.model, {}, ChangeDetectorConfig{});
        ADD_FAILURE() << "no error";
    } catch (const common::Error& e) {
        EXPECT_NE(std::string(e.what()).find("no keyframes"), std::string::npos) << e.what();
    }
    ChangeDetectorConfig bad;
    bad.band_threshold_m = 0.2;
    EXPECT_THROW(DetectChanges(s.model, s.keyframes, bad), common::Error);
    bad = ChangeDetectorConfig{};
    bad.min_multi_view_fraction = 1.5;
    EXPECT_THROW(DetectChanges(s.model, s.keyframes, bad), common::Error);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::changes
