// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// IFC ingest: checks the STEP text, lets IFC++ read it, then collects storeys, elements, roles and
// class counts; the geometry is ifc_geometry.cpp's. The IFC++ traps it works around are listed in
// ../../../shared/DESIGN.md ("Known traps") and at the top of ifc_geometry.cpp.
#include "host_tools/bim/ifc_model.hpp"

#include "host_tools/bim/assumed_floors.hpp"
#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <mutex>

#include "algorithms/common/status.hpp"
#include "algorithms/io/file_util.hpp"
#include "host_tools/bim/assumed_floors.hpp"
#include "host_tools/bim/ifc_face_bounds.hpp"
#include "host_tools/bim/ifc_geometry.hpp"

// IFC++ headers (system headers for the compiler: they are not -Wall clean).
#include <ifcpp/IFC4/include/IfcBuildingStorey.h>
#include <ifcpp/IFC4/include/IfcElement.h>
#include <ifcpp/IFC4/include/IfcFeatureElementSubtraction.h>
#include <ifcpp/IFC4/include/IfcGloballyUniqueId.h>
#include <ifcpp/IFC4/include/IfcInteger.h>
#include <ifcpp/IFC4/include/IfcLabel.h>
#include <ifcpp/IFC4/include/IfcLengthMeasure.h>
#include <ifcpp/IFC4/include/IfcOpeningElement.h>
#include <ifcpp/IFC4/include/IfcPositiveLengthMeasure.h>
#include <ifcpp/IFC4/include/IfcProduct.h>
#include <ifcpp/IFC4/include/IfcProject.h>
#include <ifcpp/IFC4/include/IfcRelAggregates.h>
#include <ifcpp/IFC4/include/IfcRelContainedInSpatialStructure.h>
#include <ifcpp/IFC4/include/IfcRelFillsElement.h>
#include <ifcpp/IFC4/include/IfcRelVoidsElement.h>
#include <ifcpp/IFC4/include/IfcSpace.h>
#include <ifcpp/IFC4/include/IfcSpatialElement.h>
#include <ifcpp/IFC4/include/IfcStairFlight.h>
#include <ifcpp/model/BuildingModel.h>
#include <ifcpp/model/UnitConverter.h>
#include <ifcpp/reader/ReaderSTEP.h>

namespace bimslam::bim {
namespace {
using common::FileError;
using common::StatusCode;

// ----- The STEP text, checked before IFC++ sees it
// ------------------------------------------------ IFC++ reports bad input by message at best, and
// walks past the end of its buffer on some (an unterminated comment, a string ending in "\X\"), so
// everything it relies on is checked here.

struct StepText {
    std::string text;    // what IFC++ gets: comments removed, string escapes made safe for it
    std::string schema;  // as BimModel::schema reports it
};

bool IsHex(char c) { return std::isxdigit(static_cast<unsigned char>(c)) != 0; }

std::string_view Trim(std::string_view s) {
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
    return s;
}

// The length of a valid escape at raw[i] == '\\' inside a string (ISO 10303-21 §6.4.3), 0 when
// it is malformed in a way IFC++ would read past its buffer on.
size_t EscapeLength(std::string_view raw, size_t i) {
    auto at = [&](size_t k) { return i + k < raw.size() ? raw[i + k] : '\0'; };
    if (at(1) == '\\') return 2;  // \\ is a backslash
    if (raw.substr(i, 3) == "\\X\\") return IsHex(at(3)) && IsHex(at(4)) ? 5 : 0;
    for (const size_t group : {size_t{4}, size_t{8}}) {  // \X2\ (UCS-2) and \X4\ (UCS-4)
        if (raw.substr(i, 4) != (group == 4 ? "\\X2\\" : "\\X4\\")) continue;
        size_t k = 4;
        while (IsHex(at(k))) ++k;
        const bool whole_groups = k > 4 && (k - 4) % group == 0;
        return whole_groups && raw.substr(i + k, 4) == "\\X0\\" ? k + 4 : 0;
    }
    return 1;  // \S\, \P?\, \N\ and the rest are harmless to IFC++
}

StepText CheckStepText(const std::string& name, const std::string& raw) {
    constexpr std::string_view kMagic = "ISO-10303-21;", kEnd = "END-ISO-10303-21;";
    size_t i = raw.compare(0, 3, "\xEF\xBB\xBF") == 0 ? 3 : 0;  // a UTF-8 byte order mark
    while (i < raw.size() && std::isspace(static_cast<unsigned char>(raw[i]))) ++i;
    if (raw.compare(i, kMagic.size(), kMagic) != 0) {
        throw FileError(
            StatusCode::kParseError, name, 0,
            std::string(Trim(raw).empty() ? "empty: " : "") + "not an ISO-10303-21 (STEP) file");
    }
    StepText out;
    out.text.reserve(raw.size());
    enum class State { kCode, kString, kComment } state = State::kCode;
    size_t line = 1, open_line = 0, statement_begin = 0, statement_line = 1, entities = 0;
    size_t schema_line = 0, schema_begin = 0, schema_end = 0, bad_escape_line = 0;
    bool in_data = false;
    std::string schema_statement;
    for (; i < raw.size(); ++i) {
        const char c = raw[i];
        const char next = i + 1 < raw.size() ? raw[i + 1] : '\0';
        if (c == '\0') {
            throw FileError(StatusCode::kParseError, name, line,
                            "binary data (a NUL byte): not a STEP text file");
        }
        if (c == '\n') ++line;
        if (state == State::kComment) {
            if (c == '*' && next == '/') {
                state = State::kCode;
                out.text += ' ';
                ++i;
            }
            continue;
        }
        if (state == State::kString) {
            if (c == '\'') {
                out.text += c;
                if (next == '\'') {
                    out.text += next;  // '' is a quote inside the string
                    ++i;
                } else {
                    state = State::kCode;
                }
            } else if (c == '\\') {
                const size_t n = EscapeLength(raw, i);
                if (n == 0 && bad_escape_line == 0) bad_escape_line = line;
                // IFC++ takes a lone \' for an escaped quote (STEP has none): double the backslash
                // so that the quote ends the string for IFC++ as it does here.
                if (n == 1 && next == '\'') out.text += '\\';
                out.text.append(raw, i, std::max<size_t>(n, 1));
                i += std::max<size_t>(n, 1) - 1;
            } else if (c == '/' && next == '*') {
                out.text += "\\X\\2F";  // IFC++ strips comments even inside strings
            } else {
                out.text += c;
            }
            continue;
        }
        if (c == '\'') {
            state = State::kString;
            open_line = line;
            out.text += c;
            continue;
        }
        if (c == '/' && next == '*') {
            state = State::kComment;
            open_line = line;
            ++i;
            continue;
        }
        if (out.text.size() == statement_begin && std::isspace(static_cast<unsigned char>(c))) {
            statement_begin = out.text.size() + 1;
            statement_line = line;
        }
        out.text += c;
        if (c != ';') continue;
        const std::string_view statement = Trim(std::string_view(out.text).substr(statement_begin));
        if (statement == "DATA;") {
            in_data = true;
        } else if (statement == "ENDSEC;") {
            in_data = false;
        } else if (in_data && statement.front() == '#') {
            ++entities;
        } else if (!in_data && statement.starts_with("FILE_SCHEMA") && schema_line == 0) {
            schema_statement = std::string(statement);
            schema_line = statement_line;
            schema_begin = statement_begin;
            schema_end = out.text.size();
        }
        statement_begin = out.text.size();
        statement_line = line;
    }
    if (state != State::kCode || !Trim(out.text).ends_with(kEnd)) {
        std::string where;
        if (state != State::kCode) {
            where = std::string(state == State::kString ? " (a string" : " (a comment") +
                    " opened on line " + std::to_string(open_line) + " never closes)";
        }
        throw FileError(StatusCode::kDataLoss, name, 0, "cut off: no END-ISO-10303-21" + where);
    }
    if (bad_escape_line != 0) {
        throw FileError(StatusCode::kParseError, name, bad_escape_line,
                        "malformed \\X\\, \\X2\\ or \\X4\\ escape in a string");
    }
    if (schema_line == 0) {
        throw FileError(StatusCode::kParseError, name, 0, "no FILE_SCHEMA in the header");
    }
    const size_t q0 = schema_statement.find('\''), q1 = schema_statement.find('\'', q0 + 1);
    if (q0 == std::string::npos || q1 == std::string::npos) {
        throw FileError(StatusCode::kParseError, name, schema_line, "FILE_SCHEMA names no schema");
    }
    std::string schema(Trim(std::string_view(schema_statement).substr(q0 + 1, q1 - q0 - 1)));
    std::transform(schema.begin(), schema.end(), schema.begin(),
                   [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
    if (schema.rfind("IFC2X3", 0) == 0) {
        out.schema = "IFC2X3";
    } else if (schema == "IFC4" || schema.rfind("IFC4_ADD", 0) == 0) {
        // IFC4 addenda are IFC4 to IFC++'s classes, but its reader only accepts "IFC4" itself.
        out.schema = "IFC4";
        out.text.replace(schema_begin, schema_end - schema_begin, "\nFILE_SCHEMA(('IFC4'));");
    } else {
        throw FileError(
            StatusCode::kParseError, name, schema_line,
            "schema " + schema + " is not supported: IFC2X3 or IFC4 (the schemas IFC++ reads)");
    }
    if (entities == 0) {
        throw FileError(StatusCode::kParseError, name, 0, "no entities in a DATA section");
    }
    return out;
}

// ----- The model's semantics
// -----------------------------------------------------------------------

// IFC++ reads an IFC2X3 IfcStairFlight's NumberOfRiser into IFC4's NumberOfRisers (the same
// position); lengths are in the file's unit.
DeclaredFlight DeclaredFlightOf(const IfcStairFlight& f, double unit) {
    DeclaredFlight d;
    d.length_unit_m = unit;
    if (f.m_NumberOfRisers) d.risers = f.m_NumberOfRisers->m_value;
    if (f.m_NumberOfTreads) d.treads = f.m_NumberOfTreads->m_value;
    if (f.m_RiserHeight) d.riser_height_m = f.m_RiserHeight->m_value * unit;
    if (f.m_TreadLength) d.tread_length_m = f.m_TreadLength->m_value * unit;
    return d;
}

std::string NameOf(const IfcRoot& o) { return o.m_Name ? ifc::Utf8(o.m_Name->m_value) : ""; }
std::string GlobalIdOf(const IfcRoot& o) {
    return o.m_GlobalId ? ifc::Utf8(o.m_GlobalId->m_value) : "";
}

// What `o` is directly part of or placed in: its spatial container, the opening it fills, the
// element an opening voids, or the whole it is aggregated into. nullptr at the top.
const IfcObjectDefinition* ParentOf(const IfcObjectDefinition& o) {
    if (const auto* e = dynamic_cast<const IfcElement*>(&o)) {
        for (const auto& rel : e->m_ContainedInStructure_inverse) {
            if (auto r = rel.lock(); r && r->m_RelatingStructure)
                return r->m_RelatingStructure.get();
        }
        for (const auto& rel : e->m_FillsVoids_inverse) {
            if (auto r = rel.lock(); r && r->m_RelatingOpeningElement) {
                return r->m_RelatingOpeningElement.get();
            }
        }
    }
    if (const auto* f = dynamic_cast<const IfcFeatureElementSubtraction*>(&o)) {
        if (auto r = f->m_VoidsElements_inverse.lock(); r && r->m_RelatingBuildingElement) {
            return r->m_RelatingBuildingElement.get();
        }
    }
    for (const auto& rel : o.m_Decomposes_inverse) {
        if (auto r = rel.lock(); r && r->m_RelatingObject) return r->m_RelatingObject.get();
    }
    return nullptr;
}

constexpr int kMaxDepth = 64;  // against cyclic relations in broken files

int StoreyOf(const IfcObjectDefinition& o, const std::map<const void*, int>& storey_index) {
    const IfcObjectDefinition* at = &o;
    for (int depth = 0; at != nullptr && depth < kMaxDepth; ++depth) {
        if (auto it = storey_index.find(at); it != storey_index.end()) return it->second;
        at = ParentOf(*at);
    }
    return -1;
}

// Members, plates and building element parts take the role of the outermost element they are
// aggregated into (a curtain wall's mullions and panels are as transient as the curtain wall).
ElementRole RoleOf(const IfcProduct& p, const IfcLoadOptions& options) {
    const std::string cls = p.className();
    if (cls.rfind("IfcMember", 0) != 0 && cls.rfind("IfcPlate", 0) != 0 &&
        cls != "IfcBuildingElementPart") {
        return RoleOfClass(cls, options);
    }
    const IfcObjectDefinition* whole = nullptr;
    const IfcObjectDefinition* at = &p;
    for (int depth = 0; depth < kMaxDepth; ++depth) {
        const IfcObjectDefinition* up = nullptr;
        for (const auto& rel : at->m_Decomposes_inverse) {
            if (auto r = rel.lock(); r && r->m_RelatingObject) up = r->m_RelatingObject.get();
        }
        if (up == nullptr || dynamic_cast<const IfcElement*>(up) == nullptr) break;
        whole = at = up;
    }
    return RoleOfClass(whole != nullptr ? whole->className() : cls, options);
}

// Elements and storeys of a model IFC++ has read; fills `out` except file, schema and warnings.
void Collect(const std::string& name, const shared_ptr<BuildingModel>& model,
             const IfcLoadOptions& options, ifc::MessageLog& log,
             const std::function<void(double)>& report, BimModel& out) {
    if (model->getMapIfcEntities().empty()) {
        throw FileError(StatusCode::kParseError, name, 0,
                        "IFC++ read no entities" + (log.kept.empty() ? "" : ": " + log.kept[0]));
    }
    if (!model->getIfcProject()) throw FileError(StatusCode::kParseError, name, 0, "no IfcProject");
    const double unit = model->getUnitConverter()->getLengthInMeterFactor();
    if (!std::isfinite(unit) || unit < 1e-9 || unit > 1e4) {
        throw FileError(StatusCode::kParseError, name, 0,
                        "unusable length unit: " + std::to_string(unit) + " m");
    }
    out.length_unit_m = unit;
    ifc::Geometry geometry(model, options.vertices_per_circle, log);

    std::vector<shared_ptr<IfcProduct>> candidates;  // products whose geometry we build
    std::vector<std::pair<const void*, BimStorey>> storeys;
    for (const auto& [id, entity] : model->getMapIfcEntities()) {
        auto product = dynamic_pointer_cast<IfcProduct>(entity);
        if (!product) continue;
        ++out.class_counts[product->className()];
        if (auto storey = dynamic_pointer_cast<IfcBuildingStorey>(product)) {
            BimStorey s{NameOf(*storey), GlobalIdOf(*storey), 0.0};
            s.elevation_m = storey->m_Elevation ? storey->m_Elevation->m_value * unit : NAN;
            if (!std::isfinite(s.elevation_m)) {
                s.elevation_m = geometry.PlacementZ(storey).value_or(0.0);
            }
            storeys.emplace_back(storey.get(), std::move(s));
        }
        const bool skip = (!options.space_geometry && dynamic_pointer_cast<IfcSpace>(product)) ||
                          (!options.opening_geometry &&
                           dynamic_pointer_cast<IfcFeatureElementSubtraction>(product));
        if (product->m_Representation && !skip) candidates.push_back(product);
    }
    std::stable_sort(storeys.begin(), storeys.end(), [](const auto& a, const auto& b) {
        return a.second.elevation_m < b.second.elevation_m;
    });
    std::map<const void*, int> storey_index;
    for (const auto& [ptr, s] : storeys) {
        storey_index[ptr] = int(out.storeys.size());
        out.storeys.push_back(s);
    }

    out.faces_reordered = ifc::PutOuterBoundsFirst(*model);
    const std::vector<ifc::ProductMesh> meshes =
        geometry.Convert(candidates, [&](double f) { report(0.3 + 0.65 * f); });
    out.faces_lost = log.lost_faces.size();

    // Far from the origin (site coordinates), floats would lose millimetres: store relative.
    Eigen::AlignedBox3d box;
    for (const auto& m : meshes) {
        for (const auto& v : m.vertices) {
            if (v.allFinite()) box.extend(v);
        }
    }
    if (!box.isEmpty() && box.center().norm() > 10e3) out.origin_m = box.center().array().round();

    constexpr uint32_t kUnused = std::numeric_limits<uint32_t>::max();
    for (size_t i = 0; i < candidates.size(); ++i) {
        const IfcProduct& p = *candidates[i];
        const ifc::ProductMesh& m = meshes[i];
        BimElement e{GlobalIdOf(p), p.className(), NameOf(p), StoreyOf(p, storey_index),
                     RoleOf(p, options)};
        if (const auto* spatial = dynamic_cast<const IfcSpatialElement*>(&p);
            spatial && spatial->m_LongName) {
            e.long_name = ifc::Utf8(spatial->m_LongName->m_value);
        }
        if (const auto* flight = dynamic_cast<const IfcStairFlight*>(&p)) {
            e.declared_flight = DeclaredFlightOf(*flight, unit);
        }
        e.first_triangle = uint32_t(out.mesh.triangles.size());
        std::vector<uint32_t> remap(m.vertices.size(), kUnused);
        const auto element_index = uint32_t(out.elements.size());
        for (const auto& tri : m.triangles) {
            std::array<Eigen::Vector3f, 3> q;
            bool ok = true;
            for (int k = 0; k < 3; ++k) {
                const Eigen::Vector3d& v = m.vertices[tri[k]];
                q[k] = (v - out.origin_m).cast<float>();
                ok = ok && v.allFinite() && q[k].allFinite();
            }
            // Zero-area triangles (CSG slivers, repeated corners) carry no surface.
            if (!ok || ((q[1] - q[0]).cast<double>().cross((q[2] - q[0]).cast<double>())).norm() <=
                           1e-12) {
                continue;
            }
            std::array<uint32_t, 3> t{};
            for (int k = 0; k < 3; ++k) {
                uint32_t& r = remap[tri[k]];
                if (r == kUnused) {
                    r = uint32_t(out.mesh.vertices.size());
                    out.mesh.vertices.push_back(q[k]);
                }
                t[k] = r;
            }
            out.mesh.triangles.push_back(t);
            out.triangle_element.push_back(element_index);
        }
        e.triangle_count = uint32_t(out.mesh.triangles.size()) - e.first_triangle;
        if (e.triangle_count > 0 && !m.lost_faces.empty()) {
            std::string reason = "without the faces IFC++ could not triangulate:";
            for (const int face : m.lost_faces) reason += " #" + std::to_string(face);
            out.incomplete.push_back({e.global_id, e.ifc_class, reason});
        }
        if (e.triangle_count > 0) {
            out.elements.push_back(std::move(e));
        } else if (m.expects_body) {
            std::string reason = m.error;
            if (reason.empty()) {
                reason = m.triangles.empty() ? "no geometry from its body representation"
                                             : "only degenerate or non-finite triangles";
            }
            out.failed.push_back({e.global_id, e.ifc_class, reason});
        }
    }
}

}  // namespace

void IfcLoadOptions::Validate() const {
    if (vertices_per_circle < 6 || vertices_per_circle > 720) {
        throw common::Error(StatusCode::kInvalidArgument, "IfcLoadOptions.vertices_per_circle = " +
                                                              std::to_string(vertices_per_circle) +
                                                              ": must be in [6, 720]");
    }
}

ElementRole RoleOfClass(std::string_view ifc_class, const IfcLoadOptions& options) {
    std::string c(ifc_class);
    std::transform(c.begin(), c.end(), c.begin(),
                   [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
    for (const char* suffix : {"standardcase", "elementedcase"}) {
        const std::string_view s(suffix);
        if (c.size() > s.size() && c.ends_with(s)) c.resize(c.size() - s.size());
    }
    for (const char* structure :
         {"ifcwall", "ifcslab", "ifccolumn", "ifcbeam", "ifcstair", "ifcstairflight", "ifcramp",
          "ifcrampflight", "ifcroof", "ifccovering", "ifcmember", "ifcplate"}) {
        if (c == structure) return ElementRole::kStructure;
    }
    if (c == "ifcrailing" && options.railings_are_structure) return ElementRole::kStructure;
    return ElementRole::kTransient;
}

BimModel ParseIfc(const std::string& name, const std::string& step_text,
                  const IfcLoadOptions& options) {
    options.Validate();
    auto report = [&](double f) {
        if (options.progress) options.progress(std::clamp(f, 0.0, 1.0));
    };
    report(0.0);
    StepText step = CheckStepText(name, step_text);
    report(0.05);
    BimModel out;
    out.file = name;
    out.schema = step.schema;
    ifc::MessageLog log;
    log.parse_progress = [&](double f) { report(0.05 + 0.25 * f); };
    {
        // IFC++ and carve keep process-global state (carve's tolerance, the standard streams
        // muted here): one load at a time.
        static std::mutex one_at_a_time;
        const std::lock_guard lock(one_at_a_time);
        const ifc::QuietStreams quiet(log);
        try {
            auto model = std::make_shared<BuildingModel>();
            ReaderSTEP reader;
            ifc::ListenTo(reader, log);
            ifc::ListenTo(*model, log);
            reader.loadModelFromString(step.text, model);
            Collect(name, model, options, log, report, out);
        } catch (const common::Error&) {
            throw;
        } catch (const std::exception& e) {
            throw FileError(StatusCode::kParseError, name, 0,
                            std::string("IFC++ could not read it: ") + e.what());
        } catch (...) {
            throw FileError(StatusCode::kParseError, name, 0, "IFC++ could not read it");
        }
    }
    out.warnings = std::move(log.kept);
    out.warning_count = log.count;
    if (options.assume_floors) AddAssumedFloors(out);
    report(1.0);
    return out;
}

BimModel LoadIfc(const std::filesystem::path& path, const IfcLoadOptions& options) {
    options.Validate();
    // Not ReaderSTEP::loadModelFromFile: in the Debian build it silently loads nothing.
    return ParseIfc(path.string(), io::ReadFileToString(path), options);
}

}  // namespace bimslam::bim
