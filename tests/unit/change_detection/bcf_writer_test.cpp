// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// changes.bcf's parts on their own (issue 34): GUIDs made from names (BCF 3.0's lower-case
// pattern, the same name the same GUID), the version option, the zip's entries and bytes (the
// same topics give the same file), merging a visit's files, and the renderer drawing the chosen
// element in its colour where the camera looks. The whole file against the schemas and a second
// reader: tests/integration/changes_bcf_test.cpp.
#include "host_tools/changes/bcf_writer.hpp"

#include <gtest/gtest.h>
#include <zip.h>

#include <regex>
#include <set>
#include <string>

#include "algorithms/common/status.hpp"
#include "algorithms/io/file_util.hpp"
#include "host_tools/changes/snapshot_renderer.hpp"
#include "tests/support/test_support.hpp"
#include "tests/unit/bim/synthetic_floor.hpp"

namespace bimslam::change_detection {
namespace {
namespace BIMSLAM_UNITY_ID {

TEST(BcfWriter, GuidsFromNamesAreLowerCaseUuidsAndRepeatable) {
    const std::regex uuid("[a-f0-9]{8}-[a-f0-9]{4}-8[a-f0-9]{3}-[89ab][a-f0-9]{3}-[a-f0-9]{12}");
    std::set<std::string> seen;
    for (const char* name : {"a", "b", "session/1/object/0", "session/1/object/1"}) {
        const std::string g = NameGuid(name);
        EXPECT_TRUE(std::regex_match(g, uuid)) << g;
        EXPECT_EQ(NameGuid(name), g);
        seen.insert(g);
    }
    EXPECT_EQ(seen.size(), 4u);
}

TEST(BcfWriter, VersionIs21Or30) {
    EXPECT_EQ(ParseBcfVersion("2.1"), BcfVersion::k2_1);
    EXPECT_EQ(ParseBcfVersion("3.0"), BcfVersion::k3_0);
    EXPECT_STREQ(ToString(BcfVersion::k3_0), "3.0");
    for (const char* bad : {"2.0", "3", "", "3.0 "}) {
        try {
            ParseBcfVersion(bad);
            ADD_FAILURE() << "accepted '" << bad << "'";
        } catch (const common::Error& e) {
            EXPECT_EQ(e.code(), common::StatusCode::kInvalidArgument);
            EXPECT_NE(std::string(e.what()).find("--bcf-version"), std::string::npos);
        }
    }
}

BcfTopic Topic(const std::string& name) {
    BcfTopic t;
    t.guid = NameGuid(name);
    t.type = "Deviation";
    t.status = "Open";
    t.priority = "Low";
    t.title = name + " & <more>";  // escaped by the XML writer
    t.creation_date = "2026-03-02T09:30:00Z";
    t.author = "bimslam";
    t.viewpoint.guid = NameGuid(name + "/viewpoint");
    t.viewpoint.selected = {"0EF31bAGn7cY_UpbsCA2np"};
    t.viewpoint.snapshot_png = "not a real PNG";
    return t;
}

// Entry name -> bytes, read back by libzip.
std::map<std::string, std::string> Read(const std::string& bytes) {
    ::bimslam::test::TempDir tmp;
    io::WriteFileAtomic(tmp.path() / "x.bcf", bytes);
    std::map<std::string, std::string> out;
    int error = 0;
    zip_t* z = zip_open((tmp.path() / "x.bcf").c_str(), ZIP_RDONLY, &error);
    EXPECT_NE(z, nullptr) << error;
    if (!z) return out;
    for (zip_int64_t i = 0; i < zip_get_num_entries(z, 0); ++i) {
        zip_stat_t st;
        zip_stat_index(z, zip_uint64_t(i), 0, &st);
        std::string b(size_t(st.size), '\0');
        zip_file_t* f = zip_fopen_index(z, zip_uint64_t(i), 0);
        zip_fread(f, b.data(), st.size);
        zip_fclose(f);
        out[st.name] = b;
    }
    zip_close(z);
    return out;
}

TEST(BcfWriter, TheSameTopicsGiveTheSameBytesAndMergingKeepsEveryTopic) {
    BcfProject p;
    p.id = NameGuid("project");
    p.name = "model.ifc";
    const int64_t date = 1772443800LL * 1000000000LL;
    const std::string a = BcfZip(p, {Topic("a")}, BcfVersion::k3_0, date);
    EXPECT_EQ(BcfZip(p, {Topic("a")}, BcfVersion::k3_0, date), a);
    const std::string b = BcfZip(p, {Topic("b"), Topic("c")}, BcfVersion::k3_0, date);

    const auto entries = Read(a);
    EXPECT_EQ(entries.size(), 6u);  // bcf.version, project.bcfp, extensions.xml, 3 of the topic
    const std::string markup = entries.at(NameGuid("a") + "/markup.bcf");
    EXPECT_NE(markup.find("a &amp; &lt;more&gt;"), std::string::npos) << markup;
    EXPECT_EQ(entries.at(NameGuid("a") + "/snapshot.png"), "not a real PNG");

    ::bimslam::test::TempDir tmp;
    io::WriteFileAtomic(tmp.path() / "a.bcf", a);
    io::WriteFileAtomic(tmp.path() / "b.bcf", b);
    const std::string merged_bytes = MergeBcf({tmp.path() / "a.bcf", tmp.path() / "b.bcf"}, date);
    // The same files merged again: the same bytes (`bimslam map` writes OUT/changes.bcf only
    // when it changed).
    EXPECT_EQ(MergeBcf({tmp.path() / "a.bcf", tmp.path() / "b.bcf"}, date), merged_bytes);
    const auto merged = Read(merged_bytes);
    EXPECT_EQ(merged.size(), 3u + 3 * 3);
    for (const char* t : {"a", "b", "c"}) {
        EXPECT_TRUE(merged.contains(NameGuid(t) + "/viewpoint.bcfv")) << t;
    }
    EXPECT_EQ(merged.at("bcf.version"), entries.at("bcf.version"));

    io::WriteFileAtomic(tmp.path() / "bad.bcf", "not a zip");
    EXPECT_FILE_ERROR(MergeBcf({tmp.path() / "bad.bcf"}, date), (tmp.path() / "bad.bcf").string(),
                      0);
}

// A floor and two columns; the camera looks at the first from 4 m.
TEST(SnapshotRenderer, DrawsTheChosenElementInItsColourWhereTheCameraLooks) {
    bim::BimModel m;
    bim::test_floor::AddBox(m, "IfcSlab", bim::ElementRole::kStructure, {-5, -5, -0.2}, {5, 5, 0});
    bim::test_floor::AddBox(m, "IfcColumn", bim::ElementRole::kStructure, {-0.2, -0.2, 0},
                            {0.2, 0.2, 3});
    bim::test_floor::AddBox(m, "IfcColumn", bim::ElementRole::kStructure, {2, 2, 0}, {2.4, 2.4, 3});
    SnapshotRenderer r(m, 160, 120);
    SnapshotCamera cam;
    cam.eye = {-4, 0, 1.5};
    cam.direction = {1, 0, 0};
    SnapshotHighlight h;
    h.element = 1;
    h.element_color = {230, 30, 30};
    const io::Image red = r.Render(cam, h);
    ASSERT_EQ(red.width, 160);
    ASSERT_EQ(red.height, 120);
    const uint8_t* c = red.At(80, 60);  // the column, in the middle of the picture
    EXPECT_GT(c[0], 2 * c[1]) << int(c[0]) << " " << int(c[1]) << " " << int(c[2]);
    const uint8_t* sky = red.At(80, 2);  // above it: the background, near white
    EXPECT_GT(sky[1], 230);
    h.element = -1;  // nothing chosen: the same column grey
    const io::Image grey = r.Render(cam, h);
    const uint8_t* g = grey.At(80, 60);
    EXPECT_LT(std::abs(int(g[0]) - int(g[1])), 8);
    // PNG as the BCF takes it: its signature and IHDR's size.
    const std::string png = io::EncodePng(red, io::PngCompression::kFast);
    ASSERT_GT(png.size(), 24u);
    EXPECT_EQ(png.substr(1, 3), "PNG");
    EXPECT_EQ(uint8_t(png[19]), 160);  // width, big-endian, bytes 16..19
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::change_detection
