// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Reading BCF (issue 34): what the writer writes comes back, in 2.1 and 3.0 (3.0 has no second
// reader: bcf-js throws on its Coloring); buildingSMART's own examples are read as their XML
// says; every damaged file is refused naming the file, the zip entry and what is wrong. Built
// under ASan and UBSan (label `sanitized`): it reads other tools' files.
#include "host_tools/changes/bcf_reader.hpp"

#include <gtest/gtest.h>
#include <zip.h>

#include <map>
#include <string>

#include "algorithms/common/status.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::change_detection {
namespace {
namespace BIMSLAM_UNITY_ID {

constexpr int64_t kDate = 1772443800LL * 1000000000LL;  // 2026-03-02T09:30:00Z

BcfTopic MakeTopic(const std::string& name, int index) {
    BcfTopic t;
    t.guid = NameGuid(name);
    t.type = "Deviation";
    t.status = "Open";
    t.priority = "High";
    t.title = name + " & <more>";
    t.description = "moved 0.12 m on \"Level 1\"";
    t.labels = {"bimslam", "as-built"};
    t.creation_date = "2026-03-02T09:30:00Z";
    t.author = "bimslam";
    t.index = index;
    t.reference_file = "office.ifc";
    BcfViewpoint& v = t.viewpoint;
    v.guid = NameGuid(name + "/viewpoint");
    v.eye = {1.25, -2.5, 1.6};
    v.direction = {0, 1, 0};
    v.up = {0, 0, 1};
    v.fov_deg = 55;
    v.aspect = 4.0 / 3.0;
    v.selected = {"0EF31bAGn7cY_UpbsCA2np"};
    v.colors = {{"E63946", {"0EF31bAGn7cY_UpbsCA2np", "1xS3BCk291UvhgP2a6eflK"}}};
    v.snapshot_png = std::string("\x89PNG\r\n\x1a\n", 8) + name;
    return t;
}

void ExpectSameTopic(const BcfReadTopic& read, const BcfTopic& t) {
    const BcfTopic& r = read.topic;
    EXPECT_EQ(r.guid, t.guid);
    EXPECT_EQ(r.type, t.type);
    EXPECT_EQ(r.status, t.status);
    EXPECT_EQ(r.priority, t.priority);
    EXPECT_EQ(r.title, t.title);
    EXPECT_EQ(r.description, t.description);
    EXPECT_EQ(r.labels, t.labels);
    EXPECT_EQ(r.creation_date, t.creation_date);
    EXPECT_EQ(r.author, t.author);
    EXPECT_EQ(r.index, t.index);
    EXPECT_EQ(r.reference_file, t.reference_file);
    ASSERT_EQ(read.viewpoints.size(), 1u);
    const BcfViewpoint& v = read.viewpoints[0];
    EXPECT_EQ(v.guid, t.viewpoint.guid);
    EXPECT_EQ(v.camera, BcfCamera::kPerspective);
    EXPECT_TRUE(v.eye.isApprox(t.viewpoint.eye, 1e-12));
    EXPECT_TRUE(v.direction.isApprox(t.viewpoint.direction, 1e-12));
    EXPECT_TRUE(v.up.isApprox(t.viewpoint.up, 1e-12));
    EXPECT_DOUBLE_EQ(v.fov_deg, t.viewpoint.fov_deg);
    EXPECT_EQ(v.selected, t.viewpoint.selected);
    EXPECT_EQ(v.colors, t.viewpoint.colors);
    EXPECT_TRUE(v.default_visibility);
    EXPECT_EQ(v.snapshot_png, t.viewpoint.snapshot_png);
    EXPECT_EQ(r.viewpoint.guid, v.guid);  // the first viewpoint, also as the topic's
}

TEST(BcfReader, WhatTheWriterWritesComesBackInBothVersions) {
    BcfProject p;
    p.id = NameGuid("project");
    p.name = "office.ifc";
    p.topic_types = {"Deviation", "New object"};
    p.topic_statuses = {"Open"};
    p.priorities = {"High", "Low"};
    p.labels = {"bimslam", "as-built"};
    p.users = {"bimslam"};
    const std::vector<BcfTopic> topics = {MakeTopic("a", 1), MakeTopic("b", 2)};
    for (const BcfVersion version : {BcfVersion::k2_1, BcfVersion::k3_0}) {
        SCOPED_TRACE(ToString(version));
        const BcfFile f = ReadBcfBytes("x.bcf", BcfZip(p, topics, version, kDate));
        EXPECT_EQ(f.version, version);
        EXPECT_EQ(f.project.id, p.id);
        EXPECT_EQ(f.project.name, p.name);
        if (version == BcfVersion::k3_0) {
            EXPECT_EQ(f.project.topic_types, p.topic_types);
            EXPECT_EQ(f.project.priorities, p.priorities);
            EXPECT_EQ(f.project.users, p.users);
        }
        ASSERT_EQ(f.topics.size(), 2u);
        ExpectSameTopic(f.topics[0], topics[0]);
        ExpectSameTopic(f.topics[1], topics[1]);
    }
}

TEST(BcfReader, VisibilityAndAnOrthogonalCameraComeBack) {
    BcfTopic t = MakeTopic("plan view", 0);
    t.viewpoint.camera = BcfCamera::kOrthogonal;
    t.viewpoint.view_to_world_scale = 12.5;
    t.viewpoint.default_visibility = false;
    t.viewpoint.visibility_exceptions = {"2O2Fr$t4X7Zf8NOew3FLOH", "0EF31bAGn7cY_UpbsCA2np"};
    for (const BcfVersion version : {BcfVersion::k2_1, BcfVersion::k3_0}) {
        SCOPED_TRACE(ToString(version));
        const BcfFile f = ReadBcfBytes("x.bcf", BcfZip({}, {t}, version, kDate));
        ASSERT_EQ(f.topics.size(), 1u);
        const BcfViewpoint& v = f.topics[0].topic.viewpoint;
        EXPECT_EQ(v.camera, BcfCamera::kOrthogonal);
        EXPECT_DOUBLE_EQ(v.view_to_world_scale, 12.5);
        EXPECT_FALSE(v.default_visibility);
        EXPECT_EQ(v.visibility_exceptions, t.viewpoint.visibility_exceptions);
    }
    t.viewpoint.camera = BcfCamera::kNone;
    const BcfFile f = ReadBcfBytes("x.bcf", BcfZip({}, {t}, BcfVersion::k3_0, kDate));
    EXPECT_EQ(f.topics.at(0).topic.viewpoint.camera, BcfCamera::kNone);
}

// A zip of the given entries (libzip, stored).
std::string Zip(const std::map<std::string, std::string>& entries) {
    zip_error_t error;
    zip_error_init(&error);
    zip_source_t* src = zip_source_buffer_create(nullptr, 0, 0, &error);
    zip_t* z = zip_open_from_source(src, ZIP_TRUNCATE, &error);
    zip_source_keep(src);
    for (const auto& [name, bytes] : entries) {
        zip_source_t* s = zip_source_buffer(z, bytes.data(), bytes.size(), 0);
        zip_file_add(z, name.c_str(), s, ZIP_FL_ENC_UTF_8);
    }
    zip_close(z);
    zip_stat_t st;
    zip_source_stat(src, &st);
    std::string out(size_t(st.size), '\0');
    zip_source_open(src);
    zip_source_read(src, out.data(), st.size);
    zip_source_close(src);
    zip_source_free(src);
    zip_error_fini(&error);
    return out;
}

const std::string kVersion21 = R"(<?xml version="1.0"?><Version VersionId="2.1"/>)";
const std::string kMarkup =
    R"(<?xml version="1.0"?><Markup><Topic Guid="t1" TopicType="Issue" TopicStatus="Open">)"
    R"(<Title>one</Title><CreationDate>2026-03-02T09:30:00Z</CreationDate></Topic>)"
    R"(<Viewpoints Guid="v1"><Viewpoint>v1.bcfv</Viewpoint></Viewpoints></Markup>)";

// `entries` read as a file must fail naming it, with `words` in the message.
void ExpectRefused(const std::map<std::string, std::string>& entries, const std::string& words) {
    SCOPED_TRACE(words);
    try {
        ReadBcfBytes("sent-back.bcf", Zip(entries));
        ADD_FAILURE() << "read without an error";
    } catch (const common::FileError& e) {
        EXPECT_EQ(e.path(), "sent-back.bcf");
        EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
}

TEST(BcfReader, DamagedFilesAreRefusedNamingTheEntryAndWhatIsWrong) {
    EXPECT_FILE_ERROR(ReadBcfBytes("notes.txt", "not a zip at all"), "notes.txt", 0);
    ExpectRefused({{"x/markup.bcf", kMarkup}}, "bcf.version: missing: not a BCF file");
    ExpectRefused({{"bcf.version", R"(<Version VersionId="1.0"/>)"}},
                  "version '1.0': BCF 2.1 and 3.0 are read");
    ExpectRefused({{"bcf.version", "<Version VersionId=\"2.1\">\n<oops></Version>"}},
                  "bcf.version: line 2:");
    ExpectRefused({{"bcf.version", R"(<Markup/>)"}}, "the root element is Markup, not Version");
    ExpectRefused({{"bcf.version", kVersion21}, {"t1/markup.bcf", kMarkup}},
                  "t1/markup.bcf: names viewpoint file v1.bcfv, which the zip lacks");
    ExpectRefused({{"bcf.version", kVersion21},
                   {"t1/markup.bcf", R"(<Markup><Topic><Title>x</Title></Topic></Markup>)"}},
                  "t1/markup.bcf: the Topic has no Guid");
    ExpectRefused({{"bcf.version", kVersion21},
                   {"t1/markup.bcf", kMarkup},
                   {"t1/v1.bcfv",
                    R"(<VisualizationInfo><PerspectiveCamera><CameraViewPoint><X>1</X><Y>two</Y>)"
                    R"(<Z>3</Z></CameraViewPoint></PerspectiveCamera></VisualizationInfo>)"}},
                  "t1/v1.bcfv: Y 'two' is not a number");
    ExpectRefused({{"bcf.version", kVersion21},
                   {"t1/markup.bcf",
                    R"(<Markup><Topic Guid="t1"><Title>x</Title><Index>1e300</Index></Topic></Markup>)"}},
                  "t1/markup.bcf: Index '1e300' is not an xs:int");
    // An entity that would read a local file (XXE) is not expanded.
    const BcfFile f = ReadBcfBytes(
        "x.bcf", Zip({{"bcf.version", kVersion21},
                      {"t1/markup.bcf",
                       R"(<?xml version="1.0"?><!DOCTYPE m [<!ENTITY x SYSTEM "file:///etc/passwd">]>)"
                       R"(<Markup><Topic Guid="t1"><Title>&x;</Title></Topic></Markup>)"}}));
    ASSERT_EQ(f.topics.size(), 1u);
    EXPECT_EQ(f.topics[0].topic.title.find("root:"), std::string::npos);
}

TEST(BcfReader, AnEntryOverTheLimitIsRefusedBeforeItIsInflated) {
    // 65 MiB of zeros deflate to about 65 kB: a small file that would take the memory.
    ExpectRefused({{"bcf.version", kVersion21},
                   {"t1/markup.bcf", kMarkup},
                   {"t1/v1.bcfv", std::string(kMaxBcfEntryBytes + 1024, '\0')}},
                  "t1/v1.bcfv: 67109888 bytes inflated, over the 67108864 a BCF entry may hold");
}

std::filesystem::path Examples() {
    const auto data = ::bimslam::test::SharedDataDir();
    return data ? *data / ".." / "specs" / "bcf" / "examples" : std::filesystem::path();
}

TEST(BcfReader, BuildingSmartsMaximumInformationExample21) {
    const auto file = Examples() / "v2.1_MaximumInformation.bcf";
    if (!std::filesystem::exists(file))
        GTEST_SKIP() << file << " is absent: buildingSMART's examples are in ../shared/specs/bcf";
    const BcfFile f = ReadBcf(file);
    EXPECT_EQ(f.version, BcfVersion::k2_1);
    ASSERT_EQ(f.topics.size(), 2u);
    const BcfReadTopic* full = nullptr;
    for (const auto& t : f.topics) {
        if (t.topic.guid == "7ddc3ef0-0ab7-43f1-918a-45e38b42369c") full = &t;
    }
    ASSERT_NE(full, nullptr);
    EXPECT_EQ(full->topic.title, "Maximum Content");
    EXPECT_EQ(full->topic.type, "Structural");
    EXPECT_EQ(full->topic.status, "Open");
    EXPECT_EQ(full->topic.priority, "High");
    EXPECT_EQ(full->topic.labels, (std::vector<std::string>{"Structural", "IT Development"}));
    EXPECT_EQ(full->topic.creation_date, "2015-06-21T12:00:00Z");
    EXPECT_EQ(full->assigned_to, "linhard@iabi.eu");
    EXPECT_EQ(full->due_date, "2016-10-02T14:22:47Z");
    EXPECT_EQ(full->topic.reference_file, "IfcPile_01.ifc");
    ASSERT_EQ(full->comments.size(), 4u);
    EXPECT_EQ(full->comments[2].viewpoint_guid, "4ab7514b-b216-4d56-98d2-45cf8500ff5a");
    // Three viewpoints, by their Index (0, 1, 2), each with its snapshot.
    ASSERT_EQ(full->viewpoints.size(), 3u);
    EXPECT_EQ(full->viewpoints[0].guid, "fc4019d7-365e-47f3-b6d0-b39fc48f15fc");
    EXPECT_EQ(full->viewpoints[1].guid, "9a4a1878-ecbd-4916-83a8-dad82e560231");
    EXPECT_EQ(full->viewpoints[2].guid, "4ab7514b-b216-4d56-98d2-45cf8500ff5a");
    for (const auto& v : full->viewpoints) EXPECT_EQ(v.snapshot_png.substr(1, 3), "PNG") << v.guid;
    const BcfViewpoint& first = full->topic.viewpoint;
    EXPECT_EQ(first.guid, full->viewpoints[0].guid);
}

TEST(BcfReader, BuildingSmartsDocumentReferenceExample30) {
    const auto file = Examples() / "v3.0_DocumentReferenceExternal.bcf";
    if (!std::filesystem::exists(file))
        GTEST_SKIP() << file << " is absent: buildingSMART's examples are in ../shared/specs/bcf";
    const BcfFile f = ReadBcf(file);
    EXPECT_EQ(f.version, BcfVersion::k3_0);
    ASSERT_EQ(f.topics.size(), 1u);
    const BcfReadTopic& t = f.topics[0];
    EXPECT_EQ(t.topic.guid, "1b66b5cb-18b4-4edd-a700-d02c3a673710");
    EXPECT_EQ(t.topic.type, "Error");
    EXPECT_EQ(t.topic.title, "Document Reference External");
    EXPECT_EQ(t.topic.reference_file, "MEP.ifc");
    ASSERT_EQ(t.comments.size(), 1u);
    EXPECT_EQ(t.comments[0].author, "pasi.paasiala@solibri.com");
    EXPECT_EQ(t.comments[0].viewpoint_guid, "bd634f89-bec7-4cb1-be74-2057c5fea0fb");
    ASSERT_EQ(t.viewpoints.size(), 1u);
    const BcfViewpoint& v = t.viewpoints[0];
    EXPECT_EQ(v.camera, BcfCamera::kPerspective);
    EXPECT_NEAR(v.eye.x(), 11.62091117526624, 1e-12);
    EXPECT_NEAR(v.direction.y(), -0.8928620023273623, 1e-12);
    EXPECT_DOUBLE_EQ(v.fov_deg, 60.0);
    EXPECT_DOUBLE_EQ(v.aspect, 1.0);
    EXPECT_TRUE(v.default_visibility);
    EXPECT_EQ(v.visibility_exceptions,
              (std::vector<std::string>{"1m5wAJelDFdhn6qBdOGjos", "1bbI761TbBCOoIa5Kt6PXt"}));
    EXPECT_TRUE(v.selected.empty());
    EXPECT_FALSE(v.snapshot_png.empty());
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::change_detection
