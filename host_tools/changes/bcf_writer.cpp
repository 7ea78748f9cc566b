// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/changes/bcf_writer.hpp"

#include <libxml/xmlwriter.h>
#include <zip.h>

#include <algorithm>
#include <ctime>
#include <deque>
#include <memory>

#include "algorithms/common/status.hpp"
#include "algorithms/io/file_util.hpp"
#include "algorithms/io/sha256.hpp"

namespace bimslam::change_detection {
namespace {

[[noreturn]] void BcfFail(const std::string& what) {
    throw common::Error(common::StatusCode::kInternal, "BCF: " + what);
}

// An XML document written by libxml2's xmlTextWriter (which escapes text and attributes).
class Xml {
public:
    explicit Xml(const char* root) : buffer_(xmlBufferCreate()) {
        if (!buffer_) BcfFail("libxml2: out of memory");
        writer_ = xmlNewTextWriterMemory(buffer_, 0);
        if (!writer_) BcfFail("libxml2: cannot make a text writer");
        xmlTextWriterSetIndent(writer_, 1);
        xmlTextWriterSetIndentString(writer_, BAD_CAST "  ");
        Check(xmlTextWriterStartDocument(writer_, nullptr, "UTF-8", "yes"));
        Start(root);
    }
    ~Xml() {
        if (writer_) xmlFreeTextWriter(writer_);
        xmlBufferFree(buffer_);
    }
    Xml(const Xml&) = delete;
    Xml& operator=(const Xml&) = delete;

    Xml& Start(const char* name) {
        Check(xmlTextWriterStartElement(writer_, BAD_CAST name));
        return *this;
    }
    Xml& End() {
        Check(xmlTextWriterEndElement(writer_));
        return *this;
    }
    Xml& Attr(const char* name, const std::string& value) {
        Check(xmlTextWriterWriteAttribute(writer_, BAD_CAST name, BAD_CAST value.c_str()));
        return *this;
    }
    Xml& Element(const char* name, const std::string& text) {
        Check(xmlTextWriterWriteElement(writer_, BAD_CAST name, BAD_CAST text.c_str()));
        return *this;
    }
    Xml& Number(const char* name, double v) { return Element(name, io::FormatDouble(v)); }
    Xml& Vector(const char* name, const Eigen::Vector3d& v) {
        return Start(name).Number("X", v.x()).Number("Y", v.y()).Number("Z", v.z()).End();
    }
    std::string Finish() {
        Check(xmlTextWriterEndDocument(writer_));  // closes every open element
        xmlFreeTextWriter(writer_);                // flushes into the buffer
        writer_ = nullptr;
        return std::string(reinterpret_cast<const char*>(xmlBufferContent(buffer_)),
                           size_t(xmlBufferLength(buffer_)));
    }

private:
    static void Check(int rc) {
        if (rc < 0) BcfFail("libxml2's text writer failed");
    }
    xmlBufferPtr buffer_;
    xmlTextWriterPtr writer_ = nullptr;
};

std::string VersionXml(BcfVersion v) {
    Xml x("Version");
    x.Attr("VersionId", ToString(v));
    if (v == BcfVersion::k2_1) x.Element("DetailedVersion", "2.1");
    return x.Finish();
}

std::string ProjectXml(const BcfProject& p, BcfVersion v) {
    Xml x(v == BcfVersion::k2_1 ? "ProjectExtension" : "ProjectInfo");
    x.Start("Project").Attr("ProjectId", p.id).Element("Name", p.name).End();
    // 2.1 requires the (possibly empty) URI of an extension schema; we use none.
    if (v == BcfVersion::k2_1) x.Element("ExtensionSchema", "");
    return x.Finish();
}

// 3.0's extensions.xml: the values the topics take, so that a tool offers them.
std::string ExtensionsXml(const BcfProject& p) {
    Xml x("Extensions");
    auto list = [&](const char* outer, const char* inner, const std::vector<std::string>& values) {
        x.Start(outer);
        for (const std::string& s : values) x.Element(inner, s);
        x.End();
    };
    list("TopicTypes", "TopicType", p.topic_types);
    list("TopicStatuses", "TopicStatus", p.topic_statuses);
    list("Priorities", "Priority", p.priorities);
    list("TopicLabels", "TopicLabel", p.labels);
    list("Users", "User", p.users);
    return x.Finish();
}

std::string MarkupXml(const BcfTopic& t, BcfVersion v) {
    const bool v3 = v == BcfVersion::k3_0;
    Xml x("Markup");
    if (!t.reference_file.empty()) {
        x.Start("Header");
        if (v3) x.Start("Files");
        x.Start("File").Attr(v3 ? "IsExternal" : "isExternal", "true");
        x.Element("Filename", t.reference_file).Element("Reference", t.reference_file).End();
        if (v3) x.End();
        x.End();
    }
    x.Start("Topic").Attr("Guid", t.guid).Attr("TopicType", t.type).Attr("TopicStatus", t.status);
    x.Element("Title", t.title)
        .Element("Priority", t.priority)
        .Element("Index", std::to_string(t.index));
    if (v3) x.Start("Labels");
    for (const std::string& l : t.labels) x.Element(v3 ? "Label" : "Labels", l);
    if (v3) x.End();
    x.Element("CreationDate", t.creation_date).Element("CreationAuthor", t.author);
    x.Element("Description", t.description);
    auto viewpoint = [&] {
        x.Start(v3 ? "ViewPoint" : "Viewpoints").Attr("Guid", t.viewpoint.guid);
        x.Element("Viewpoint", "viewpoint.bcfv");
        if (!t.viewpoint.snapshot_png.empty()) x.Element("Snapshot", "snapshot.png");
        x.Element("Index", "0").End();
    };
    if (v3) {  // inside Topic
        x.Start("Viewpoints");
        viewpoint();
        x.End();
    }
    x.End();  // Topic
    if (!v3) viewpoint();
    return x.Finish();
}

std::string VisinfoXml(const BcfViewpoint& vp, BcfVersion v) {
    const bool v3 = v == BcfVersion::k3_0;
    Xml x("VisualizationInfo");
    x.Attr("Guid", vp.guid);
    x.Start("Components");
    auto components = [&](const std::vector<std::string>& ids) {
        for (const std::string& id : ids) x.Start("Component").Attr("IfcGuid", id).End();
    };
    if (!vp.selected.empty()) {
        x.Start("Selection");
        components(vp.selected);
        x.End();
    }
    // 2.1 requires the element; 3.0's default is false, so it is always said.
    x.Start("Visibility").Attr("DefaultVisibility", vp.default_visibility ? "true" : "false");
    if (!vp.visibility_exceptions.empty()) {
        x.Start("Exceptions");
        components(vp.visibility_exceptions);
        x.End();
    }
    x.End();
    if (!vp.colors.empty()) {
        x.Start("Coloring");
        for (const auto& [color, ids] : vp.colors) {
            x.Start("Color").Attr("Color", color);
            if (v3) x.Start("Components");
            components(ids);
            if (v3) x.End();
            x.End();
        }
        x.End();
    }
    x.End();  // Components
    if (vp.camera == BcfCamera::kNone) return x.Finish();
    const bool perspective = vp.camera == BcfCamera::kPerspective;
    x.Start(perspective ? "PerspectiveCamera" : "OrthogonalCamera");
    x.Vector("CameraViewPoint", vp.eye).Vector("CameraDirection", vp.direction.normalized());
    x.Vector("CameraUpVector", vp.up.normalized());
    if (perspective) {  // 2.1 allows 45..60 degrees only
        x.Number("FieldOfView", v3 ? vp.fov_deg : std::clamp(vp.fov_deg, 45.0, 60.0));
    } else {
        x.Number("ViewToWorldScale", vp.view_to_world_scale);
    }
    if (v3) x.Number("AspectRatio", vp.aspect);
    x.End();
    return x.Finish();
}

// A zip in memory, entries added from strings that it keeps until Close.
class Zip {
public:
    Zip() {
        zip_error_t error;
        zip_error_init(&error);
        source_ = zip_source_buffer_create(nullptr, 0, 0, &error);
        if (source_) zip_ = zip_open_from_source(source_, ZIP_TRUNCATE, &error);
        if (!zip_) {
            const std::string why = zip_error_strerror(&error);
            zip_error_fini(&error);
            if (source_) zip_source_free(source_);
            BcfFail("libzip: " + why);
        }
        zip_error_fini(&error);
        zip_source_keep(source_);  // zip_close would free it otherwise
    }
    ~Zip() {
        if (zip_) zip_discard(zip_);
        zip_source_free(source_);
    }
    zip_t* get() { return zip_; }
    // compress = false for what is compressed already (PNG).
    void Add(const std::string& name, std::string bytes, time_t mtime, bool compress = true) {
        data_.push_back(std::move(bytes));
        zip_source_t* s = zip_source_buffer(zip_, data_.back().data(), data_.back().size(), 0);
        if (!s) BcfFail("libzip: " + std::string(zip_strerror(zip_)));
        Finish(name, zip_file_add(zip_, name.c_str(), s, ZIP_FL_ENC_UTF_8 | ZIP_FL_OVERWRITE), s,
               mtime, compress);
    }
    // Entry `index` of another open archive, as it is there.
    void Copy(zip_t* from, zip_uint64_t index, time_t mtime) {
        const char* name = zip_get_name(from, index, ZIP_FL_ENC_GUESS);
        zip_source_t* s = name ? zip_source_zip(zip_, from, index, 0, 0, -1) : nullptr;
        if (!s) BcfFail("libzip: " + std::string(zip_strerror(zip_)));
        Finish(name, zip_file_add(zip_, name, s, ZIP_FL_ENC_UTF_8 | ZIP_FL_OVERWRITE), s, mtime,
               !std::string(name).ends_with(".png"));
    }
    std::string Close() {
        if (zip_close(zip_) != 0) BcfFail("libzip: " + std::string(zip_strerror(zip_)));
        zip_ = nullptr;
        std::string out;
        zip_stat_t st;
        if (zip_source_stat(source_, &st) != 0 || zip_source_open(source_) != 0)
            BcfFail("libzip: cannot read the archive back");
        out.resize(size_t(st.size));
        const zip_int64_t n = zip_source_read(source_, out.data(), st.size);
        zip_source_close(source_);
        if (n != zip_int64_t(st.size)) BcfFail("libzip: short read of the archive");
        return out;
    }

private:
    void Finish(const std::string& name, zip_int64_t index, zip_source_t* s, time_t mtime,
                bool compress) {
        if (index < 0) {
            zip_source_free(s);
            BcfFail("libzip: cannot add " + name + ": " + zip_strerror(zip_));
        }
        const auto i = zip_uint64_t(index);
        if (zip_set_file_compression(zip_, i, compress ? ZIP_CM_DEFLATE : ZIP_CM_STORE, 0) != 0 ||
            zip_file_set_mtime(zip_, i, mtime, 0) != 0)
            BcfFail("libzip: " + name + ": " + zip_strerror(zip_));
    }
    zip_source_t* source_ = nullptr;
    zip_t* zip_ = nullptr;
    std::deque<std::string> data_;  // stable addresses
};

}  // namespace

const char* ToString(BcfVersion version) { return version == BcfVersion::k2_1 ? "2.1" : "3.0"; }

BcfVersion ParseBcfVersion(const std::string& text) {
    if (text == "2.1") return BcfVersion::k2_1;
    if (text == "3.0") return BcfVersion::k3_0;
    throw common::Error(common::StatusCode::kInvalidArgument,
                        "--bcf-version: '" + text + "' is not a BCF version we write (2.1, 3.0)");
}

std::string NameGuid(const std::string& name) {
    std::string h = io::Sha256Hex(name).substr(0, 32);
    h[12] = '8';                                                        // version 8
    h[16] = "89ab"[std::stoi(std::string(1, h[16]), nullptr, 16) & 3];  // variant 10
    return h.substr(0, 8) + "-" + h.substr(8, 4) + "-" + h.substr(12, 4) + "-" + h.substr(16, 4) +
           "-" + h.substr(20, 12);
}

std::string BcfZip(const BcfProject& project, const std::vector<BcfTopic>& topics,
                   BcfVersion version, int64_t unix_ns) {
    const auto mtime = time_t(unix_ns / 1000000000);
    Zip zip;
    zip.Add("bcf.version", VersionXml(version), mtime);
    zip.Add("project.bcfp", ProjectXml(project, version), mtime);
    if (version == BcfVersion::k3_0) zip.Add("extensions.xml", ExtensionsXml(project), mtime);
    for (const BcfTopic& t : topics) {
        zip.Add(t.guid + "/markup.bcf", MarkupXml(t, version), mtime);
        zip.Add(t.guid + "/viewpoint.bcfv", VisinfoXml(t.viewpoint, version), mtime);
        if (!t.viewpoint.snapshot_png.empty())
            zip.Add(t.guid + "/snapshot.png", t.viewpoint.snapshot_png, mtime, false);
    }
    return zip.Close();
}

std::string MergeBcf(const std::vector<std::filesystem::path>& files, int64_t unix_ns) {
    const auto mtime = time_t(unix_ns / 1000000000);
    std::vector<std::unique_ptr<zip_t, decltype(&zip_discard)>> inputs;
    Zip out;
    for (size_t f = 0; f < files.size(); ++f) {
        int error = 0;
        zip_t* in = zip_open(files[f].c_str(), ZIP_RDONLY, &error);
        if (!in) {
            zip_error_t e;
            zip_error_init_with_code(&e, error);
            const std::string why = zip_error_strerror(&e);
            zip_error_fini(&e);
            throw common::FileError(common::StatusCode::kDataLoss, files[f].string(), 0,
                                    "not a BCF zip: " + why);
        }
        inputs.emplace_back(in, &zip_discard);  // open until `out` is closed
        const zip_int64_t n = zip_get_num_entries(in, 0);
        for (zip_int64_t i = 0; i < n; ++i) {
            const char* name = zip_get_name(in, zip_uint64_t(i), 0);
            // The first file's root files; every file's topic folders.
            if (name && (f == 0 || std::string(name).find('/') != std::string::npos))
                out.Copy(in, zip_uint64_t(i), mtime);
        }
    }
    return out.Close();
}

}  // namespace bimslam::change_detection
