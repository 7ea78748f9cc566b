// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// `bimslam bim plan`, `bimslam bim stairs` and `bimslam bim2session` as a user runs them: files,
// exit codes, messages.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>

#include "algorithms/io/file_util.hpp"
#include "algorithms/io/session.hpp"
#include "algorithms/io/sha256.hpp"
#include "algorithms/io/trajectory.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam {
namespace {
namespace BIMSLAM_UNITY_ID {
namespace fs = std::filesystem;

const std::string kCli = BIMSLAM_CLI_PATH;

// The sample building, written by the command itself.
fs::path Sample(const test::TempDir& tmp) {
    const fs::path file = tmp / "building.ifc";
    const auto r = test::RunCommand(kCli + " bim sample -o " + file.string());
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return file;
}

TEST(BimCli, PlanWritesGridsAndWalksOfEveryStorey) {
    test::TempDir tmp;
    const fs::path model = Sample(tmp);
    const auto r = test::RunCommand(kCli + " bim plan " + model.string() + " -o " +
                                    (tmp / "plan").string() + " --json");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    for (const std::string stem : {"ground_floor", "first_floor"}) {
        for (const std::string ext : {".pgm", ".yaml", ".png", "_path.png", "_path.tum"}) {
            EXPECT_TRUE(fs::exists(tmp / "plan" / (stem + ext))) << stem + ext;
        }
        const auto walk = io::ReadTum(tmp / "plan" / (stem + "_path.tum"));
        EXPECT_GT(walk.size(), 500u);
    }
    const auto plan = nlohmann::json::parse(io::ReadFileToString(tmp / "plan" / "plan.json"));
    ASSERT_EQ(plan.size(), 2u);
    EXPECT_EQ(plan[0].at("storey"), "Ground Floor");
    EXPECT_GE(plan[0].at("rooms").get<int>(), 9);
    EXPECT_EQ(plan[0].at("unreachable_viewpoints"), 0);
    // One storey only, and a storey the model does not have.
    const auto one = test::RunCommand(kCli + " bim plan " + model.string() + " -o " +
                                      (tmp / "one").string() + " --storey 'First Floor'");
    EXPECT_EQ(one.exit_code, 0) << one.err;
    EXPECT_FALSE(fs::exists(tmp / "one" / "ground_floor.pgm"));
    const auto bad = test::RunCommand(kCli + " bim plan " + model.string() + " -o " +
                                      (tmp / "bad").string() + " --storey Attic");
    EXPECT_EQ(bad.exit_code, 2);
    EXPECT_NE(bad.err.find("'Ground Floor'"), std::string::npos) << bad.err;
    // A seed point: inside the building it gives the same free space; in a wall it is an error.
    const auto seeded = test::RunCommand(kCli + " bim plan " + model.string() + " -o " +
                                         (tmp / "seeded").string() + " --free-seed 15 7.15");
    EXPECT_EQ(seeded.exit_code, 0) << seeded.err;
    EXPECT_EQ(io::ReadFileToString(tmp / "seeded" / "ground_floor.pgm"),
              io::ReadFileToString(tmp / "plan" / "ground_floor.pgm"));
    const auto in_wall = test::RunCommand(kCli + " bim plan " + model.string() + " -o " +
                                          (tmp / "wall").string() + " --free-seed 0.1 7");
    EXPECT_EQ(in_wall.exit_code, 2);
    EXPECT_NE(in_wall.err.find("seed"), std::string::npos) << in_wall.err;
}

TEST(BimCli, Bim2SessionWritesTheReferenceSession) {
    test::TempDir tmp;
    const fs::path model = Sample(tmp);
    const fs::path session = tmp / "ref";
    const auto r =
        test::RunCommand(kCli + " bim2session " + model.string() + " -o " + session.string() +
                         " --storey 'Ground Floor' --keyframe-gap 4 --json");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const io::Session s = io::ReadSession(session, {.load_clouds = false});
    ASSERT_TRUE(s.complete);
    EXPECT_EQ(s.manifest.source, "bim");
    EXPECT_EQ(s.manifest.world_frame, "bim");
    ASSERT_TRUE(s.manifest.model.has_value());
    EXPECT_EQ(s.manifest.model->file, "building.ifc");
    EXPECT_EQ(s.manifest.model->sha256, io::Sha256File(model));
    EXPECT_EQ(s.manifest.model->storeys, std::vector<std::string>{"Ground Floor"});
    EXPECT_DOUBLE_EQ(s.manifest.keyframe.distance_m, 4.0);
    EXPECT_GT(s.keyframes.size(), 20u);
    EXPECT_EQ(s.edges.size(), s.keyframes.size() - 1);
    // The figures a user compares: faster than the walk it stands for.
    const auto j = nlohmann::json::parse(r.out.substr(r.out.find('{')));
    EXPECT_EQ(j.at("keyframes").get<size_t>(), s.keyframes.size());
    EXPECT_GT(j.at("realtime_ratio").get<double>(), 1.0);

    // It never replaces a session silently.
    const auto again = test::RunCommand(kCli + " bim2session " + model.string() + " -o " +
                                        session.string() + " --keyframe-gap 4");
    EXPECT_EQ(again.exit_code, 2);
    EXPECT_NE(again.err.find(session.string()), std::string::npos) << again.err;
}

TEST(BimCli, Bim2SessionRejectsBadInput) {
    test::TempDir tmp;
    const fs::path model = Sample(tmp);
    const std::string text = io::ReadFileToString(model);
    test::WriteBytes(tmp / "cut.ifc", text.substr(0, text.size() / 2));
    const auto cut = test::RunCommand(kCli + " bim2session " + (tmp / "cut.ifc").string() + " -o " +
                                      (tmp / "s1").string());
    EXPECT_EQ(cut.exit_code, 2);
    EXPECT_NE(cut.err.find((tmp / "cut.ifc").string()), std::string::npos) << cut.err;
    EXPECT_FALSE(fs::exists(tmp / "s1" / "session.json"));

    const auto gap = test::RunCommand(kCli + " bim2session " + model.string() + " -o " +
                                      (tmp / "s2").string() + " --keyframe-gap 0");
    EXPECT_EQ(gap.exit_code, 2);
    EXPECT_NE(gap.err.find("keyframe gap"), std::string::npos) << gap.err;

    test::WriteBytes(tmp / "meta.json", "{\"beam_altitude_angles\": [1, 2]}");
    const auto meta =
        test::RunCommand(kCli + " bim2session " + model.string() + " -o " + (tmp / "s3").string() +
                         " --sensor " + (tmp / "meta.json").string());
    EXPECT_EQ(meta.exit_code, 2);
    EXPECT_NE(meta.err.find((tmp / "meta.json").string()), std::string::npos) << meta.err;
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam

// `bimslam simulate` as a user runs it: the default Go1 walk, a shipped scenario, bad input.
namespace bimslam {
namespace {
namespace BIMSLAM_UNITY_ID {

TEST(SimulateCli, WritesACaptureTheOtherCommandsRead) {
    test::TempDir tmp;
    const fs::path model = Sample(tmp);
    const fs::path cap = tmp / "capture";
    const auto r = test::RunCommand(kCli + " simulate --model " + model.string() +
                                    " --duration 6 --seed 3 -o " + cap.string() + " --json");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("x real time"), std::string::npos) << r.out;
    for (const std::string f :
         {"lidar.pcap", "metadata.json", "go1_can.log", "go1_can.pcap", "ground_truth.tum",
          "changes.json", "capture.json", "scenario.yaml"}) {
        EXPECT_TRUE(fs::exists(cap / f)) << f;
    }
    EXPECT_EQ(io::ReadTum(cap / "ground_truth.tum").size(), 60u);
    // The project's own readers take it as a real capture.
    const auto info =
        test::RunCommand(kCli + " ouster info " + (cap / "lidar.pcap").string() + " --json");
    ASSERT_EQ(info.exit_code, 0) << info.err;
    const auto j = nlohmann::json::parse(info.out);
    EXPECT_EQ(j.at("frames_complete"), 60);
    EXPECT_EQ(j.at("frames_incomplete"), 0);
    EXPECT_EQ(j.at("crc_checked"), j.at("lidar_packets"));  // FW 3: every packet has its CRC-64
    const auto can = test::RunCommand(kCli + " can info " + (cap / "go1_can.log").string());
    ASSERT_EQ(can.exit_code, 0) << can.err;
    EXPECT_NE(can.out.find("faults      none"), std::string::npos) << can.out;
    // The recorded scenario runs again to the same capture.
    const fs::path again = tmp / "again";
    const auto r2 =
        test::RunCommand(kCli + " simulate --scenario " + (cap / "scenario.yaml").string() +
                         " --model " + model.string() + " -o " + again.string());
    ASSERT_EQ(r2.exit_code, 0) << r2.err;
    EXPECT_EQ(io::ReadFileToString(cap / "ground_truth.tum"),
              io::ReadFileToString(again / "ground_truth.tum"));
    EXPECT_EQ(io::ReadFileToString(cap / "lidar.pcap"), io::ReadFileToString(again / "lidar.pcap"));
    // An existing capture is not overwritten by accident.
    const auto exists = test::RunCommand(kCli + " simulate --model " + model.string() +
                                         " --duration 1 -o " + cap.string());
    EXPECT_EQ(exists.exit_code, 2);
    EXPECT_NE(exists.err.find("--overwrite"), std::string::npos) << exists.err;
}

TEST(SimulateCli, RejectsBadInputNamingIt) {
    test::TempDir tmp;
    const fs::path model = Sample(tmp);
    auto run = [&](const std::string& args) {
        return test::RunCommand(kCli + " simulate " + args + " -o " + (tmp / "out").string());
    };
    std::ofstream(tmp / "typo.yaml") << "speed:\n  sped_mps: 1\n";
    const auto typo =
        run("--model " + model.string() + " --scenario " + (tmp / "typo.yaml").string());
    EXPECT_EQ(typo.exit_code, 2);
    EXPECT_NE(typo.err.find("speed.sped_mps"), std::string::npos) << typo.err;
    const auto no_model = run("");
    EXPECT_EQ(no_model.exit_code, 2);
    EXPECT_NE(no_model.err.find("--model"), std::string::npos) << no_model.err;
    // Outside a building with no door to the outside.
    std::ofstream(tmp / "outside.yaml") << "path:\n  start: {xy: [-5, 7.5], yaw_deg: 0}\n";
    const auto outside =
        run("--model " + model.string() + " --scenario " + (tmp / "outside.yaml").string());
    EXPECT_EQ(outside.exit_code, 2);
    EXPECT_NE(outside.err.find("--exterior-doors"), std::string::npos) << outside.err;
    std::ofstream(tmp / "broken.ifc") << "ISO-10303-21;\nHEADER;\n";
    const auto broken = run("--model " + (tmp / "broken.ifc").string());
    EXPECT_EQ(broken.exit_code, 2);
    EXPECT_NE(broken.err.find("broken.ifc"), std::string::npos) << broken.err;
}

// From outside, through an entrance, into the coverage walk.
TEST(SimulateCli, StartsOutsideThroughADoor) {
    test::TempDir tmp;
    const fs::path model = tmp / "entrances.ifc";
    ASSERT_EQ(
        test::RunCommand(kCli + " bim sample --exterior-doors -o " + model.string()).exit_code, 0);
    const fs::path cap = tmp / "capture";
    const auto r = test::RunCommand(
        kCli + " simulate --model " + model.string() + " --scenario " +
        std::string(BIMSLAM_SOURCE_ROOT) +
        "/host_tools/simulate/scenarios/outdoor_start.yaml --duration 40 -o " + cap.string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto truth = io::ReadTum(cap / "ground_truth.tum");
    ASSERT_FALSE(truth.empty());
    EXPECT_LT(truth.front().translation.x(), -4.0);  // outdoors at first
    EXPECT_GT(truth.back().translation.x(), 0.5);    // inside after 40 s
}

// Issue 33, item 7: the shipped office_visits.yaml through the command, its walks cut to 4 s of
// OS1-16: one capture per visit on its date, visits.json's truth between v2 and v3, `--visit`
// giving the same files as the visit's folder, and the options a visit owns refused without it.
TEST(SimulateCli, VisitsOfTheSampleOfficeAndOneVisitAlone) {
    test::TempDir tmp;
    const fs::path model = Sample(tmp);
    const std::string scenario =
        std::string(BIMSLAM_SOURCE_ROOT) + "/host_tools/simulate/scenarios/office_visits.yaml";
    const std::string args = " simulate --model " + model.string() + " --scenario " + scenario +
                             " --duration 4 --sensor OS1-16";
    const fs::path out = tmp / "visits";
    const auto r = test::RunCommand(kCli + args + " -o " + out.string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto visits = nlohmann::json::parse(io::ReadFileToString(out / "visits.json"));
    ASSERT_EQ(visits["visits"].size(), 3u);
    std::string last;
    for (const auto& v : visits["visits"]) {
        const auto manifest = nlohmann::json::parse(
            io::ReadFileToString(out / v["folder"].get<std::string>() / "capture.json"));
        EXPECT_EQ(manifest["start"], v["date"]);
        EXPECT_GT(v["date"].get<std::string>(), last);
        last = v["date"];
    }
    ASSERT_EQ(visits["pairs"].size(), 3u);  // every pair
    const auto& pair = visits["pairs"][2];
    ASSERT_EQ(pair["earlier"], "v2");
    ASSERT_EQ(pair["later"], "v3");
    const auto names = [](const nlohmann::json& list) {
        std::vector<std::string> v;
        for (const auto& e : list) v.push_back(e["name"]);
        return v;
    };
    EXPECT_EQ(names(pair["objects"]["gone"]), (std::vector<std::string>{"bookcase", "plant"}));
    EXPECT_EQ(names(pair["objects"]["moved"]), (std::vector<std::string>{"crate", "sofa"}));
    EXPECT_EQ(pair["objects"]["moved"][0]["yaw_deg"], 20.0);
    EXPECT_EQ(pair["objects"]["new"].size(), 4u);  // the annex's walls and roof
    EXPECT_EQ(names(pair["elements"]["newly_removed"]),
              std::vector<std::string>{"Ground Floor partition x=6.0"});

    const fs::path alone = tmp / "v2";
    const auto one = test::RunCommand(kCli + args + " --visit v2 -o " + alone.string());
    ASSERT_EQ(one.exit_code, 0) << one.err;
    for (const std::string f : {"lidar.pcap", "go1_can.log", "ground_truth.tum", "changes.json",
                                "capture.json", "scenario.yaml"}) {
        EXPECT_TRUE(io::ReadFileToString(alone / f) == io::ReadFileToString(out / "v2" / f)) << f;
    }
    const auto seed = test::RunCommand(kCli + args + " --seed 4 -o " + (tmp / "x").string());
    EXPECT_EQ(seed.exit_code, 2);
    EXPECT_NE(seed.err.find("--visit"), std::string::npos) << seed.err;
    const auto unknown = test::RunCommand(kCli + args + " --visit v9 -o " + (tmp / "x").string());
    EXPECT_EQ(unknown.exit_code, 2);
    EXPECT_NE(unknown.err.find("v1, v2, v3"), std::string::npos) << unknown.err;
}

// The sample office's stair joins its storeys; with the flight's geometry taken out of the file
// (IfcStair and IfcStairFlight left without a representation) the first floor cannot be reached:
// `bim stairs` and `simulate --storey all` name the storey and the reason and exit 2, and the
// simulator still writes the capture of the ground floor.
TEST(BimCli, AStairThatCannotBeWalkedIsNamedWithItsStoreysAndExits2) {
    test::TempDir tmp;
    const fs::path model = Sample(tmp);
    const auto ok = test::RunCommand(kCli + " bim stairs " + model.string() + " --json");
    ASSERT_EQ(ok.exit_code, 0) << ok.err;
    const auto graph = nlohmann::json::parse(ok.out);
    EXPECT_TRUE(graph.at("all_reached").get<bool>());
    ASSERT_EQ(graph.at("flights").size(), 1u);
    EXPECT_EQ(graph["flights"][0].at("risers"), 16);
    EXPECT_EQ(graph["flights"][0].at("lower"), "Ground Floor");
    EXPECT_EQ(graph["flights"][0].at("upper"), "First Floor");
    // What the file declares of the flight agrees with its geometry, and is said.
    const nlohmann::json& declared = graph["flights"][0].at("declared");
    EXPECT_EQ(declared.at("risers"), 16);
    EXPECT_EQ(declared.at("treads"), 15);
    EXPECT_EQ(declared.at("differs"), "");
    const auto text_out = test::RunCommand(kCli + " bim stairs " + model.string());
    EXPECT_NE(text_out.out.find("declared 16 risers, 15 treads, risers of 0.200 m, treads of "
                                "0.280 m: agrees"),
              std::string::npos)
        << text_out.out;

    const std::regex flight(R"((IFCSTAIRFLIGHT\('[^']*',#\d+,'[^']*',\$,\$,#\d+,)#\d+)");
    const std::string text = io::ReadFileToString(model);
    ASSERT_TRUE(std::regex_search(text, flight));
    const fs::path broken = tmp / "no_flight.ifc";
    io::WriteFileAtomic(broken, std::regex_replace(text, flight, "$1$$"));
    const std::string reason =
        "storey 'First Floor' is not reached from 'Ground Floor': the model has no stair or ramp "
        "with geometry";
    const auto stairs = test::RunCommand(kCli + " bim stairs " + broken.string());
    EXPECT_EQ(stairs.exit_code, 2) << stairs.err;
    EXPECT_NE(stairs.err.find(reason), std::string::npos) << stairs.err;
    EXPECT_NE(stairs.err.find(broken.string()), std::string::npos) << stairs.err;

    const fs::path capture = tmp / "capture";
    const auto sim = test::RunCommand(kCli + " simulate --model " + broken.string() +
                                      " --storey all --duration 2 -o " + capture.string());
    EXPECT_EQ(sim.exit_code, 2) << sim.err;
    EXPECT_NE(sim.out.find(reason), std::string::npos) << sim.out;
    EXPECT_NE(sim.err.find("1 storey(s) cannot be reached by the stairs"), std::string::npos)
        << sim.err;
    const auto manifest = nlohmann::json::parse(io::ReadFileToString(capture / "capture.json"));
    EXPECT_EQ(manifest["walk"]["storeys"], nlohmann::json::array({"Ground Floor"}));
    EXPECT_TRUE(fs::exists(capture / "ground_truth_storeys.csv"));
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam
