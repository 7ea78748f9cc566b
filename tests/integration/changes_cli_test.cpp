// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// `bimslam changes` as a user runs it: the sample building, a simulated handheld walk along its
// ground-floor corridor past an added crate, a wall built 3 cm off and a person walking the other
// way; the odometry session placed on the capture's ground truth (what `bimslam anchor` will
// write); then the command with --truth. The updated IFC is read back with IFC++ and web-ifc,
// the map with Open3D and CloudCompare, map_bim.las with loaders.gl and copc (node,
// tests/tools/las): each reader a test of its own, which skips saying why
// where its tool is not installed (toolchain/install-deps.sh --test). Bad input exits 2 naming
// what is wrong.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "algorithms/io/file_util.hpp"
#include "algorithms/io/las.hpp"
#include "algorithms/io/ply.hpp"
#include "algorithms/io/session.hpp"
#include "algorithms/io/trajectory.hpp"
#include "host_tools/bim/ifc_model.hpp"
#include "host_tools/bim/sample_building.hpp"
#include "host_tools/changes/change_evaluation.hpp"
#include "host_tools/changes/ifc_update.hpp"
#include "tests/integration/changes_walk.hpp"
#include "tests/integration/las_reader_support.hpp"
#include "tests/integration/web_ifc_support.hpp"
#include "tests/support/ground_truth_session.hpp"
#include "tests/support/test_support.hpp"
#include "tests/unit/change_detection/ifc_update_fixtures.hpp"

namespace bimslam {
namespace {
namespace BIMSLAM_UNITY_ID {
namespace fs = std::filesystem;
using nlohmann::json;

const std::string kCli = BIMSLAM_CLI_PATH;

std::string Quote(const fs::path& p) { return "'" + p.string() + "'"; }

// The corridor runs x 0.3 .. 29.7 between y 6.15 and 8.15 (host_tools/bim/sample_building.hpp);
// the GlobalId is the corridor's north wall in the sample building of seed 1.
const char* const kScenario = R"(platform: handheld
path:
  mode: waypoints
  waypoints: [[1.5, 7.2], [28.0, 7.2]]
seed: 3
edits:
  boxes:
    - {name: crate, center: [14.0, 7.75, 0.3], size: [0.6, 0.5, 0.6]}
  as_built:
    walls:
      - {global_id: "0EF31bAGn7cY_UpbsCA2np", offset_m: 0.03}
  people:
    - {from: [26.0, 6.6], to: [3.0, 6.6], speed_mps: 1.2}
)";

test::CommandResult Cli(const std::string& args) { return test::RunCommand(kCli + " " + args); }

void MustRun(const std::string& args) {
    const auto r = Cli(args);
    ASSERT_EQ(r.exit_code, 0) << "bimslam " << args << "\n" << r.out << r.err;
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace

namespace changes_test {
using namespace BIMSLAM_UNITY_ID;  // the helpers above
// The walk of kScenario through the sample building, its odometry session placed on the ground
// truth (anchored/) and `bimslam changes --truth --json` of it (out/, summary.json): made once per
// build of `bimslam` and shared by the tests below, each a process of its own under ctest, so
// that each reader of the files is a test of its own that skips, saying why, on its own.
fs::path Walk() {
    static const fs::path root =
        test::FixtureRootFor(BIMSLAM_TEST_BINARY_DIR "/changes_fixtures", kCli);
    return test::CachedFixture(root, "walk", [](const fs::path& d) {
        MustRun("bim sample -o " + Quote(d / "building.ifc"));
        io::WriteFileAtomic(d / "scenario.yaml", kScenario);
        MustRun("simulate --model " + Quote(d / "building.ifc") + " --scenario " +
                Quote(d / "scenario.yaml") + " -o " + Quote(d / "capture"));
        MustRun("odometry " + Quote(d / "capture") + " -o " + Quote(d / "session"));
        test::PlaceSessionOnGroundTruth(d / "session", d / "capture" / "ground_truth.tum",
                                        d / "anchored");
        const auto r = Cli("changes --model " + Quote(d / "building.ifc") + " --session " +
                           Quote(d / "anchored") + " -o " + Quote(d / "out") + " --truth " +
                           Quote(d / "capture" / "changes.json") + " --json --date " + kWalkDate);
        ASSERT_EQ(r.exit_code, 0) << r.err;
        io::WriteFileAtomic(d / "summary.json", r.out);
    });
}
}  // namespace changes_test

namespace {
namespace BIMSLAM_UNITY_ID {
using changes_test::Walk;

TEST(ChangesCli, FindsTheChangesOfASimulatedWalk) {
    const fs::path walk = Walk();
    const json summary = json::parse(io::ReadFileToString(walk / "summary.json"));
    ASSERT_EQ(summary["sessions"].size(), 1u);
    const json& s = summary["sessions"][0];
    const json& ev = s["evaluation"];
    std::cout << ev.dump(1) << "\n";

    // The crate is found and nothing else is taken for a new object (no false object: the
    // person is transient, the wall's 3 cm are a deviation); the wall's 3 cm are measured.
    EXPECT_EQ(ev["added"]["truth_matched"], 1);
    EXPECT_EQ(ev["added"]["found"], ev["added"]["found_matched"]) << ev["added"].dump();
    EXPECT_EQ(ev["people"]["reported_as_new_objects"], 0);
    EXPECT_EQ(ev["people"]["with_transient_clusters"], 1);
    ASSERT_EQ(ev["as_built"]["observed"], 1);
    EXPECT_LT(ev["as_built"]["max_error_m"].get<double>(), 0.01);
    EXPECT_EQ(ev["as_built"]["walls"][0]["verdict"], "deviating");
    // The poses were refined (on by default) and, being the truth, stayed within a centimetre.
    const json& refined = s["refinement"];
    EXPECT_TRUE(refined["enabled"].get<bool>());
    EXPECT_LT(refined["mean_correction_m"].get<double>(), 0.01) << refined.dump();
    EXPECT_EQ(io::ReadTum(walk / "out" / "keyframes_refined.tum").size(),
              s["keyframes"].get<size_t>());

    // The files.
    const fs::path out = walk / "out";
    const json changes = json::parse(io::ReadFileToString(out / "changes.json"));
    EXPECT_EQ(changes["format"], "bimslam-changes");
    EXPECT_EQ(changes["new_objects"].size(), s["new_objects"].get<size_t>());
    const io::PlyData map = io::ReadPly(out / "map_bim.ply");
    EXPECT_EQ(map.vertices.size(), changes["map"]["points"].get<size_t>());
    for (const char* field : {"scalar_distance", "scalar_element", "scalar_keyframes",
                              "scalar_class", "scalar_object"}) {
        EXPECT_NE(map.Find(field), nullptr) << field;
    }
    // The crate stands in its storey and in the corridor's IfcSpace.
    for (const json& o : changes["new_objects"]) {
        if (std::abs(o["centroid"][0].get<double>() - 14.0) > 0.3) continue;
        EXPECT_EQ(o["storey"]["name"], "Ground Floor");
        ASSERT_TRUE(o["space"].is_object()) << o.dump();
        EXPECT_EQ(o["space"]["long_name"], "Corridor") << o.dump();  // its IfcSpace.LongName
        EXPECT_TRUE(o["on_floor"].get<bool>());
    }
    // Every change is placed on a storey (issue 31, item 6): new objects by their height, the
    // model's elements by their IfcBuildingStorey (every element of the sample has one).
    for (const json& o : changes["new_objects"]) EXPECT_EQ(o["storey"]["from"], "height");
    for (const char* kind : {"missing", "deviating"}) {
        for (const json& e : changes[kind]) {
            ASSERT_TRUE(e["storey"].is_object()) << e.dump();
            EXPECT_EQ(e["storey"]["from"], "ifc") << e.dump();
            EXPECT_FALSE(e["storey"]["name"].get<std::string>().empty());
        }
    }
    // Each object's plan rectangle's centre (where the history puts a moved one) is within its
    // box, read back; a damaged one is refused, naming the file.
    const change_detection::FoundChanges read = change_detection::ReadFoundChanges(out);
    ASSERT_EQ(read.objects.size(), changes["new_objects"].size());
    for (const auto& o : read.objects) {
        ASSERT_TRUE(o.plan_center.has_value()) << o.id;
        EXPECT_TRUE(Eigen::AlignedBox2d(o.box.min().head<2>(), o.box.max().head<2>())
                        .contains(*o.plan_center))
            << o.id;
    }
    if (!changes["new_objects"].empty()) {
        const test::TempDir tmp;
        const fs::path damaged = tmp / "out";
        fs::copy(out, damaged, fs::copy_options::recursive);
        json bad = changes;
        bad["new_objects"][0]["plan_center_m"] = {1.0};
        io::WriteFileAtomic(damaged / "changes.json", bad.dump());
        EXPECT_FILE_ERROR(change_detection::ReadFoundChanges(damaged),
                          (damaged / "changes.json").string(), 0);
    }
    const io::PlyData objects = io::ReadPly(out / "new_objects.ply");
    EXPECT_GT(objects.triangles.size(), 0u);
    EXPECT_NE(objects.Find("red"), nullptr);
    const std::string csv = io::ReadFileToString(out / "elements.csv");
    EXPECT_EQ(csv.find("index,global_id,class,name,storey,verdict"), 0u);

    // The updated IFC in IFC++: the original elements and a proxy per new object.
    const bim::BimModel original = bim::LoadIfc(walk / "building.ifc");
    const bim::BimModel updated = bim::LoadIfc(out / "model_updated.ifc");
    const size_t objects_found = s["new_objects"].get<size_t>();
    ASSERT_GT(objects_found, 0u);
    EXPECT_EQ(updated.elements.size(), original.elements.size() + objects_found);
    EXPECT_EQ(updated.class_counts.at("IfcBuildingElementProxy"), objects_found);

    // A datum: the corridor's south wall surveyed where the model has it. It is seen and holds
    // the frame; the north wall's 3 cm are still measured, and the datum is in changes.json.
    test::TempDir tmp;
    std::string south;
    {
        std::istringstream rows(io::ReadFileToString(walk / "out" / "elements.csv"));
        for (std::string row; std::getline(rows, row);) {
            if (row.find(",Ground Floor corridor wall south,") == std::string::npos) continue;
            const size_t a = row.find(',') + 1;
            south = row.substr(a, row.find(',', a) - a);
        }
    }
    ASSERT_EQ(south.size(), 22u) << "no south corridor wall in elements.csv";
    io::WriteFileAtomic(tmp / "datum.csv",
                        "global_id,dx,dy,dz\n# surveyed 2026-11-29\n" + south + ",0,0.001,0\n");
    const auto r = Cli("changes --model " + Quote(walk / "building.ifc") + " --session " +
                       Quote(walk / "anchored") + " -o " + Quote(tmp / "out_datum") + " --truth " +
                       Quote(walk / "capture" / "changes.json") + " --datum " +
                       Quote(tmp / "datum.csv") + " --json");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const json with_datum = json::parse(r.out)["sessions"][0];
    EXPECT_EQ(with_datum["refinement"]["datum_elements"], 1);
    EXPECT_EQ(with_datum["refinement"]["datum_seen"], 1);
    EXPECT_EQ(with_datum["evaluation"]["as_built"]["observed"], 1);
    EXPECT_LT(with_datum["evaluation"]["as_built"]["max_error_m"].get<double>(), 0.01);
    const json datum = json::parse(io::ReadFileToString(
        tmp / "out_datum" / "changes.json"))["parameters"]["refinement"]["datum"];
    ASSERT_EQ(datum.size(), 1u);
    EXPECT_EQ(datum[0]["global_id"], south);
    EXPECT_DOUBLE_EQ(datum[0]["offset_m"][1].get<double>(), 0.001);
}

// elements.csv as rows of named fields (RFC 4180: quoted fields may hold commas and quotes).
std::vector<std::map<std::string, std::string>> CsvRows(const std::string& text) {
    std::vector<std::vector<std::string>> lines(1, std::vector<std::string>(1));
    bool quoted = false;
    for (size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (quoted) {
            if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
                lines.back().back() += '"';
                ++i;
            } else if (c == '"') {
                quoted = false;
            } else {
                lines.back().back() += c;
            }
        } else if (c == '"') {
            quoted = true;
        } else if (c == ',') {
            lines.back().emplace_back();
        } else if (c == '\n') {
            lines.emplace_back(1);
        } else {
            lines.back().back() += c;
        }
    }
    std::vector<std::map<std::string, std::string>> rows;
    for (size_t l = 1; l < lines.size(); ++l) {
        if (lines[l].size() != lines[0].size()) continue;  // the empty last line
        std::map<std::string, std::string> row;
        for (size_t k = 0; k < lines[0].size(); ++k) row[lines[0][k]] = lines[l][k];
        rows.push_back(row);
    }
    return rows;
}

// Issue 34 item 3: elements.csv's tolerance_verdict against --tolerance (default 1 cm), from each
// element's measured deviation (offset_m). The corridor's north wall, built 3 cm off, is beyond
// 1 cm and within 5 cm; --tolerance changes no change found (--deviation-tolerance decides that).
TEST(ChangesCli, ElementsCsvJudgesEachElementAgainstTheTolerance) {
    const fs::path walk = Walk();
    const auto verdicts = [](const fs::path& csv, double tolerance) {
        std::map<std::string, std::string> by_id;
        std::map<std::string, int> counts;
        for (const auto& row : CsvRows(io::ReadFileToString(csv))) {
            const std::string& v = row.at("tolerance_verdict");
            by_id[row.at("global_id")] = v;
            ++counts[v];
            // The rule, row by row: not judged -> not_observed; missing -> beyond; else by the
            // measured deviation when it was measured (30 support points or more).
            const std::string& verdict = row.at("verdict");
            std::string want;
            if (verdict == "not_observed") {
                want = "not_observed";
            } else if (verdict == "missing" || row.at("moved") == "1") {
                want = "beyond";
            } else if (std::stoul(row.at("support_points")) < 30 ||
                       row.at("constrained_axes") == "0") {
                want = "not_observed";
            } else {
                want = std::stod(row.at("offset_m")) <= tolerance ? "within" : "beyond";
            }
            EXPECT_EQ(v, want) << row.at("name") << " " << verdict << " " << row.at("offset_m");
        }
        return std::make_pair(by_id, counts);
    };
    const auto [tight, tight_counts] = verdicts(walk / "out" / "elements.csv", 0.01);
    EXPECT_EQ(tight.at("0EF31bAGn7cY_UpbsCA2np"), "beyond");
    EXPECT_GT(tight_counts.at("within"), 0);
    EXPECT_GT(tight_counts.at("not_observed"), 0);  // the rooms off the corridor
    const json changes = json::parse(io::ReadFileToString(walk / "out" / "changes.json"));
    EXPECT_DOUBLE_EQ(changes["parameters"]["elements"]["tolerance_m"].get<double>(), 0.01);

    test::TempDir tmp;
    const auto r = Cli("changes --model " + Quote(walk / "building.ifc") + " --session " +
                       Quote(walk / "anchored") + " -o " + Quote(tmp / "out") +
                       " --tolerance 0.05 --date " + changes_test::kWalkDate);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto [loose, loose_counts] = verdicts(tmp / "out" / "elements.csv", 0.05);
    EXPECT_EQ(loose.at("0EF31bAGn7cY_UpbsCA2np"), "within");
    EXPECT_GT(loose_counts.at("within"), tight_counts.at("within"));
    const json again = json::parse(io::ReadFileToString(tmp / "out" / "changes.json"));
    const auto ids = [](const json& list) {
        std::vector<std::string> v;
        for (const json& e : list) v.push_back(e.at("global_id"));
        return v;
    };
    EXPECT_EQ(ids(again["deviating"]), ids(changes["deviating"]));
    EXPECT_EQ(ids(again["missing"]), ids(changes["missing"]));
    EXPECT_DOUBLE_EQ(again["parameters"]["elements"]["tolerance_m"].get<double>(), 0.05);

    EXPECT_EQ(Cli("changes --model " + Quote(walk / "building.ifc") + " --session " +
                  Quote(walk / "anchored") + " -o " + Quote(tmp / "bad") + " --tolerance 0")
                  .exit_code,
              2);
    const auto help = Cli("changes --help");
    EXPECT_NE(help.out.find("--tolerance"), std::string::npos) << help.out;
    EXPECT_NE(help.out.find("Unlike --deviation-tolerance"), std::string::npos) << help.out;
}

// The second reader on both geometries the update writes (IFC4 tessellated, IFC2X3 B-rep).
TEST(ChangesCli, UpdatedIfc4AndIfc2x3OpenInWebIfc) {
    if (const std::string why = web_ifc::Missing(); !why.empty()) GTEST_SKIP() << why;
    test::TempDir tmp;
    const std::string sample = bim::SampleBuildingIfc(bim::SampleBuildingOptions{});
    const bim::BimModel model4 = bim::ParseIfc("building.ifc", sample);
    const change_detection::IfcUpdate u4 = change_detection::UpdateIfc(
        "building.ifc", sample, model4,
        change_detection::test::Found(model4, {3, 2, 0}, 0, changes::Verdict::kMissing), 7);
    io::WriteFileAtomic(tmp / "updated4.ifc", u4.text);
    const bim::BimModel model2 = bim::ParseIfc("tiny.ifc", change_detection::test::kTinyIfc2x3);
    const change_detection::IfcUpdate u2 = change_detection::UpdateIfc(
        "tiny.ifc", change_detection::test::kTinyIfc2x3, model2,
        change_detection::test::Found(model2, {1, 1, 0}, 0, changes::Verdict::kDeviating), 7);
    io::WriteFileAtomic(tmp / "updated2x3.ifc", u2.text);
    const json w4 = web_ifc::Read(tmp / "updated4.ifc");
    EXPECT_EQ(w4["schema"], "IFC4");
    EXPECT_EQ(w4["mesh_classes"]["IfcBuildingElementProxy"], 1);
    EXPECT_EQ(w4["counts"]["IFCTRIANGULATEDFACESET"], 1);
    const json w2 = web_ifc::Read(tmp / "updated2x3.ifc");
    EXPECT_EQ(w2["schema"], "IFC2X3");
    EXPECT_EQ(w2["mesh_classes"]["IfcBuildingElementProxy"], 1);
    EXPECT_EQ(w2["counts"]["IFCFACETEDBREP"], 1);
    EXPECT_EQ(w2["counts"]["IFCPROPERTYSET"], 2);  // the proxy's and the wall's verdict
    // The proxy's box in metres, web-ifc's own coordinates turned back to the model's.
    const auto& obj =
        change_detection::test::Found(model2, {1, 1, 0}, 0, changes::Verdict::kDeviating)
            .result.objects[0];
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(w2["bbox_ifc_m"]["min"][k].get<double>(),
                    std::min(obj.box_min[k], k == 1 ? -0.1 : 0.0), 1e-4)
            << k;  // the wall spans x 0..4, y -0.1..0.1, z 0..3
    }
}

TEST(ChangesCli, BadInputExits2WithAClearMessage) {
    test::TempDir tmp;
    ASSERT_EQ(Cli("bim sample -o " + Quote(tmp / "building.ifc")).exit_code, 0);
    const std::string model = " --model " + Quote(tmp / "building.ifc");

    // An empty session: anchored, but no keyframe. (Source "simulation": a rig session without
    // keyframes has no odom_poses.txt, which the reader then asks for.)
    io::SessionManifest manifest;
    manifest.source = "simulation";
    manifest.world_frame = "bim";
    io::SessionWriter(tmp / "empty", manifest).Finish();
    auto r = Cli("changes" + model + " --session " + Quote(tmp / "empty") + " -o " +
                 Quote(tmp / "out1"));
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("no keyframes"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find((tmp / "empty").string()), std::string::npos) << r.err;

    // A session of one keyframe in the odometry frame (not anchored), and the same anchored.
    for (const std::string frame : {"odom", "bim"}) {
        manifest.world_frame = frame;
        io::SessionWriter w(tmp / frame, manifest);
        io::SessionKeyframe k;
        k.cloud = test::MakeRoomScan(8, 64, 1);
        k.descriptor = io::DescriptorMatrix::Zero(20, 60);
        k.T_odom_lidar = Eigen::Isometry3d::Identity();
        w.AddKeyframe(k);
        w.Finish();
    }
    r = Cli("changes" + model + " --session " + Quote(tmp / "odom") + " -o " + Quote(tmp / "out2"));
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("bimslam anchor"), std::string::npos) << r.err;

    // A model with no geometry: a project and a storey, no element.
    io::WriteFileAtomic(tmp / "bare.ifc", R"(ISO-10303-21;
HEADER;
FILE_DESCRIPTION((''),'2;1');
FILE_NAME('bare.ifc','2024-01-01T00:00:00',(''),(''),'','','');
FILE_SCHEMA(('IFC4'));
ENDSEC;
DATA;
#1=IFCSIUNIT(*,.LENGTHUNIT.,$,.METRE.);
#2=IFCUNITASSIGNMENT((#1));
#3=IFCCARTESIANPOINT((0.,0.,0.));
#4=IFCAXIS2PLACEMENT3D(#3,$,$);
#5=IFCGEOMETRICREPRESENTATIONCONTEXT($,'Model',3,1.E-05,#4,$);
#6=IFCPROJECT('0YvctVUKr0kugbFTf53O9L',$,'bare',$,$,$,$,(#5),#2);
#7=IFCLOCALPLACEMENT($,#4);
#8=IFCBUILDINGSTOREY('3YvctVUKr0kugbFTf53O9L',$,'Ground',$,$,#7,$,$,.ELEMENT.,0.);
#9=IFCRELAGGREGATES('0AvctVUKr0kugbFTf53O9L',$,$,$,#6,(#8));
ENDSEC;
END-ISO-10303-21;
)");
    r = Cli("changes --model " + Quote(tmp / "bare.ifc") + " --session " + Quote(tmp / "bim") +
            " -o " + Quote(tmp / "out3"));
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("no element with geometry"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("bare.ifc"), std::string::npos) << r.err;

    // A missing session folder, a missing option, a truth per session, an output in the way.
    r = Cli("changes" + model + " --session " + Quote(tmp / "nowhere") + " -o " + Quote(tmp / "o"));
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("nowhere"), std::string::npos) << r.err;
    EXPECT_EQ(Cli("changes" + model + " -o " + Quote(tmp / "o")).exit_code, 2);
    r = Cli("changes" + model + " --session " + Quote(tmp / "empty") +
            " --truth a.json --truth "
            "b.json -o " +
            Quote(tmp / "o"));
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("--truth"), std::string::npos) << r.err;
    fs::create_directories(tmp / "taken");
    io::WriteFileAtomic(tmp / "taken" / "x", "");
    r = Cli("changes" + model + " --session " + Quote(tmp / "bim") + " -o " + Quote(tmp / "taken"));
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("--overwrite"), std::string::npos) << r.err;
    r = Cli("changes" + model + " --session " + Quote(tmp / "bim") + " --min-multi-view 1.5 -o " +
            Quote(tmp / "o"));
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("--min-multi-view"), std::string::npos) << r.err;

    // Datum files: missing, an unknown GlobalId, a field that is not a number, a moved element,
    // and a datum without the refinement it is for. Each names the file (and line).
    const std::string bim = " --session " + Quote(tmp / "bim") + " -o " + Quote(tmp / "o");
    r = Cli("changes" + model + bim + " --datum " + Quote(tmp / "no_datum.csv"));
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("no_datum.csv"), std::string::npos) << r.err;
    const bim::BimModel sample = bim::LoadIfc(tmp / "building.ifc");
    const std::string id = sample.elements.front().global_id;
    const std::vector<std::pair<std::string, std::string>> bad = {
        {"# walls\n0000000000000000000000\n", "datum.csv:2: the model has no element"},
        {id + ",0,0.01\n", "datum.csv:1: expected GlobalId or GlobalId,dx,dy,dz"},
        {"\n" + id + ",0,abc,0\n", "datum.csv:2: 'abc' is not a number"},
        {id + ",0,1.5,0\n", "datum.csv:1: an offset of 1.5"},
        {id + "\n" + id + "\n", "datum.csv:2: " + id + " is listed twice"},
        {"# nothing\n", "datum.csv: no surveyed element"}};
    for (const auto& [text, message] : bad) {
        io::WriteFileAtomic(tmp / "datum.csv", text);
        r = Cli("changes" + model + bim + " --datum " + Quote(tmp / "datum.csv"));
        EXPECT_EQ(r.exit_code, 2) << text;
        EXPECT_NE(r.err.find(message), std::string::npos) << text << " -> " << r.err;
    }
    r = Cli("changes" + model + bim + " --no-refine --datum " + Quote(tmp / "datum.csv"));
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("--no-refine"), std::string::npos) << r.err;

    r = Cli("changes --help");
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_NE(r.out.find("--min-multi-view"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("--datum"), std::string::npos) << r.out;
}

TEST(ChangesCli, SeveralSessionsKeepTheirOwnFiles) {
    test::TempDir tmp;
    ASSERT_EQ(Cli("bim sample -o " + Quote(tmp / "building.ifc")).exit_code, 0);
    io::SessionManifest manifest;
    manifest.world_frame = "bim";
    for (const char* name : {"monday", "tuesday"}) {
        io::SessionWriter w(tmp / name, manifest);
        io::SessionKeyframe k;
        k.cloud = test::MakeRoomScan(16, 256, 2);
        k.descriptor = io::DescriptorMatrix::Zero(20, 60);
        k.T_odom_lidar = Eigen::Isometry3d::Identity();
        k.T_world_lidar.translation() = Eigen::Vector3d(5, 7, 1);  // in the corridor
        w.AddKeyframe(k);
        w.Finish();
    }
    const auto r = Cli("changes --model " + Quote(tmp / "building.ifc") + " --session " +
                       Quote(tmp / "monday") + " --session " + Quote(tmp / "tuesday") + " -o " +
                       Quote(tmp / "out") + " --json");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const json j = json::parse(r.out);
    ASSERT_EQ(j["sessions"].size(), 2u);
    for (const char* name : {"monday", "tuesday"}) {
        for (const char* f : {"changes.json", "new_objects.ply", "map_bim.ply", "map_bim.las",
                              "elements.csv", "model_updated.ifc"}) {
            EXPECT_TRUE(fs::exists(tmp / "out" / name / f)) << name << "/" << f;
        }
        const json c = json::parse(io::ReadFileToString(tmp / "out" / name / "changes.json"));
        EXPECT_EQ(c["session"]["label"], name);
        EXPECT_TRUE(c["parameters"]["refinement"]["enabled"].get<bool>());
        EXPECT_EQ(c["counts"]["refinement"]["keyframes"], 1);
    }
    // --no-refine: the poses as they are, and changes.json says so.
    const auto off = Cli("changes --model " + Quote(tmp / "building.ifc") + " --session " +
                         Quote(tmp / "monday") + " -o " + Quote(tmp / "off") + " --no-refine");
    ASSERT_EQ(off.exit_code, 0) << off.err;
    const json c = json::parse(io::ReadFileToString(tmp / "off" / "changes.json"));
    EXPECT_FALSE(c["parameters"]["refinement"]["enabled"].get<bool>());
    EXPECT_FALSE(c["counts"]["refinement"]["enabled"].get<bool>());
    EXPECT_EQ(off.out.find("refined"), std::string::npos) << off.out;
    EXPECT_FALSE(fs::exists(tmp / "off" / "keyframes_refined.tum"));
    EXPECT_TRUE(fs::exists(tmp / "out" / "monday" / "keyframes_refined.tum"));
}

// The readers of the walk's files, each a test of its own that skips where its tool is missing.
// Last in the file: ctest (-j) starts them after the tests above, so they wait less for the walk
// the first test makes.

// The map as Open3D (tensor API) reads it: every point and the scalar fields.
TEST(ChangesCli, MapOpensInOpen3d) {
    if (test::RunCommand("/usr/bin/python3 -c 'import open3d'").exit_code != 0) {
        GTEST_SKIP() << "/usr/bin/python3 has no open3d: run toolchain/install-deps.sh --test";
    }
    const fs::path file = Walk() / "out" / "map_bim.ply";
    const io::PlyData ours = io::ReadPly(file);
    const auto r = test::RunCommand(
        "/usr/bin/python3 -c \"import open3d as o3d, sys; "
        "p = o3d.t.io.read_point_cloud(sys.argv[1]); "
        "print('read', p.point.positions.shape[0], sorted(k for k in p.point))\" " +
        Quote(file));
    EXPECT_EQ(r.exit_code, 0) << r.err;
    // Open3D prints warnings on stdout too: look for our line.
    EXPECT_NE(r.out.find("read " + std::to_string(ours.vertices.size()) + " "), std::string::npos)
        << r.out;
    for (const char* field : {"scalar_distance", "scalar_element", "scalar_keyframes",
                              "scalar_class", "scalar_object"}) {
        EXPECT_NE(r.out.find(field), std::string::npos) << r.out;
    }
}

// The map as CloudCompare (headless) reads it and writes it back: every point, the distances.
TEST(ChangesCli, MapOpensInCloudCompare) {
    if (!fs::exists("/usr/bin/CloudCompare")) {
        GTEST_SKIP() << "/usr/bin/CloudCompare is missing: run toolchain/install-deps.sh --test";
    }
    const fs::path file = Walk() / "out" / "map_bim.ply";
    const io::PlyData ours = io::ReadPly(file);
    test::TempDir dir;
    const auto r = test::RunCommand(
        "cd " + Quote(dir.path()) + " && QT_QPA_PLATFORM=offscreen /usr/bin/CloudCompare " +
        "-SILENT -AUTO_SAVE OFF -O " + Quote(file) +
        " -C_EXPORT_FMT PLY -PLY_EXPORT_FMT BINARY_LE -SAVE_CLOUDS FILE cc.ply");
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    const io::PlyData back = io::ReadPly(dir / "cc.ply");
    EXPECT_EQ(back.vertices.size(), ours.vertices.size());
    const io::PlyProperty* d = back.Find("scalar_distance");
    ASSERT_NE(d, nullptr) << "CloudCompare lost the distance field";
    EXPECT_EQ(d->values, ours.Find("scalar_distance")->values);
}

// map_bim.las as two readers independent of ours read it (loaders.gl and copc, through node):
// every point of map_bim.ply in the same order and place, its ASPRS class (issue 34: 6 building
// for the model's points, 1 unclassified for unexplained and outside, user classes 64 new object,
// 65 transient, 66 moved element), map_bim.ply's class in the user data, the visit (1, a lone
// run) as point source id, the extra bytes equal to the PLY's fields, and GPS times within the
// simulated capture's span (adjusted standard GPS time: the session knows its clock offset).
TEST(ChangesCli, MapLasMatchesThePlyInLoadersGlAndCopc) {
    if (const std::string why = las_readers::Missing(); !why.empty()) GTEST_SKIP() << why;
    const fs::path walk = Walk();
    const io::PlyData ply = io::ReadPly(walk / "out" / "map_bim.ply");
    const json j = las_readers::Read(walk / "out" / "map_bim.las");
    ASSERT_TRUE(j.is_object());
    const size_t n = ply.vertices.size();
    const json& lg = j["loadersGl"];
    const json& cp = j["copc"];
    ASSERT_EQ(lg["points"].get<size_t>(), n);
    ASSERT_EQ(cp["points"].get<size_t>(), n);
    EXPECT_EQ(lg["version"], "1.4");
    EXPECT_EQ(cp["format"], 6);
    EXPECT_EQ(cp["globalEncoding"].get<int>() & 1, 1) << "not adjusted standard GPS time";
    EXPECT_EQ(cp["vlrs"], json::array({"LASF_Spec/4"}));
    const std::map<int, int> asprs = {{0, 6}, {1, 64}, {2, 65}, {3, 1}, {4, 1}, {5, 66}};
    const json& dims = cp["dimensions"];
    const auto column = [&](const json& array, size_t per_point = 1) {
        EXPECT_EQ(array.size(), array.is_array() ? n * per_point : 0);
        return array.get<std::vector<double>>();
    };
    const std::vector<double> lg_position = column(lg["position"], 3);  // x y z x y z ...
    const std::vector<double> lg_class = column(lg["classification"]);
    const std::vector<double> x = column(dims["X"]), y = column(dims["Y"]), z = column(dims["Z"]);
    const std::vector<double> cp_class = column(dims["Classification"]);
    const std::vector<double> user = column(dims["UserData"]);
    const std::vector<double> source = column(dims["PointSourceId"]);
    const std::vector<double>& cls = ply.Find("scalar_class")->values;
    std::map<int, size_t> counts;
    for (size_t i = 0; i < n; ++i) {
        const Eigen::Vector3d p = ply.vertices[i].cast<double>();
        const Eigen::Vector3d by_loaders_gl(lg_position[3 * i], lg_position[3 * i + 1],
                                            lg_position[3 * i + 2]);
        ASSERT_LT((by_loaders_gl - p).cwiseAbs().maxCoeff(), 1e-3) << i;
        ASSERT_LT((Eigen::Vector3d(x[i], y[i], z[i]) - p).cwiseAbs().maxCoeff(), 1e-3) << i;
        const int expected = asprs.at(int(cls[i]));
        ASSERT_EQ(lg_class[i], expected) << i;
        ASSERT_EQ(cp_class[i], expected) << i;
        ASSERT_EQ(user[i], cls[i]) << i;
        ASSERT_EQ(source[i], 1) << i;
        ++counts[expected];
    }
    EXPECT_GT(counts[6], 0u);
    EXPECT_GT(counts[64], 0u) << "the crate's points";
    EXPECT_GT(counts[65], 0u) << "the person's points";
    for (const auto& [las, ours] : {std::pair{"distance", "scalar_distance"},
                                    {"element", "scalar_element"},
                                    {"object", "scalar_object"},
                                    {"keyframes", "scalar_keyframes"}}) {
        ASSERT_TRUE(dims.contains(las)) << las;
        EXPECT_EQ(column(dims[las]), ply.Find(ours)->values) << las;
    }
    const json capture = json::parse(io::ReadFileToString(walk / "capture" / "capture.json"));
    const double start = io::UnixNsToAdjustedGpsSeconds(capture["start_ns"].get<int64_t>());
    const double end = start + capture["walk"]["duration_s"].get<double>();
    for (const double t : column(dims["GpsTime"])) {
        ASSERT_TRUE(t >= start - 1 && t <= end + 1)
            << t << " not in [" << start << ", " << end << "]";
    }
}

// The walk's updated IFC in web-ifc: a proxy with a mesh per new object.
TEST(ChangesCli, UpdatedIfcOfTheWalkOpensInWebIfc) {
    if (const std::string why = web_ifc::Missing(); !why.empty()) GTEST_SKIP() << why;
    const fs::path walk = Walk();
    const size_t objects_found =
        json::parse(io::ReadFileToString(walk / "summary.json"))["sessions"][0]["new_objects"]
            .get<size_t>();
    ASSERT_GT(objects_found, 0u);
    const json w = web_ifc::Read(walk / "out" / "model_updated.ifc");
    EXPECT_EQ(w["counts"]["IFCBUILDINGELEMENTPROXY"].get<size_t>(), objects_found);
    EXPECT_EQ(w["mesh_classes"]["IfcBuildingElementProxy"].get<size_t>(), objects_found);
    EXPECT_EQ(w["counts"]["IFCTRIANGULATEDFACESET"].get<size_t>(), objects_found);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam
