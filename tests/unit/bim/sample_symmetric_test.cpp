// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The "symmetric" sample building (sample_building.hpp): checked numerically, every room, wall,
// door, window, slab and piece of furniture has its mirror image under the mirror about each centre
// line (so under the half turn too), with and without furniture and entrances, for several seeds;
// and the geometry IFC++ reads back from the file is its own mirror image, element by element.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "host_tools/bim/ifc_model.hpp"
#include "host_tools/bim/sample_building.hpp"
#include "tests/unit/bim/sample_ifc_support.hpp"

namespace bimslam::bim {
namespace {
namespace BIMSLAM_UNITY_ID {

using Eigen::AlignedBox2d;
using Eigen::Vector2d;
using Eigen::Vector3d;

constexpr double kTol = 1e-9;

SampleBuildingOptions Symmetric(bool exterior_doors, bool furniture, uint64_t seed) {
    SampleBuildingOptions o;
    o.layout = BuildingLayout::kSymmetric;
    o.exterior_doors = exterior_doors;
    o.furniture = furniture;
    o.seed = seed;
    return o;
}

// The mirror about the centre line x = length / 2 (axis 0) or y = width / 2 (axis 1).
struct Mirror {
    int axis;
    Vector2d footprint;
    Vector2d operator()(const Vector2d& p) const {
        Vector2d q = p;
        q[axis] = footprint[axis] - p[axis];
        return q;
    }
    AlignedBox2d operator()(const AlignedBox2d& b) const {
        const Vector2d a = (*this)(b.min()), c = (*this)(b.max());
        return {a.cwiseMin(c), a.cwiseMax(c)};
    }
};

bool Near(const Vector2d& a, const Vector2d& b) { return (a - b).norm() < kTol; }
bool Near(const AlignedBox2d& a, const AlignedBox2d& b) {
    return Near(a.min(), b.min()) && Near(a.max(), b.max());
}
bool Near(double a, double b) { return std::abs(a - b) < kTol; }

// Each element of `items` has one in `items` that `same(item, mirrored candidate)` accepts.
template <typename T>
void ExpectMirrored(const std::vector<T>& items, const std::string& what,
                    const std::function<bool(const T&, const T&)>& image,
                    const std::function<std::string(const T&)>& name) {
    for (const T& item : items) {
        const bool found = std::any_of(items.begin(), items.end(),
                                       [&](const T& other) { return image(item, other); });
        EXPECT_TRUE(found) << what << " " << name(item) << " has no mirror image";
    }
}

// The room whose polygon holds p inside (not only on its boundary): -1 outdoors.
int RoomAt(const SampleLayout& L, const Vector2d& p) {
    for (size_t r = 0; r < L.rooms.size(); ++r) {
        if (L.rooms[r].Contains(p)) return int(r);
    }
    return -1;
}

void ExpectSymmetric(const SampleLayout& L, const Mirror& M) {
    SCOPED_TRACE("mirror about axis " + std::to_string(M.axis));
    ExpectMirrored<SampleRoom>(
        L.rooms, "room",
        [&](const SampleRoom& a, const SampleRoom& b) {
            if (a.kind != b.kind || a.polygon.size() != b.polygon.size()) return false;
            return std::all_of(a.polygon.begin(), a.polygon.end(), [&](const Vector2d& p) {
                return std::any_of(b.polygon.begin(), b.polygon.end(),
                                   [&](const Vector2d& q) { return Near(M(p), q); });
            });
        },
        [](const SampleRoom& r) { return r.number; });
    ExpectMirrored<SampleWall>(
        L.walls, "wall",
        [&](const SampleWall& a, const SampleWall& b) {
            const bool ends = (Near(M(a.start), b.start) && Near(M(a.end), b.end)) ||
                              (Near(M(a.start), b.end) && Near(M(a.end), b.start));
            return ends && Near(a.thickness_m, b.thickness_m) && Near(a.height_m, b.height_m) &&
                   a.exterior == b.exterior;
        },
        [](const SampleWall& w) { return w.name; });
    ExpectMirrored<SampleDoor>(
        L.doors, "door",
        [&](const SampleDoor& a, const SampleDoor& b) {
            if (!Near(M(a.centre), b.centre) || !Near(a.width_m, b.width_m) ||
                !Near(a.height_m, b.height_m) || a.leaves != b.leaves) {
                return false;
            }
            // It joins the mirror images of the rooms it joins and swings into the image of its
            // room (the leaves stand in rooms[1]).
            for (int k = 0; k < 2; ++k) {
                const int ra = a.rooms[k], rb = b.rooms[k];
                if ((ra < 0) != (rb < 0)) return false;
                if (ra >= 0 && RoomAt(L, M(L.rooms[ra].Bounds().center())) != rb) return false;
            }
            return true;
        },
        [](const SampleDoor& d) { return d.name; });
    ExpectMirrored<SampleWindow>(
        L.windows, "window",
        [&](const SampleWindow& a, const SampleWindow& b) {
            return Near(M(a.centre), b.centre) && Near(a.width_m, b.width_m) &&
                   Near(a.sill_m, b.sill_m) && Near(a.height_m, b.height_m);
        },
        [](const SampleWindow& w) { return w.name; });
    ExpectMirrored<SampleColumn>(
        L.columns, "column",
        [&](const SampleColumn& a, const SampleColumn& b) {
            return Near(M(a.centre), b.centre) && Near(a.size_m, b.size_m) && a.round == b.round;
        },
        [](const SampleColumn& c) { return c.name; });
    ExpectMirrored<SampleSlab>(
        L.slabs, "slab",
        [&](const SampleSlab& a, const SampleSlab& b) {
            if (!Near(M(a.outline), b.outline) || a.openings.size() != b.openings.size()) {
                return false;
            }
            return Near(a.top_m, b.top_m) && Near(a.thickness_m, b.thickness_m);
        },
        [](const SampleSlab& s) { return s.name; });
    ExpectMirrored<SampleFurniture>(
        L.furniture, "furniture",
        [&](const SampleFurniture& a, const SampleFurniture& b) {
            return a.kind == b.kind && Near(M(a.Footprint()), b.Footprint()) &&
                   Near(a.size.z(), b.size.z()) && RoomAt(L, M(a.centre)) == b.room;
        },
        [](const SampleFurniture& f) { return f.name; });
}

TEST(SymmetricLayout, EveryElementHasItsMirrorImageAboutBothCentreLines) {
    for (const bool exterior : {false, true}) {
        for (const bool furniture : {false, true}) {
            for (const uint64_t seed : {1, 2, 3, 42}) {
                if (!furniture && seed != 1) continue;
                SCOPED_TRACE("exterior doors " + std::to_string(exterior) + ", furniture " +
                             std::to_string(furniture) + ", seed " + std::to_string(seed));
                const SampleLayout L = SampleBuildingLayout(Symmetric(exterior, furniture, seed));
                EXPECT_EQ(L.layout, BuildingLayout::kSymmetric);
                if (furniture) {
                    EXPECT_GE(L.furniture.size(), 8u);
                }
                ExpectSymmetric(L, {0, L.footprint_m});
                ExpectSymmetric(L, {1, L.footprint_m});
            }
        }
    }
}

TEST(SymmetricLayout, OneStoreyWithoutStairOrSlantedWallAndTheSameEntranceAtBothEnds) {
    const SampleLayout L = SampleBuildingLayout(Symmetric(true, true, 1));
    ASSERT_EQ(L.storeys.size(), 1u);
    EXPECT_TRUE(L.stairs.empty());
    EXPECT_TRUE(L.railings.empty());
    for (const SampleWall& w : L.walls) EXPECT_FALSE(w.Slanted()) << w.name;
    for (const SampleSlab& s : L.slabs) EXPECT_TRUE(s.openings.empty()) << s.name;
    // Identical rooms on both sides of the corridor, which runs through the middle.
    const AlignedBox2d corridor = L.rooms[L.Corridor(0)].Bounds();
    EXPECT_TRUE(Near(corridor.center(), L.footprint_m / 2));
    int south = 0, north = 0;
    for (const SampleRoom& r : L.rooms) {
        if (r.Circulation()) continue;
        (r.Bounds().center().y() < L.footprint_m.y() / 2 ? south : north)++;
    }
    EXPECT_EQ(south, north);
    EXPECT_GE(south, 4);
    std::vector<SampleDoor> entrances;
    for (const SampleDoor& d : L.doors) {
        if (d.rooms[0] < 0) entrances.push_back(d);
    }
    ASSERT_EQ(entrances.size(), 2u);
    EXPECT_TRUE(Near(entrances[0].centre.x() + entrances[1].centre.x(), L.footprint_m.x()));
    EXPECT_TRUE(Near(entrances[0].centre.y(), L.footprint_m.y() / 2));
    EXPECT_TRUE(Near(entrances[1].centre.y(), L.footprint_m.y() / 2));
    EXPECT_DOUBLE_EQ(entrances[0].width_m, entrances[1].width_m);
    EXPECT_EQ(entrances[0].leaves, 2);  // a double door is its own mirror image
}

// The file as IFC++ reads it: for every element and each mirror, an element of the same class
// whose surface holds the mirrored vertices, and whose vertices lie on the mirrored surface.
TEST(SymmetricLayout, TheGeometryReadBackIsItsOwnMirrorImage) {
    const SampleBuildingOptions o = Symmetric(true, true, 7);
    const SampleLayout L = SampleBuildingLayout(o);
    const BimModel m = ParseIfc("symmetric.ifc", SampleBuildingIfc(o));
    ASSERT_TRUE(m.failed.empty());
    std::vector<ElementMesh> meshes;
    for (const BimElement& e : m.elements) meshes.push_back(MeshOf(m, e));
    for (int axis = 0; axis < 2; ++axis) {
        const Vector2d f = L.footprint_m;
        auto mirror = [&](const Eigen::Vector3d& p) {
            Eigen::Vector3d q = p;
            q[axis] = f[axis] - p[axis];
            return q;
        };
        for (size_t i = 0; i < m.elements.size(); ++i) {
            ElementMesh image;
            for (const auto& t : meshes[i].triangles) {
                image.triangles.push_back({mirror(t[0]), mirror(t[1]), mirror(t[2])});
            }
            for (const auto& v : meshes[i].vertices) {
                image.vertices.push_back(mirror(v));
                image.box.extend(image.vertices.back());
            }
            bool found = false;
            for (size_t k = 0; k < m.elements.size() && !found; ++k) {
                if (m.elements[k].ifc_class != m.elements[i].ifc_class) continue;
                if ((meshes[k].box.min() - image.box.min()).norm() > 1e-4 ||
                    (meshes[k].box.max() - image.box.max()).norm() > 1e-4) {
                    continue;
                }
                found = OneSidedDistance(image, meshes[k]) < 1e-4 &&
                        OneSidedDistance(meshes[k], image) < 1e-4;
            }
            EXPECT_TRUE(found) << m.elements[i].ifc_class << " " << m.elements[i].name
                               << " has no mirror image about axis " << axis;
        }
    }
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::bim
