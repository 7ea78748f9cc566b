// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The reference session's walk over every storey (host_tools/bim/reference_walk.hpp): on the
// sample office, one connected walk up its flight, with keyframes on it; the hall's three storeys
// joined by its two flights; without the flight's geometry, the storeys walked apart with a note;
// a region joined to no other (a room walled up) walked as a piece of its own.
#include "host_tools/bim/reference_walk.hpp"

#include <gtest/gtest.h>

#include <regex>

#include "host_tools/bim/ifc_model.hpp"
#include "host_tools/bim/reference_session.hpp"
#include "host_tools/bim/sample_building.hpp"
#include "host_tools/bim/stairs.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::bim {
namespace {
namespace BIMSLAM_UNITY_ID {

BimModel SampleOffice() { return ParseIfc("office.ifc", SampleBuildingIfc()); }

ReferenceWalk WalkAll(const BimModel& model) {
    return PlanReferenceWalk(model, StoreyIndices(model, {}), GridConfig{}, PathConfig{});
}

// No jump anywhere in a piece: consecutive poses at most `step` apart, stamps increasing.
void ExpectContinuous(const std::vector<io::StampedPose>& piece, double step) {
    for (size_t i = 1; i < piece.size(); ++i) {
        ASSERT_GT(piece[i].stamp_ns, piece[i - 1].stamp_ns) << i;
        ASSERT_LE((piece[i].translation - piece[i - 1].translation).norm(), step) << i;
    }
}

TEST(ReferenceWalk, TheOfficesStoreysAreOneWalkUpItsFlight) {
    const BimModel model = SampleOffice();
    const ReferenceWalk w = WalkAll(model);
    ASSERT_EQ(w.storeys, (std::vector<int>{0, 1}));
    EXPECT_TRUE(w.notes.empty()) << w.notes.front();
    EXPECT_EQ(w.flights_walked, 1u);
    ASSERT_EQ(w.pieces.size(), 1u) << "one connected walk";
    const std::vector<io::StampedPose>& p = w.pieces[0];
    ExpectContinuous(p, 0.25);  // the walk's 0.1 m spacing; a riser's 0.2 m rise
    const PathConfig c;
    const double ground = model.storeys[0].elevation_m + c.sensor_height_m;
    const double first = model.storeys[1].elevation_m + c.sensor_height_m;
    EXPECT_NEAR(p.front().translation.z(), ground, 1e-9);
    EXPECT_NEAR(p.back().translation.z(), first, 1e-9);
    // Segments: the ground floor, the way up the flight, the first floor, in time order; the
    // flight's poses rise from one floor's height to the other's, never lower than they were.
    ASSERT_EQ(w.segments.size(), 3u);
    EXPECT_FALSE(w.segments[0].flight);
    EXPECT_TRUE(w.segments[1].flight);
    EXPECT_EQ(w.segments[2].storey, 1);
    double z = ground;
    size_t on_flight = 0;
    for (const io::StampedPose& q : p) {
        const WalkSegment& s = w.SegmentAt(q.stamp_ns);
        if (!s.flight) {
            EXPECT_NEAR(q.translation.z(), s.storey == 0 ? ground : first, 1e-9);
            continue;
        }
        ++on_flight;
        EXPECT_GE(q.translation.z(), z - 1e-9);
        z = q.translation.z();
    }
    EXPECT_NEAR(z, first, 1e-9);
    const double flight_m = FindStairFlights(model)[0].LengthM();
    EXPECT_GT(double(on_flight) * c.spacing_m, flight_m) << "the flight and the ways to it";
}

TEST(ReferenceWalk, TheReferenceSessionHasKeyframesOnTheFlight) {
    test::TempDir tmp;
    ReferenceSessionOptions o;
    o.keyframe_gap_m = 1.0;
    o.lidar = simulation::LidarModel::DefaultOs1_32(256);
    const ReferenceSessionReport r = WriteReferenceSession(SampleOffice(), "ab12", tmp / "s", o);
    EXPECT_EQ(r.flights_walked, 1u);
    // 3.2 m of climb over about 4.5 m of flight, plus the ways to and from it.
    EXPECT_GE(r.flight_keyframes, 5u);
    size_t on_floors = 0;
    for (const StoreyReport& s : r.storeys) on_floors += s.keyframes;
    EXPECT_EQ(on_floors + r.flight_keyframes, r.keyframes);
}

TEST(ReferenceWalk, TheHallsThreeStoreysAreJoinedByItsTwoFlights) {
    SampleBuildingOptions options;
    options.layout = BuildingLayout::kHall;
    const ReferenceWalk w = WalkAll(ParseIfc("hall.ifc", SampleBuildingIfc(options)));
    EXPECT_EQ(w.storeys.size(), 3u);
    EXPECT_EQ(w.flights_walked, 2u);
    ASSERT_EQ(w.pieces.size(), 1u) << (w.notes.empty() ? "" : w.notes.front());
    ExpectContinuous(w.pieces[0], 0.25);
}

TEST(ReferenceWalk, StoreysThatNoFlightJoinsAreWalkedApartWithANote) {
    // The flight's representation removed from the file (as stairs_test.cpp does).
    std::string text = SampleBuildingIfc();
    const std::regex flight(R"((IFCSTAIRFLIGHT\('[^']*',#\d+,'[^']*',\$,\$,#\d+,)#\d+)");
    ASSERT_TRUE(std::regex_search(text, flight));
    text = std::regex_replace(text, flight, "$1$$");
    const ReferenceWalk w = WalkAll(ParseIfc("office.ifc", text));
    EXPECT_EQ(w.flights_walked, 0u);
    ASSERT_EQ(w.pieces.size(), 2u);
    EXPECT_GE(w.pieces[1].front().stamp_ns, w.pieces[0].back().stamp_ns + 1'000'000'000);
    std::string all;
    for (const std::string& n : w.notes) all += n + "\n";
    EXPECT_NE(all.find("storeys 'Ground Floor' and 'First Floor' are not joined in the reference"),
              std::string::npos)
        << all;
}

// The sample office with office 0.01's only door walled up: the IfcRelVoidsElement of the door's
// opening removed, so the wall is whole. The office is then an enclosed region of its own on the
// ground floor, joined to the rest by nothing (as Duplex_A's two dwellings are joined outside
// only).
std::string OfficeWithARoomWalledUp() {
    std::string text = SampleBuildingIfc();
    const std::regex door(R"(#(\d+)=IFCDOOR\('[^']*',#\d+,'Door 0\.01-1')");
    std::smatch d;
    EXPECT_TRUE(std::regex_search(text, d, door));
    const std::regex fills("IFCRELFILLSELEMENT\\('[^']*',#\\d+,\\$,\\$,#(\\d+),#" + d[1].str() +
                           "\\)");
    std::smatch f;
    EXPECT_TRUE(std::regex_search(text, f, fills));
    const std::regex voids("#\\d+=IFCRELVOIDSELEMENT\\('[^']*',#\\d+,\\$,\\$,#\\d+,#" + f[1].str() +
                           "\\);\n");
    const std::string walled = std::regex_replace(text, voids, "");
    EXPECT_LT(walled.size(), text.size()) << "the opening's void";
    return walled;
}

TEST(ReferenceWalk, AnEnclosedRegionJoinedToNoOtherIsWalkedAsAPieceOfItsOwn) {
    const BimModel model = ParseIfc("office.ifc", OfficeWithARoomWalledUp());
    const ReferenceWalk w = WalkAll(model);
    // The ground floor's regions: the building, then the walled-up office (about 28 m2).
    ASSERT_GE(w.grids[0].region_areas_m2.size(), 2u);
    EXPECT_GT(w.grids[0].region_areas_m2[1], kMinWalkedRegionM2);
    ASSERT_EQ(w.more_regions.size(), 1u);
    const RegionWalk& r = w.more_regions[0];
    EXPECT_EQ(r.storey, 0);
    EXPECT_EQ(r.region, 1);
    EXPECT_EQ(w.flights_walked, 1u) << "the storeys are still joined by the flight";
    // Two pieces: the building up its flight, then the office, a second later, every pose of it
    // on the office's free cells and none on the first walk's.
    ASSERT_EQ(w.pieces.size(), 2u);
    EXPECT_GE(w.pieces[1].front().stamp_ns, w.pieces[0].back().stamp_ns + 1'000'000'000);
    ExpectContinuous(w.pieces[1], 0.25);
    for (const io::StampedPose& p : w.pieces[1]) {
        int x, y;
        ASSERT_TRUE(r.grid.ToCell(p.translation.head<2>(), &x, &y));
        ASSERT_EQ(r.grid.At(x, y), Cell::kFree);
        ASSERT_TRUE(w.grids[0].ToCell(p.translation.head<2>(), &x, &y));
        ASSERT_NE(w.grids[0].At(x, y), Cell::kFree);
    }
    EXPECT_EQ(w.SegmentAt(w.pieces[1].back().stamp_ns).storey, 0);
    std::string all;
    for (const std::string& n : w.notes) all += n + "\n";
    EXPECT_NE(all.find("storey 'Ground Floor': its second enclosed region"), std::string::npos)
        << all;
    // The reference session counts it on its storey.
    test::TempDir tmp;
    ReferenceSessionOptions o;
    o.lidar = simulation::LidarModel::DefaultOs1_32(256);
    const ReferenceSessionReport rep = WriteReferenceSession(model, "ab12", tmp / "s", o);
    ASSERT_EQ(rep.storeys.size(), 2u);
    EXPECT_EQ(rep.storeys[0].regions, 2);
    EXPECT_EQ(rep.storeys[1].regions, 1);
}

TEST(ReferenceWalk, SmallPocketsGetNoWalkOfTheirOwn) {
    const ReferenceWalk w = WalkAll(SampleOffice());  // pockets of 1.4 m2 and less
    ASSERT_GE(w.grids[0].region_areas_m2.size(), 2u);
    EXPECT_LT(w.grids[0].region_areas_m2[1], kMinWalkedRegionM2);
    EXPECT_TRUE(w.more_regions.empty());
    EXPECT_EQ(w.pieces.size(), 1u);
}

TEST(ReferenceWalk, OneStoreyIsItsCoverageWalk) {
    const BimModel model = SampleOffice();
    const ReferenceWalk w = PlanReferenceWalk(model, {1}, GridConfig{}, PathConfig{});
    ASSERT_EQ(w.pieces.size(), 1u);
    EXPECT_EQ(w.flights_walked, 0u);
    EXPECT_TRUE(w.notes.empty());
    ASSERT_EQ(w.pieces[0].size(), w.coverage[0].poses.size());
    EXPECT_EQ(w.pieces[0].back().stamp_ns, w.coverage[0].poses.back().stamp_ns);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::bim
