// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// changes.bcf of the walk (changes_walk.hpp: a crate added, a wall built 3 cm off) as BIM tools
// get it: a zip Debian's unzip tests clean, every XML file valid against buildingSMART's schemas
// (xmllint --schema, ../shared/specs/bcf/<version>/), one topic per change of changes.json with
// its words, type, priority, date, camera and components, the same topics read by a second reader
// (@parametricos/bcf-js, tests/tools/bcf_js), and snapshots that are pictures of the change. BCF
// 2.1 (the walk's own file) and 3.0 (`--bcf-version 3.0` on the same session). Each tool's test
// skips, saying why, where the tool is not installed (toolchain/install-deps.sh --test).
#include <gtest/gtest.h>
#include <libxml/parser.h>
#include <libxml/xpath.h>
#include <png.h>
#include <zip.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "algorithms/io/file_util.hpp"
#include "tests/integration/changes_walk.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::bcf_test {
namespace {
namespace BIMSLAM_UNITY_ID {
namespace fs = std::filesystem;
using nlohmann::json;

const std::string kCli = BIMSLAM_CLI_PATH;

std::string Quote(const fs::path& p) { return "'" + p.string() + "'"; }

fs::path SourceRoot() {
    const char* env = std::getenv("BIMSLAM_SOURCE_DIR");  // set by ctest
    return env && *env ? fs::path(env) : fs::path(BIMSLAM_SOURCE_ROOT);
}

fs::path Specs() { return SourceRoot() / ".." / "shared" / "specs" / "bcf"; }

// The walk's changes.bcf in `version`: 2.1 is the walk's own, 3.0 made once per build of
// bimslam beside it by `bimslam changes --bcf-version 3.0` on the same session.
fs::path BcfOf(const std::string& version) {
    const fs::path walk = changes_test::Walk();
    if (version == "2.1") return walk / "out" / "changes.bcf";
    static const fs::path root = test::FixtureRootFor(BIMSLAM_TEST_BINARY_DIR "/changes_fixtures", kCli);
    return test::CachedFixture(root, "walk_bcf30",
                               [&](const fs::path& d) {
                                   const auto r = test::RunCommand(
                                       kCli + " changes --model " + Quote(walk / "building.ifc") +
                                       " --session " + Quote(walk / "anchored") + " -o " +
                                       Quote(d / "out") + " --bcf-version 3.0 --date " +
                                       changes_test::kWalkDate);
                                   ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
                               }) /
           "out" / "changes.bcf";
}

// Every entry of a zip, read with libzip.
std::map<std::string, std::string> Entries(const fs::path& file) {
    std::map<std::string, std::string> out;
    int error = 0;
    zip_t* z = zip_open(file.c_str(), ZIP_RDONLY, &error);
    EXPECT_NE(z, nullptr) << file << ": libzip error " << error;
    if (!z) return out;
    for (zip_int64_t i = 0; i < zip_get_num_entries(z, 0); ++i) {
        zip_stat_t st;
        zip_stat_index(z, zip_uint64_t(i), 0, &st);
        std::string bytes(size_t(st.size), '\0');
        zip_file_t* f = zip_fopen_index(z, zip_uint64_t(i), 0);
        EXPECT_EQ(zip_fread(f, bytes.data(), st.size), zip_int64_t(st.size)) << st.name;
        zip_fclose(f);
        out[st.name] = bytes;
    }
    zip_close(z);
    return out;
}

// XPath string values of an XML document (libxml2).
class XmlDoc {
public:
    explicit XmlDoc(const std::string& text)
        : doc_(xmlReadMemory(text.data(), int(text.size()), "x.xml", nullptr, XML_PARSE_NONET)) {
        EXPECT_NE(doc_, nullptr) << text.substr(0, 200);
    }
    ~XmlDoc() { xmlFreeDoc(doc_); }
    std::vector<std::string> All(const std::string& xpath) const {
        std::vector<std::string> out;
        if (!doc_) return out;
        xmlXPathContextPtr ctx = xmlXPathNewContext(doc_);
        xmlXPathObjectPtr r = xmlXPathEvalExpression(BAD_CAST xpath.c_str(), ctx);
        if (r && r->nodesetval) {
            for (int i = 0; i < r->nodesetval->nodeNr; ++i) {
                xmlChar* s = xmlNodeGetContent(r->nodesetval->nodeTab[i]);
                out.emplace_back(reinterpret_cast<const char*>(s));
                xmlFree(s);
            }
        }
        xmlXPathFreeObject(r);
        xmlXPathFreeContext(ctx);
        return out;
    }
    std::string One(const std::string& xpath) const {
        const auto all = All(xpath);
        return all.empty() ? std::string() : all.front();
    }

private:
    xmlDocPtr doc_;
};

// One topic as the zip holds it.
struct Topic {
    std::string folder, type, priority, title, description, date;
    std::vector<std::string> selected, colors;
    std::vector<double> eye, direction;
    std::string png;
};

std::vector<Topic> Topics(const std::map<std::string, std::string>& zip) {
    std::vector<Topic> out;
    for (const auto& [name, bytes] : zip) {
        if (!name.ends_with("/markup.bcf")) continue;
        Topic t;
        t.folder = name.substr(0, name.find('/'));
        const XmlDoc m(bytes);
        t.type = m.One("/Markup/Topic/@TopicType");
        t.priority = m.One("/Markup/Topic/Priority");
        t.title = m.One("/Markup/Topic/Title");
        t.description = m.One("/Markup/Topic/Description");
        t.date = m.One("/Markup/Topic/CreationDate");
        EXPECT_EQ(m.One("/Markup/Topic/@Guid"), t.folder);
        const std::string vp = m.One("//Viewpoint"), snapshot = m.One("//Snapshot");
        EXPECT_TRUE(zip.contains(t.folder + "/" + vp)) << name << ": " << vp;
        EXPECT_TRUE(zip.contains(t.folder + "/" + snapshot)) << name << ": " << snapshot;
        if (zip.contains(t.folder + "/" + snapshot)) t.png = zip.at(t.folder + "/" + snapshot);
        if (!zip.contains(t.folder + "/" + vp)) continue;
        const XmlDoc v(zip.at(t.folder + "/" + vp));
        t.selected = v.All("//Selection/Component/@IfcGuid");
        t.colors = v.All("//Coloring/Color/@Color");
        for (const char* c : {"X", "Y", "Z"}) {
            t.eye.push_back(std::stod(v.One(std::string("//CameraViewPoint/") + c)));
            t.direction.push_back(std::stod(v.One(std::string("//CameraDirection/") + c)));
        }
        out.push_back(t);
    }
    return out;
}

bool Has(const std::string& tool) {
    return test::RunCommand("command -v " + tool + " >/dev/null").exit_code == 0;
}

class ChangesBcf : public ::testing::TestWithParam<std::string> {};

TEST_P(ChangesBcf, ZipTestsCleanAndEveryXmlFileValidatesAgainstTheSchemas) {
    if (!Has("unzip") || !Has("xmllint"))
        GTEST_SKIP() << "unzip or xmllint is missing: run toolchain/install-deps.sh --test";
    const fs::path xsd = Specs() / GetParam();
    if (!fs::is_directory(xsd))
        GTEST_SKIP() << xsd << " is absent: the BCF schemas are in ../shared/specs/bcf";
    const fs::path bcf = BcfOf(GetParam());
    const auto t = test::RunCommand("unzip -t " + Quote(bcf));
    EXPECT_EQ(t.exit_code, 0) << t.out << t.err;
    EXPECT_NE(t.out.find("No errors detected"), std::string::npos) << t.out;

    test::TempDir tmp;
    const std::map<std::string, std::string> schema = {{".version", "version.xsd"},
                                                       {".bcfp", "project.xsd"},
                                                       {".bcf", "markup.xsd"},
                                                       {".bcfv", "visinfo.xsd"},
                                                       {"extensions.xml", "extensions.xsd"}};
    std::map<std::string, int> validated;
    for (const auto& [name, bytes] : Entries(bcf)) {
        if (name.ends_with(".png")) continue;
        std::string kind;
        for (const auto& [suffix, file] : schema) {
            if (name.ends_with(suffix)) kind = file;
        }
        ASSERT_FALSE(kind.empty()) << "an entry of no BCF kind: " << name;
        const fs::path f = tmp.path() / "entry.xml";
        io::WriteFileAtomic(f, bytes);
        const auto r = test::RunCommand("xmllint --noout --schema " + Quote(xsd / kind) + " " +
                                        Quote(f) + " 2>&1");
        EXPECT_EQ(r.exit_code, 0) << name << " against " << kind << ":\n" << r.out << bytes;
        ++validated[kind];
    }
    EXPECT_EQ(validated["version.xsd"], 1);
    EXPECT_EQ(validated["project.xsd"], 1);
    EXPECT_EQ(validated["extensions.xsd"], GetParam() == "3.0" ? 1 : 0);
    EXPECT_GE(validated["markup.xsd"], 2);  // the crate and the wall at least
    EXPECT_EQ(validated["markup.xsd"], validated["visinfo.xsd"]);
}

TEST_P(ChangesBcf, OneTopicPerChangeWithWordsPriorityDateCameraAndComponents) {
    const fs::path walk = changes_test::Walk();
    const json changes = json::parse(io::ReadFileToString(walk / "out" / "changes.json"));
    const std::vector<Topic> topics = Topics(Entries(BcfOf(GetParam())));
    ASSERT_EQ(topics.size(), changes["new_objects"].size() + changes["missing"].size() +
                                 changes["deviating"].size());
    std::map<std::string, const Topic*> by_id;  // the selected GlobalId
    for (const Topic& t : topics) {
        ASSERT_EQ(t.selected.size(), 1u) << t.title;
        by_id[t.selected[0]] = &t;
        ASSERT_EQ(t.colors.size(), 1u) << t.title;
        EXPECT_EQ(t.date, changes_test::kWalkDate);  // the recording's (--date)
        const double norm = std::hypot(t.direction[0], t.direction[1], t.direction[2]);
        EXPECT_NEAR(norm, 1.0, 1e-6);
        // The camera stands in the walked corridor (y 6.15 .. 8.15, at the sensor's height).
        EXPECT_GT(t.eye[1], 6.15) << t.title;
        EXPECT_LT(t.eye[1], 8.15) << t.title;
        EXPECT_GT(t.eye[2], 0.5) << t.title;
        EXPECT_LT(t.eye[2], 2.5) << t.title;
    }
    for (const json& o : changes["new_objects"]) {
        const std::string gid = o["ifc_global_id"];
        ASSERT_TRUE(by_id.contains(gid)) << "no topic for new object " << gid;
        const Topic& t = *by_id[gid];
        EXPECT_EQ(t.type, "New object");
        EXPECT_NE(t.title.find("Ground Floor"), std::string::npos) << t.title;
        if (o["space"].is_object()) {
            // The space as people call it (LongName), then its Name (the sample's number).
            const std::string long_name = o["space"]["long_name"];
            ASSERT_FALSE(long_name.empty()) << o.dump();
            EXPECT_NE(t.description.find("IfcSpace '" + long_name + "' (" +
                                         o["space"]["name"].get<std::string>() + ", "),
                      std::string::npos)
                << t.description;
        }
        const double largest = std::max({o["size_m"][0].get<double>(), o["size_m"][1].get<double>(),
                                         o["size_m"][2].get<double>()});
        EXPECT_EQ(t.priority, largest >= 1.0 ? "High" : largest >= 0.3 ? "Normal" : "Low");
    }
    const double tol = changes["parameters"]["elements"]["deviation_tolerance_m"];
    for (const json& d : changes["deviating"]) {
        const std::string gid = d["global_id"];
        ASSERT_TRUE(by_id.contains(gid)) << "no topic for deviating element " << gid;
        const Topic& t = *by_id[gid];
        if (!d["moved"].is_null()) continue;
        EXPECT_EQ(t.type, "Deviation");
        const double n = d["offset_norm_m"];
        EXPECT_EQ(t.priority, n < 2 * tol ? "Low" : n < 5 * tol ? "Normal" : "High");
        char cm[32];
        std::snprintf(cm, sizeof cm, "%.1f cm", 100 * n);
        EXPECT_NE(t.title.find(cm), std::string::npos) << t.title;
        EXPECT_NE(t.description.find("storey 'Ground Floor'"), std::string::npos) << t.description;
    }
    // The wall built 3 cm off (changes_walk.hpp) is one of them.
    EXPECT_TRUE(by_id.contains("0EF31bAGn7cY_UpbsCA2np"));
    for (const json& m : changes["missing"]) {
        ASSERT_TRUE(by_id.contains(m["global_id"])) << m.dump();
        EXPECT_EQ(by_id[m["global_id"]]->type, "Missing element");
    }
}

// Each of our topics beside what a second reader made of it (its "topics", by GUID), their words
// compared; the callers compare the rest, which the two readers print differently.
std::vector<std::pair<Topic, json>> ReadBack(const json& read, const std::vector<Topic>& ours) {
    std::map<std::string, json> theirs;
    for (const json& t : read["topics"]) theirs[t["guid"]] = t;
    EXPECT_EQ(theirs.size(), ours.size());
    std::vector<std::pair<Topic, json>> out;
    for (const Topic& t : ours) {
        EXPECT_TRUE(theirs.contains(t.folder)) << t.folder;
        if (!theirs.contains(t.folder)) continue;
        const json& j = theirs[t.folder];
        EXPECT_EQ(j["title"], t.title);
        EXPECT_EQ(j["type"], t.type);
        EXPECT_EQ(j["status"], "Open");
        EXPECT_EQ(j["priority"], t.priority);
        EXPECT_EQ(j["description"], t.description);
        EXPECT_EQ(j["viewpoints"].size(), 1u) << j.dump();
        if (j["viewpoints"].size() == 1) out.emplace_back(t, j);
    }
    return out;
}

std::string BcfJsMissing() {
    const fs::path tool = SourceRoot() / "tests" / "tools" / "bcf_js";
    if (test::RunCommand("node --version").exit_code != 0)
        return "node is not installed: run toolchain/install-deps.sh --test";
    if (!fs::exists(tool / "node_modules" / "@parametricos" / "bcf-js"))
        return (tool / "node_modules").string() +
               " is missing: run toolchain/install-deps.sh --test (or npm ci --prefix "
               "tests/tools/bcf_js)";
    return "";
}

// BCF 2.1 only: bcf-js 0.2.6 reads a 3.0 viewpoint's Coloring as 2.1's (Color/Component) and
// throws on the 3.0 schema's Color/Components/Component, which xmllint validates above.
TEST(ChangesBcf21, BcfJsReadsTheSameTopics) {
    if (const std::string why = BcfJsMissing(); !why.empty()) GTEST_SKIP() << why;
    const fs::path bcf = BcfOf("2.1");
    const auto r = test::RunCommand(
        "node " + Quote(SourceRoot() / "tests" / "tools" / "bcf_js" / "check.mjs") + " " +
        Quote(bcf) + " 2.1");
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    const auto topics = ReadBack(json::parse(r.out), Topics(Entries(bcf)));
    ASSERT_FALSE(topics.empty());
    for (const auto& [t, j] : topics) {
        EXPECT_EQ(j["author"], "bimslam");
        const json& v = j["viewpoints"][0];
        EXPECT_EQ(v["selected"], json(t.selected));
        EXPECT_EQ(v["snapshot_bytes"], t.png.size());
        for (int k = 0; k < 3; ++k)
            EXPECT_NEAR(v["camera"]["eye"][k].get<double>(), t.eye[k], 1e-9);
        EXPECT_EQ(v["camera"]["fov_deg"], 60);
    }
}

// The second reader for both versions (3.0 has no other here): `bimslam bcf info --json`
// (host_tools/changes/bcf_reader.hpp) against the XML read by XPath above.
TEST_P(ChangesBcf, BimslamsReaderGetsTheSameTopics) {
    const fs::path bcf = BcfOf(GetParam());
    const auto r = test::RunCommand(kCli + " bcf info --json " + Quote(bcf));
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    const json read = json::parse(r.out);
    EXPECT_EQ(read["version"], GetParam());
    const auto topics = ReadBack(read, Topics(Entries(bcf)));
    ASSERT_FALSE(topics.empty());
    for (const auto& [t, j] : topics) {
        EXPECT_EQ(j["creation_date"], t.date);
        const json& v = j["viewpoints"][0];
        EXPECT_EQ(v["camera"], "perspective");
        EXPECT_EQ(v["selected"], json(t.selected));
        ASSERT_EQ(v["colors"].size(), t.colors.size());
        EXPECT_EQ(v["colors"][0]["color"], t.colors[0]);
        EXPECT_EQ(v["snapshot_bytes"], t.png.size());
        for (int k = 0; k < 3; ++k) {
            EXPECT_NEAR(v["eye"][k].get<double>(), t.eye[k], 1e-9);
            EXPECT_NEAR(v["direction"][k].get<double>(), t.direction[k], 1e-9);
        }
    }
    // Not a BCF: exit 2, the file named.
    const fs::path json_file = changes_test::Walk() / "out" / "changes.json";
    const auto bad = test::RunCommand(kCli + " bcf info " + Quote(json_file));
    EXPECT_EQ(bad.exit_code, 2) << bad.out << bad.err;
    EXPECT_NE(bad.err.find(json_file.string() + ": not a BCF zip"), std::string::npos) << bad.err;
}

// An RGB picture, decoded by libpng.
struct Picture {
    int width = 0, height = 0;
    std::vector<uint8_t> rgb;
};

Picture Decode(const std::string& png) {
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    Picture p;
    if (!png_image_begin_read_from_memory(&image, png.data(), png.size())) return p;
    image.format = PNG_FORMAT_RGB;
    p.rgb.resize(PNG_IMAGE_SIZE(image));
    if (!png_image_finish_read(&image, nullptr, p.rgb.data(), 0, nullptr)) return {};
    p.width = int(image.width), p.height = int(image.height);
    return p;
}

TEST_P(ChangesBcf, SnapshotsArePicturesOfTheChangeInItsColour) {
    for (const Topic& t : Topics(Entries(BcfOf(GetParam())))) {
        const Picture p = Decode(t.png);
        ASSERT_EQ(p.width, 640) << t.title;
        ASSERT_EQ(p.height, 480) << t.title;
        // The model is grey and the background near white: coloured pixels are the change's,
        // lit (so darker or lighter), of its colour's hue.
        const unsigned c = std::stoul(t.colors[0], nullptr, 16);
        const double want[3] = {double(c >> 16), double((c >> 8) & 255), double(c & 255)};
        const double want_mean = (want[0] + want[1] + want[2]) / 3;
        size_t coloured = 0, of_its_hue = 0;
        for (size_t i = 0; i < p.rgb.size(); i += 3) {
            const uint8_t* px = &p.rgb[i];
            if (std::max({px[0], px[1], px[2]}) - std::min({px[0], px[1], px[2]}) < 40) continue;
            ++coloured;
            const double mean = (px[0] + px[1] + px[2]) / 3.0;
            double dot = 0, a = 0, b = 0;
            for (int k = 0; k < 3; ++k) {
                dot += (px[k] - mean) * (want[k] - want_mean);
                a += (px[k] - mean) * (px[k] - mean);
                b += (want[k] - want_mean) * (want[k] - want_mean);
            }
            of_its_hue += dot / std::sqrt(a * b) > 0.9;
        }
        EXPECT_GT(coloured, size_t(640 * 480 / 200)) << t.title << ": the change is not in view";
        EXPECT_GT(of_its_hue, 0.9 * coloured) << t.title;
    }
}

INSTANTIATE_TEST_SUITE_P(Versions, ChangesBcf, ::testing::Values("2.1", "3.0"), [](const auto& p) {
    return "Bcf" + std::string(p.param == "2.1" ? "21" : "30");
});

TEST(ChangesBcfCli, AnotherBcfVersionExits2NamingTheOption) {
    test::TempDir tmp;
    const auto r = test::RunCommand(kCli + " changes --model x.ifc --session y -o " +
                                    Quote(tmp.path() / "out") + " --bcf-version 2.0");
    EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
    EXPECT_NE(r.err.find("--bcf-version: '2.0'"), std::string::npos) << r.err;
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::bcf_test
