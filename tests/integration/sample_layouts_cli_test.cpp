// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The other sample buildings (`bimslam bim sample --layout hall|symmetric`) through the commands of
// Step 1 and the simulator as a user runs them: the option and its errors, `bim info`, `bim plan`
// (every storey planned, every viewpoint reached), `bim2session`, `simulate` for a Go1 and a
// handheld rig, and a start outside through the entrances. The odometry on the hall is in
// odometry_cli_test.cpp.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "algorithms/io/file_util.hpp"
#include "algorithms/io/session.hpp"
#include "algorithms/io/trajectory.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam {
namespace {
namespace BIMSLAM_UNITY_ID {
namespace fs = std::filesystem;

const std::string kCli = BIMSLAM_CLI_PATH;

// `bimslam bim sample --layout LAYOUT [extra] -o DIR/NAME`, which must succeed.
fs::path Sample(const test::TempDir& tmp, const std::string& layout,
                const std::string& extra = "") {
    const fs::path file = tmp / (layout + ".ifc");
    const auto r = test::RunCommand(kCli + " bim sample --layout " + layout + " " + extra + " -o " +
                                    file.string());
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return file;
}

// Runs a command that must succeed; the JSON it prints last, from the first line that opens it.
nlohmann::json Json(const std::string& command) {
    const auto r = test::RunCommand(command);
    EXPECT_EQ(r.exit_code, 0) << command << "\n" << r.err;
    if (r.exit_code != 0) return nullptr;
    size_t start = 0;
    while (start < r.out.size() && r.out[start] != '{' && r.out[start] != '[') {
        const size_t eol = r.out.find('\n', start);
        start = eol == std::string::npos ? r.out.size() : eol + 1;
    }
    return nlohmann::json::parse(r.out.substr(start));
}

TEST(SampleLayoutsCli, TheLayoutOptionWritesEachBuilding) {
    test::TempDir tmp;
    const auto help = test::RunCommand(kCli + " bim sample --help");
    EXPECT_EQ(help.exit_code, 0);
    for (const char* word :
         {"--layout", "office", "hall", "symmetric", "wing", "--exterior-doors"}) {
        EXPECT_NE(help.out.find(word), std::string::npos) << word << "\n" << help.out;
    }
    // The default is the office, byte for byte the same as --layout office.
    ASSERT_EQ(test::RunCommand(kCli + " bim sample -o " + (tmp / "default.ifc").string()).exit_code,
              0);
    EXPECT_EQ(io::ReadFileToString(tmp / "default.ifc"),
              io::ReadFileToString(Sample(tmp, "office")));

    const std::map<std::string, size_t> storeys = {
        {"office", 2}, {"hall", 3}, {"symmetric", 1}, {"wing", 2}};
    for (const auto& [layout, n] : storeys) {
        SCOPED_TRACE(layout);
        const fs::path file = tmp / (layout + "_mm.ifc");
        const auto r = test::RunCommand(kCli + " bim sample --layout " + layout +
                                        " --unit mm --exterior-doors -o " + file.string());
        ASSERT_EQ(r.exit_code, 0) << r.err;
        EXPECT_NE(r.out.find("(layout " + layout + ")"), std::string::npos) << r.out;
        const nlohmann::json info = Json(kCli + " bim info " + file.string() + " --json");
        ASSERT_TRUE(info.is_object());
        EXPECT_EQ(info.at("storeys").size(), n);
        EXPECT_EQ(info.at("length_unit_m").get<double>(), 0.001);
        EXPECT_TRUE(info.at("failed").empty()) << info.at("failed");
        EXPECT_GT(info.at("elements").at("IfcDoor").get<int>(), 5);
    }

    const auto bad =
        test::RunCommand(kCli + " bim sample --layout attic -o " + (tmp / "attic.ifc").string());
    EXPECT_EQ(bad.exit_code, 2);
    EXPECT_NE(bad.err.find("--layout"), std::string::npos) << bad.err;
    EXPECT_FALSE(fs::exists(tmp / "attic.ifc"));
}

TEST(SampleLayoutsCli, PlanCoversEveryStoreyOfTheHallAndTheSymmetricBuilding) {
    test::TempDir tmp;
    for (const std::string layout : {"hall", "symmetric"}) {
        SCOPED_TRACE(layout);
        const fs::path model = Sample(tmp, layout);
        const fs::path dir = tmp / ("plan_" + layout);
        const nlohmann::json plan =
            Json(kCli + " bim plan " + model.string() + " -o " + dir.string() + " --json");
        ASSERT_TRUE(plan.is_array());
        ASSERT_EQ(plan.size(), layout == "hall" ? 3u : 1u);
        for (const auto& storey : plan) {
            EXPECT_EQ(storey.at("unreachable_viewpoints"), 0) << storey;
            EXPECT_GE(storey.at("rooms").get<int>(), 8) << storey;
            EXPECT_GT(storey.at("walk_m").get<double>(), 60.0) << storey;
            EXPECT_GE(storey.at("min_clearance_m").get<double>(), 0.25) << storey;
            const std::string files = storey.at("files");
            EXPECT_GT(io::ReadTum(files + "_path.tum").size(), 500u);
            EXPECT_TRUE(fs::exists(files + ".pgm"));
        }
    }
}

TEST(SampleLayoutsCli, Bim2SessionOfTheHallsTopStorey) {
    test::TempDir tmp;
    const fs::path model = Sample(tmp, "hall");
    const fs::path session = tmp / "ref";
    const nlohmann::json j =
        Json(kCli + " bim2session " + model.string() + " -o " + session.string() +
             " --storey 'Second Floor' --keyframe-gap 4 --json");
    ASSERT_TRUE(j.is_object());
    const io::Session s = io::ReadSession(session, {.load_clouds = false});
    ASSERT_TRUE(s.complete);
    ASSERT_TRUE(s.manifest.model.has_value());
    EXPECT_EQ(s.manifest.model->storeys, std::vector<std::string>{"Second Floor"});
    EXPECT_GT(s.keyframes.size(), 30u);
    EXPECT_EQ(j.at("keyframes").get<size_t>(), s.keyframes.size());
    // The keyframes stand on the second floor: sensor 0.6 m above its elevation, 7 m.
    for (const auto& kf : s.keyframes) EXPECT_NEAR(kf.T_world_lidar.translation().z(), 7.6, 0.05);
}

TEST(SampleLayoutsCli, SimulatesAGo1AndAHandheldRig) {
    test::TempDir tmp;
    const fs::path hall = Sample(tmp, "hall"), symmetric = Sample(tmp, "symmetric");
    struct Case {
        fs::path model;
        std::string args;
        double floor_z;
    };
    const Case cases[] = {{hall, "--platform handheld --storey 'First Floor'", 3.5},
                          {hall, "--platform go1 --storey 'Second Floor'", 7.0},
                          {symmetric, "--platform go1", 0.0},
                          {symmetric, "--platform handheld", 0.0}};
    int k = 0;
    for (const Case& c : cases) {
        SCOPED_TRACE(c.model.string() + " " + c.args);
        const fs::path cap = tmp / ("capture" + std::to_string(k++));
        const auto r = test::RunCommand(kCli + " simulate --model " + c.model.string() + " " +
                                        c.args + " --duration 4 -o " + cap.string());
        ASSERT_EQ(r.exit_code, 0) << r.err;
        const auto truth = io::ReadTum(cap / "ground_truth.tum");
        ASSERT_EQ(truth.size(), 40u);
        for (const auto& p : truth) {
            EXPECT_GT(p.translation.z(), c.floor_z + 0.3);
            EXPECT_LT(p.translation.z(), c.floor_z + 1.6);
        }
        const nlohmann::json info =
            Json(kCli + " ouster info " + (cap / "lidar.pcap").string() + " --json");
        ASSERT_TRUE(info.is_object());
        EXPECT_EQ(info.at("frames_complete"), 40);
        EXPECT_EQ(fs::exists(cap / "go1_can.log"), c.args.find("go1") != std::string::npos);
    }
}

// From outside, through the entrances, into the coverage walk; without them the start is refused.
TEST(SampleLayoutsCli, StartsOutsideThroughTheEntrance) {
    test::TempDir tmp;
    const std::string scenarios =
        std::string(BIMSLAM_SOURCE_ROOT) + "/host_tools/simulate/scenarios/";
    struct Case {
        std::string layout, scenario;
        int axis;  // the start is 5 m outside along this axis, at coordinate -5
    };
    for (const Case& c :
         {Case{"hall", "hall_outdoor_start.yaml", 1}, Case{"symmetric", "outdoor_start.yaml", 0}}) {
        SCOPED_TRACE(c.layout);
        const fs::path open = Sample(tmp, c.layout, "--exterior-doors");
        const fs::path cap = tmp / ("outdoor_" + c.layout);
        const auto r =
            test::RunCommand(kCli + " simulate --model " + open.string() + " --scenario " +
                             scenarios + c.scenario + " --duration 25 -o " + cap.string());
        ASSERT_EQ(r.exit_code, 0) << r.err;
        const auto truth = io::ReadTum(cap / "ground_truth.tum");
        ASSERT_FALSE(truth.empty());
        EXPECT_LT(truth.front().translation[c.axis], -4.0);  // outdoors at first
        EXPECT_GT(truth.back().translation[c.axis], 1.0);    // inside after 25 s

        const fs::path closed = tmp / (c.layout + "_closed.ifc");
        ASSERT_EQ(
            test::RunCommand(kCli + " bim sample --layout " + c.layout + " -o " + closed.string())
                .exit_code,
            0);
        const auto refused = test::RunCommand(kCli + " simulate --model " + closed.string() +
                                              " --scenario " + scenarios + c.scenario +
                                              " --duration 5 -o " + (tmp / "refused").string());
        EXPECT_EQ(refused.exit_code, 2);
        EXPECT_NE(refused.err.find("--exterior-doors"), std::string::npos) << refused.err;
    }
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam
