// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The sample building: its layout (every room reachable, a slanted wall, the stair between the
// storeys), its IFC4 text (framing, GlobalIds, references, units, determinism) and, read back by
// the project's IFC reader (IFC++), the same building in metres and in millimetres.
#include "host_tools/bim/sample_building.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <queue>
#include <set>
#include <string>
#include <vector>

#include "algorithms/common/status.hpp"
#include "algorithms/io/file_util.hpp"
#include "host_tools/bim/ifc_model.hpp"
#include "tests/support/test_support.hpp"
#include "tests/unit/bim/sample_ifc_support.hpp"

namespace bimslam::bim {
namespace {
namespace BIMSLAM_UNITY_ID {

using Eigen::Vector2d;
using Eigen::Vector3d;

SampleBuildingOptions Millimetres(uint64_t seed = 1) {
    SampleBuildingOptions o;
    o.length_unit_m = 0.001;
    o.seed = seed;
    return o;
}

// ---- the text ----------------------------------------------------------------------------

TEST(SampleBuilding, IsFramedIso10303Ifc4Text) {
    const std::string text = SampleBuildingIfc();
    EXPECT_EQ(text.rfind("ISO-10303-21;\nHEADER;\n", 0), 0u);
    const std::string tail = "ENDSEC;\nEND-ISO-10303-21;\n";
    ASSERT_GT(text.size(), tail.size());
    EXPECT_EQ(text.substr(text.size() - tail.size()), tail);
    EXPECT_NE(text.find("FILE_SCHEMA(('IFC4'));"), std::string::npos);
    EXPECT_NE(text.find("FILE_DESCRIPTION(('ViewDefinition ["), std::string::npos);
    EXPECT_NE(text.find("IFCSIUNIT(*,.LENGTHUNIT.,$,.METRE.)"), std::string::npos);
    EXPECT_NE(SampleBuildingIfc(Millimetres()).find("IFCSIUNIT(*,.LENGTHUNIT.,.MILLI.,.METRE.)"),
              std::string::npos);
    for (const char c : text) {
        EXPECT_TRUE(c == '\n' || (c >= 0x20 && c < 0x7f)) << "byte " << int(c);
    }
}

TEST(SampleBuilding, EveryReferencePointsToAnEntityDefinedOnce) {
    const auto data = ParseData(SampleBuildingIfc());
    ASSERT_GT(data.size(), 1000u);
    // Numbered 1..n without gaps.
    EXPECT_EQ(data.begin()->first, 1);
    EXPECT_EQ(data.rbegin()->first, int(data.size()));
    size_t refs = 0;
    for (const auto& [id, e] : data) {
        for (const Token& t : e.args) {
            if (t.kind != Token::kRef) continue;
            ++refs;
            EXPECT_EQ(data.count(std::stoi(t.text)), 1u) << "#" << id << " refers to #" << t.text;
        }
    }
    EXPECT_GT(refs, data.size());
}

TEST(SampleBuilding, GlobalIdsAreUniqueValidAndDeterministic) {
    // The classes of IfcRoot the generator writes: their first attribute is the GlobalId.
    const std::set<std::string> roots = {
        "IFCPROJECT",        "IFCSITE",    "IFCBUILDING",  "IFCBUILDINGSTOREY",
        "IFCSPACE",          "IFCWALL",    "IFCDOOR",      "IFCWINDOW",
        "IFCOPENINGELEMENT", "IFCSLAB",    "IFCCOLUMN",    "IFCSTAIR",
        "IFCSTAIRFLIGHT",    "IFCRAILING", "IFCFURNITURE", "IFCPROPERTYSET"};
    const std::string alphabet = "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz_$";
    auto ids_of = [&](const std::string& text) {
        std::vector<std::string> ids;
        for (const auto& [id, e] : ParseData(text)) {
            if (!roots.count(e.cls) && e.cls.rfind("IFCREL", 0) != 0) continue;
            EXPECT_EQ(e.args.at(0).kind, Token::kString) << e.cls << " #" << id;
            ids.push_back(e.args.at(0).text);
        }
        return ids;
    };
    const std::vector<std::string> ids = ids_of(SampleBuildingIfc());
    ASSERT_GT(ids.size(), 300u);
    EXPECT_EQ(std::set<std::string>(ids.begin(), ids.end()).size(), ids.size()) << "duplicates";
    for (const std::string& id : ids) {
        ASSERT_EQ(id.size(), 22u) << id;
        EXPECT_NE(std::string("0123").find(id[0]), std::string::npos) << id;  // 2 bits
        EXPECT_EQ(id.find_first_not_of(alphabet), std::string::npos) << id;
    }
    // The same elements keep their ids in the millimetre file; another seed gives other ids.
    EXPECT_EQ(ids_of(SampleBuildingIfc(Millimetres())), ids);
    SampleBuildingOptions other;
    other.seed = 2;
    other.furniture = false;
    const std::vector<std::string> other_ids = ids_of(SampleBuildingIfc(other));
    for (const std::string& id : other_ids) {
        EXPECT_EQ(std::find(ids.begin(), ids.end(), id), ids.end()) << id;
    }
}

TEST(SampleBuilding, SameSeedSameBytesOtherSeedOtherFurniture) {
    EXPECT_EQ(SampleBuildingIfc(), SampleBuildingIfc());
    SampleBuildingOptions a, b;
    a.seed = 7;
    b.seed = 8;
    EXPECT_EQ(SampleBuildingIfc(a), SampleBuildingIfc(a));
    EXPECT_NE(SampleBuildingIfc(a), SampleBuildingIfc(b));
    // The seed moves furniture, never the building.
    const SampleLayout la = SampleBuildingLayout(a), lb = SampleBuildingLayout(b);
    EXPECT_EQ(la.walls.size(), lb.walls.size());
    EXPECT_EQ(la.doors.size(), lb.doors.size());
    EXPECT_EQ(la.windows.size(), lb.windows.size());
    bool furniture_differs = la.furniture.size() != lb.furniture.size();
    for (size_t i = 0; !furniture_differs && i < la.furniture.size(); ++i) {
        furniture_differs = la.furniture[i].centre != lb.furniture[i].centre ||
                            la.furniture[i].size != lb.furniture[i].size;
    }
    EXPECT_TRUE(furniture_differs);
}

TEST(SampleBuilding, MillimetreFileHoldsEveryLengthTimesAThousand) {
    const auto m = ParseData(SampleBuildingIfc());
    const auto mm = ParseData(SampleBuildingIfc(Millimetres()));
    ASSERT_EQ(m.size(), mm.size());
    size_t lengths = 0;
    for (const auto& [id, a] : m) {
        const Entity& b = mm.at(id);
        ASSERT_EQ(a.cls, b.cls) << "#" << id;
        ASSERT_EQ(a.args.size(), b.args.size()) << "#" << id;
        for (size_t k = 0; k < a.args.size(); ++k) {
            const Token& x = a.args[k];
            const Token& y = b.args[k];
            ASSERT_EQ(x.kind, y.kind) << "#" << id;
            // Every real outside a direction is a length (or the context's precision, also one).
            if (x.kind == Token::kReal && a.cls != "IFCDIRECTION") {
                ++lengths;
                const double vm = std::stod(x.text), vmm = std::stod(y.text);
                EXPECT_NEAR(vmm, 1000.0 * vm, 1e-9 * std::max(1.0, std::abs(vmm)))
                    << a.cls << " #" << id << ": " << x.text << " m vs " << y.text << " mm";
            } else if (a.cls != "IFCSIUNIT") {  // the length unit's prefix differs
                EXPECT_EQ(x.text, y.text) << a.cls << " #" << id;
            }
        }
    }
    EXPECT_GT(lengths, 3000u);
}

TEST(SampleBuilding, CountsPerClassFollowTheLayout) {
    const SampleLayout L = SampleBuildingLayout();
    const auto data = ParseData(SampleBuildingIfc());
    size_t slab_openings = 0;
    for (const SampleSlab& s : L.slabs) slab_openings += s.openings.size();
    EXPECT_EQ(CountClass(data, "IFCBUILDINGSTOREY"), 2u);
    EXPECT_EQ(CountClass(data, "IFCSPACE"), L.rooms.size());
    EXPECT_EQ(CountClass(data, "IFCWALL"), L.walls.size());
    EXPECT_EQ(CountClass(data, "IFCDOOR"), L.doors.size());
    EXPECT_EQ(CountClass(data, "IFCWINDOW"), L.windows.size());
    EXPECT_EQ(CountClass(data, "IFCCOLUMN"), L.columns.size());
    EXPECT_EQ(CountClass(data, "IFCSLAB"), L.slabs.size());
    EXPECT_EQ(CountClass(data, "IFCSTAIR"), 1u);
    EXPECT_EQ(CountClass(data, "IFCSTAIRFLIGHT"), 1u);
    EXPECT_EQ(CountClass(data, "IFCRAILING"), L.railings.size());
    EXPECT_EQ(CountClass(data, "IFCFURNITURE"), L.furniture.size());
    EXPECT_EQ(CountClass(data, "IFCOPENINGELEMENT"),
              L.doors.size() + L.windows.size() + slab_openings);
    EXPECT_EQ(CountClass(data, "IFCRELVOIDSELEMENT"), CountClass(data, "IFCOPENINGELEMENT"));
    EXPECT_EQ(CountClass(data, "IFCRELFILLSELEMENT"), L.doors.size() + L.windows.size());
    EXPECT_EQ(CountClass(data, "IFCRELCONTAINEDINSPATIALSTRUCTURE"), 2u);
    EXPECT_EQ(CountClass(data, "IFCWALLSTANDARDCASE"), 0u);

    SampleBuildingOptions bare;
    bare.furniture = false;
    EXPECT_TRUE(SampleBuildingLayout(bare).furniture.empty());
    EXPECT_EQ(CountClass(ParseData(SampleBuildingIfc(bare)), "IFCFURNITURE"), 0u);
}

TEST(SampleBuilding, RejectsOtherUnits) {
    SampleBuildingOptions o;
    o.length_unit_m = 0.3048;
    EXPECT_THROW(SampleBuildingIfc(o), common::Error);
    EXPECT_THROW(SampleBuildingLayout(o), common::Error);
}

TEST(SampleBuilding, WritesTheFileAtomically) {
    test::TempDir tmp;
    WriteSampleBuilding(tmp / "b.ifc", Millimetres(3));
    EXPECT_EQ(io::ReadFileToString(tmp / "b.ifc"), SampleBuildingIfc(Millimetres(3)));
    EXPECT_THROW(WriteSampleBuilding(tmp / "missing" / "b.ifc"), common::FileError);
}

// ---- the layout ----------------------------------------------------------------------------

TEST(SampleLayout, TwoStoreysOfOfficesAlongACorridor) {
    const SampleLayout L = SampleBuildingLayout();
    ASSERT_EQ(L.storeys.size(), 2u);
    EXPECT_EQ(L.storeys[0].name, "Ground Floor");
    EXPECT_EQ(L.storeys[1].name, "First Floor");
    EXPECT_DOUBLE_EQ(L.storeys[0].elevation_m, 0.0);
    EXPECT_DOUBLE_EQ(L.storeys[1].elevation_m, 3.2);
    for (int s = 0; s < 2; ++s) {
        const int corridor = L.Corridor(s);
        ASSERT_GE(corridor, 0);
        // Along the building: most of its length.
        EXPECT_GT(L.rooms[corridor].Bounds().sizes().x(), 25.0);
        std::set<long> areas;
        int rooms = 0, south = 0, north = 0;
        for (const SampleRoom& r : L.rooms) {
            if (r.storey != s || r.Circulation()) continue;
            ++rooms;
            areas.insert(std::lround(r.Area() * 10));
            (r.Bounds().center().y() < L.rooms[corridor].Bounds().center().y() ? south : north)++;
            EXPECT_GT(r.Area(), 10.0) << r.number;
        }
        EXPECT_GE(rooms, 4);
        EXPECT_GE(south, 2);
        EXPECT_GE(north, 2);
        EXPECT_GE(areas.size(), 4u) << "rooms of different sizes";
    }
    const Eigen::AlignedBox3d box = L.Bounds();
    EXPECT_TRUE(box.min().isApprox(Vector3d(0, 0, -0.2)));
    EXPECT_TRUE(box.max().isApprox(Vector3d(30, 15, 6.4)));
}

TEST(SampleLayout, WallsDoorsAndWindows) {
    const SampleLayout L = SampleBuildingLayout();
    int slanted = 0;
    for (const SampleWall& w : L.walls) {
        slanted += w.Slanted();
        EXPECT_NEAR(w.thickness_m, w.exterior ? 0.3 : 0.15, 1e-12) << w.name;
        EXPECT_NEAR(w.height_m, 3.0, 1e-12);
    }
    EXPECT_GE(slanted, 1);
    for (const SampleDoor& d : L.doors) {
        const SampleWall& w = L.walls[d.wall];
        EXPECT_EQ(d.storey, w.storey);
        // On the wall's centreline, within its length, clear of its ends.
        EXPECT_LT((w.start + d.offset_m * w.Direction() - d.centre).norm(), 1e-9) << d.name;
        EXPECT_GT(d.offset_m - d.width_m / 2, 0.0) << d.name;
        EXPECT_LT(d.offset_m + d.width_m / 2, w.Length()) << d.name;
        EXPECT_NEAR(d.height_m, 2.1, 1e-12);
        if (d.rooms[0] >= 0) {
            EXPECT_GE(d.width_m, 0.9);
            EXPECT_LE(d.width_m, 1.0);
        }
        // Each side of the door is in the room it names (or outside the footprint).
        const Vector2d n(-w.Direction().y(), w.Direction().x());
        const Vector2d a = d.centre + n * (w.thickness_m / 2 + 0.3);
        const Vector2d b = d.centre - n * (w.thickness_m / 2 + 0.3);
        for (const int r : d.rooms) {
            if (r < 0) {
                const bool outside = a.x() < 0 || a.y() < 0 || b.x() < 0 || b.y() < 0 ||
                                     a.x() > 30 || b.x() > 30 || a.y() > 15 || b.y() > 15;
                EXPECT_TRUE(outside) << d.name;
            } else {
                EXPECT_EQ(L.rooms[r].storey, d.storey);
                EXPECT_TRUE(L.rooms[r].Contains(a) || L.rooms[r].Contains(b)) << d.name;
            }
        }
    }
    for (const SampleWindow& win : L.windows) {
        EXPECT_TRUE(L.walls[win.wall].exterior) << win.name;
        EXPECT_NEAR(win.sill_m, 0.9, 1e-12);
        EXPECT_GT(win.offset_m - win.width_m / 2, 0.0);
        EXPECT_LT(win.offset_m + win.width_m / 2, L.walls[win.wall].Length());
    }
}

TEST(SampleLayout, EveryRoomIsReachableThroughDoorsAndTheStair) {
    for (const bool exterior : {false, true}) {
        SampleBuildingOptions o;
        o.exterior_doors = exterior;
        const SampleLayout L = SampleBuildingLayout(o);
        std::vector<std::vector<int>> next(L.rooms.size());
        for (const SampleDoor& d : L.doors) {
            if (d.rooms[0] < 0 || d.rooms[1] < 0) continue;
            next[d.rooms[0]].push_back(d.rooms[1]);
            next[d.rooms[1]].push_back(d.rooms[0]);
        }
        ASSERT_EQ(L.stairs.size(), 1u);
        const SampleStair& st = L.stairs[0];
        next[st.room_bottom].push_back(st.room_top);
        next[st.room_top].push_back(st.room_bottom);
        std::vector<bool> seen(L.rooms.size(), false);
        std::queue<int> q;
        q.push(L.Corridor(0));
        seen[L.Corridor(0)] = true;
        while (!q.empty()) {
            const int r = q.front();
            q.pop();
            for (const int n : next[r]) {
                if (!seen[n]) q.push(n), seen[n] = true;
            }
        }
        for (size_t r = 0; r < L.rooms.size(); ++r) {
            EXPECT_TRUE(seen[r]) << L.rooms[r].number << " " << L.rooms[r].name;
        }
        // Every room but the corridors has a door of its own to its storey's corridor.
        for (size_t r = 0; r < L.rooms.size(); ++r) {
            if (L.rooms[r].kind == RoomKind::kCorridor) continue;
            const bool door = std::any_of(L.doors.begin(), L.doors.end(), [&](const auto& d) {
                return d.rooms[1] == int(r) && d.rooms[0] == L.Corridor(L.rooms[r].storey);
            });
            EXPECT_TRUE(door) << L.rooms[r].number;
        }
        size_t outside = 0;
        for (const SampleDoor& d : L.doors) outside += d.rooms[0] < 0;
        EXPECT_EQ(outside, exterior ? 2u : 0u);
    }
}

TEST(SampleLayout, StairClimbsOneStoreyThroughTheSlabOpening) {
    const SampleLayout L = SampleBuildingLayout();
    ASSERT_EQ(L.stairs.size(), 1u);
    const SampleStair& st = L.stairs[0];
    EXPECT_EQ(st.storey, 0);
    EXPECT_NEAR(st.risers * st.riser_m, L.storeys[1].elevation_m - L.storeys[0].elevation_m, 1e-9);
    EXPECT_EQ(L.rooms[st.room_bottom].kind, RoomKind::kStair);
    EXPECT_EQ(L.rooms[st.room_top].kind, RoomKind::kStair);
    EXPECT_EQ(L.rooms[st.room_top].storey, 1);
    const Eigen::AlignedBox2d flight = st.Footprint();
    EXPECT_TRUE(L.rooms[st.room_bottom].Contains(flight.min()));
    EXPECT_TRUE(L.rooms[st.room_bottom].Contains(flight.max()));
    // The first floor's slab has an opening over the whole flight.
    bool covered = false;
    for (const SampleSlab& s : L.slabs) {
        if (s.storey != 1 || s.roof) continue;
        for (const auto& o : s.openings) covered |= o.contains(flight);
    }
    EXPECT_TRUE(covered);
    // Its top tread is one riser below the upper floor; the landing beyond it is free.
    EXPECT_NEAR((st.risers - 1) * st.riser_m, 3.0, 1e-9);
}

TEST(SampleLayout, FurnitureStandsInItsRoomAndKeepsDoorsClear) {
    for (const uint64_t seed : {1, 2, 3, 42, 1000}) {
        SampleBuildingOptions o;
        o.seed = seed;
        const SampleLayout L = SampleBuildingLayout(o);
        ASSERT_GE(L.furniture.size(), 10u) << "seed " << seed;
        for (size_t i = 0; i < L.furniture.size(); ++i) {
            const SampleFurniture& f = L.furniture[i];
            const Eigen::AlignedBox2d box = f.Footprint();
            const SampleRoom& room = L.rooms[f.room];
            EXPECT_FALSE(room.Circulation()) << f.name;
            for (const Vector2d& c : {box.min(), box.max(), Vector2d(box.min().x(), box.max().y()),
                                      Vector2d(box.max().x(), box.min().y())}) {
                EXPECT_TRUE(room.Contains(c)) << f.name << " seed " << seed;
            }
            for (const SampleDoor& d : L.doors) {
                if (d.storey != f.storey) continue;
                // The door's clear passage, 1.2 m into the rooms on both sides.
                const Eigen::AlignedBox2d pass(d.centre - Vector2d(1.2, 1.2),
                                               d.centre + Vector2d(1.2, 1.2));
                const SampleWall& w = L.walls[d.wall];
                const bool along_x = std::abs(w.Direction().x()) > 0.5;
                Eigen::AlignedBox2d lane = pass;
                if (along_x) {
                    lane.min().x() = d.centre.x() - d.width_m / 2;
                    lane.max().x() = d.centre.x() + d.width_m / 2;
                } else {
                    lane.min().y() = d.centre.y() - d.width_m / 2;
                    lane.max().y() = d.centre.y() + d.width_m / 2;
                }
                EXPECT_FALSE(lane.intersects(box)) << f.name << " blocks " << d.name;
            }
            for (size_t k = 0; k < i; ++k) {
                if (L.furniture[k].storey != f.storey) continue;
                const Eigen::AlignedBox2d other = L.furniture[k].Footprint();
                const double overlap =
                    other.intersects(box) ? other.intersection(box).volume() : 0.0;
                EXPECT_LE(overlap, 1e-9) << f.name << " overlaps " << L.furniture[k].name;
            }
        }
    }
}

// ---- read back by the project's IFC reader -------------------------------------------------

TEST(SampleBuildingIfc, ReadsBackTheSameBuildingInMetresAndMillimetres) {
    const SampleLayout L = SampleBuildingLayout();
    const BimModel m = ParseIfc("sample_m.ifc", SampleBuildingIfc());
    const BimModel mm = ParseIfc("sample_mm.ifc", SampleBuildingIfc(Millimetres()));
    EXPECT_EQ(m.schema, "IFC4");
    EXPECT_DOUBLE_EQ(m.length_unit_m, 1.0);
    EXPECT_DOUBLE_EQ(mm.length_unit_m, 0.001);
    for (const BimModel* model : {&m, &mm}) {
        ASSERT_EQ(model->storeys.size(), 2u);
        EXPECT_EQ(model->storeys[0].name, "Ground Floor");
        EXPECT_EQ(model->storeys[1].name, "First Floor");
        EXPECT_NEAR(model->storeys[0].elevation_m, 0.0, 1e-9);
        EXPECT_NEAR(model->storeys[1].elevation_m, 3.2, 1e-9);
        for (const FailedElement& f : model->failed) {
            ADD_FAILURE() << model->file << ": " << f.ifc_class << " " << f.global_id << ": "
                          << f.reason;
        }
        const std::map<std::string, size_t> expected = {{"IfcBuildingStorey", 2},
                                                        {"IfcSpace", L.rooms.size()},
                                                        {"IfcWall", L.walls.size()},
                                                        {"IfcDoor", L.doors.size()},
                                                        {"IfcWindow", L.windows.size()},
                                                        {"IfcColumn", L.columns.size()},
                                                        {"IfcSlab", L.slabs.size()},
                                                        {"IfcStair", 1},
                                                        {"IfcStairFlight", 1},
                                                        {"IfcRailing", L.railings.size()},
                                                        {"IfcFurniture", L.furniture.size()}};
        for (const auto& [cls, n] : expected) {
            const auto it = model->class_counts.find(cls);
            EXPECT_EQ(it == model->class_counts.end() ? 0 : it->second, n)
                << model->file << ": " << cls;
        }
        // Every element with a body has triangles, in the layout's box.
        std::map<std::string, size_t> with_geometry;
        for (const BimElement& e : model->elements) {
            EXPECT_GT(e.triangle_count, 0u) << e.ifc_class << " " << e.name;
            ++with_geometry[e.ifc_class];
        }
        EXPECT_EQ(with_geometry["IfcWall"], L.walls.size());
        EXPECT_EQ(with_geometry["IfcDoor"], L.doors.size());
        EXPECT_EQ(with_geometry["IfcWindow"], L.windows.size());
        EXPECT_EQ(with_geometry["IfcFurniture"], L.furniture.size());
        EXPECT_EQ(with_geometry["IfcStairFlight"], 1u);
        const Eigen::AlignedBox3d box = model->Bounds();
        EXPECT_LT((box.min() - L.Bounds().min()).norm(), 1e-4) << box.min().transpose();
        EXPECT_LT((box.max() - L.Bounds().max()).norm(), 1e-4) << box.max().transpose();
    }

    // The same surfaces element by element. Not the same triangles: IFC++ (carve) triangulates
    // the faces its boolean operations leave (walls with openings) differently from run to run,
    // even for one file, so triangle counts and vertex order are not comparable; every vertex
    // of one mesh lies on the other's surface instead, and the areas agree.
    ASSERT_EQ(m.elements.size(), mm.elements.size());
    std::map<std::string, const BimElement*> by_id;
    for (const BimElement& e : mm.elements) by_id[e.global_id] = &e;
    for (const BimElement& e : m.elements) {
        const auto it = by_id.find(e.global_id);
        ASSERT_NE(it, by_id.end()) << e.ifc_class << " " << e.name;
        const BimElement& f = *it->second;
        EXPECT_EQ(e.ifc_class, f.ifc_class);
        EXPECT_EQ(e.name, f.name);
        EXPECT_EQ(e.storey, f.storey);
        EXPECT_EQ(e.role, f.role);
        const ElementMesh a = MeshOf(m, e), b = MeshOf(mm, f);
        EXPECT_LT((a.box.min() - b.box.min()).norm(), 1e-4) << e.name;
        EXPECT_LT((a.box.max() - b.box.max()).norm(), 1e-4) << e.name;
        EXPECT_NEAR(a.area, b.area, 1e-4 * std::max(1.0, a.area)) << e.name;
        EXPECT_LT(OneSidedDistance(a, b), 1e-4) << e.name;
        EXPECT_LT(OneSidedDistance(b, a), 1e-4) << e.name;
    }
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::bim
