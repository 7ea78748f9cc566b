// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// A sample building's layout (sample_building.cpp) written as IFC4 STEP text through IfcWriter.
// The spatial structure is IfcProject -> IfcSite -> IfcBuilding -> IfcBuildingStorey (IfcRel-
// Aggregates), rooms are IfcSpaces aggregated to their storey, and every element is contained in
// its storey (IfcRelContainedInSpatialStructure), as the IFC4 concepts "Spatial Decomposition" and
// "Spatial Containment" prescribe. Geometry is 'Body' 'SweptSolid': IfcExtrudedAreaSolid of
// rectangles, circles and polylines, placed by IfcLocalPlacement relative to the storey (openings
// relative to the element they void, doors and windows relative to their opening).
#include <cmath>

#include "algorithms/io/file_util.hpp"
#include "host_tools/bim/ifc_writer.hpp"
#include "host_tools/bim/sample_building.hpp"

namespace bimslam::bim {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;
using W = IfcWriter;

Vector3d At(const Vector2d& p, double z) { return {p.x(), p.y(), z}; }

class SampleIfc {
public:
    SampleIfc(const SampleLayout& layout, const SampleBuildingOptions& options)
        : L_(layout), o_(options), w_(options.length_unit_m, options.seed) {}

    std::string Build() {
        Context();
        SpatialStructure();
        contained_.assign(L_.storeys.size(), {});
        Spaces();
        Walls();
        for (size_t i = 0; i < L_.doors.size(); ++i) Door(i);
        for (size_t i = 0; i < L_.windows.size(); ++i) Window(i);
        Columns();
        Slabs();
        Stairs();
        Railings();
        Furniture();
        for (size_t s = 0; s < L_.storeys.size(); ++s) {
            // IfcRelContainedInSpatialStructure(GlobalId, OwnerHistory, Name, Description,
            // RelatedElements, RelatingStructure).
            w_.Add("IfcRelContainedInSpatialStructure",
                   w_.Guid("contained/" + std::to_string(s)) + "," + W::Ref(history_) +
                       ",'Storey elements',$," + W::Refs(contained_[s]) + "," +
                       W::Ref(storeys_[s]));
        }
        std::string description = "bimslam sample " + std::string(ToString(L_.layout)) +
                                  " building, seed " + std::to_string(o_.seed) + ", length unit " +
                                  (o_.length_unit_m == 1.0 ? "metre" : "millimetre");
        if (!o_.furniture) description += ", no furniture";
        return w_.Text("sample_building.ifc", description);
    }

private:
    // The common head of every IfcProduct: GlobalId, OwnerHistory, Name, Description,
    // ObjectType, ObjectPlacement, Representation; `tail` holds the class's own attributes.
    int Product(std::string_view ifc_class, const std::string& key, const std::string& name,
                int placement, int shape, const std::string& tail) {
        return w_.Add(ifc_class, w_.Guid(key) + "," + W::Ref(history_) + "," + W::Str(name) +
                                     ",$,$," + W::Ref(placement) + "," +
                                     (shape ? W::Ref(shape) : std::string("$")) + "," + tail);
    }

    // IfcRelAggregates(GlobalId, OwnerHistory, Name, Description, RelatingObject, RelatedObjects).
    void Aggregate(const std::string& key, int whole, const std::vector<int>& parts) {
        w_.Add("IfcRelAggregates", w_.Guid(key) + "," + W::Ref(history_) + ",$,$," + W::Ref(whole) +
                                       "," + W::Refs(parts));
    }

    void Context() {
        // IfcOwnerHistory(OwningUser, OwningApplication, State, ChangeAction, LastModifiedDate,
        // LastModifyingUser, LastModifyingApplication, CreationDate); without a modification
        // date ChangeAction must be NOCHANGE or NOTDEFINED (rule CorrectChangeAction).
        const int person = w_.Add("IfcPerson", "$,'bimslam',$,$,$,$,$,$");
        const int org = w_.Add("IfcOrganization", "$,'bimslam',$,$,$");
        const int user =
            w_.Add("IfcPersonAndOrganization", W::Ref(person) + "," + W::Ref(org) + ",$");
        const int app = w_.Add("IfcApplication", W::Ref(org) +
                                                     ",'0.1.0','bimslam sample building generator',"
                                                     "'bimslam'");
        history_ = w_.Add("IfcOwnerHistory",
                          W::Ref(user) + "," + W::Ref(app) + ",$,.NOTDEFINED.,$,$,$,1704067200");
        // IfcSIUnit(Dimensions (derived), UnitType, Prefix, Name): lengths in METRE or MILLI
        // METRE; areas, volumes and angles in plain SI.
        const std::string prefix = o_.length_unit_m == 1.0 ? "$" : ".MILLI.";
        const int length = w_.Add("IfcSIUnit", "*,.LENGTHUNIT.," + prefix + ",.METRE.");
        const int area = w_.Add("IfcSIUnit", "*,.AREAUNIT.,$,.SQUARE_METRE.");
        const int volume = w_.Add("IfcSIUnit", "*,.VOLUMEUNIT.,$,.CUBIC_METRE.");
        const int angle = w_.Add("IfcSIUnit", "*,.PLANEANGLEUNIT.,$,.RADIAN.");
        units_ = w_.Add("IfcUnitAssignment", W::Refs({length, area, volume, angle}));
        // IfcGeometricRepresentationContext(ContextIdentifier, ContextType,
        // CoordinateSpaceDimension, Precision, WorldCoordinateSystem, TrueNorth): y is north.
        const int wcs = w_.Placement(Vector3d::Zero());
        const int north = w_.Add("IfcDirection", "(0.,1.)");
        context_ = w_.Add("IfcGeometricRepresentationContext",
                          "$,'Model',3," + w_.Len(1e-5) + "," + W::Ref(wcs) + "," + W::Ref(north));
        // IfcGeometricRepresentationSubContext: the first six attributes are derived from the
        // parent (*); then ParentContext, TargetScale, TargetView, UserDefinedTargetView.
        body_ = w_.Add("IfcGeometricRepresentationSubContext",
                       "'Body','Model',*,*,*,*," + W::Ref(context_) + ",$,.MODEL_VIEW.,$");
    }

    void SpatialStructure() {
        // IfcProject(GlobalId, OwnerHistory, Name, Description, ObjectType, LongName, Phase,
        // RepresentationContexts, UnitsInContext).
        project_ = w_.Add("IfcProject", w_.Guid("project") + "," + W::Ref(history_) +
                                            ",'bimslam sample building',$,$," + W::Str(L_.summary) +
                                            ",$,(" + W::Ref(context_) + ")," + W::Ref(units_));
        // IfcSite(... ObjectPlacement, Representation, LongName, CompositionType, RefLatitude,
        // RefLongitude, RefElevation, LandTitleNumber, SiteAddress).
        const int site_placement = w_.LocalPlacement(0, Vector3d::Zero());
        const int site =
            Product("IfcSite", "site", "Site", site_placement, 0, "$,.ELEMENT.,$,$,$,$,$");
        // IfcBuilding(... LongName, CompositionType, ElevationOfRefHeight, ElevationOfTerrain,
        // BuildingAddress).
        const int building_placement = w_.LocalPlacement(site_placement, Vector3d::Zero());
        const int building = Product("IfcBuilding", "building", L_.building_name,
                                     building_placement, 0, "$,.ELEMENT.,$,$,$");
        for (size_t s = 0; s < L_.storeys.size(); ++s) {
            const double z = L_.storeys[s].elevation_m;
            storey_placements_.push_back(w_.LocalPlacement(building_placement, {0, 0, z}));
            // IfcBuildingStorey(... LongName, CompositionType, Elevation).
            storeys_.push_back(Product("IfcBuildingStorey", "storey/" + std::to_string(s),
                                       L_.storeys[s].name, storey_placements_.back(), 0,
                                       "$,.ELEMENT.," + w_.Len(z)));
        }
        Aggregate("aggregate/project", project_, {site});
        Aggregate("aggregate/site", site, {building});
        Aggregate("aggregate/building", building, storeys_);
    }

    double ClearHeight(int storey) const { return L_.storeys[storey].height_m - L_.slab_m; }

    void Spaces() {
        std::vector<std::vector<int>> per_storey(L_.storeys.size());
        for (size_t r = 0; r < L_.rooms.size(); ++r) {
            const SampleRoom& room = L_.rooms[r];
            const int placement =
                w_.LocalPlacement(storey_placements_[room.storey], Vector3d::Zero());
            const int shape =
                w_.BodyShape(body_, {w_.Prism(room.polygon, 0, ClearHeight(room.storey))});
            // IfcSpace(... LongName, CompositionType, PredefinedType, ElevationWithFlooring).
            per_storey[room.storey].push_back(
                Product("IfcSpace", "space/" + std::to_string(r), room.number, placement, shape,
                        W::Str(room.name) + ",.ELEMENT.,.INTERNAL.,$"));
        }
        for (size_t s = 0; s < per_storey.size(); ++s) {
            Aggregate("aggregate/storey/" + std::to_string(s), storeys_[s], per_storey[s]);
        }
    }

    void Walls() {
        std::vector<int> exterior, interior;
        for (size_t i = 0; i < L_.walls.size(); ++i) {
            const SampleWall& wall = L_.walls[i];
            // Local x along the centreline from its start, y across, z up from the floor.
            wall_placements_.push_back(w_.LocalPlacement(storey_placements_[wall.storey],
                                                         At(wall.start, 0), Vector3d::UnitZ(),
                                                         At(wall.Direction(), 0)));
            const double t = wall.thickness_m;
            const int shape = w_.BodyShape(
                body_, {w_.Box({0, -t / 2, 0}, {wall.Length(), t / 2, wall.height_m})});
            // IfcWall(... Tag, PredefinedType): IFC4 deprecates IfcWallStandardCase's implicit
            // geometry rules; a plain IfcWall with its own body is the general form.
            walls_.push_back(Product("IfcWall", "wall/" + std::to_string(i), wall.name,
                                     wall_placements_.back(), shape,
                                     wall.exterior ? "$,.STANDARD." : "$,.PARTITIONING."));
            contained_[wall.storey].push_back(walls_.back());
            (wall.exterior ? exterior : interior).push_back(walls_.back());
        }
        // Pset_WallCommon.IsExternal, shared by all walls of each kind.
        for (const bool ext : {true, false}) {
            const std::string key = ext ? "external" : "internal";
            const int value =
                w_.Add("IfcPropertySingleValue",
                       std::string("'IsExternal',$,IFCBOOLEAN(") + (ext ? ".T." : ".F.") + "),$");
            // IfcPropertySet(GlobalId, OwnerHistory, Name, Description, HasProperties).
            const int pset =
                w_.Add("IfcPropertySet", w_.Guid("pset/" + key) + "," + W::Ref(history_) +
                                             ",'Pset_WallCommon',$,(" + W::Ref(value) + ")");
            // IfcRelDefinesByProperties(GlobalId, OwnerHistory, Name, Description,
            // RelatedObjects, RelatingPropertyDefinition).
            w_.Add("IfcRelDefinesByProperties",
                   w_.Guid("pset-rel/" + key) + "," + W::Ref(history_) + ",$,$," +
                       W::Refs(ext ? exterior : interior) + "," + W::Ref(pset));
        }
    }

    // An IfcOpeningElement voiding `element`: placed at `origin` relative to the element's
    // placement, its body the box [lo, hi] in its own coordinates. Returns its placement.
    int Opening(const std::string& key, const std::string& name, int element, int element_placement,
                const Vector3d& origin, const Vector3d& lo, const Vector3d& hi) {
        const int placement = w_.LocalPlacement(element_placement, origin);
        const int shape = w_.BodyShape(body_, {w_.Box(lo, hi)});
        // IfcOpeningElement(... Tag, PredefinedType).
        opening_ = Product("IfcOpeningElement", key, name, placement, shape, "$,.OPENING.");
        // IfcRelVoidsElement(GlobalId, OwnerHistory, Name, Description,
        // RelatingBuildingElement, RelatedOpeningElement).
        w_.Add("IfcRelVoidsElement", w_.Guid(key + "/voids") + "," + W::Ref(history_) + ",$,$," +
                                         W::Ref(element) + "," + W::Ref(opening_));
        return placement;
    }

    // IfcRelFillsElement(GlobalId, OwnerHistory, Name, Description, RelatingOpeningElement,
    // RelatedBuildingElement).
    void Fill(const std::string& key, int filling) {
        w_.Add("IfcRelFillsElement", w_.Guid(key + "/fills") + "," + W::Ref(history_) + ",$,$," +
                                         W::Ref(opening_) + "," + W::Ref(filling));
    }

    void Door(size_t i) {
        const SampleDoor& d = L_.doors[i];
        const SampleWall& wall = L_.walls[d.wall];
        const std::string key = "door/" + std::to_string(i);
        const double t = wall.thickness_m, wd = d.width_m;
        // The opening goes 0.1 m beyond both faces and below the floor, so that it cuts the
        // wall's faces cleanly (no coplanar faces for the readers' boolean operations).
        const double half_t = t / 2 + 0.1;
        const int opening_placement = Opening(
            key + "/opening", "Opening for " + d.name, walls_[d.wall], wall_placements_[d.wall],
            {d.offset_m, 0, 0}, {-wd / 2, -half_t, -0.1}, {wd / 2, half_t, d.height_m});
        // The leaves stand open at 90 degrees on the side of rooms[1], hinged at the jambs:
        // thin boxes at right angles to the wall, leaving the opening passable.
        const Vector2d left(-wall.Direction().y(), wall.Direction().x());
        const bool into_left =
            d.rooms[1] >= 0 && L_.rooms[d.rooms[1]].Contains(d.centre + left * (t / 2 + 0.5));
        const double s = into_left ? 1.0 : -1.0;
        const double leaf_w = wd / d.leaves, leaf_t = 0.04, leaf_h = d.height_m - 0.01;
        std::vector<int> items;
        for (int k = 0; k < d.leaves; ++k) {
            const double x0 = k == 0 ? -wd / 2 : wd / 2 - leaf_t;
            const double y0 = s * (t / 2), y1 = s * (t / 2 + leaf_w);
            items.push_back(
                w_.Box({x0, std::min(y0, y1), 0}, {x0 + leaf_t, std::max(y0, y1), leaf_h}));
        }
        // The frame's head across the top of the opening: what closes the building's outline
        // for the occupancy grid (bim/occupancy_grid.hpp, closures) while the leaves stand open.
        items.push_back(w_.Box({-wd / 2, -t / 2, d.height_m - 0.06}, {wd / 2, t / 2, d.height_m}));
        const int placement = w_.LocalPlacement(opening_placement, Vector3d::Zero());
        // IfcDoor(... Tag, OverallHeight, OverallWidth, PredefinedType, OperationType,
        // UserDefinedOperationType).
        const int door = Product(
            "IfcDoor", key, d.name, placement, w_.BodyShape(body_, items),
            "$," + w_.Len(d.height_m) + "," + w_.Len(wd) + ",.DOOR.," +
                (d.leaves == 1 ? ".SINGLE_SWING_LEFT." : ".DOUBLE_DOOR_SINGLE_SWING.") + ",$");
        Fill(key, door);
        contained_[d.storey].push_back(door);
    }

    void Window(size_t i) {
        const SampleWindow& win = L_.windows[i];
        const SampleWall& wall = L_.walls[win.wall];
        const std::string key = "window/" + std::to_string(i);
        const double half_t = wall.thickness_m / 2 + 0.1;
        const int opening_placement =
            Opening(key + "/opening", "Opening for " + win.name, walls_[win.wall],
                    wall_placements_[win.wall], {win.offset_m, 0, 0},
                    {-win.width_m / 2, -half_t, win.sill_m},
                    {win.width_m / 2, half_t, win.sill_m + win.height_m});
        // The glazing: a 6 cm pane filling the opening in the middle of the wall.
        const int shape =
            w_.BodyShape(body_, {w_.Box({-win.width_m / 2, -0.03, win.sill_m},
                                        {win.width_m / 2, 0.03, win.sill_m + win.height_m})});
        const int placement = w_.LocalPlacement(opening_placement, Vector3d::Zero());
        // IfcWindow(... Tag, OverallHeight, OverallWidth, PredefinedType, PartitioningType,
        // UserDefinedPartitioningType).
        const int window = Product(
            "IfcWindow", key, win.name, placement, shape,
            "$," + w_.Len(win.height_m) + "," + w_.Len(win.width_m) + ",.WINDOW.,.SINGLE_PANEL.,$");
        Fill(key, window);
        contained_[win.storey].push_back(window);
    }

    void Columns() {
        for (size_t i = 0; i < L_.columns.size(); ++i) {
            const SampleColumn& c = L_.columns[i];
            const int placement = w_.LocalPlacement(storey_placements_[c.storey], At(c.centre, 0));
            const double h = c.size_m / 2;
            const int item = c.round ? w_.Cylinder({0, 0}, h, 0, c.height_m)
                                     : w_.Box({-h, -h, 0}, {h, h, c.height_m});
            // IfcColumn(... Tag, PredefinedType).
            contained_[c.storey].push_back(Product("IfcColumn", "column/" + std::to_string(i),
                                                   c.name, placement, w_.BodyShape(body_, {item}),
                                                   "$,.COLUMN."));
        }
    }

    void Slabs() {
        for (size_t i = 0; i < L_.slabs.size(); ++i) {
            const SampleSlab& s = L_.slabs[i];
            const int placement = w_.LocalPlacement(storey_placements_[s.storey], Vector3d::Zero());
            const double z0 = s.top_m - s.thickness_m;
            const int shape = w_.BodyShape(
                body_, {w_.Box(At(s.outline.min(), z0), At(s.outline.max(), s.top_m))});
            // IfcSlab(... Tag, PredefinedType).
            const std::string key = "slab/" + std::to_string(i);
            const int slab = Product("IfcSlab", key, s.name, placement, shape,
                                     s.roof ? "$,.ROOF." : "$,.FLOOR.");
            contained_[s.storey].push_back(slab);
            for (size_t k = 0; k < s.openings.size(); ++k) {
                // Through the slab with 0.1 m to spare above and below.
                const Eigen::AlignedBox2d& o = s.openings[k];
                Opening(key + "/opening/" + std::to_string(k), "Opening in " + s.name, slab,
                        placement, Vector3d::Zero(), At(o.min(), z0 - 0.1),
                        At(o.max(), s.top_m + 0.1));
            }
        }
    }

    void Stairs() {
        for (size_t i = 0; i < L_.stairs.size(); ++i) {
            const SampleStair& st = L_.stairs[i];
            const std::string key = "stair/" + std::to_string(i);
            // Local x up the flight from the middle of its first riser, y to the left.
            const int placement = w_.LocalPlacement(storey_placements_[st.storey], At(st.foot, 0),
                                                    Vector3d::UnitZ(), At(st.direction, 0));
            // IfcStair(... Tag, PredefinedType): its geometry is its flight's (aggregated).
            const int stair =
                Product("IfcStair", key, st.name, placement, 0, "$,.STRAIGHT_RUN_STAIR.");
            contained_[st.storey].push_back(stair);
            // The flight's side profile in its vertical plane (x up the flight, y up): risers
            // and treads on top, a soffit parallel to the pitch 0.2 m (vertically) below the
            // inner corners. Listed counter-clockwise: down the soffit first.
            const double r = st.riser_m, t = st.tread_m, waist = 0.2;
            const int steps = st.risers - 1;  // the last riser is the upper slab's edge
            std::vector<Vector2d> profile{
                {0, 0}, {t * waist / r, 0}, {steps * t, steps * r - waist}};
            for (int k = steps; k >= 1; --k) {
                profile.emplace_back(k * t, k * r);
                profile.emplace_back((k - 1) * t, k * r);
            }
            // The profile plane stands at the flight's left edge and is extruded to the right:
            // position axis (0,-1,0), ref direction x, so the profile's y is up.
            const int position =
                w_.Placement({0, st.width_m / 2, 0}, -Vector3d::UnitY(), Vector3d::UnitX());
            const int flight_placement = w_.LocalPlacement(placement, Vector3d::Zero());
            // IfcStairFlight(... Tag, NumberOfRisers, NumberOfTreads, RiserHeight, TreadLength,
            // PredefinedType): the risers climbed, the slab's edge included, as Revit counts them
            // (Duplex_A's flights: 16 risers, 15 treads).
            const int flight =
                Product("IfcStairFlight", key + "/flight", st.name + " flight", flight_placement,
                        w_.BodyShape(body_, {w_.Prism(profile, position, st.width_m)}),
                        "$," + std::to_string(st.risers) + "," + std::to_string(steps) + "," +
                            w_.Len(r) + "," + w_.Len(t) + ",.STRAIGHT.");
            Aggregate(key + "/aggregate", stair, {flight});
        }
    }

    void Railings() {
        for (size_t i = 0; i < L_.railings.size(); ++i) {
            const SampleRailing& rail = L_.railings[i];
            const int placement =
                w_.LocalPlacement(storey_placements_[rail.storey], Vector3d::Zero());
            std::vector<int> items;
            for (const auto& part : rail.parts) {
                items.push_back(w_.Box(At(part.min(), 0), At(part.max(), rail.height_m)));
            }
            // IfcRailing(... Tag, PredefinedType).
            contained_[rail.storey].push_back(Product("IfcRailing", "railing/" + std::to_string(i),
                                                      rail.name, placement,
                                                      w_.BodyShape(body_, items), "$,.GUARDRAIL."));
        }
    }

    void Furniture() {
        for (size_t i = 0; i < L_.furniture.size(); ++i) {
            const SampleFurniture& f = L_.furniture[i];
            const Vector3d x = f.rotated ? Vector3d::UnitY() : Vector3d::UnitX();
            const int placement = w_.LocalPlacement(storey_placements_[f.storey], At(f.centre, 0),
                                                    Vector3d::UnitZ(), x);
            const double hx = f.size.x() / 2, hy = f.size.y() / 2, h = f.size.z();
            std::vector<int> items;
            const char* type = ".NOTDEFINED.";
            switch (f.kind) {
                case FurnitureKind::kDesk:  // a top on two side panels
                    items.push_back(w_.Box({-hx, -hy, h - 0.03}, {hx, hy, h}));
                    items.push_back(w_.Box({-hx, -hy, 0}, {-hx + 0.03, hy, h - 0.03}));
                    items.push_back(w_.Box({hx - 0.03, -hy, 0}, {hx, hy, h - 0.03}));
                    type = ".DESK.";
                    break;
                case FurnitureKind::kTable:  // a top on four legs
                    items.push_back(w_.Box({-hx, -hy, h - 0.04}, {hx, hy, h}));
                    for (const double sx : {-1.0, 1.0}) {
                        for (const double sy : {-1.0, 1.0}) {
                            const Vector2d c(sx * (hx - 0.08), sy * (hy - 0.08));
                            items.push_back(w_.Box(At(c - Vector2d(0.03, 0.03), 0),
                                                   At(c + Vector2d(0.03, 0.03), h - 0.04)));
                        }
                    }
                    type = ".TABLE.";
                    break;
                case FurnitureKind::kCabinet:
                case FurnitureKind::kShelf:
                    items.push_back(w_.Box({-hx, -hy, 0}, {hx, hy, h}));
                    type = f.kind == FurnitureKind::kCabinet ? ".FILECABINET." : ".SHELF.";
                    break;
            }
            // IfcFurniture (IFC4, an IfcFurnishingElement)(... Tag, PredefinedType).
            contained_[f.storey].push_back(Product("IfcFurniture", "furniture/" + std::to_string(i),
                                                   f.name, placement, w_.BodyShape(body_, items),
                                                   std::string("$,") + type));
        }
    }

    const SampleLayout& L_;
    const SampleBuildingOptions& o_;
    IfcWriter w_;
    int history_ = 0, units_ = 0, context_ = 0, body_ = 0, project_ = 0, opening_ = 0;
    std::vector<int> storeys_, storey_placements_, walls_, wall_placements_;
    std::vector<std::vector<int>> contained_;  // per storey: the elements it contains
};

}  // namespace

std::string SampleBuildingIfc(const SampleBuildingOptions& options) {
    const SampleLayout layout = SampleBuildingLayout(options);
    return SampleIfc(layout, options).Build();
}

void WriteSampleBuilding(const std::filesystem::path& path, const SampleBuildingOptions& options) {
    io::WriteFileAtomic(path, SampleBuildingIfc(options));
}

}  // namespace bimslam::bim
