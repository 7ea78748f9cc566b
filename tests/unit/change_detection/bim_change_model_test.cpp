// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Where a change is placed in the building (issue 31, item 6): a new object on the storey under
// its lowest point, on either storey of a two-storey model; a model element on its own
// IfcBuildingStorey whatever its height, and one contained in no storey by its lowest point.
#include "host_tools/changes/bim_change_model.hpp"

#include <gtest/gtest.h>

#include <string>

#include "tests/unit/bim/synthetic_floor.hpp"

namespace bimslam::change_detection {
namespace {
namespace BIMSLAM_UNITY_ID {

// A column from lo to hi on `storey` (-1: contained in no storey).
void AddBox(bim::BimModel& m, int storey, Eigen::Vector3d lo, Eigen::Vector3d hi) {
    bim::test_floor::AddBox(m, "IfcColumn", bim::ElementRole::kStructure, lo, hi);
    m.elements.back().storey = storey;
}

bim::BimModel TwoStoreys() {
    bim::BimModel m;
    m.storeys = {{"Ground Floor", "g0", 0.0}, {"First Floor", "g1", 3.2}};
    AddBox(m, 0, {0, 0, 0}, {0.3, 0.3, 3.0});      // a column of the ground floor
    AddBox(m, 1, {0, 0, 3.2}, {0.3, 0.3, 6.2});    // one of the first
    AddBox(m, 0, {5, 0, 3.3}, {5.3, 0.3, 4.0});    // declared on the ground floor, set higher
    AddBox(m, -1, {9, 0, 3.25}, {9.3, 0.3, 5.0});  // in no storey, upstairs
    AddBox(m, -1, {9, 0, -0.4}, {9.3, 0.3, 1.0});  // in no storey, below the ground floor
    return m;
}

changes::NewObject Object(double bottom, double top) {
    changes::NewObject o;
    o.box_min = {1, 1, bottom};
    o.box_max = {2, 2, top};
    return o;
}

TEST(PlaceChanges, NewObjectsStandOnTheStoreyUnderThemOnEitherStorey) {
    const bim::BimModel m = TwoStoreys();
    // A crate on the ground floor, one on the first floor's finish (above its elevation), a lamp
    // hanging under the first floor's slab (its bottom on the ground floor's side).
    const std::vector<ObjectPlace> p =
        PlaceObjects(m, {Object(0.0, 0.6), Object(3.25, 3.9), Object(2.4, 2.9)});
    ASSERT_EQ(p.size(), 3u);
    EXPECT_EQ(p[0].storey, 0);
    EXPECT_EQ(p[1].storey, 1);
    EXPECT_EQ(p[2].storey, 0) << "hanging from the first floor's slab, it is in the room below";
    EXPECT_EQ(StoreyUnder(m, 1.0), 0);
    EXPECT_EQ(StoreyUnder(m, -2.0), 0) << "below every storey: the lowest";
    EXPECT_EQ(StoreyUnder(bim::BimModel{}, 1.0), -1);
}

TEST(PlaceChanges, AnElementIsOnItsIfcStoreyElseOnTheStoreyUnderItsLowestPoint) {
    const bim::BimModel m = TwoStoreys();
    bool from_height = true;
    EXPECT_EQ(ElementStorey(m, 0, &from_height), 0);
    EXPECT_FALSE(from_height);
    EXPECT_EQ(ElementStorey(m, 1, &from_height), 1);
    EXPECT_EQ(ElementStorey(m, 2, &from_height), 0) << "its IfcBuildingStorey, not its height";
    EXPECT_FALSE(from_height);
    EXPECT_EQ(ElementStorey(m, 3, &from_height), 1);
    EXPECT_TRUE(from_height);
    EXPECT_EQ(ElementStorey(m, 4, &from_height), 0);
    EXPECT_TRUE(from_height);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::change_detection
