// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The capture scenario: defaults, validation, and its YAML form (strict reading, round trip).
#include "host_tools/simulate/scenario.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "algorithms/common/status.hpp"
#include "host_tools/simulate/scenario_yaml.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::simulate {
namespace {
namespace BIMSLAM_UNITY_ID {
namespace fs = std::filesystem;
using common::FileError;
using common::StatusCode;

fs::path SourceDir() {
    const char* env = std::getenv("BIMSLAM_SOURCE_DIR");  // set by ctest
    return env && *env ? fs::path(env) : fs::path(BIMSLAM_DEFAULT_SOURCE_DIR);
}

Scenario Parse(const std::string& text) { return ParseScenario("test.yaml", text, {}); }

// The FileError that parsing `text` throws (fails the test when it parses).
FileError ParseError(const std::string& text) {
    try {
        Parse(text);
    } catch (const FileError& e) {
        return e;
    }
    ADD_FAILURE() << "no error for:\n" << text;
    return FileError(StatusCode::kOk, "", 0, "");
}

void WriteText(const fs::path& path, const std::string& text) {
    fs::create_directories(path.parent_path());
    std::ofstream(path) << text;
}

TEST(ScenarioTest, ShippedScenariosLoadAndValidate) {
    const fs::path dir = SourceDir() / "host_tools" / "simulate" / "scenarios";
    ASSERT_TRUE(fs::is_directory(dir)) << dir;
    int count = 0;
    for (const auto& entry : fs::directory_iterator(dir)) {
        if (entry.path().extension() != ".yaml") continue;
        SCOPED_TRACE(entry.path().string());
        try {
            const Scenario s = LoadScenario(entry.path());
            s.Validate();
            // Shared scenarios never carry a machine's absolute model path.
            EXPECT_TRUE(s.model.empty()) << s.model;
        } catch (const std::exception& e) {
            ADD_FAILURE() << e.what();
        }
        ++count;
    }
    EXPECT_GE(count, 4);
}

TEST(ScenarioTest, ReferenceFileSpellsOutTheDefaults) {
    const fs::path file = SourceDir() / "host_tools/simulate/scenarios/go1_coverage.yaml";
    EXPECT_EQ(LoadScenario(file), DefaultScenario(Platform::kGo1));
}

TEST(ScenarioTest, EmptyTextGivesGo1Defaults) {
    EXPECT_EQ(Parse(""), DefaultScenario(Platform::kGo1));
    EXPECT_EQ(Parse("# only a comment\n"), DefaultScenario());
    EXPECT_EQ(DefaultScenario(Platform::kGo1), Scenario{});
    EXPECT_NO_THROW(Scenario{}.Validate());
}

TEST(ScenarioTest, PlatformPicksItsDefaults) {
    const Scenario h = Parse("platform: handheld\n");
    EXPECT_EQ(h, DefaultScenario(Platform::kHandheld));
    EXPECT_EQ(h.platform, Platform::kHandheld);
    EXPECT_DOUBLE_EQ(h.speed.speed_mps, 1.0);
    EXPECT_DOUBLE_EQ(h.speed.max_yaw_rate_deg_s, 90.0);
    EXPECT_EQ(h.sensor.mount_xyz, Eigen::Vector3d(0, 0, 0.1));
    EXPECT_NO_THROW(h.Validate());
    // Keys overlay the platform's defaults wherever `platform` stands in the file.
    const Scenario h2 = Parse("speed: {speed_mps: 1.5}\nplatform: handheld\n");
    EXPECT_DOUBLE_EQ(h2.speed.speed_mps, 1.5);
    EXPECT_DOUBLE_EQ(h2.speed.max_yaw_rate_deg_s, 90.0);
    // A vehicle drives at 3 m/s with the sensor on its roof, and only waypoints.
    const Scenario v = Parse("platform: vehicle\npath: {mode: waypoints, waypoints: [[0, -5]]}\n");
    EXPECT_EQ(v.platform, Platform::kVehicle);
    EXPECT_DOUBLE_EQ(v.speed.speed_mps, 3.0);
    EXPECT_EQ(v.sensor.mount_xyz, Eigen::Vector3d(0, 0, 0.2));
    EXPECT_NO_THROW(v.Validate());
    EXPECT_THROW(Parse("platform: vehicle\npath: {mode: coverage}\n").Validate(), common::Error);
}

TEST(ScenarioTest, NamesRoundTrip) {
    for (const Platform p : {Platform::kGo1, Platform::kHandheld, Platform::kVehicle}) {
        EXPECT_EQ(PlatformFromString(ToString(p)), p);
    }
    for (const PathMode m : {PathMode::kCoverage, PathMode::kWaypoints}) {
        EXPECT_EQ(PathModeFromString(ToString(m)), m);
    }
    EXPECT_EQ(ToString(Platform::kGo1), "go1");
    EXPECT_EQ(ToString(PathMode::kWaypoints), "waypoints");
    EXPECT_FALSE(PlatformFromString("Go1"));
}

TEST(ScenarioTest, UnknownKeyAtEveryLevelNamesItsPath) {
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"speeed: 1\n", "unknown key 'speeed'"},
        {"speed: {sped_mps: 1}\n", "unknown key 'speed.sped_mps'"},
        {"path: {start: {yaw: 1}}\n", "unknown key 'path.start.yaw'"},
        {"noise: {lidar: {sigma: 1}}\n", "unknown key 'noise.lidar.sigma'"},
        {"edits: {boxes: [{name: a}, {sise: [1, 1, 1]}]}\n", "unknown key 'edits.boxes[1].sise'"},
        {"edits: {clutter: {density: 1}}\n", "unknown key 'edits.clutter.density'"},
        {"edits: {as_built: {walls: [{global_id: a, offset: 1}]}}\n",
         "unknown key 'edits.as_built.walls[0].offset'"},
        {"edits: {people: [{from: [0, 0], to: [1, 1], speed: 1}]}\n",
         "unknown key 'edits.people[0].speed'"},
    };
    for (const auto& [text, expected] : cases) {
        const FileError e = ParseError(text);
        EXPECT_EQ(e.path(), "test.yaml");
        EXPECT_EQ(e.line(), 1u) << e.what();
        EXPECT_NE(e.detail().find(expected), std::string::npos) << e.what();
        EXPECT_NE(e.detail().find("allowed"), std::string::npos) << e.what();
    }
    // The allowed keys of that level are listed.
    EXPECT_NE(
        ParseError("edits: {boxes: [{sise: 1}]}").detail().find("name, center, size, yaw_deg"),
        std::string::npos);
    EXPECT_NE(ParseError("speed:\n  speed_mps: 1\n  speed_mps: 2\n")
                  .detail()
                  .find("duplicate key 'speed.speed_mps'"),
              std::string::npos);
}

TEST(ScenarioTest, WrongValueNamesTheField) {
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"speed: {speed_mps: -1}", "speed.speed_mps = -1: must be > 0"},
        {"speed: {speed_mps: 50}", "speed.speed_mps = 50"},
        {"speed: {speed_mps: fast}", "speed.speed_mps: expected a number, got 'fast'"},
        {"speed: {speed_mps: [1]}", "speed.speed_mps: expected a number, got a sequence"},
        {"sensor: {lidar_mode: 999x10}", "sensor.lidar_mode = '999x10': must be one of"},
        {"sensor: {udp_profile: FOO}", "sensor.udp_profile = 'FOO'"},
        {"sensor: {model: OS3-64}", "sensor.model = 'OS3-64': must be one of"},
        {"sensor: {mount_xyz: [1, 2]}",
         "sensor.mount_xyz: expected [x, y, z], got a sequence of 2"},
        {"sensor: {mount_xyz: [0, 0, x]}", "sensor.mount_xyz[2]: expected a number, got 'x'"},
        {"sensor: {clock_jump_s: 30}", "sensor.clock_jump_at_s = 0"},
        {"sensor: {clock_jump_at_s: 5, clock_jump_s: 1e9}", "sensor.clock_jump_s = "},
        {"network: {packet_loss: 1.5}", "network.packet_loss = 1.5: must be in [0, 1)"},
        {"network: {fragment: maybe}", "network.fragment: expected true or false, got 'maybe'"},
        {"network: {go1_highstate_crc: encrypted}",
         "network.go1_highstate_crc: expected scrambled or plain, got 'encrypted'"},
        {"noise: {lidar: {dropout: .nan}}", "noise.lidar.dropout = nan"},
        {"noise: {imu: {gyro_sigma_deg_s: -0.1}}", "noise.imu.gyro_sigma_deg_s = -0.1"},
        {"platform: dog", "platform: expected go1 or handheld, got 'dog'"},
        {"path: {mode: spiral}", "path.mode: expected coverage or waypoints, got 'spiral'"},
        {"path: {mode: waypoints}", "path.waypoints = []: mode waypoints needs at least 1"},
        {"path: {waypoints: [[1, 2]]}",
         "path.waypoints = 1 points: must be empty with mode coverage"},
        {"path: {mode: waypoints, waypoints: [[1, 2, 3]]}", "path.waypoints[0]: expected [x, y]"},
        {"path: {start: {xy: [1, .inf]}}", "path.start.xy = [1, inf]: must be finite"},
        {"duration_s: -1", "duration_s = -1: must be >= 0"},
        {"seed: -3", "seed: expected a whole number >= 0, got '-3'"},
        {"date: 2026-02-30", "date = '2026-02-30': not an ISO 8601 date-time (no such day"},
        {"date: yesterday", "date = 'yesterday': not an ISO 8601 date-time"},
        {"edits: {boxes: [{}, {size: [1, 0, 1]}]}", "edits.boxes[1].size = [1, 0, 1]"},
        {"edits: {cylinders: [{radius_m: 0}]}", "edits.cylinders[0].radius_m = 0: must be > 0"},
        {"edits: {meshes: [{name: chair}]}", "edits.meshes[0].file = '': must not be empty"},
        {"edits: {clutter: {min_size_m: 1, max_size_m: 0.5}}", "edits.clutter.max_size_m = 0.5"},
        {"edits: {removed: {global_ids: ['']}}", "edits.removed.global_ids[0] = ''"},
        {"edits: {removed: {classes: [Door]}}", "edits.removed.classes[0] = 'Door'"},
        {"edits: {moved: [{translation: [1, 0, 0]}]}", "edits.moved[0].global_id = ''"},
        {"edits: {as_built: {wall_offset_sigma_m: -0.1}}", "edits.as_built.wall_offset_sigma_m"},
        {"edits: {people: [{from: [1, 1], to: [1, 1]}]}",
         "edits.people[0].to = [1, 1]: must differ"},
        {"edits: {boxes: {name: a}}", "edits.boxes: expected a sequence, got a mapping"},
        {"edits: {glass: yes please}", "edits.glass: expected true or false, got 'yes please'"},
        {"edits: {mirrors: [{size: [1, -1]}]}",
         "edits.mirrors[0].size = [1, -1]: must be > 0 and <= 20 m in each axis"},
        {"edits: {mirrors: [{center: [1, 2]}]}", "edits.mirrors[0].center: expected [x, y, z]"},
        {"edits: {mirrors: [{colour: silver}]}", "unknown key 'edits.mirrors[0].colour'"},
        {"edits: {moving_doors: {period_s: 0}}",
         "edits.moving_doors.period_s = 0: must be > 0 and <= 3600"},
        {"edits: {moving_doors: {max_angle_deg: 270}}",
         "edits.moving_doors.max_angle_deg = 270: must be in [0, 180]"},
        {"edits: {moving_doors: {classes: [Door]}}", "edits.moving_doors.classes[0] = 'Door'"},
        {"edits: {moving_doors: {speed: 1}}", "unknown key 'edits.moving_doors.speed'"},
        {"noise: {lidar: {glass_return_probability: 2}}",
         "noise.lidar.glass_return_probability = 2: must be in [0, 1]"},
        {"noise: {lidar: {glass_return_exponent: -1}}", "noise.lidar.glass_return_exponent = -1"},
        {"speed: 1", "speed: expected a mapping, got '1'"},
        {"[1, 2]", "the top level: expected a mapping"},
    };
    for (const auto& [text, expected] : cases) {
        const FileError e = ParseError(text);
        EXPECT_EQ(e.path(), "test.yaml");
        EXPECT_NE(e.detail().find(expected), std::string::npos)
            << "text: " << text << "\nexpected: " << expected << "\ngot: " << e.what();
    }
    // Validation errors are invalid arguments, pointing at the line of their key.
    const FileError e = ParseError("seed: 2\nspeed:\n  speed_mps: -1\n");
    EXPECT_EQ(e.code(), StatusCode::kInvalidArgument);
    EXPECT_EQ(e.line(), 3u) << e.what();
    EXPECT_EQ(std::string(e.what()), "test.yaml:3: speed.speed_mps = -1: must be > 0 and <= 5");
}

TEST(ScenarioTest, RelativePathsResolveAgainstTheFilesFolder) {
    test::TempDir tmp;
    const fs::path file = tmp / "site/scenario.yaml";
    WriteText(file,
              "model: building.ifc\n"
              "sensor: {metadata: ../sensors/os1.json}\n"
              "edits:\n"
              "  meshes:\n"
              "    - {file: parts/chair.ply}\n"
              "    - {file: /abs/table.obj}\n");
    const Scenario s = LoadScenario(file);
    const fs::path dir = fs::absolute(tmp.path()).lexically_normal();
    EXPECT_EQ(s.model, dir / "site/building.ifc");
    EXPECT_EQ(s.sensor.metadata, dir / "sensors/os1.json");
    ASSERT_EQ(s.edits.meshes.size(), 2u);
    EXPECT_EQ(s.edits.meshes[0].file, dir / "site/parts/chair.ply");
    EXPECT_EQ(s.edits.meshes[1].file, fs::path("/abs/table.obj"));
    // An empty metadata stays empty (the built-in sensor), and without a base folder paths stay
    // as written.
    EXPECT_TRUE(Parse("sensor: {metadata: ''}").sensor.metadata.empty());
    EXPECT_EQ(Parse("model: a/b.ifc").model, fs::path("a/b.ifc"));
}

TEST(ScenarioTest, FileErrorsNameTheFile) {
    test::TempDir tmp;
    const fs::path missing = tmp / "nope.yaml";
    try {
        LoadScenario(missing);
        ADD_FAILURE() << "no error";
    } catch (const FileError& e) {
        EXPECT_EQ(e.path(), missing.string());
        EXPECT_EQ(e.code(), StatusCode::kNotFound);
    }
    const fs::path bad = tmp / "bad.yaml";
    WriteText(bad, "seed: 1\nspeed:\n  speed_mps: 0.5\n  max_accel_mps2: [1, 2\nduration_s: 3\n");
    // yaml-cpp notices the unclosed [ where the next key starts.
    EXPECT_FILE_ERROR(LoadScenario(bad), bad.string(), 5);
    const fs::path invalid = tmp / "invalid.yaml";
    WriteText(invalid, "network:\n  packet_loss: 1.5\n");
    EXPECT_FILE_ERROR(LoadScenario(invalid), invalid.string(), 2);
}

TEST(ScenarioTest, SyntaxErrorNamesLineAndColumn) {
    const FileError e = ParseError("seed: 1\nspeed: {speed_mps: 1\n");
    EXPECT_EQ(e.code(), StatusCode::kParseError);
    EXPECT_GT(e.line(), 0u) << e.what();
    EXPECT_NE(e.detail().find("YAML syntax error, column"), std::string::npos) << e.what();
    const FileError tab = ParseError("speed:\n  speed_mps: 1\n\tmax_accel_mps2: 1\n");
    EXPECT_EQ(tab.line(), 3u) << tab.what();
}

// A scenario with every list non-empty and every number off its default.
Scenario Everything() {
    Scenario s = DefaultScenario(Platform::kHandheld);
    s.model = "/data/building.ifc";
    s.storey = "Ground Floor";
    s.path.mode = PathMode::kWaypoints;
    s.path.waypoints = {{1.5, 7.2}, {0.1, -3e-7}};
    s.path.start = Pose2d{{-5, 7.5}, 12.25};
    s.date = "2026-03-02T09:30:00+01:00";
    s.speed = {0.7, 0.4, 45, 0.3, true};
    s.duration_s = 600.5;
    s.sensor.metadata = "/data/os1 metadata.json";
    s.sensor.model = "OS0-128";
    s.sensor.lidar_mode = "2048x10";
    s.sensor.udp_profile = "LEGACY";
    s.sensor.mount_xyz = {0.1, -0.02, 0.3};
    s.sensor.mount_rpy_deg = {1, -2, 180};
    s.sensor.body_in_view = true;
    s.sensor.clock_jump_at_s = 12.5;
    s.sensor.clock_jump_s = -7.25;
    s.network = {false, 0.01, go1::CrcForm::kPlain};
    s.noise.lidar = {0.02, 0.005, 120, 0.35, 12.5};
    s.noise.imu = {0.03, 0.06, 0.07, 0.3};
    s.noise.odometry = {-0.05, 0.03, -1.5, 0.5, 0.2, 0.1};
    s.seed = 18446744073709551615ull;
    s.edits.boxes = {{"null", {1, 2, 0.5}, {0.4, 0.5, 1}, 30}, {"1.5", {0, 0, 0}, {1, 1, 1}, -10}};
    s.edits.cylinders = {{"a: b # c", {3, 4, 0}, 0.2, 0.9}};
    s.edits.meshes = {{"yes", "/meshes/chair.ply", {5, 6, 0}, 90, 1.1}};
    s.edits.clutter = {0.05, 0.1, 0.5, 0.8};
    s.edits.removed = {{"0hP2cR9XZj33YcIT2ke3qV", "'quoted'"}, {"IfcColumn", "IfcDoor"}};
    s.edits.moved = {{"1dCh950b31l0h0po1ldorf", {0.5, -0.3, 0}, 15}};
    s.edits.as_built = {0.02, {{"0EF31bAGn7cY_UpbsCA2np", 0.03}, {"$x", -0.01}}};
    s.edits.people = {{{2, 6.8}, {26, 6.8}, 1.3, 0.22, 1.65}};
    s.edits.glass = true;
    s.edits.mirrors = {{"hall mirror", {4, 3.4, 1.2}, {0.8, 1.6}, -90}, {"", {1, 2, 3}, {1, 1}, 0}};
    s.edits.moving_doors = {{"2O2Fr$t4X7Zf8NOew3FLOH"}, {"IfcDoor"}, 6.5, 75};
    return s;
}

TEST(ScenarioTest, YamlRoundTrips) {
    const Scenario s = Everything();
    ASSERT_NO_THROW(s.Validate());
    const std::string yaml = ScenarioToYaml(s);
    // Absolute paths stay as they are wherever the text is read.
    EXPECT_EQ(ParseScenario("rt.yaml", yaml, "/elsewhere"), s) << yaml;
    for (const Platform p : {Platform::kGo1, Platform::kHandheld, Platform::kVehicle}) {
        Scenario d = DefaultScenario(p);
        if (p == Platform::kVehicle) d.path.waypoints = {{-5, 2}, {40, 2}};  // it has no default
        EXPECT_EQ(Parse(ScenarioToYaml(d)), d);
    }
    // Removing the start is written too (no `start` key).
    Scenario no_start = s;
    no_start.path.start.reset();
    EXPECT_EQ(Parse(ScenarioToYaml(no_start)), no_start);
}

// Issue 33, item 7: visits. Each inherits the top level's keys it does not set; `path` and `edits`
// replace the top level's as a whole; a visit's edits open removed elements to the walk.
constexpr const char* kTwoVisits = R"(platform: handheld
seed: 5
duration_s: 30
sensor: {model: OS1-16}
path: {mode: waypoints, waypoints: [[1, 1], [2, 2]]}
edits:
  boxes: [{name: crate, center: [1, 2, 0.5]}]
visits:
  - label: spring
    date: "2026-04-01T08:00:00Z"
  - label: winter
    date: "2026-01-01T08:00:00Z"
    platform: go1
    seed: 9
    duration_s: 12
    storey: Ground
    path: {mode: coverage}
    edits:
      removed: {global_ids: [w1]}
      boxes: [{name: crate, center: [3, 2, 0.5], yaw_deg: 10}]
)";

TEST(ScenarioVisits, EachVisitIsTheTopLevelWithItsOwnKeys) {
    const Scenario s = Parse(kTwoVisits);
    ASSERT_EQ(s.visits.size(), 2u);
    const Scenario spring = VisitScenario(s, 0);
    EXPECT_TRUE(spring.visits.empty());
    EXPECT_EQ(spring.date, "2026-04-01T08:00:00Z");
    EXPECT_EQ(spring.platform, Platform::kHandheld);
    EXPECT_EQ(spring.seed, 5u);
    EXPECT_EQ(spring.duration_s, 30);
    EXPECT_EQ(spring.path, s.path);
    EXPECT_EQ(spring.edits, s.edits);
    EXPECT_FALSE(spring.edits.removed.walk_through);  // the top level's default

    const Scenario winter = VisitScenario(s, 1);
    EXPECT_EQ(winter.date, "2026-01-01T08:00:00Z");
    EXPECT_EQ(winter.platform, Platform::kGo1);
    EXPECT_EQ(winter.seed, 9u);
    EXPECT_EQ(winter.duration_s, 12);
    EXPECT_EQ(winter.storey, "Ground");
    EXPECT_EQ(winter.path.mode, PathMode::kCoverage);
    EXPECT_TRUE(winter.path.waypoints.empty());
    EXPECT_EQ(winter.sensor.model, "OS1-16");  // not a visit's key: the top level's
    // Another platform takes its speed and mount: a Go1 trots at 0.5 m/s, the sensor on its back.
    EXPECT_EQ(winter.speed, DefaultScenario(Platform::kGo1).speed);
    EXPECT_EQ(winter.sensor.mount_xyz, DefaultScenario(Platform::kGo1).sensor.mount_xyz);
    // Its edits replace the top level's as a whole, relative to the model.
    ASSERT_EQ(winter.edits.boxes.size(), 1u);
    EXPECT_EQ(winter.edits.boxes[0].center, Eigen::Vector3d(3, 2, 0.5));
    EXPECT_EQ(winter.edits.removed.global_ids, std::vector<std::string>{"w1"});
    EXPECT_TRUE(winter.edits.removed.walk_through);  // a visit's default

    EXPECT_EQ(FindVisit(s, "winter"), 1u);
    try {
        FindVisit(s, "summer");
        ADD_FAILURE() << "no error";
    } catch (const common::Error& e) {
        EXPECT_NE(std::string(e.what()).find("(the scenario's: spring, winter)"), std::string::npos)
            << e.what();
    }
}

TEST(ScenarioVisits, RoundTripThroughYaml) {
    Scenario s = Parse(kTwoVisits);
    s.visits[1].edits->removed.walk_through = false;  // written, since a visit's default is on
    EXPECT_EQ(Parse(ScenarioToYaml(s)), s) << ScenarioToYaml(s);
    // A visit's own scenario is a plain one (no visits) and reads back equal too.
    const Scenario winter = VisitScenario(Parse(kTwoVisits), 1);
    EXPECT_EQ(Parse(ScenarioToYaml(winter)), winter) << ScenarioToYaml(winter);
    // Without visits and with walk_through off, nothing new is written: a capture's scenario.yaml
    // stays as it was before visits.
    const std::string plain = ScenarioToYaml(Scenario{});
    EXPECT_EQ(plain.find("visits"), std::string::npos);
    EXPECT_EQ(plain.find("walk_through"), std::string::npos);
}

TEST(ScenarioVisits, ErrorsNameTheVisitsKeyAndLine) {
    const std::string head = "visits:\n  - label: a\n    date: \"2026-01-01T00:00:00Z\"\n";
    struct Case {
        std::string text, expected;
        size_t line;
    };
    const std::vector<Case> cases = {
        {head + "    colour: red\n", "unknown key 'visits[0].colour'", 4},
        {head + "    edits:\n      boxes:\n        - {name: b, sise: [1, 1, 1]}\n",
         "unknown key 'visits[0].edits.boxes[0].sise'", 6},
        {head + "    path: {mode: coverage, start: {yaw: 1}}\n",
         "unknown key 'visits[0].path.start.yaw'", 4},
        {head + "    seed: x\n", "visits[0].seed: expected a whole number", 4},
        {head + "    duration_s: -1\n", "visits[0].duration_s = -1: must be >= 0", 4},
        {head + "    edits: {boxes: [{name: b, size: [1, 0, 1]}]}\n",
         "visits[0].edits.boxes[0].size = [1, 0, 1]", 4},
        {head + "  - label: a\n    date: \"2026-02-01T00:00:00Z\"\n",
         "visits[1].label = 'a': the label of visits[0] too", 4},
        {head + "  - label: ../up\n    date: \"2026-02-01T00:00:00Z\"\n",
         "visits[1].label = '../up': must be a folder name", 4},
        {head + "  - label: b\n", "visits[1].date = '': every visit needs its date", 4},
        {head + "  - {label: b, date: yesterday}\n", "visits[1].date = ", 4},
        {head + "    edits: {boxes: [{name: b}, {name: b}]}\n",
         "visits[0].edits.boxes[1].name = 'b': another object of the visit has this name", 4},
        {head + "    edits: {cylinders: [{base: [0, 0, 0]}]}\n",
         "visits[0].edits.cylinders[0].name = '': a visit's objects are matched", 4},
        {"visits: {label: a}\n", "visits: expected a sequence", 1},
        {"visits: [a]\n", "visits[0]: expected a mapping", 1},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.text);
        const FileError e = ParseError(c.text);
        EXPECT_EQ(e.path(), "test.yaml");
        EXPECT_NE(e.detail().find(c.expected), std::string::npos) << e.what();
        EXPECT_EQ(e.line(), c.line) << e.what();
    }
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::simulate
