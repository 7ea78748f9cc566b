// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// `bimslam odometry` as a user runs it: a simulated capture (Go1 with its CAN log, handheld
// without) replayed into a session, its trajectory checked with `bimslam evaluate` against the
// capture's ground truth, the session read back by `bimslam session info`; the same in the hall,
// the second sample building; bad input exits 2 naming the file.
//
// The accuracy bounds are regression bounds, well above what is measured (about 1 cm and 0.1 deg
// on these short walks); the measured figures are printed and recorded as test properties.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>
#include <tuple>

#include "algorithms/io/file_util.hpp"
#include "algorithms/io/trajectory.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam {
namespace {
namespace BIMSLAM_UNITY_ID {
namespace fs = std::filesystem;

const std::string kCli = BIMSLAM_CLI_PATH;
constexpr int kCaptureSeconds = 20;
// The accuracy tests count the budget in CPU time (--budget-cpu): their bounds are about twice
// the measured error, and scans cut short by other processes' load would be another run. A scan
// can still run over it (caches, memory bandwidth shared with the other test): RunOdometry.
const std::string kBudget = " --budget-cpu";

// The sample buildings and the captures simulated in them, made once per test process (ctest runs
// every test in a process of its own, so only what a test asks for is simulated).
class OdometryCli : public ::testing::Test {
protected:
    static void SetUpTestSuite() { tmp_ = std::make_unique<test::TempDir>(); }
    static void TearDownTestSuite() { tmp_.reset(); }

    static const test::TempDir& Tmp() { return *tmp_; }

    static fs::path Model() {
        const fs::path file = Tmp() / "building.ifc";
        if (!fs::exists(file)) {
            const auto r = test::RunCommand(kCli + " bim sample -o " + file.string());
            EXPECT_EQ(r.exit_code, 0) << r.err;
        }
        return file;
    }

    // The hall, the project's second building (`bim sample --layout hall`).
    static fs::path HallModel() {
        const fs::path file = Tmp() / "hall.ifc";
        if (!fs::exists(file)) {
            const auto r = test::RunCommand(kCli + " bim sample --layout hall -o " + file.string());
            EXPECT_EQ(r.exit_code, 0) << r.err;
        }
        return file;
    }

    // A capture of the default walk, `kCaptureSeconds` long.
    static fs::path Capture(const std::string& platform) {
        return Simulate(Model(), platform, Tmp() / ("capture_" + platform));
    }
    // The same in the hall (its ground floor).
    static fs::path HallCapture(const std::string& platform) {
        return Simulate(HallModel(), platform, Tmp() / ("hall_capture_" + platform));
    }

    static fs::path Simulate(const fs::path& model, const std::string& platform,
                             const fs::path& dir, int seconds = kCaptureSeconds) {
        if (!fs::exists(dir / "ground_truth.tum")) {
            const auto r = test::RunCommand(
                kCli + " simulate --model " + model.string() + " --platform " + platform +
                " --duration " + std::to_string(seconds) + " -o " + dir.string() + " --overwrite");
            EXPECT_EQ(r.exit_code, 0) << r.err;
        }
        return dir;
    }

private:
    static std::unique_ptr<test::TempDir> tmp_;
};
std::unique_ptr<test::TempDir> OdometryCli::tmp_;

// Runs a command that must succeed and print JSON; the parsed JSON (null on failure).
nlohmann::json RunJson(const std::string& command) {
    const auto r = test::RunCommand(command);
    EXPECT_EQ(r.exit_code, 0) << command << "\n" << r.err;
    if (r.exit_code != 0) return nullptr;
    try {
        return nlohmann::json::parse(r.out);
    } catch (const nlohmann::json::exception& e) {
        ADD_FAILURE() << command << ": not JSON (" << e.what() << "):\n" << r.out;
        return nullptr;
    }
}

// `bimslam evaluate --json` of a session's trajectory against the capture's ground truth.
nlohmann::json Evaluate(const fs::path& session, const fs::path& capture) {
    return RunJson(kCli + " evaluate --est " + (session / "trajectory.tum").string() + " --ref " +
                   (capture / "ground_truth.tum").string() + " --json");
}

// Shows the measured figures in the log and in the test's XML properties.
void Report(const std::string& what, const nlohmann::json& odo, const nlohmann::json& eval) {
    const double ape_cm = 100.0 * eval.at("ape_trans_rmse_m").get<double>();
    const double rot_deg = eval.at("ape_rot_rmse_deg").get<double>();
    std::cout << what << ": " << odo.at("scans") << " scans, " << odo.at("keyframes")
              << " keyframes, APE trans rmse " << ape_cm << " cm (max "
              << 100.0 * eval.at("ape_trans_max_m").get<double>() << " cm), APE rot rmse "
              << rot_deg << " deg, RPE 1 m trans rmse "
              << 100.0 * eval.at("rpe_trans_rmse_m").get<double>() << " cm, drift "
              << eval.at("drift_percent") << " %, per scan p50 " << odo.at("scan_ms_p50")
              << " ms, p99 " << odo.at("scan_ms_p99") << " ms, max " << odo.at("scan_ms_max")
              << " ms\n";
    ::testing::Test::RecordProperty("ape_trans_rmse_cm", std::to_string(ape_cm));
    ::testing::Test::RecordProperty("ape_rot_rmse_deg", std::to_string(rot_deg));
    ::testing::Test::RecordProperty("scan_ms_p50",
                                    std::to_string(odo.at("scan_ms_p50").get<double>()));
}

// Scans of a --scans-csv file (a header, then a line a scan: scan,stamp_ns,flags,...): how many,
// and how many failed (too few correspondences, or their check) although the budget did not cut
// them short (lidar_odometry.hpp: kOverBudget 1 << 1, kRegistrationFailed 1 << 3, kCheckFailed
// 1 << 13).
struct ScanCounts {
    size_t scans = 0;
    size_t failed_within_budget = 0;
};
ScanCounts CountScans(const fs::path& csv) {
    const std::string text = io::ReadFileToString(csv);
    ScanCounts n;
    EXPECT_EQ(text.rfind("scan,stamp_ns,flags,", 0), 0u) << csv << ": not a --scans-csv file";
    size_t pos = text.find('\n');
    while (pos != std::string::npos && pos + 1 < text.size()) {
        const size_t end = text.find('\n', pos + 1);
        const std::string line = text.substr(pos + 1, end - pos - 1);
        const size_t a = line.find(','), b = line.find(',', a + 1), c = line.find(',', b + 1);
        const uint32_t flags = uint32_t(std::stoul(line.substr(b + 1, c - b - 1)));
        if ((flags & ((1u << 3) | (1u << 13))) && !(flags & (1u << 1))) ++n.failed_within_budget;
        ++n.scans;
        pos = end;
    }
    return n;
}

// `bimslam odometry --json` of a capture on the default budget (kBudget), every scan's flags
// written to SES_scans.csv; the JSON with "failed_within_budget" added. On a loaded machine (CI's
// two cores run two tests) a scan can still run over the 50 ms of CPU (CI saw an OS1-128 scan
// at 56.7 ms) and a scan the budget cut short may fail its registration check: the tests on the
// default budget assert that no scan that had its whole budget failed, and print the rest.
nlohmann::json RunOdometry(const fs::path& cap, const fs::path& ses, const std::string& flags) {
    const fs::path csv = ses.string() + "_scans.csv";
    nlohmann::json odo = RunJson(kCli + " odometry " + cap.string() + " -o " + ses.string() +
                                 flags + kBudget + " --json --scans-csv " + csv.string());
    if (!odo.is_object()) return odo;
    const ScanCounts n = CountScans(csv);
    EXPECT_EQ(n.scans, odo.at("scans").get<size_t>()) << csv << ": a line for every scan";
    odo["failed_within_budget"] = n.failed_within_budget;
    std::cout << "scans " << odo.at("scans") << ", over the budget " << odo.at("over_budget")
              << ", failed " << odo.at("failed") << " (" << n.failed_within_budget
              << " within the budget)\n";
    return odo;
}

// No scan that had its whole budget failed (RunOdometry).
void ExpectNoFailureWithinBudget(const nlohmann::json& odo) {
    EXPECT_EQ(odo.at("failed_within_budget").get<size_t>(), 0u)
        << odo.at("failed") << " failed, " << odo.at("over_budget") << " over the budget";
}

TEST_F(OdometryCli, Go1WithCanTracksTheGroundTruth) {
    const fs::path cap = Capture("go1");
    const size_t frames = io::ReadTum(cap / "ground_truth.tum").size();
    ASSERT_NEAR(double(frames), 10.0 * kCaptureSeconds, 5.0);  // 10 Hz
    const fs::path ses = Tmp() / "session_go1";
    const nlohmann::json odo = RunOdometry(cap, ses, "");
    ASSERT_TRUE(odo.is_object());
    EXPECT_TRUE(odo.at("used_can").get<bool>());
    EXPECT_GT(odo.at("body_samples").get<size_t>(), 0u);
    EXPECT_GT(odo.at("imu_samples").get<size_t>(), 0u);
    EXPECT_EQ(odo.at("scans").get<size_t>(), frames);
    EXPECT_GT(odo.at("keyframes").get<size_t>(), 3u);
    ExpectNoFailureWithinBudget(odo);
    EXPECT_TRUE(odo.at("notes").empty()) << odo.at("notes");
    EXPECT_GT(odo.at("distance_m").get<double>(), 1.0);
    EXPECT_NEAR(odo.at("capture_s").get<double>(), kCaptureSeconds, 0.5);
    for (const char* key : {"scan_ms_p50", "scan_ms_p99", "scan_ms_max", "scan_cpu_ms_p50",
                            "scan_cpu_ms_p99", "scan_cpu_ms_max", "wall_s"}) {
        EXPECT_GT(odo.at(key).get<double>(), 0.0) << key;
    }
    EXPECT_TRUE(fs::is_regular_file(ses / "session.json"));

    const nlohmann::json eval = Evaluate(ses, cap);
    ASSERT_TRUE(eval.is_object());
    Report("go1 with CAN", odo, eval);
    EXPECT_EQ(eval.at("matched"), odo.at("scans"));
    // About twice the measured 0.76-0.82 cm, 0.12-0.13 deg (seeds 1-3).
    EXPECT_LT(eval.at("ape_trans_rmse_m").get<double>(), 0.016);
    EXPECT_LT(eval.at("ape_rot_rmse_deg").get<double>(), 0.25);

    const nlohmann::json info = RunJson(kCli + " session info " + ses.string() + " --json");
    ASSERT_TRUE(info.is_object());
    EXPECT_EQ(info.at("keyframes"), odo.at("keyframes"));
    EXPECT_EQ(info.at("scans"), odo.at("scans"));
    EXPECT_TRUE(info.at("complete").get<bool>());
}

// Handheld captures have no CAN log; --no-can is how a Go1 capture is replayed without it too.
TEST_F(OdometryCli, HandheldWithoutCanTracksTheGroundTruth) {
    const fs::path cap = Capture("handheld");
    EXPECT_FALSE(fs::exists(cap / "go1_can.log"));
    const size_t frames = io::ReadTum(cap / "ground_truth.tum").size();
    const fs::path ses = Tmp() / "session_handheld";
    const nlohmann::json odo = RunOdometry(cap, ses, " --no-can");
    ASSERT_TRUE(odo.is_object());
    EXPECT_FALSE(odo.at("used_can").get<bool>());
    EXPECT_EQ(odo.at("body_samples").get<size_t>(), 0u);
    EXPECT_GT(odo.at("imu_samples").get<size_t>(), 0u);
    EXPECT_EQ(odo.at("scans").get<size_t>(), frames);
    EXPECT_GT(odo.at("keyframes").get<size_t>(), 3u);
    ExpectNoFailureWithinBudget(odo);

    const nlohmann::json eval = Evaluate(ses, cap);
    ASSERT_TRUE(eval.is_object());
    Report("handheld, --no-can", odo, eval);
    EXPECT_EQ(eval.at("matched"), odo.at("scans"));
    // About twice the measured 0.78-0.79 cm, 0.06-0.07 deg (seeds 1-3).
    EXPECT_LT(eval.at("ape_trans_rmse_m").get<double>(), 0.016);
    EXPECT_LT(eval.at("ape_rot_rmse_deg").get<double>(), 0.15);
}

// --edge-features (LOAM edges, off by default): the same capture, as accurate.
TEST_F(OdometryCli, Go1WithEdgeFeaturesTracksTheGroundTruth) {
    const fs::path cap = Capture("go1");
    const fs::path ses = Tmp() / "session_go1_edges";
    const nlohmann::json odo = RunOdometry(cap, ses, " --edge-features");
    ASSERT_TRUE(odo.is_object());
    ExpectNoFailureWithinBudget(odo);
    const nlohmann::json eval = Evaluate(ses, cap);
    ASSERT_TRUE(eval.is_object());
    Report("go1 with CAN, --edge-features", odo, eval);
    // About twice the measured 0.79 cm, 0.12 deg.
    EXPECT_LT(eval.at("ape_trans_rmse_m").get<double>(), 0.016);
    EXPECT_LT(eval.at("ape_rot_rmse_deg").get<double>(), 0.25);
}

// The hall: a building the odometry was not tuned on (other footprint, heights, walls, rooms,
// columns in a central hall). Bounds about twice the measured: Go1 0.61 cm, 0.09-0.10 deg;
// handheld 0.67-0.72 cm, 0.06-0.13 deg (seeds 1-3).
void ExpectTracksTheGroundTruth(const std::string& what, const fs::path& cap, const fs::path& ses,
                                bool go1) {
    const size_t frames = io::ReadTum(cap / "ground_truth.tum").size();
    ASSERT_NEAR(double(frames), 10.0 * kCaptureSeconds, 5.0);
    const nlohmann::json odo = RunOdometry(cap, ses, "");
    ASSERT_TRUE(odo.is_object());
    EXPECT_EQ(odo.at("used_can").get<bool>(), go1);
    EXPECT_EQ(odo.at("scans").get<size_t>(), frames);
    ExpectNoFailureWithinBudget(odo);
    EXPECT_GT(odo.at("keyframes").get<size_t>(), 3u);
    EXPECT_GT(odo.at("distance_m").get<double>(), 5.0);
    const nlohmann::json eval = Evaluate(ses, cap);
    ASSERT_TRUE(eval.is_object());
    Report(what, odo, eval);
    EXPECT_EQ(eval.at("matched"), odo.at("scans"));
    EXPECT_LT(eval.at("ape_trans_rmse_m").get<double>(), go1 ? 0.013 : 0.0145);
    EXPECT_LT(eval.at("ape_rot_rmse_deg").get<double>(), go1 ? 0.2 : 0.26);
}

TEST_F(OdometryCli, Go1TracksTheGroundTruthInTheHall) {
    ExpectTracksTheGroundTruth("hall, go1 with CAN", HallCapture("go1"), Tmp() / "hall_go1", true);
}

TEST_F(OdometryCli, HandheldTracksTheGroundTruthInTheHall) {
    ExpectTracksTheGroundTruth("hall, handheld", HallCapture("handheld"), Tmp() / "hall_handheld",
                               false);
}

// LiDAR only (issue 17, item 4), no budget so that the result does not depend on the machine's
// load. On a Go1 walk the trot rolls the body by 1.5 deg at 2 Hz, which a constant velocity
// neither predicts nor deskews. Before issue 17 the directions the registration found weak kept
// that prediction outright and the roll drifted: 64 cm / 27 deg on this minute (seed 1), 96 cm
// over three minutes. With the fusion 5.5-6.2 cm; with one-sided map planes 2.0 cm / 0.91 deg and
// with deskewing until it holds 1.26 cm / 0.77 deg; the hand-held minute 8.7 -> 3.8 -> 2.3 cm /
// 0.63 deg (algorithms/odometry/README.md, "One-sided planes", "Deskew until it holds"). Bounds
// about twice that.
void ExpectLidarOnly(const std::string& what, const fs::path& cap, const fs::path& ses,
                     double max_cm, double max_deg) {
    const nlohmann::json odo = RunJson(kCli + " odometry " + cap.string() + " -o " + ses.string() +
                                       " --no-imu --no-can --budget-ms 10000 --json");
    ASSERT_TRUE(odo.is_object());
    EXPECT_EQ(odo.at("imu_samples").get<size_t>(), 0u);
    EXPECT_EQ(odo.at("body_samples").get<size_t>(), 0u);
    EXPECT_EQ(odo.at("failed").get<size_t>(), 0u);
    const nlohmann::json eval = Evaluate(ses, cap);
    ASSERT_TRUE(eval.is_object());
    Report(what, odo, eval);
    EXPECT_LT(eval.at("ape_trans_rmse_m").get<double>(), max_cm / 100);
    EXPECT_LT(eval.at("ape_rot_rmse_deg").get<double>(), max_deg);
}

TEST_F(OdometryCli, Go1LidarOnlyHoldsTheTrotsWobble) {
    ExpectLidarOnly("go1, 60 s, --no-imu --no-can",
                    Simulate(Model(), "go1", Tmp() / "capture_go1_60s", 60),
                    Tmp() / "session_go1_lidar_only", 2.5, 1.5);
}

TEST_F(OdometryCli, HandheldLidarOnlyHoldsTheCarriersSway) {
    ExpectLidarOnly("handheld, 60 s, --no-imu",
                    Simulate(Model(), "handheld", Tmp() / "capture_handheld_60s", 60),
                    Tmp() / "session_handheld_lidar_only", 4.6, 1.3);
}

// Dense sensors (issue 17, item 1): a 128-beam OS1 and a 64-beam OS0 (the simulator's built-in
// ones, 1024x10) give 4x and 2x the OS1-32's points; the voxel sizes adapt to the count, so every
// scan fits the default 50 ms budget (p99 measured 24 ms of CPU time for the OS1-128 on a shared
// machine, odometry_benchmark BM_OdometrySensor, which counts the scans over budget). --budget-cpu
// counts the odometry's own CPU time, which depends less on the machine's load than the wall
// clock does; this test asserts the accuracy and prints the scans over budget. The first second is
// in these 10 s: the map is empty and the sizes not yet adapted there. (5 s walk too little of a
// curve for the se3 alignment to fix the rotation about it: 13 deg APE rotation for 0.7 cm.)
class OdometryCliSensor : public OdometryCli, public ::testing::WithParamInterface<const char*> {};

TEST_P(OdometryCliSensor, HoldsItsAccuracyOnTheDefaultBudget) {
    const std::string sensor = GetParam();
    const fs::path cap = Tmp() / ("capture_" + sensor);
    const auto sim = test::RunCommand(kCli + " simulate --model " + Model().string() +
                                      " --platform go1 --sensor " + sensor + " --duration 10 -o " +
                                      cap.string());
    ASSERT_EQ(sim.exit_code, 0) << sim.err;
    EXPECT_NE(io::ReadFileToString(cap / "metadata.json").find("OS-" + sensor.substr(2)),
              std::string::npos);
    const fs::path ses = Tmp() / ("session_" + sensor);
    const nlohmann::json odo = RunOdometry(cap, ses, "");
    ASSERT_TRUE(odo.is_object());
    // Whether a scan ran over the 50 ms depends on the machine (its caches, its other loads):
    // printed by RunOdometry; odometry_benchmark BM_OdometrySensor measures the time and counts
    // them. A scan the budget cut short may fail its registration check (CI saw one in 100 at
    // 56.7 ms), so what is asserted is that no scan that had its whole budget failed.
    ExpectNoFailureWithinBudget(odo);
    EXPECT_NEAR(odo.at("scans").get<double>(), 100.0, 2.0);
    const nlohmann::json eval = Evaluate(ses, cap);
    ASSERT_TRUE(eval.is_object());
    Report(sensor + ", go1 with CAN", odo, eval);
    // Measured 0.69 / 0.70 cm and 0.14 / 0.12 deg (OS1-128 / OS0-64); bounds about twice that.
    EXPECT_LT(eval.at("ape_trans_rmse_m").get<double>(), 0.015);
    EXPECT_LT(eval.at("ape_rot_rmse_deg").get<double>(), 0.3);
}

INSTANTIATE_TEST_SUITE_P(Dense, OdometryCliSensor, ::testing::Values("OS1-128", "OS0-64"),
                         [](const auto& param_info) {
                             std::string name = param_info.param;
                             name.erase(std::remove(name.begin(), name.end(), '-'), name.end());
                             return name;
                         });

// Issue 17, item 5: the sensor mounted rotated on the Go1's back (pitched 15 deg, yawed 90 deg),
// and the calibration options of `bimslam odometry`. The mount matters to the Go1 prior (its
// motion is moved into the lidar frame) and the self-filter box. Given by hand exactly as
// capture.json holds it, --mount gives the same trajectory to the byte; given off by a realistic
// calibration error (1 cm and 1 deg, the IMU's rotation 1 deg, its clock and the CAN's 1 ms), the
// odometry still holds (odometry_benchmark BM_OdometryCalibration measures the cost).
class OdometryCliMount
    : public OdometryCli,
      public ::testing::WithParamInterface<std::tuple<const char*, const char*, const char*>> {};

TEST_P(OdometryCliMount, ARotatedMountTracksAndItsCalibrationCanBeGivenOrOff) {
    const auto [name_c, rpy_c, off_rpy] = GetParam();  // off: 0.58 deg added to each angle
    const std::string name = name_c, rpy = rpy_c;
    const fs::path scenario = Tmp() / ("mount_" + name + ".yaml");
    io::WriteFileAtomic(scenario,
                        "platform: go1\nsensor:\n  mount_xyz: [0.05, 0, 0.28]\n"
                        "  mount_rpy_deg: [" +
                            rpy + "]\n");
    const fs::path cap = Tmp() / ("capture_mount_" + name);
    const auto sim =
        test::RunCommand(kCli + " simulate --model " + Model().string() + " --scenario " +
                         scenario.string() + " --duration 10 -o " + cap.string());
    ASSERT_EQ(sim.exit_code, 0) << sim.err;
    const auto run = [&](const std::string& ses, const std::string& flags) {
        return RunJson(kCli + " odometry " + cap.string() + " -o " + (Tmp() / ses).string() +
                       kBudget + " --json" + flags);
    };
    const nlohmann::json odo = run("mount_" + name, "");
    ASSERT_TRUE(odo.is_object());
    EXPECT_TRUE(odo.at("mount_from_capture").get<bool>());
    const nlohmann::json eval = Evaluate(Tmp() / ("mount_" + name), cap);
    ASSERT_TRUE(eval.is_object());
    Report("go1, mount " + name, odo, eval);
    // Measured 0.67 / 0.58 cm and 0.13 / 0.20 deg (pitched / yawed).
    EXPECT_LT(eval.at("ape_trans_rmse_m").get<double>(), 0.014);
    EXPECT_LT(eval.at("ape_rot_rmse_deg").get<double>(), 0.4);

    // The same mount by hand: the same trajectory, to the byte (no budget can cut a scan short).
    std::string r = rpy;
    std::replace(r.begin(), r.end(), ',', ' ');
    const auto exact = test::RunCommand(kCli + " odometry " + cap.string() + " -o " +
                                        (Tmp() / ("mount_exact_" + name)).string() +
                                        " --budget-ms 10000 --json --mount 0.05 0 0.28 " + r);
    ASSERT_EQ(exact.exit_code, 0) << exact.err;
    EXPECT_FALSE(nlohmann::json::parse(exact.out).at("mount_from_capture").get<bool>());
    ASSERT_EQ(test::RunCommand(kCli + " odometry " + cap.string() + " -o " +
                               (Tmp() / ("mount_file_" + name)).string() + " --budget-ms 10000")
                  .exit_code,
              0);
    EXPECT_EQ(io::ReadFileToString(Tmp() / ("mount_exact_" + name) / "trajectory.tum"),
              io::ReadFileToString(Tmp() / ("mount_file_" + name) / "trajectory.tum"));

    // Off by 1 cm and about 1 deg (0.58 cm and 0.58 deg along each axis), the IMU's rotation
    // likewise, the clocks by 1 ms: still within the bound.
    const nlohmann::json off =
        run("mount_off_" + name, " --mount 0.0558 0.0058 0.2858 " + std::string(off_rpy) +
                                     " --imu-rotation 0.58 0.58 0.58 --time-offset-ms 1");
    ASSERT_TRUE(off.is_object());
    const nlohmann::json off_eval = Evaluate(Tmp() / ("mount_off_" + name), cap);
    ASSERT_TRUE(off_eval.is_object());
    Report("go1, mount " + name + ", calibration off by 1 cm, 1 deg, 1 ms", off, off_eval);
    // Measured 0.69 / 0.59 cm and 0.15 / 0.22 deg.
    EXPECT_LT(off_eval.at("ape_trans_rmse_m").get<double>(), 0.014);
    EXPECT_LT(off_eval.at("ape_rot_rmse_deg").get<double>(), 0.4);
}

INSTANTIATE_TEST_SUITE_P(Rotated, OdometryCliMount,
                         ::testing::Values(std::tuple{"pitched15", "0, 15, 0", "0.58 15.58 0.58"},
                                           std::tuple{"yawed90", "0, 0, 90", "0.58 0.58 90.58"}),
                         [](const auto& p) { return std::string(std::get<0>(p.param)); });

// A calibration option of the wrong shape or out of range: exit 2, saying which.
TEST_F(OdometryCli, CalibrationOptionsOfTheWrongShapeExit2) {
    const fs::path cap = Capture("go1");
    for (const std::string flags :
         {" --mount 0.05 0 0.28", " --time-offset-ms 5000", " --imu-rotation 1 2"}) {
        const auto r = test::RunCommand(kCli + " odometry " + cap.string() + " -o " +
                                        (Tmp() / "bad_calibration").string() + flags);
        EXPECT_EQ(r.exit_code, 2) << flags << "\n" << r.err;
        EXPECT_NE(r.err.find(flags.substr(1, flags.find(' ', 1) - 1)), std::string::npos)
            << flags << "\n"
            << r.err;
    }
}

// Issue 17, item 2: a recording that starts at walking speed (the scenario's
// speed.start_at_speed; handheld at 1.5 m/s). The first scan is deskewed with no motion known;
// once the second gives the velocity, the first is deskewed again and the second registered
// again (LidarOdometryConfig::start_refinements). Without it the first scan-to-scan motion came
// out 4.5 cm for 14.5 cm true and the first second's per-scan error was 11x the rest's.
TEST_F(OdometryCli, AStartAtWalkingSpeedGetsItsFirstScansRight) {
    const fs::path scenario = Tmp() / "start_at_speed.yaml";
    io::WriteFileAtomic(scenario,
                        "platform: handheld\n"
                        "speed: {speed_mps: 1.5, max_accel_mps2: 1.0, start_at_speed: true}\n");
    const fs::path cap = Tmp() / "capture_start_at_speed";
    const auto sim =
        test::RunCommand(kCli + " simulate --model " + Model().string() + " --scenario " +
                         scenario.string() + " --duration 10 -o " + cap.string());
    ASSERT_EQ(sim.exit_code, 0) << sim.err;
    const fs::path ses = Tmp() / "session_start_at_speed";
    const nlohmann::json odo =
        RunJson(kCli + " odometry " + cap.string() + " -o " + ses.string() + kBudget + " --json");
    ASSERT_TRUE(odo.is_object());
    const auto est = io::ReadTum(ses / "trajectory.tum");
    const auto truth = io::ReadTum(cap / "ground_truth.tum");
    ASSERT_EQ(est.size(), truth.size());
    ASSERT_GT(est.size(), 50u);
    // It does start in motion: 15 cm between the first two scans.
    const double first_true = (truth[1].translation - truth[0].translation).norm();
    EXPECT_GT(first_true, 0.12);
    // Per scan: how far the estimated motion's length is from the true one.
    double first_sum = 0, rest_sum = 0;
    size_t first_n = 0, rest_n = 0;
    for (size_t k = 1; k < est.size(); ++k) {
        ASSERT_EQ(est[k].stamp_ns, truth[k].stamp_ns);
        const double e = std::abs((est[k].translation - est[k - 1].translation).norm() -
                                  (truth[k].translation - truth[k - 1].translation).norm());
        const bool first_second = truth[k].stamp_ns - truth[0].stamp_ns <= 1'000'000'000;
        (first_second ? first_sum : rest_sum) += e;
        ++(first_second ? first_n : rest_n);
    }
    const double first_cm = 100 * first_sum / double(first_n);
    const double rest_cm = 100 * rest_sum / double(rest_n);
    std::cout << "start at 1.5 m/s: per-scan motion error, first second " << first_cm
              << " cm, the rest " << rest_cm << " cm; first step "
              << 100 * (est[1].translation - est[0].translation).norm() << " cm for "
              << 100 * first_true << " cm\n";
    // No worse than the rest (measured 0.27 and 0.25 cm; without the fix 2.75 cm).
    EXPECT_LT(first_cm, 2 * rest_cm);
    EXPECT_NEAR((est[1].translation - est[0].translation).norm(), first_true, 0.02);
    const nlohmann::json eval = Evaluate(ses, cap);
    ASSERT_TRUE(eval.is_object());
    Report("handheld starting at 1.5 m/s", odo, eval);
    EXPECT_LT(eval.at("ape_trans_rmse_m").get<double>(), 0.02);  // measured 0.97 cm
}

// Issue 17, item 2, outdoors: a vehicle already at 3 m/s when the recording starts, on its loop
// around the sample building (host_tools/simulate/scenarios/vehicle_outdoor.yaml: open space,
// neighbouring blocks 20-40 m off, parked cars, trees). The target: the first 2 s's APE <= 5 cm.
TEST_F(OdometryCli, AVehicleStartingAt3MetresPerSecondOutdoors) {
    const fs::path cap = Tmp() / "capture_vehicle";
    const auto sim = test::RunCommand(
        kCli + " simulate --model " + Model().string() + " --scenario " +
        std::string(BIMSLAM_SOURCE_ROOT) +
        "/host_tools/simulate/scenarios/vehicle_outdoor.yaml --duration 10 -o " + cap.string());
    ASSERT_EQ(sim.exit_code, 0) << sim.err;
    const fs::path ses = Tmp() / "session_vehicle";
    const nlohmann::json odo = RunOdometry(cap, ses, "");
    ASSERT_TRUE(odo.is_object());
    ExpectNoFailureWithinBudget(odo);
    const auto est = io::ReadTum(ses / "trajectory.tum");
    const auto truth = io::ReadTum(cap / "ground_truth.tum");
    ASSERT_EQ(est.size(), truth.size());
    ASSERT_GT(est.size(), 90u);
    // It does start at speed: 30 cm between the first two scans.
    EXPECT_GT((truth[1].translation - truth[0].translation).norm(), 0.28);
    // The first 2 s (21 scans), aligned on their own, as `bimslam evaluate` does.
    std::vector<io::StampedPose> est2, truth2;
    for (size_t k = 0; k < est.size(); ++k) {
        if (truth[k].stamp_ns - truth[0].stamp_ns > 2'000'000'000) break;
        est2.push_back(est[k]);
        truth2.push_back(truth[k]);
    }
    io::WriteTum(Tmp() / "vehicle_est_2s.tum", est2);
    io::WriteTum(Tmp() / "vehicle_truth_2s.tum", truth2);
    const nlohmann::json first =
        RunJson(kCli + " evaluate --est " + (Tmp() / "vehicle_est_2s.tum").string() + " --ref " +
                (Tmp() / "vehicle_truth_2s.tum").string() + " --json");
    ASSERT_TRUE(first.is_object());
    const nlohmann::json eval = Evaluate(ses, cap);
    ASSERT_TRUE(eval.is_object());
    // (Only its translation: 2 s of a straight road leave the roll about it unobservable to the
    // alignment, so the subset's rotation figure means nothing.)
    std::cout << "vehicle outdoors starting at 3 m/s: the first 2 s's APE "
              << 100 * first.at("ape_trans_rmse_m").get<double>() << " cm RMSE, max "
              << 100 * first.at("ape_trans_max_m").get<double>() << " cm\n";
    Report("vehicle outdoors starting at 3 m/s, 10 s", odo, eval);
    // About twice the measured 0.47-0.56 cm (first 2 s) and 0.53 cm (10 s): a regression shows
    // long before the issue's target (5 cm), which it meets with a margin of ten.
    EXPECT_LT(first.at("ape_trans_rmse_m").get<double>(), 0.012);
    EXPECT_LT(eval.at("ape_trans_rmse_m").get<double>(), 0.012);
}

// Issue 17, item 6: glass windows, three mirrors on the corridor walls and every door swinging
// (host_tools/simulate/scenarios/glass_mirrors_doors.yaml), a minute of a Go1's walk. Measured in
// algorithms/odometry/README.md, "Glass, mirrors and moving doors" and "One-sided planes": 6.6 cm
// until the map's planes had a front (the walk leaves the corridor through a door at 43 s and
// the scan slid onto the far face of a room's side wall), 0.79 cm / 0.17 deg since.
TEST_F(OdometryCli, Go1AmongGlassMirrorsAndMovingDoors) {
    const fs::path cap = Tmp() / "capture_glass_mirrors_doors";
    const auto sim = test::RunCommand(
        kCli + " simulate --model " + Model().string() + " --scenario " +
        std::string(BIMSLAM_SOURCE_ROOT) +
        "/host_tools/simulate/scenarios/glass_mirrors_doors.yaml --duration 60 -o " + cap.string());
    ASSERT_EQ(sim.exit_code, 0) << sim.err;
    // The walk line says how much of the walk the minute covers (the Go1 at about 0.5 m/s) and on
    // which storey.
    std::smatch walk;
    ASSERT_TRUE(std::regex_search(
        sim.out, walk,
        std::regex(R"(walk +go1, ([0-9.]+) m in 60\.0 s of a ([0-9.]+) m walk, storey '([^']+)')")))
        << sim.out;
    EXPECT_GT(std::stod(walk[1]), 20.0);
    EXPECT_LT(std::stod(walk[1]), 40.0);
    EXPECT_GT(std::stod(walk[2]), std::stod(walk[1])) << "a minute covers part of the walk";
    EXPECT_EQ(walk[3], "Ground Floor");
    const nlohmann::json changes =
        nlohmann::json::parse(io::ReadFileToString(cap / "changes.json"));
    EXPECT_EQ(changes.at("added").size(), 3u);  // the mirrors
    EXPECT_GT(changes.at("moving_doors").size(), 10u);
    const fs::path ses = Tmp() / "session_glass_mirrors_doors";
    const nlohmann::json odo = RunOdometry(cap, ses, "");
    ASSERT_TRUE(odo.is_object());
    ExpectNoFailureWithinBudget(odo);
    const nlohmann::json eval = Evaluate(ses, cap);
    ASSERT_TRUE(eval.is_object());
    Report("Go1 among glass, mirrors and moving doors, 60 s", odo, eval);
    EXPECT_LT(eval.at("ape_trans_rmse_m").get<double>(), 0.016);
    EXPECT_LT(eval.at("ape_rot_rmse_deg").get<double>(), 0.35);
}

// Every file in a folder (relative path) with its bytes.
std::map<std::string, std::string> Contents(const fs::path& dir) {
    std::map<std::string, std::string> out;
    for (const auto& e : fs::recursive_directory_iterator(dir)) {
        if (e.is_regular_file()) {
            out[fs::relative(e.path(), dir).string()] = io::ReadFileToString(e.path());
        }
    }
    return out;
}

TEST_F(OdometryCli, BadInputExits2NamingTheFile) {
    const fs::path cap = Capture("go1");
    const fs::path out = Tmp() / "bad_session";
    const auto odometry = [&](const fs::path& capture, const std::string& extra = "") {
        return test::RunCommand(kCli + " odometry " + capture.string() + " -o " + out.string() +
                                extra);
    };

    // No capture folder.
    const fs::path nowhere = Tmp() / "nowhere";
    const auto missing = odometry(nowhere);
    EXPECT_EQ(missing.exit_code, 2) << missing.out << missing.err;
    EXPECT_NE(missing.err.find(nowhere.string()), std::string::npos) << missing.err;
    EXPECT_FALSE(fs::exists(out));

    // A capture folder without its lidar.pcap.
    const fs::path no_pcap = Tmp() / "no_pcap";
    fs::create_directories(no_pcap);
    for (const char* f : {"metadata.json", "capture.json", "go1_can.log", "ground_truth.tum"}) {
        fs::copy_file(cap / f, no_pcap / f);
    }
    const auto absent = odometry(no_pcap);
    EXPECT_EQ(absent.exit_code, 2) << absent.out << absent.err;
    EXPECT_NE(absent.err.find((no_pcap / "lidar.pcap").string()), std::string::npos) << absent.err;
    EXPECT_FALSE(fs::exists(out));

    // A real capture whose pcap file header (its first 24 bytes) is garbage.
    const fs::path corrupt = Tmp() / "corrupt";
    fs::copy(cap, corrupt, fs::copy_options::recursive);
    {
        std::string pcap = io::ReadFileToString(corrupt / "lidar.pcap");
        ASSERT_GT(pcap.size(), 24u);
        pcap.replace(0, 24, "this is not a pcap file!");
        test::WriteBytes(corrupt / "lidar.pcap", pcap);
    }
    const auto garbage = odometry(corrupt);
    EXPECT_EQ(garbage.exit_code, 2) << garbage.out << garbage.err;
    EXPECT_NE(garbage.err.find((corrupt / "lidar.pcap").string()), std::string::npos)
        << garbage.err;
    EXPECT_FALSE(fs::exists(out));

    // Corrupt half way: exit 2 naming the file and the byte; what was done before stays, as a
    // session without session.json that `session info` recovers, and the message says where.
    const fs::path half = Tmp() / "half";
    fs::copy(cap, half, fs::copy_options::recursive);
    {
        std::string pcap = io::ReadFileToString(half / "lidar.pcap");
        ASSERT_GT(pcap.size(), 2'000'000u);
        pcap.replace(pcap.size() / 2, 2000, std::string(2000, '\xff'));
        test::WriteBytes(half / "lidar.pcap", pcap);
    }
    const fs::path half_out = Tmp() / "half_session";
    const auto broken =
        test::RunCommand(kCli + " odometry " + half.string() + " -o " + half_out.string());
    EXPECT_EQ(broken.exit_code, 2) << broken.out << broken.err;
    EXPECT_NE(broken.err.find((half / "lidar.pcap").string() + ": at byte "), std::string::npos)
        << broken.err;
    EXPECT_NE(broken.err.find("session info"), std::string::npos) << broken.err;
    const auto recovered = test::RunCommand(kCli + " session info " + half_out.string());
    EXPECT_EQ(recovered.exit_code, 0) << recovered.err;
    EXPECT_NE(recovered.out.find("INCOMPLETE"), std::string::npos) << recovered.out;

    // An existing session is not replaced without --overwrite, and is left as it was.
    const auto first = odometry(cap, " --duration 3");
    ASSERT_EQ(first.exit_code, 0) << first.err;
    const auto before = Contents(out);
    ASSERT_TRUE(before.contains("session.json"));
    ASSERT_TRUE(before.contains("trajectory.tum"));
    const size_t before_poses = io::ReadTum(out / "trajectory.tum").size();
    const auto again = odometry(cap, " --duration 2");
    EXPECT_EQ(again.exit_code, 2) << again.out << again.err;
    EXPECT_NE(again.err.find(out.string()), std::string::npos) << again.err;
    EXPECT_NE(again.err.find("overwrite"), std::string::npos) << again.err;
    EXPECT_EQ(Contents(out), before);
    // With --overwrite it is replaced.
    const auto replaced = odometry(cap, " --duration 2 --overwrite");
    EXPECT_EQ(replaced.exit_code, 0) << replaced.err;
    EXPECT_LT(io::ReadTum(out / "trajectory.tum").size(), before_poses);
}

TEST(OdometryCliHelp, NamesTheOptionsAndTheNextStep) {
    const auto help = test::RunCommand(kCli + " odometry --help");
    EXPECT_EQ(help.exit_code, 0) << help.err;
    for (const char* word :
         {"--no-can", "--no-imu", "--edge-features", "evaluate", "--overwrite", "--json"}) {
        EXPECT_NE(help.out.find(word), std::string::npos) << word << "\n" << help.out;
    }
    // Without the required arguments: a usage error.
    EXPECT_EQ(test::RunCommand(kCli + " odometry").exit_code, 2);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam
