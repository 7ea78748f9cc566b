// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/changes/ifc_update.hpp"

#include <map>

#include "algorithms/common/status.hpp"
#include "host_tools/bim/ifc_writer.hpp"
#include "host_tools/changes/step_index.hpp"

namespace bimslam::change_detection {
namespace {
using bim::IfcWriter;
using changes::kNoElement;

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

}  // namespace

struct IfcAppender::State {
    State(const std::string& file_name, const std::string& file_text, const bim::BimModel& m,
          uint64_t seed)
        : name(file_name),
          text(file_text),
          model(m),
          index(file_name, file_text),
          w(IfcWriter::Appending(m.length_unit_m, seed, index.max_id() + 1)) {}
    const std::string& name;
    const std::string& text;
    const bim::BimModel& model;
    const StepIndex index;
    IfcWriter w;
    bool ifc4 = false;
    std::string owner;  // the file's first IfcOwnerHistory, or $
    int context = 0;
    int placement = 0;                          // the proxies' (absolute), made on first use
    std::map<int, std::vector<int>> by_storey;  // storey index -> proxies
    IfcUpdate out;
};

IfcAppender::IfcAppender(const std::string& name, const std::string& text,
                         const bim::BimModel& model, uint64_t seed) {
    if (model.schema != "IFC4" && model.schema != "IFC2X3") {
        throw common::Error(
            common::StatusCode::kInvalidArgument,
            name + ": schema " + model.schema + ": only IFC2X3 and IFC4 are updated");
    }
    s_ = std::make_unique<State>(name, text, model, seed);
    s_->ifc4 = model.schema == "IFC4";
    const auto owners = s_->index.OfType("IFCOWNERHISTORY");
    s_->owner = owners.empty() ? std::string("$") : IfcWriter::Ref(owners.front()->id);
    if (owners.empty() && !s_->ifc4)
        s_->out.notes.push_back("no IfcOwnerHistory in the file: written as $");
    s_->context = BodyContext(s_->index, name);
}

IfcAppender::~IfcAppender() = default;

std::string IfcAppender::Label(const std::string& s) {
    return "IFCLABEL(" + IfcWriter::Str(s) + ")";
}
std::string IfcAppender::Text(const std::string& s) { return "IFCTEXT(" + IfcWriter::Str(s) + ")"; }
std::string IfcAppender::Int(size_t v) { return "IFCINTEGER(" + std::to_string(v) + ")"; }
std::string IfcAppender::Real(double v) { return "IFCREAL(" + IfcWriter::Real(v) + ")"; }
std::string IfcAppender::Length(double metres) const {
    return "IFCLENGTHMEASURE(" + s_->w.Len(metres) + ")";
}

int IfcAppender::Proxy(const std::vector<Eigen::Vector3d>& vertices,
                       const std::vector<std::array<uint32_t, 3>>& triangles,
                       const std::string& global_id, const std::string& name,
                       const std::string& description, const std::string& object_type, int storey) {
    IfcWriter& w = s_->w;
    if (s_->placement == 0) s_->placement = w.LocalPlacement(0, Eigen::Vector3d::Zero());
    int item = 0;
    if (s_->ifc4) {
        // IfcCartesianPointList3D(CoordList); IfcTriangulatedFaceSet(Coordinates, Normals,
        // Closed, CoordIndex, PnIndex), indices from 1.
        std::string coords = "(";
        for (size_t v = 0; v < vertices.size(); ++v) {
            const Eigen::Vector3d& p = vertices[v];
            coords +=
                (v ? ",(" : "(") + w.Len(p.x()) + "," + w.Len(p.y()) + "," + w.Len(p.z()) + ")";
        }
        const int list = w.Add("IfcCartesianPointList3D", coords + ")");
        std::string faces = "(";
        for (size_t t = 0; t < triangles.size(); ++t) {
            const auto& tri = triangles[t];
            faces += (t ? ",(" : "(") + std::to_string(tri[0] + 1) + "," +
                     std::to_string(tri[1] + 1) + "," + std::to_string(tri[2] + 1) + ")";
        }
        item = w.Add("IfcTriangulatedFaceSet", IfcWriter::Ref(list) + ",$,.T.," + faces + "),$");
    } else {
        // IfcFacetedBrep(Outer: IfcClosedShell(CfsFaces)), each face an IfcFace of one
        // IfcFaceOuterBound(IfcPolyLoop(Polygon), Orientation).
        std::vector<int> points;
        for (const Eigen::Vector3d& v : vertices) points.push_back(w.Point(v));
        std::vector<int> faces;
        for (const auto& tri : triangles) {
            const int loop = w.Add(
                "IfcPolyLoop", IfcWriter::Refs({points[tri[0]], points[tri[1]], points[tri[2]]}));
            const int bound = w.Add("IfcFaceOuterBound", IfcWriter::Ref(loop) + ",.T.");
            faces.push_back(w.Add("IfcFace", "(" + IfcWriter::Ref(bound) + ")"));
        }
        const int shell = w.Add("IfcClosedShell", IfcWriter::Refs(faces));
        item = w.Add("IfcFacetedBrep", IfcWriter::Ref(shell));
    }
    // IfcShapeRepresentation(ContextOfItems, RepresentationIdentifier, RepresentationType,
    // Items); IfcProductDefinitionShape(Name, Description, Representations).
    const int representation =
        w.Add("IfcShapeRepresentation", IfcWriter::Ref(s_->context) + ",'Body'," +
                                            (s_->ifc4 ? "'Tessellation'" : "'Brep'") + ",(" +
                                            IfcWriter::Ref(item) + ")");
    const int shape =
        w.Add("IfcProductDefinitionShape", "$,$,(" + IfcWriter::Ref(representation) + ")");
    // IfcBuildingElementProxy(GlobalId, OwnerHistory, Name, Description, ObjectType,
    // ObjectPlacement, Representation, Tag, PredefinedType (IFC4) | CompositionType (2X3)).
    const int proxy =
        w.Add("IfcBuildingElementProxy",
              IfcWriter::Str(global_id) + "," + s_->owner + "," + IfcWriter::Str(name) + "," +
                  IfcWriter::Str(description) + "," + IfcWriter::Str(object_type) + "," +
                  IfcWriter::Ref(s_->placement) + "," + IfcWriter::Ref(shape) + ",$," +
                  (s_->ifc4 ? ".NOTDEFINED." : "$"));
    ++s_->out.proxies;
    s_->by_storey[storey].push_back(proxy);
    return proxy;
}

// IfcPropertySet(GlobalId, OwnerHistory, Name, Description, HasProperties) on `entities` by an
// IfcRelDefinesByProperties(GlobalId, OwnerHistory, Name, Description, RelatedObjects,
// RelatingPropertyDefinition).
void IfcAppender::PropertySet(const std::string& key, const std::string& set_name,
                              const Values& values, const std::vector<int>& entities) {
    IfcWriter& w = s_->w;
    std::vector<int> properties;
    for (const auto& [property, value] : values) {
        // IfcPropertySingleValue(Name, Description, NominalValue, Unit).
        properties.push_back(
            w.Add("IfcPropertySingleValue", IfcWriter::Str(property) + ",$," + value + ",$"));
    }
    const int set =
        w.Add("IfcPropertySet", w.Guid("pset " + key) + "," + s_->owner + "," +
                                    IfcWriter::Str(set_name) + ",$," + IfcWriter::Refs(properties));
    w.Add("IfcRelDefinesByProperties", w.Guid("rel pset " + key) + "," + s_->owner + ",$,$," +
                                           IfcWriter::Refs(entities) + "," + IfcWriter::Ref(set));
}

bool IfcAppender::ElementPropertySet(const std::string& global_id, const std::string& ifc_class,
                                     const std::string& key, const std::string& set_name,
                                     const Values& values) {
    const StepEntity* entity = s_->index.FindGlobalId(global_id);
    if (!entity) {
        s_->out.notes.push_back(ifc_class + " " + global_id + ": not found by its GlobalId");
        return false;
    }
    PropertySet(key, set_name, values, {entity->id});
    ++s_->out.element_property_sets;
    return true;
}

size_t IfcAppender::Group(const std::string& key, const std::string& name,
                          const std::string& description,
                          const std::vector<std::string>& global_ids) {
    std::vector<int> members;
    for (const std::string& id : global_ids) {
        const StepEntity* entity = s_->index.FindGlobalId(id);
        if (entity) {
            members.push_back(entity->id);
        } else {
            s_->out.notes.push_back(id + ": not found by its GlobalId");
        }
    }
    if (members.empty()) return 0;
    IfcWriter& w = s_->w;
    // IfcGroup(GlobalId, OwnerHistory, Name, Description, ObjectType); IfcRelAssignsToGroup(
    // GlobalId, OwnerHistory, Name, Description, RelatedObjects, RelatedObjectsType,
    // RelatingGroup): the same attributes in IFC2X3 and IFC4.
    const int group =
        w.Add("IfcGroup", w.Guid("group " + key) + "," + s_->owner + "," + IfcWriter::Str(name) +
                              "," + IfcWriter::Str(description) + ",$");
    w.Add("IfcRelAssignsToGroup", w.Guid("rel group " + key) + "," + s_->owner + ",$,$," +
                                      IfcWriter::Refs(members) + ",$," + IfcWriter::Ref(group));
    return members.size();
}

void IfcAppender::Contain(const std::string& group) {
    IfcWriter& w = s_->w;
    const StepIndex& index = s_->index;
    // IfcRelContainedInSpatialStructure(GlobalId, OwnerHistory, Name, Description,
    // RelatedElements, RelatingStructure): the storey, else the building.
    for (const auto& [storey, proxies] : s_->by_storey) {
        const StepEntity* structure = nullptr;
        if (storey >= 0)
            structure = index.FindGlobalId(s_->model.storeys[size_t(storey)].global_id);
        if (!structure) {
            const auto buildings = index.OfType("IFCBUILDING");
            if (!buildings.empty()) structure = buildings.front();
        }
        if (!structure) {
            s_->out.notes.push_back(std::to_string(proxies.size()) +
                                    " new objects are in no spatial structure: the file has no "
                                    "storey or building to put them in");
            continue;
        }
        w.Add("IfcRelContainedInSpatialStructure",
              w.Guid("contained " + group + " " + std::to_string(storey)) + "," + s_->owner +
                  ",'bimslam new objects',$," + IfcWriter::Refs(proxies) + "," +
                  IfcWriter::Ref(structure->id));
    }
    s_->by_storey.clear();
}

IfcUpdate IfcAppender::Finish(const std::string& group) {
    Contain(group);
    IfcWriter& w = s_->w;
    const StepIndex& index = s_->index;
    IfcUpdate out = std::move(s_->out);
    out.entities = size_t(w.entities() - index.max_id());
    std::string data = w.Data();
    if (index.newline() != "\n") {
        std::string converted;
        for (const char c : data) converted += c == '\n' ? index.newline() : std::string(1, c);
        data = std::move(converted);
    }
    const std::string& text = s_->text;
    out.text.reserve(text.size() + data.size());
    out.text.append(text, 0, index.data_end());
    out.text += data;
    out.text.append(text, index.data_end());
    return out;
}

IfcUpdate UpdateIfc(const std::string& name, const std::string& text, const bim::BimModel& model,
                    const SessionChanges& found, uint64_t seed) {
    IfcAppender append(name, text, model, seed);
    const changes::ChangeResult& r = found.result;
    const Eigen::Vector3d origin = model.origin_m;
    using A = IfcAppender;

    // New objects.
    for (size_t k = 0; k < r.objects.size(); ++k) {
        const changes::NewObject& obj = r.objects[k];
        if (obj.moved_element != kNoElement) continue;
        std::vector<Eigen::Vector3d> vertices;
        for (const auto& v : obj.mesh.vertices) vertices.push_back(v.cast<double>() + origin);
        std::vector<std::array<uint32_t, 3>> triangles;
        for (const auto& t : obj.mesh.triangles)
            triangles.push_back({uint32_t(t[0]), uint32_t(t[1]), uint32_t(t[2])});
        const int proxy = append.Proxy(vertices, triangles, found.object_global_ids[k],
                                       "bimslam new object " + std::to_string(k),
                                       "found by bimslam changes in session " + found.label,
                                       "new object", found.places[k].storey);
        std::string space;
        if (found.places[k].space >= 0)
            space = model.elements[size_t(found.places[k].space)].global_id;
        const Eigen::Vector3d c = obj.centroid + origin;
        append.PropertySet("object " + found.object_global_ids[k], "bimslam_NewObject",
                           {{"Session", A::Label(found.label)},
                            {"ObjectId", A::Int(k)},
                            {"Points", A::Int(obj.points.size())},
                            {"VolumeCubicMetres", A::Real(obj.volume_m3)},
                            {"CentroidX", append.Length(c.x())},
                            {"CentroidY", append.Length(c.y())},
                            {"CentroidZ", append.Length(c.z())},
                            {"Space", space.empty() ? std::string("$") : A::Label(space)}},
                           {proxy});
    }

    append.Contain(found.label);

    // Verdicts on missing and deviating elements.
    for (size_t e = 0; e < r.elements.size(); ++e) {
        const changes::ElementReport& rep = r.elements[e];
        if (rep.verdict != changes::Verdict::kMissing &&
            rep.verdict != changes::Verdict::kDeviating) {
            continue;
        }
        const bim::BimElement& el = model.elements[e];
        IfcAppender::Values values = {
            {"Verdict", A::Label(std::string(changes::ToString(rep.verdict)))},
            {"Session", A::Label(found.label)},
            {"ExpectedVisibleAreaSquareMetres", A::Real(rep.evidence.expected_area_m2)},
            {"SeenAreaSquareMetres", A::Real(rep.evidence.seen_area_m2)},
            {"SupportPoints", A::Int(rep.support_points)}};
        if (rep.verdict == changes::Verdict::kDeviating) {
            values.push_back({"Offset", append.Length(rep.offset.norm())});
            values.push_back({"OffsetX", append.Length(rep.offset.x())});
            values.push_back({"OffsetY", append.Length(rep.offset.y())});
            values.push_back({"OffsetZ", append.Length(rep.offset.z())});
            values.push_back({"MeanSignedDistance", append.Length(rep.mean_signed_m)});
            values.push_back({"MaxSignedDistance", append.Length(rep.max_signed_m)});
            values.push_back({"Moved", rep.moved ? "IFCBOOLEAN(.T.)" : "IFCBOOLEAN(.F.)"});
            if (rep.moved) values.push_back({"MovedYawDegrees", A::Real(rep.moved_yaw_deg)});
        }
        append.ElementPropertySet(el.global_id, el.ifc_class,
                                  "verdict " + found.label + " " + el.global_id,
                                  "bimslam_ChangeDetection", values);
    }
    return append.Finish(found.label);
}

}  // namespace bimslam::change_detection
