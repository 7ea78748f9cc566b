// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/changes/bcf_reader.hpp"

#include <libxml/parser.h>
#include <libxml/tree.h>
#include <zip.h>

#include <algorithm>
#include <cctype>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <map>
#include <memory>

#include "algorithms/common/status.hpp"
#include "algorithms/io/file_util.hpp"

namespace bimslam::change_detection {
namespace {

using common::FileError;
using common::StatusCode;

// The zip's entries by name, read on demand and bounded in size.
class ZipIn {
public:
    ZipIn(std::string name, std::string_view bytes) : name_(std::move(name)) {
        zip_error_t error;
        zip_error_init(&error);
        zip_source_t* source = zip_source_buffer_create(bytes.data(), bytes.size(), 0, &error);
        if (source) zip_ = zip_open_from_source(source, ZIP_RDONLY | ZIP_CHECKCONS, &error);
        if (!zip_) {
            const std::string why = zip_error_strerror(&error);
            zip_error_fini(&error);
            if (source) zip_source_free(source);
            throw FileError(StatusCode::kParseError, name_, 0, "not a BCF zip: " + why);
        }
        zip_error_fini(&error);
        const zip_int64_t n = zip_get_num_entries(zip_, 0);
        for (zip_int64_t i = 0; i < n; ++i) {
            const char* entry = zip_get_name(zip_, zip_uint64_t(i), ZIP_FL_ENC_GUESS);
            if (entry) index_.emplace(entry, zip_uint64_t(i)), order_.emplace_back(entry);
        }
    }
    ~ZipIn() { zip_discard(zip_); }
    ZipIn(const ZipIn&) = delete;
    ZipIn& operator=(const ZipIn&) = delete;

    const std::vector<std::string>& names() const { return order_; }
    bool Has(const std::string& entry) const { return index_.contains(entry); }

    std::string Read(const std::string& entry) const {
        const auto it = index_.find(entry);
        if (it == index_.end()) Fail(entry, "missing");
        zip_stat_t st;
        zip_stat_init(&st);
        if (zip_stat_index(zip_, it->second, 0, &st) != 0 || !(st.valid & ZIP_STAT_SIZE))
            Fail(entry, "no size in the zip's directory");
        if (st.size > kMaxBcfEntryBytes) {
            Fail(entry, std::to_string(st.size) + " bytes inflated, over the " +
                            std::to_string(kMaxBcfEntryBytes) + " a BCF entry may hold");
        }
        std::unique_ptr<zip_file_t, decltype(&zip_fclose)> f(zip_fopen_index(zip_, it->second, 0),
                                                             &zip_fclose);
        if (!f) Fail(entry, std::string("cannot open: ") + zip_strerror(zip_));
        std::string out(size_t(st.size), '\0');
        const zip_int64_t got = zip_fread(f.get(), out.data(), st.size);
        if (got != zip_int64_t(st.size))
            Fail(entry, std::string("damaged: ") + zip_file_strerror(f.get()));
        return out;
    }

    [[noreturn]] void Fail(const std::string& entry, const std::string& what) const {
        throw FileError(StatusCode::kParseError, name_, 0, entry + ": " + what);
    }
    const std::string& name() const { return name_; }

private:
    std::string name_;
    zip_t* zip_ = nullptr;
    std::map<std::string, zip_uint64_t> index_;
    std::vector<std::string> order_;
};

using Doc = std::unique_ptr<xmlDoc, decltype(&xmlFreeDoc)>;

// Parses an entry: no network, no entities substituted, no DTD loaded (the defaults, said).
Doc Parse(const ZipIn& zip, const std::string& entry, const char* root) {
    const std::string text = zip.Read(entry);
    xmlResetLastError();
    Doc doc(xmlReadMemory(text.data(), int(text.size()), entry.c_str(), nullptr,
                          XML_PARSE_NONET | XML_PARSE_NOERROR | XML_PARSE_NOWARNING),
            &xmlFreeDoc);
    if (!doc) {
        const xmlError* e = xmlGetLastError();
        std::string why = e && e->message ? e->message : "not XML";
        while (!why.empty() && why.back() == '\n') why.pop_back();
        zip.Fail(entry, "line " + std::to_string(e ? e->line : 0) + ": " + why);
    }
    const xmlNode* r = xmlDocGetRootElement(doc.get());
    if (!r || std::string_view(reinterpret_cast<const char*>(r->name)) != root) {
        zip.Fail(entry, std::string("the root element is ") +
                            (r ? reinterpret_cast<const char*>(r->name) : "missing") + ", not " +
                            root);
    }
    return doc;
}

bool Is(const xmlNode* n, const char* name) {
    return n->type == XML_ELEMENT_NODE && xmlStrcmp(n->name, BAD_CAST name) == 0;
}

std::vector<const xmlNode*> Children(const xmlNode* parent, const char* name) {
    std::vector<const xmlNode*> out;
    if (!parent) return out;
    for (const xmlNode* c = parent->children; c; c = c->next) {
        if (Is(c, name)) out.push_back(c);
    }
    return out;
}

const xmlNode* Child(const xmlNode* parent, const char* name) {
    if (!parent) return nullptr;
    for (const xmlNode* c = parent->children; c; c = c->next) {
        if (Is(c, name)) return c;
    }
    return nullptr;
}

std::string Text(const xmlNode* n) {
    if (!n) return {};
    std::unique_ptr<xmlChar, decltype(xmlFree)> t(xmlNodeGetContent(n), xmlFree);
    return t ? reinterpret_cast<const char*>(t.get()) : "";
}

std::string Text(const xmlNode* parent, const char* name) { return Text(Child(parent, name)); }

std::string Attr(const xmlNode* n, const char* name) {
    if (!n) return {};
    std::unique_ptr<xmlChar, decltype(xmlFree)> a(xmlGetProp(n, BAD_CAST name), xmlFree);
    return a ? reinterpret_cast<const char*>(a.get()) : "";
}

// A number the schema requires: a missing or unreadable one names the entry and element.
double Number(const ZipIn& zip, const std::string& entry, const xmlNode* parent,
              const char* name) {
    const std::string t = Text(parent, name);
    char* end = nullptr;
    const double v = std::strtod(t.c_str(), &end);
    // xs:double's text: surrounding white space allowed, nothing else after the number.
    while (end && *end != '\0' && std::isspace(static_cast<unsigned char>(*end))) ++end;
    if (t.empty() || end == t.c_str() || *end != '\0' || !std::isfinite(v))
        zip.Fail(entry, std::string(name) + " '" + t + "' is not a number");
    return v;
}

// An xs:int (an Index): a number that is a whole one within int's range, else refused (a cast
// of 1e300 to int would be undefined).
int Integer(const ZipIn& zip, const std::string& entry, const xmlNode* parent, const char* name) {
    const double v = Number(zip, entry, parent, name);
    if (v != std::floor(v) || v < INT_MIN || v > INT_MAX)
        zip.Fail(entry, std::string(name) + " '" + Text(parent, name) + "' is not an xs:int");
    return static_cast<int>(v);
}

Eigen::Vector3d Vector(const ZipIn& zip, const std::string& entry, const xmlNode* parent,
                       const char* name) {
    const xmlNode* v = Child(parent, name);
    if (!v) zip.Fail(entry, std::string("the camera has no ") + name);
    return {Number(zip, entry, v, "X"), Number(zip, entry, v, "Y"), Number(zip, entry, v, "Z")};
}

// The IfcGuids of a list's Component elements; 3.0 wraps them in Components.
std::vector<std::string> Components(const xmlNode* list) {
    std::vector<std::string> out;
    const xmlNode* wrapped = Child(list, "Components");
    for (const xmlNode* c : Children(wrapped ? wrapped : list, "Component")) {
        out.push_back(Attr(c, "IfcGuid"));
    }
    return out;
}

void ReadVisinfo(const ZipIn& zip, const std::string& entry, BcfViewpoint& vp) {
    const Doc doc = Parse(zip, entry, "VisualizationInfo");
    const xmlNode* root = xmlDocGetRootElement(doc.get());
    if (vp.guid.empty()) vp.guid = Attr(root, "Guid");
    const xmlNode* components = Child(root, "Components");
    vp.selected = Components(Child(components, "Selection"));
    const xmlNode* visibility = Child(components, "Visibility");
    // DefaultVisibility defaults to false (3.0's schema; 2.1's documentation); a viewpoint with
    // no Visibility at all hides nothing. xs:boolean is true, false, 1 or 0.
    const std::string shown = Attr(visibility, "DefaultVisibility");
    vp.default_visibility = visibility == nullptr || shown == "true" || shown == "1";
    vp.visibility_exceptions = Components(Child(visibility, "Exceptions"));
    for (const xmlNode* color : Children(Child(components, "Coloring"), "Color")) {
        vp.colors.emplace_back(Attr(color, "Color"), Components(color));
    }
    const xmlNode* camera = Child(root, "PerspectiveCamera");
    vp.camera = BcfCamera::kPerspective;
    if (!camera) {
        camera = Child(root, "OrthogonalCamera");
        vp.camera = camera ? BcfCamera::kOrthogonal : BcfCamera::kNone;
    }
    if (!camera) return;
    vp.eye = Vector(zip, entry, camera, "CameraViewPoint");
    vp.direction = Vector(zip, entry, camera, "CameraDirection");
    vp.up = Vector(zip, entry, camera, "CameraUpVector");
    if (vp.camera == BcfCamera::kPerspective) {
        vp.fov_deg = Number(zip, entry, camera, "FieldOfView");
    } else {
        vp.view_to_world_scale = Number(zip, entry, camera, "ViewToWorldScale");
    }
    if (Child(camera, "AspectRatio")) vp.aspect = Number(zip, entry, camera, "AspectRatio");
}

// A markup's viewpoint reference (2.1 Markup/Viewpoints, 3.0 Topic/Viewpoints/ViewPoint): its
// files are relative to the topic's folder.
BcfViewpoint ReadViewpoint(const ZipIn& zip, const std::string& folder, const std::string& markup,
                           const xmlNode* ref, int* index) {
    BcfViewpoint vp;
    vp.guid = Attr(ref, "Guid");
    const std::string index_text = Text(ref, "Index");
    *index = INT_MAX;
    if (!index_text.empty()) *index = Integer(zip, markup, ref, "Index");
    // 2.1 and 3.0 name the file; an older habit leaves it out for "viewpoint.bcfv".
    std::string file = Text(ref, "Viewpoint");
    if (file.empty() && zip.Has(folder + "viewpoint.bcfv")) file = "viewpoint.bcfv";
    if (!file.empty()) {
        if (!zip.Has(folder + file))
            zip.Fail(markup, "names viewpoint file " + file + ", which the zip lacks");
        ReadVisinfo(zip, folder + file, vp);
    }
    const std::string snapshot = Text(ref, "Snapshot");
    if (!snapshot.empty()) {
        if (!zip.Has(folder + snapshot))
            zip.Fail(markup, "names snapshot " + snapshot + ", which the zip lacks");
        vp.snapshot_png = zip.Read(folder + snapshot);
    }
    return vp;
}

BcfComment ReadComment(const xmlNode* c) {
    BcfComment out;
    out.guid = Attr(c, "Guid");
    out.date = Text(c, "Date");
    out.author = Text(c, "Author");
    out.text = Text(c, "Comment");
    out.viewpoint_guid = Attr(Child(c, "Viewpoint"), "Guid");
    return out;
}

BcfReadTopic ReadTopic(const ZipIn& zip, const std::string& markup, bool v3) {
    const std::string folder = markup.substr(0, markup.size() - std::string("markup.bcf").size());
    const Doc doc = Parse(zip, markup, "Markup");
    const xmlNode* root = xmlDocGetRootElement(doc.get());
    const xmlNode* topic = Child(root, "Topic");
    if (!topic) zip.Fail(markup, "no Topic element");
    BcfReadTopic out;
    BcfTopic& t = out.topic;
    t.guid = Attr(topic, "Guid");
    if (t.guid.empty()) zip.Fail(markup, "the Topic has no Guid");
    t.type = Attr(topic, "TopicType");
    t.status = Attr(topic, "TopicStatus");
    t.title = Text(topic, "Title");
    t.priority = Text(topic, "Priority");
    if (Child(topic, "Index")) t.index = Integer(zip, markup, topic, "Index");
    if (v3) {
        for (const xmlNode* l : Children(Child(topic, "Labels"), "Label")) t.labels.push_back(Text(l));
    } else {
        for (const xmlNode* l : Children(topic, "Labels")) t.labels.push_back(Text(l));
    }
    t.creation_date = Text(topic, "CreationDate");
    t.author = Text(topic, "CreationAuthor");
    t.description = Text(topic, "Description");
    out.modified_date = Text(topic, "ModifiedDate");
    out.due_date = Text(topic, "DueDate");
    out.assigned_to = Text(topic, "AssignedTo");
    const xmlNode* header = Child(root, "Header");
    const xmlNode* files = v3 ? Child(header, "Files") : header;
    t.reference_file = Text(Child(files, "File"), "Filename");

    const xmlNode* comments = v3 ? Child(topic, "Comments") : root;
    for (const xmlNode* c : Children(comments, "Comment")) out.comments.push_back(ReadComment(c));
    const auto refs = v3 ? Children(Child(topic, "Viewpoints"), "ViewPoint")
                         : Children(root, "Viewpoints");
    std::vector<std::pair<int, BcfViewpoint>> viewpoints;
    for (const xmlNode* ref : refs) {
        int index = 0;
        BcfViewpoint vp = ReadViewpoint(zip, folder, markup, ref, &index);
        viewpoints.emplace_back(index, std::move(vp));
    }
    std::stable_sort(viewpoints.begin(), viewpoints.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    for (auto& [index, vp] : viewpoints) out.viewpoints.push_back(std::move(vp));
    if (!out.viewpoints.empty()) t.viewpoint = out.viewpoints.front();
    else t.viewpoint.camera = BcfCamera::kNone;
    return out;
}

BcfProject ReadProject(const ZipIn& zip, bool v3) {
    BcfProject p;
    if (zip.Has("project.bcfp")) {
        const Doc doc = Parse(zip, "project.bcfp", v3 ? "ProjectInfo" : "ProjectExtension");
        const xmlNode* project = Child(xmlDocGetRootElement(doc.get()), "Project");
        p.id = Attr(project, "ProjectId");
        p.name = Text(project, "Name");
    }
    if (v3 && zip.Has("extensions.xml")) {
        const Doc doc = Parse(zip, "extensions.xml", "Extensions");
        const xmlNode* root = xmlDocGetRootElement(doc.get());
        auto list = [&](const char* outer, const char* inner) {
            std::vector<std::string> out;
            for (const xmlNode* n : Children(Child(root, outer), inner)) out.push_back(Text(n));
            return out;
        };
        p.topic_types = list("TopicTypes", "TopicType");
        p.topic_statuses = list("TopicStatuses", "TopicStatus");
        p.priorities = list("Priorities", "Priority");
        p.labels = list("TopicLabels", "TopicLabel");
        p.users = list("Users", "User");
    }
    return p;
}

}  // namespace

BcfFile ReadBcfBytes(const std::string& name, std::string_view bytes) {
    const ZipIn zip(name, bytes);
    if (!zip.Has("bcf.version")) zip.Fail("bcf.version", "missing: not a BCF file");
    BcfFile out;
    {
        const Doc doc = Parse(zip, "bcf.version", "Version");
        const std::string id = Attr(xmlDocGetRootElement(doc.get()), "VersionId");
        if (id == "2.1") {
            out.version = BcfVersion::k2_1;
        } else if (id == "3.0") {
            out.version = BcfVersion::k3_0;
        } else {
            zip.Fail("bcf.version", "version '" + id + "': BCF 2.1 and 3.0 are read");
        }
    }
    const bool v3 = out.version == BcfVersion::k3_0;
    out.project = ReadProject(zip, v3);
    for (const std::string& entry : zip.names()) {
        // A topic is a folder at the top holding markup.bcf (other files may lie beside them).
        const size_t slash = entry.find('/');
        if (slash == std::string::npos || entry.substr(slash + 1) != "markup.bcf") continue;
        out.topics.push_back(ReadTopic(zip, entry, v3));
    }
    return out;
}

BcfFile ReadBcf(const std::filesystem::path& path) {
    return ReadBcfBytes(path.string(), io::ReadFileToString(path));
}

}  // namespace bimslam::change_detection
