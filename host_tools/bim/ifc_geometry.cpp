// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// IFC++'s geometry (GeometryConverter over carve) to triangles in metres, and its messages. See
// ifc_geometry.hpp. Verified on IFC++ 0~git20190402 (Debian 12):
// - coordinates come out in metres (its point, curve and placement converters apply the length
//   unit), so nothing is scaled here;
// - ProductShapeData meshes are in the product's local frame: the placement chain is in
//   getTransform(), which its own viewer applies at draw time, and so do we;
// - it subtracts openings (IfcRelVoidsElement) inside convertIfcProductShape, but where carve's
//   CSG fails it keeps the element uncut without a message, so we subtract them ourselves
//   (Impl::SubtractOpenings);
// - carve's results vary slightly from run to run (it orders by pointer): triangle counts of the
//   same file differ by a few tenths of a percent.
#include "host_tools/bim/ifc_geometry.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <iostream>
#include <map>
#include <unordered_map>
#include <unordered_set>
#include <utility>

// IFC++ headers (system headers for the compiler: they are not -Wall clean).
#include <ifcpp/IFC4/include/IfcFace.h>
#include <ifcpp/IFC4/include/IfcGloballyUniqueId.h>
#include <ifcpp/IFC4/include/IfcLabel.h>
#include <ifcpp/IFC4/include/IfcProduct.h>
#include <ifcpp/IFC4/include/IfcProductRepresentation.h>
#include <ifcpp/IFC4/include/IfcRelVoidsElement.h>
#include <ifcpp/IFC4/include/IfcRepresentation.h>
#include <ifcpp/geometry/Carve/GeometryConverter.h>
#include <ifcpp/model/AttributeObject.h>
#include <ifcpp/model/BuildingException.h>
#include <ifcpp/model/BuildingModel.h>
#include <ifcpp/model/StatusCallback.h>

namespace bimslam::bim::ifc {
namespace {

std::string Lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

void OnMessage(void* target, shared_ptr<StatusCallback::Message> m) {
    auto& log = *static_cast<MessageLog*>(target);
    if (!m) return;
    switch (m->m_message_type) {
        case StatusCallback::MESSAGE_TYPE_PROGRESS_VALUE:
            if (m->m_progress_type == "parse" && log.parse_progress && m->m_progress_value >= 0) {
                log.parse_progress(std::min(1.0, m->m_progress_value));
            }
            return;
        case StatusCallback::MESSAGE_TYPE_PROGRESS_TEXT:
        case StatusCallback::MESSAGE_TYPE_CLEAR_MESSAGES:
        case StatusCallback::MESSAGE_TYPE_CANCELED:
        case StatusCallback::MESSAGE_TYPE_GENERAL_MESSAGE:  // "Detected IFC version: ..."
            return;
        default:
            break;
    }
    std::string text = Utf8(m->m_message_text);
    while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back()))) text.pop_back();
    if (text.empty()) return;
    // Sweeper::createTriangulated3DFace drops the face it says this of (it returns without adding
    // triangles): the element then lacks that face, which is reported, not silently thinned.
    if (dynamic_cast<const IfcFace*>(m->m_entity) != nullptr &&
        (text.find("incorporateHolesIntoPolygon failed") != std::string::npos ||
         text.find("unable to project to plane") != std::string::npos)) {
        log.AddLostFace(m->m_entity->m_entity_id);
    }
    // An entity other than the product being converted (a profile, a solid) is worth naming.
    if (m->m_entity != nullptr) {
        text +=
            " (#" + std::to_string(m->m_entity->m_entity_id) + " " + m->m_entity->className() + ")";
    }
    log.Add(text);
}

// Representations meant as 3D bodies. Others (Axis, FootPrint, Box, Annotation, Clearance...) are
// not geometry a LiDAR sees; IfcBoundingBox items ("Box") already yield nothing in IFC++.
bool IsBodyIdentifier(const std::string& id) { return id == "body"; }
bool IsNonBodyIdentifier(const std::string& id) {
    for (const char* other : {"axis", "footprint", "box", "annotation", "clearance", "lighting",
                              "profile", "reference", "cog", "survey"}) {
        if (id == other) return true;
    }
    return false;
}
bool IsBodyType(const std::string& type) {
    for (const char* body :
         {"sweptsolid", "advancedsweptsolid", "brep", "advancedbrep", "csg", "clipping",
          "surfacemodel", "tessellation", "solidmodel", "surface3d", "advancedsurface"}) {
        if (type == body) return true;
    }
    return false;
}

bool ExpectsBody(const IfcProduct& product) {
    if (!product.m_Representation) return false;
    for (const auto& rep : product.m_Representation->m_Representations) {
        if (!rep) continue;
        const std::string id = rep->m_RepresentationIdentifier
                                   ? Lower(Utf8(rep->m_RepresentationIdentifier->m_value))
                                   : "";
        const std::string type =
            rep->m_RepresentationType ? Lower(Utf8(rep->m_RepresentationType->m_value)) : "";
        if (IsBodyIdentifier(id) || IsBodyType(type)) return true;
    }
    return false;
}

// Appends the faces of one carve mesh set. Faces are planar polygons (CSG results come out
// triangulated, B-rep faces and extrusion caps need not), possibly non-convex: ear clipping
// (carve's triangulator) in the face's own 2D projection, with a fan as fallback. Each triangle is
// wound like its polygon (Newell normal), which keeps the outward orientation carve gives closed
// solids.
void AppendMeshSet(const carve::mesh::MeshSet<3>& meshset, const carve::math::Matrix& transform,
                   ProductMesh& out, std::unordered_map<const void*, uint32_t>& index_of) {
    std::vector<carve::mesh::Vertex<3>*> verts;
    std::vector<carve::geom2d::P2> poly;
    std::vector<carve::triangulate::tri_idx> tris;
    std::vector<uint32_t> ids;
    for (const auto* mesh : meshset.meshes) {
        for (const auto* face : mesh->faces) {
            face->getVertices(verts);
            const size_t n = verts.size();
            if (n < 3) continue;
            ids.clear();
            for (const auto* v : verts) {
                auto [it, fresh] = index_of.try_emplace(v, uint32_t(out.vertices.size()));
                if (fresh) {
                    const vec3 w = transform * v->v;
                    out.vertices.emplace_back(w.x, w.y, w.z);
                }
                ids.push_back(it->second);
            }
            tris.clear();
            if (n > 3) {
                poly.clear();
                for (const auto* v : verts) poly.push_back(face->project(v->v));
                try {
                    carve::triangulate::triangulate(poly, tris);
                    carve::triangulate::improve(poly, tris);
                } catch (...) {
                    tris.clear();
                }
            }
            if (tris.empty()) {
                for (unsigned k = 1; k + 1 < n; ++k) tris.emplace_back(0, k, k + 1);
            }
            // The polygon's normal (Newell) after the transform, to wind every triangle the same
            // way; a mirroring placement (negative determinant) is thereby accounted for.
            Eigen::Vector3d normal = Eigen::Vector3d::Zero();
            for (size_t k = 0; k < n; ++k) {
                const Eigen::Vector3d& a = out.vertices[ids[k]];
                const Eigen::Vector3d& b = out.vertices[ids[(k + 1) % n]];
                normal += a.cross(b);
            }
            for (const auto& t : tris) {
                if (t.a >= n || t.b >= n || t.c >= n) continue;
                std::array<uint32_t, 3> tri{ids[t.a], ids[t.b], ids[t.c]};
                const Eigen::Vector3d& a = out.vertices[tri[0]];
                const Eigen::Vector3d tn =
                    (out.vertices[tri[1]] - a).cross(out.vertices[tri[2]] - a);
                if (tn.dot(normal) < 0) std::swap(tri[1], tri[2]);
                out.triangles.push_back(tri);
            }
        }
    }
}

using MeshSetPtr = shared_ptr<carve::mesh::MeshSet<3>>;

std::string Subject(const IfcProduct& p) {
    return std::string(p.className()) + " " +
           (p.m_GlobalId ? Utf8(p.m_GlobalId->m_value) : "#" + std::to_string(p.m_entity_id));
}

// Calls fn(MeshSetPtr&) on the solids (and, with `open`, the surfaces) of the representations a
// product is drawn with: its "Body" ones when it has any (others may repeat the body), else all
// but the kinds that are no body (axes, footprints, boxes...).
template <typename Fn>
void ForEachBodyMeshSet(ProductShapeData& shape, bool open, Fn&& fn) {
    bool has_body = false;
    for (const auto& rep : shape.m_vec_representations) {
        has_body |= rep && IsBodyIdentifier(Lower(Utf8(rep->m_representation_identifier)));
    }
    for (const auto& rep : shape.m_vec_representations) {
        if (!rep) continue;
        const std::string id = Lower(Utf8(rep->m_representation_identifier));
        if (has_body ? !IsBodyIdentifier(id) : IsNonBodyIdentifier(id)) continue;
        for (const auto& item : rep->m_vec_item_data) {
            if (!item) continue;
            for (auto& m : item->m_meshsets) {
                if (m) fn(m);
            }
            if (!open) continue;
            for (auto& m : item->m_meshsets_open) {
                if (m) fn(m);
            }
        }
    }
}

// How an opening is cut: grown by grow_m along each of its axes (about its box's centre) and
// shifted by shift_m, both in its own frame. See Impl::SubtractOpenings.
struct CutAttempt {
    double grow_m;
    double shift_m[3];
};
constexpr CutAttempt kCutAttempts[] = {
    {1e-3, {0, 0, 0}}, {2e-3, {3.1e-4, 1.7e-4, 2.3e-4}}, {0, {0, 0, 0}}};

// A copy of `solid` changed as `attempt` says, then moved by `transform`.
MeshSetPtr Placed(const carve::mesh::MeshSet<3>& solid, const carve::math::Matrix& transform,
                  const CutAttempt& attempt) {
    MeshSetPtr out(solid.clone());
    const carve::geom::aabb<3> box = out->getAABB();  // pos: centre, extent: half sizes
    for (auto& vertex : out->vertex_storage) {
        for (int k = 0; k < 3; ++k) {
            const double half = box.extent.v[k];
            const double scale = half > 0 ? (half + attempt.grow_m / 2) / half : 1.0;
            vertex.v.v[k] =
                box.pos.v[k] + (vertex.v.v[k] - box.pos.v[k]) * scale + attempt.shift_m[k];
        }
    }
    GeomUtils::applyTransform(out, transform);  // recalculates faces and planes
    return out;
}

}  // namespace

// Not in the anonymous namespace: Geometry::Impl holds one.
// Finds what IFC++'s geometry code would crash on in a damaged file: a list attribute holding a
// reference of the wrong type (its reader stores a null there, which the converters dereference)
// and reference cycles (they would recurse forever). An entity is broken when it, or anything it
// refers to, is. Only forward attributes are followed; styles, the one thing IFC++ reaches through
// inverse attributes, are switched off (Geometry's constructor).
class ReferenceCheck {
public:
    // Why `e` is broken; empty when it is not.
    std::string Check(const BuildingEntity& e, int depth = 0) {
        auto [it, fresh] = state_.try_emplace(&e, kVisiting);
        if (!fresh) {
            if (it->second == kVisiting) return Name(e) + " is part of a reference cycle";
            if (it->second == kFine) return {};
            return broken_.at(&e);
        }
        std::string why;
        if (depth > kMaxDepth) {
            why = Name(e) + ": references nested deeper than " + std::to_string(kMaxDepth);
        } else {
            std::vector<std::pair<std::string, shared_ptr<BuildingObject>>> attributes;
            e.getAttributes(attributes);
            for (const auto& [name, value] : attributes) {
                why = CheckValue(e, name, value.get(), depth);
                if (!why.empty()) break;
            }
        }
        state_[&e] = why.empty() ? kFine : kBroken;
        if (!why.empty()) broken_[&e] = why;
        return why;
    }

private:
    enum State : uint8_t { kVisiting, kFine, kBroken };
    static constexpr int kMaxDepth = 1000;

    static std::string Name(const BuildingEntity& e) {
        return "#" + std::to_string(e.m_entity_id) + " (" + e.className() + ")";
    }

    std::string CheckValue(const BuildingEntity& owner, const std::string& attribute,
                           const BuildingObject* value, int depth) {
        if (value == nullptr) return {};  // unset ($)
        if (const auto* list = dynamic_cast<const AttributeObjectVector*>(value)) {
            for (const auto& item : list->m_vec) {
                if (!item) {
                    return Name(owner) + ": its " + attribute +
                           " list refers to something of the wrong type";
                }
                std::string why = CheckValue(owner, attribute, item.get(), depth);
                if (!why.empty()) return why;
            }
            return {};
        }
        if (const auto* entity = dynamic_cast<const BuildingEntity*>(value)) {
            return Check(*entity, depth + 1);
        }
        return {};  // a value (label, measure, enumeration)
    }

    std::unordered_map<const BuildingEntity*, State> state_;
    std::unordered_map<const BuildingEntity*, std::string> broken_;
};

void MessageLog::SetSubject(std::string subject) {
    subject_ = std::move(subject);
    subject_first_.clear();
    subject_lost_faces_.clear();
}

void MessageLog::AddLostFace(int face_id) {
    lost_faces.insert(face_id);
    if (std::find(subject_lost_faces_.begin(), subject_lost_faces_.end(), face_id) ==
        subject_lost_faces_.end()) {
        subject_lost_faces_.push_back(face_id);
    }
}

void MessageLog::Add(const std::string& text) {
    ++count;
    const std::string full = subject_.empty() ? text : subject_ + ": " + text;
    if (!subject_.empty() && subject_first_.empty()) subject_first_ = text;
    if (kept.size() < kMaxKept && seen_.insert(full).second) kept.push_back(full);
}

void ListenTo(StatusCallback& source, MessageLog& log) {
    source.setMessageCallBack(&log, &OnMessage);
}

QuietStreams::QuietStreams(MessageLog& log)
    : log_(log),
      cout_(std::cout.rdbuf(narrow_.rdbuf())),
      cerr_(std::cerr.rdbuf(narrow_.rdbuf())),
      clog_(std::clog.rdbuf(narrow_.rdbuf())),
      wcout_(std::wcout.rdbuf(wide_.rdbuf())),
      wcerr_(std::wcerr.rdbuf(wide_.rdbuf())),
      wclog_(std::wclog.rdbuf(wide_.rdbuf())) {}

QuietStreams::~QuietStreams() {
    std::cout.rdbuf(cout_);
    std::cerr.rdbuf(cerr_);
    std::clog.rdbuf(clog_);
    std::wcout.rdbuf(wcout_);
    std::wcerr.rdbuf(wcerr_);
    std::wclog.rdbuf(wclog_);
    try {
        const std::string printed = narrow_.str() + "\n" + Utf8(wide_.str());
        std::istringstream lines(printed);
        for (std::string line; std::getline(lines, line);) {
            if (!line.empty()) log_.Add("IFC++ printed: " + line);
        }
    } catch (...) {  // a destructor must not throw; losing diagnostics is acceptable
    }
}

std::string Utf8(const std::wstring& text) {
    std::string out;
    out.reserve(text.size());
    for (const wchar_t wc : text) {
        auto c = static_cast<uint32_t>(wc);
        if (c > 0x10FFFF || (c >= 0xD800 && c <= 0xDFFF)) c = 0xFFFD;  // not a code point
        if (c < 0x80) {
            out += static_cast<char>(c);
        } else if (c < 0x800) {
            out += static_cast<char>(0xC0 | (c >> 6));
            out += static_cast<char>(0x80 | (c & 0x3F));
        } else if (c < 0x10000) {
            out += static_cast<char>(0xE0 | (c >> 12));
            out += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
            out += static_cast<char>(0x80 | (c & 0x3F));
        } else {
            out += static_cast<char>(0xF0 | (c >> 18));
            out += static_cast<char>(0x80 | ((c >> 12) & 0x3F));
            out += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
            out += static_cast<char>(0x80 | (c & 0x3F));
        }
    }
    return out;
}

// An opening's solids in its own frame, and that frame's placement in the world.
struct OpeningShape {
    std::string name;  // "IfcOpeningElement <GlobalId>"
    carve::math::Matrix placement;
    std::vector<MeshSetPtr> solids;
};

struct Geometry::Impl {
    shared_ptr<BuildingModel> model;
    MessageLog& log;
    GeometryConverter converter;
    // Openings converted so far (an element's parts share its openings).
    std::map<const IfcFeatureElementSubtraction*, std::unique_ptr<OpeningShape>> openings;
    // The openings taken away from IFC++ while Convert runs (see there).
    std::map<const IfcElement*, std::vector<weak_ptr<IfcRelVoidsElement>>> taken;
    ReferenceCheck references;

    Impl(shared_ptr<BuildingModel> m, MessageLog& l)
        : model(std::move(m)), log(l), converter(model) {}

    const OpeningShape& OpeningOf(const shared_ptr<IfcFeatureElementSubtraction>& o) {
        auto& slot = openings[o.get()];
        if (slot) return *slot;
        slot = std::make_unique<OpeningShape>();
        slot->name = Subject(*o);
        if (const std::string broken = references.Check(*o); !broken.empty()) {
            log.Add(slot->name + " not subtracted: " + broken);
            return *slot;
        }
        auto shape = std::make_shared<ProductShapeData>(o->m_entity_id);
        shape->m_ifc_object_definition = o;
        try {
            converter.convertIfcProductShape(shape);
            slot->placement = shape->getTransform();
            ForEachBodyMeshSet(*shape, false, [&](MeshSetPtr& m) { slot->solids.push_back(m); });
        } catch (...) {
            slot->solids.clear();
            log.Add(slot->name + ": its geometry failed, so it is not subtracted");
        }
        return *slot;
    }

    // The openings that cut `p`: its own, and those of the whole it is aggregated into (a wall
    // exported as layers: IFC++'s subtractOpeningsInRelatedObjects does the same).
    std::vector<shared_ptr<IfcFeatureElementSubtraction>> OpeningsOf(const IfcProduct& p) const {
        std::vector<shared_ptr<IfcFeatureElementSubtraction>> out;
        auto add = [&](const IfcElement* e) {
            const auto it = taken.find(e);
            for (const auto& rel : it != taken.end() ? it->second : e->m_HasOpenings_inverse) {
                const auto r = rel.lock();
                if (r && r->m_RelatedOpeningElement &&
                    r->m_RelatedOpeningElement->m_Representation) {
                    out.push_back(r->m_RelatedOpeningElement);
                }
            }
        };
        if (const auto* e = dynamic_cast<const IfcElement*>(&p)) add(e);
        for (const auto& rel : p.m_Decomposes_inverse) {
            const auto r = rel.lock();
            if (!r) continue;
            if (const auto* whole = dynamic_cast<const IfcElement*>(r->m_RelatingObject.get())) {
                add(whole);
            }
        }
        return out;
    }

    MeshSetPtr Minus(MeshSetPtr& solid, MeshSetPtr cut, IfcProduct& p) {
        MeshSetPtr result;
        CSG_Adapter::computeCSG(solid, cut, carve::csg::CSG::A_MINUS_B, result, &converter, &p);
        return result == solid ? nullptr : result;  // IFC++ hands the solid back when carve fails
    }

    // Subtracts the openings from the product's solids (in the product's frame, as IFC++ does).
    void SubtractOpenings(ProductShapeData& shape, IfcProduct& p) {
        const auto cutters = OpeningsOf(p);
        if (cutters.empty()) return;
        carve::math::Matrix to_product;
        if (!GeomUtils::computeInverse(shape.getTransform(), to_product)) {
            log.Add("singular placement: openings not subtracted");
            return;
        }
        ForEachBodyMeshSet(shape, false, [&](MeshSetPtr& solid) {
            for (const auto& cutter : cutters) {
                const OpeningShape& opening = OpeningOf(cutter);
                const carve::math::Matrix relative = to_product * opening.placement;
                for (const auto& cut : opening.solids) {
                    // Exporters make openings exactly as thick as their wall, and carve fails on
                    // faces that lie in each other: IFC++ then keeps the wall uncut (Office_A had
                    // 23 of 171 windows and doors shut) or leaves faces across the hole. Grown by
                    // a millimetre, openings cut cleanly. carve's result also depends on pointer
                    // order (it varies from run to run), so a failure is retried a little
                    // differently, and at last with the opening as modelled.
                    MeshSetPtr result;
                    bool touches = false;
                    for (const CutAttempt& attempt : kCutAttempts) {
                        MeshSetPtr placed = Placed(*cut, relative, attempt);
                        if (!placed->getAABB().intersects(solid->getAABB())) break;
                        touches = true;
                        if ((result = Minus(solid, placed, p))) break;
                    }
                    if (result) {
                        solid = result;
                    } else if (touches) {
                        log.Add(opening.name + " not subtracted: carve's CSG failed");
                    }
                }
            }
        });
    }
};

Geometry::Geometry(std::shared_ptr<BuildingModel> model, int vertices_per_circle, MessageLog& log)
    : impl_(std::make_unique<Impl>(std::move(model), log)) {
    GeometryConverter& c = impl_->converter;
    // The converter makes itself the model's and its sub-converters' message target.
    ListenTo(c, log);
    c.getGeomSettings()->setNumVerticesPerCircle(vertices_per_circle);
    // Colours are of no use here, and styles are reached through inverse attributes, where
    // ReferenceCheck does not look.
    c.getGeomSettings()->setHandleStyledItems(false);
    c.getGeomSettings()->setHandleLayerAssignments(false);
    // convertGeometry() sets carve's (global) tolerance to 1.5e-5 times the length unit, but the
    // geometry is in metres whatever the unit, so a millimetre file would get 1.5e-8 m. The
    // metre-file value for every file: the same model in mm and m gives the same mesh.
    carve::setEpsilon(1.5e-5);
}

Geometry::~Geometry() = default;

std::optional<double> Geometry::PlacementZ(const std::shared_ptr<IfcProduct>& product) {
    if (!product || !product->m_ObjectPlacement) return std::nullopt;
    try {
        auto data = std::make_shared<ProductShapeData>(product->m_entity_id);
        std::unordered_set<IfcObjectPlacement*> applied;
        impl_->converter.getRepresentationConverter()
            ->getPlacementConverter()
            ->convertIfcObjectPlacement(product->m_ObjectPlacement, data, applied, false);
        const vec3 origin = data->getTransform() * carve::geom::VECTOR(0.0, 0.0, 0.0);
        if (std::isfinite(origin.z)) return origin.z;
    } catch (...) {  // a broken placement: no height from it
    }
    return std::nullopt;
}

std::vector<ProductMesh> Geometry::Convert(const std::vector<std::shared_ptr<IfcProduct>>& products,
                                           const std::function<void(double)>& progress) {
    Impl& im = *impl_;
    std::vector<ProductMesh> out(products.size());
    // IFC++ subtracts an element's openings inside convertIfcProductShape and, when carve fails,
    // keeps the uncut solid without a word. Hidden from it here, they are subtracted by
    // Impl::SubtractOpenings, which retries and reports.
    // It also reads colours from property sets there, dereferencing property names that a
    // damaged file may lack; colours are of no use here, so the property sets are hidden too.
    std::vector<std::vector<weak_ptr<IfcRelDefinesByProperties>>> defined_by(products.size());
    for (size_t i = 0; i < products.size(); ++i) {
        auto* e = dynamic_cast<IfcElement*>(products[i].get());
        if (e && !e->m_HasOpenings_inverse.empty()) {
            im.taken[e] = std::exchange(e->m_HasOpenings_inverse, {});
        }
        defined_by[i] = std::exchange(products[i]->m_IsDefinedBy_inverse, {});
    }
    // What GeometryConverter::convertGeometry() does, one product at a time, so that each
    // message and exception is attributed to its product and progress advances per product.
    im.converter.clearInputCache();
    for (size_t i = 0; i < products.size(); ++i) {
        IfcProduct& product = *products[i];
        ProductMesh& mesh = out[i];
        im.log.SetSubject(Subject(product));
        mesh.expects_body = ExpectsBody(product);
        if (std::string broken = im.references.Check(product); !broken.empty()) {
            mesh.error = "not converted: " + broken;
            im.log.Add(mesh.error);
            if (progress) progress(double(i + 1) / double(products.size()));
            continue;
        }
        auto shape = std::make_shared<ProductShapeData>(product.m_entity_id);
        shape->m_ifc_object_definition = products[i];
        try {
            im.converter.convertIfcProductShape(shape);
            im.SubtractOpenings(*shape, product);
            const carve::math::Matrix transform = shape->getTransform();
            std::unordered_map<const void*, uint32_t> index_of;
            ForEachBodyMeshSet(
                *shape, true, [&](MeshSetPtr& m) { AppendMeshSet(*m, transform, mesh, index_of); });
        } catch (const carve::exception& e) {
            mesh.error = "carve: " + e.str();
        } catch (const std::exception& e) {
            mesh.error = e.what();
        } catch (...) {
            mesh.error = "unknown exception in IFC++";
        }
        if (!mesh.error.empty()) im.log.Add(mesh.error);
        if (mesh.error.empty()) mesh.error = im.log.subject_first();
        mesh.lost_faces = im.log.subject_lost_faces();
        if (progress) progress(double(i + 1) / double(products.size()));
    }
    im.log.SetSubject("");
    for (size_t i = 0; i < products.size(); ++i) {
        products[i]->m_IsDefinedBy_inverse = std::move(defined_by[i]);
    }
    for (auto& [element, rels] : im.taken) {
        const_cast<IfcElement*>(element)->m_HasOpenings_inverse = std::move(rels);
    }
    im.taken.clear();
    im.openings.clear();
    im.converter.clearInputCache();
    return out;
}

}  // namespace bimslam::bim::ifc
