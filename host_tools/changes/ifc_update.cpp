#include "host_tools/changes/ifc_update.hpp"

#include <map>

#include "algorithms/common/status.hpp"
#include "host_tools/bim/ifc_writer.hpp"
#include "host_tools/changes/step_index.hpp"

namespace bimslam::change_detection {
namespace {
using bim::IfcWriter;
using changes::kNoElement;

std::string Label(const std::string& s) { return "IFCLABEL(" + IfcWriter::Str(s) + ")"; }
std::string Int(size_t v) { return "IFCINTEGER(" + std::to_string(v) + ")"; }
std::string RealValue(double v) { return "IFCREAL(" + IfcWriter::Real(v) + ")"; }

// The 'Body' subcontext, else the 3D 'Model' context, else the first context.
int BodyContext(const StepIndex& index, const std::string& name) {
    for (const StepEntity* e : index.OfType("IFCGEOMETRICREPRESENTATIONSUBCONTEXT")) {
        const auto args = StepIndex::SplitArgs(e->args);
        if (!args.empty() && args[0] == "'Body'") return e->id;
    }
    const auto contexts = index.OfType("IFCGEOMETRICREPRESENTATIONCONTEXT");
    for (const StepEntity* e : contexts) {
        const auto args = StepIndex::SplitArgs(e->args);
        if (args.size() > 1 && args[1] == "'Model'") return e->id;
    }
    if (!contexts.empty()) return contexts.front()->id;
    throw common::FileError(common::StatusCode::kParseError, name, 0,
                            "no IfcGeometricRepresentationContext to put new geometry in");
}

class Appender {
public:
    Appender(IfcWriter& w, std::string owner) : w_(w), owner_(std::move(owner)) {}

    // IfcPropertySet(GlobalId, OwnerHistory, Name, Description, HasProperties) on `objects` by an
    // IfcRelDefinesByProperties(GlobalId, OwnerHistory, Name, Description, RelatedObjects,
    // RelatingPropertyDefinition).
    void PropertySet(const std::string& key, const std::string& set_name,
                     const std::vector<std::pair<std::string, std::string>>& values,
                     const std::vector<int>& objects) {
        std::vector<int> properties;
        for (const auto& [name, value] : values) {
            // IfcPropertySingleValue(Name, Description, NominalValue, Unit).
            properties.push_back(
                w_.Add("IfcPropertySingleValue", IfcWriter::Str(name) + ",$," + value + ",$"));
        }
        const int set = w_.Add("IfcPropertySet", w_.Guid("pset " + key) + "," + owner_ + "," +
                                                     IfcWriter::Str(set_name) + ",$," +
                                                     IfcWriter::Refs(properties));
        w_.Add("IfcRelDefinesByProperties", w_.Guid("rel pset " + key) + "," + owner_ + ",$,$," +
                                                IfcWriter::Refs(objects) + "," +
                                                IfcWriter::Ref(set));
    }
    const std::string& owner() const { return owner_; }

private:
    IfcWriter& w_;
    std::string owner_;
};

}  // namespace

IfcUpdate UpdateIfc(const std::string& name, const std::string& text, const bim::BimModel& model,
                    const SessionChanges& found, uint64_t seed) {
    const bool ifc4 = model.schema == "IFC4";
    if (!ifc4 && model.schema != "IFC2X3") {
        throw common::Error(
            common::StatusCode::kInvalidArgument,
            name + ": schema " + model.schema + ": only IFC2X3 and IFC4 are updated");
    }
    const StepIndex index(name, text);
    IfcUpdate out;
    IfcWriter w = IfcWriter::Appending(model.length_unit_m, seed, index.max_id() + 1);
    const auto owners = index.OfType("IFCOWNERHISTORY");
    Appender append(w, owners.empty() ? std::string("$") : IfcWriter::Ref(owners.front()->id));
    if (owners.empty() && !ifc4)
        out.notes.push_back("no IfcOwnerHistory in the file: written as $");
    const int context = BodyContext(index, name);
    const changes::ChangeResult& r = found.result;
    const Eigen::Vector3d origin = model.origin_m;

    // New objects.
    int placement = 0;
    std::map<int, std::vector<int>> by_storey;  // storey index -> proxies
    for (size_t k = 0; k < r.objects.size(); ++k) {
        const changes::NewObject& obj = r.objects[k];
        if (obj.moved_element != kNoElement) continue;
        if (placement == 0) placement = w.LocalPlacement(0, Eigen::Vector3d::Zero());
        int item = 0;
        if (ifc4) {
            // IfcCartesianPointList3D(CoordList); IfcTriangulatedFaceSet(Coordinates, Normals,
            // Closed, CoordIndex, PnIndex), indices from 1.
            std::string coords = "(";
            for (size_t v = 0; v < obj.mesh.vertices.size(); ++v) {
                const Eigen::Vector3d p = obj.mesh.vertices[v].cast<double>() + origin;
                coords +=
                    (v ? ",(" : "(") + w.Len(p.x()) + "," + w.Len(p.y()) + "," + w.Len(p.z()) + ")";
            }
            const int list = w.Add("IfcCartesianPointList3D", coords + ")");
            std::string faces = "(";
            for (size_t t = 0; t < obj.mesh.triangles.size(); ++t) {
                const auto& tri = obj.mesh.triangles[t];
                faces += (t ? ",(" : "(") + std::to_string(tri[0] + 1) + "," +
                         std::to_string(tri[1] + 1) + "," + std::to_string(tri[2] + 1) + ")";
            }
            item =
                w.Add("IfcTriangulatedFaceSet", IfcWriter::Ref(list) + ",$,.T.," + faces + "),$");
        } else {
            // IfcFacetedBrep(Outer: IfcClosedShell(CfsFaces)), each face an IfcFace of one
            // IfcFaceOuterBound(IfcPolyLoop(Polygon), Orientation).
            std::vector<int> points;
            for (const auto& v : obj.mesh.vertices) {
                points.push_back(w.Point(v.cast<double>() + origin));
            }
            std::vector<int> faces;
            for (const auto& tri : obj.mesh.triangles) {
                const int loop =
                    w.Add("IfcPolyLoop",
                          IfcWriter::Refs({points[tri[0]], points[tri[1]], points[tri[2]]}));
                const int bound = w.Add("IfcFaceOuterBound", IfcWriter::Ref(loop) + ",.T.");
                faces.push_back(w.Add("IfcFace", "(" + IfcWriter::Ref(bound) + ")"));
            }
            const int shell = w.Add("IfcClosedShell", IfcWriter::Refs(faces));
            item = w.Add("IfcFacetedBrep", IfcWriter::Ref(shell));
        }
        // IfcShapeRepresentation(ContextOfItems, RepresentationIdentifier, RepresentationType,
        // Items); IfcProductDefinitionShape(Name, Description, Representations).
        const int representation =
            w.Add("IfcShapeRepresentation", IfcWriter::Ref(context) + ",'Body'," +
                                                (ifc4 ? "'Tessellation'" : "'Brep'") + ",(" +
                                                IfcWriter::Ref(item) + ")");
        const int shape =
            w.Add("IfcProductDefinitionShape", "$,$,(" + IfcWriter::Ref(representation) + ")");
        const std::string object_name = "bimslam new object " + std::to_string(k);
        const std::string description = "found by bimslam changes in session " + found.label;
        // IfcBuildingElementProxy(GlobalId, OwnerHistory, Name, Description, ObjectType,
        // ObjectPlacement, Representation, Tag, PredefinedType (IFC4) | CompositionType (2X3)).
        const int proxy =
            w.Add("IfcBuildingElementProxy",
                  IfcWriter::Str(found.object_global_ids[k]) + "," + append.owner() + "," +
                      IfcWriter::Str(object_name) + "," + IfcWriter::Str(description) +
                      ",'new object'," + IfcWriter::Ref(placement) + "," + IfcWriter::Ref(shape) +
                      ",$," + (ifc4 ? ".NOTDEFINED." : "$"));
        ++out.proxies;
        by_storey[found.places[k].storey].push_back(proxy);
        std::string space;
        if (found.places[k].space >= 0)
            space = model.elements[size_t(found.places[k].space)].global_id;
        const Eigen::Vector3d c = obj.centroid + origin;
        append.PropertySet("object " + found.object_global_ids[k], "bimslam_NewObject",
                           {{"Session", Label(found.label)},
                            {"ObjectId", Int(k)},
                            {"Points", Int(obj.points.size())},
                            {"VolumeCubicMetres", RealValue(obj.volume_m3)},
                            {"CentroidX", "IFCLENGTHMEASURE(" + w.Len(c.x()) + ")"},
                            {"CentroidY", "IFCLENGTHMEASURE(" + w.Len(c.y()) + ")"},
                            {"CentroidZ", "IFCLENGTHMEASURE(" + w.Len(c.z()) + ")"},
                            {"Space", space.empty() ? std::string("$") : Label(space)}},
                           {proxy});
    }
    // IfcRelContainedInSpatialStructure(GlobalId, OwnerHistory, Name, Description,
    // RelatedElements, RelatingStructure): the storey, else the building.
    for (const auto& [storey, proxies] : by_storey) {
        const StepEntity* structure = nullptr;
        if (storey >= 0) structure = index.FindGlobalId(model.storeys[size_t(storey)].global_id);
        if (!structure) {
            const auto buildings = index.OfType("IFCBUILDING");
            if (!buildings.empty()) structure = buildings.front();
        }
        if (!structure) {
            out.notes.push_back(std::to_string(proxies.size()) +
                                " new objects are in no spatial structure: the file has no "
                                "storey or building to put them in");
            continue;
        }
        w.Add("IfcRelContainedInSpatialStructure",
              w.Guid("contained " + found.label + " " + std::to_string(storey)) + "," +
                  append.owner() + ",'bimslam new objects',$," + IfcWriter::Refs(proxies) + "," +
                  IfcWriter::Ref(structure->id));
    }

    // Verdicts on missing and deviating elements.
    for (size_t e = 0; e < r.elements.size(); ++e) {
        const changes::ElementReport& rep = r.elements[e];
        if (rep.verdict != changes::Verdict::kMissing &&
            rep.verdict != changes::Verdict::kDeviating) {
            continue;
        }
        const bim::BimElement& el = model.elements[e];
        const StepEntity* entity = index.FindGlobalId(el.global_id);
        if (!entity) {
            out.notes.push_back(el.ifc_class + " " + el.global_id + ": not found by its GlobalId");
            continue;
        }
        std::vector<std::pair<std::string, std::string>> values = {
            {"Verdict", Label(std::string(changes::ToString(rep.verdict)))},
            {"Session", Label(found.label)},
            {"ExpectedVisibleAreaSquareMetres", RealValue(rep.evidence.expected_area_m2)},
            {"SeenAreaSquareMetres", RealValue(rep.evidence.seen_area_m2)},
            {"SupportPoints", Int(rep.support_points)}};
        if (rep.verdict == changes::Verdict::kDeviating) {
            values.push_back({"Offset", "IFCLENGTHMEASURE(" + w.Len(rep.offset.norm()) + ")"});
            values.push_back({"OffsetX", "IFCLENGTHMEASURE(" + w.Len(rep.offset.x()) + ")"});
            values.push_back({"OffsetY", "IFCLENGTHMEASURE(" + w.Len(rep.offset.y()) + ")"});
            values.push_back({"OffsetZ", "IFCLENGTHMEASURE(" + w.Len(rep.offset.z()) + ")"});
            values.push_back(
                {"MeanSignedDistance", "IFCLENGTHMEASURE(" + w.Len(rep.mean_signed_m) + ")"});
            values.push_back(
                {"MaxSignedDistance", "IFCLENGTHMEASURE(" + w.Len(rep.max_signed_m) + ")"});
            values.push_back({"Moved", rep.moved ? "IFCBOOLEAN(.T.)" : "IFCBOOLEAN(.F.)"});
            if (rep.moved) values.push_back({"MovedYawDegrees", RealValue(rep.moved_yaw_deg)});
        }
        append.PropertySet("verdict " + found.label + " " + el.global_id, "bimslam_ChangeDetection",
                           values, {entity->id});
        ++out.element_property_sets;
    }

    out.entities = size_t(w.entities() - index.max_id());
    std::string data = w.Data();
    if (index.newline() != "\n") {
        std::string converted;
        for (const char c : data) converted += c == '\n' ? index.newline() : std::string(1, c);
        data = std::move(converted);
    }
    out.text.reserve(text.size() + data.size());
    out.text.append(text, 0, index.data_end());
    out.text += data;
    out.text.append(text, index.data_end());
    return out;
}

}  // namespace bimslam::change_detection
