// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// `bimslam evaluate` as a user runs it: two TUM files in, figures (table or JSON) out, exit 2 on
// bad input naming the file.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "algorithms/io/trajectory.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam {
namespace {
namespace BIMSLAM_UNITY_ID {
namespace fs = std::filesystem;

const std::string kCli = BIMSLAM_CLI_PATH;

// A 20 s walk at 10 Hz that turns and climbs (not on one line), stamped in a sensor clock at 42 s.
std::vector<io::StampedPose> Walk() {
    std::vector<io::StampedPose> out;
    for (int k = 0; k < 200; ++k) {
        const double a = 0.05 * k;
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
        T.linear() = Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).toRotationMatrix();
        T.translation() =
            Eigen::Vector3d(5.0 * std::cos(a) + 0.1 * k, 5.0 * std::sin(a), 0.5 * std::sin(2 * a));
        out.push_back(io::StampedPose::FromIsometry(42'000'000'000 + k * 100'000'000LL, T));
    }
    return out;
}

// Runs `bimslam evaluate` and parses its --json output.
nlohmann::json EvaluateJson(const std::string& args) {
    const auto r = test::RunCommand(kCli + " evaluate " + args + " --json");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return nlohmann::json::parse(r.out);
}

TEST(EvaluateCli, ReportsTheErrorOfAnOffsetTrajectory) {
    test::TempDir tmp;
    const auto ref = Walk();
    // Off by 30 cm east and 40 cm north (0.5 m), 3 ms late, and missing its first 10 poses.
    std::vector<io::StampedPose> est(ref.begin() + 10, ref.end());
    for (auto& p : est) {
        p.translation += Eigen::Vector3d(0.3, 0.4, 0.0);
        p.stamp_ns += 3'000'000;
    }
    io::WriteTum(tmp / "ref.tum", ref);
    io::WriteTum(tmp / "est.tum", est);
    const std::string files =
        "--est " + (tmp / "est.tum").string() + " --ref " + (tmp / "ref.tum").string();

    const nlohmann::json none = EvaluateJson(files + " --align none");
    EXPECT_EQ(none.at("matched"), 190);
    EXPECT_EQ(none.at("est_poses"), 190);
    EXPECT_EQ(none.at("ref_poses"), 200);
    EXPECT_EQ(none.at("align"), "none");
    for (const char* key :
         {"ape_trans_rmse_m", "ape_trans_mean_m", "ape_trans_median_m", "ape_trans_max_m"}) {
        EXPECT_NEAR(none.at(key).get<double>(), 0.5, 1e-9) << key;
    }
    EXPECT_NEAR(none.at("ape_rot_rmse_deg").get<double>(), 0.0, 1e-6);
    EXPECT_NEAR(none.at("ape_rot_max_deg").get<double>(), 0.0, 1e-6);
    EXPECT_NEAR(none.at("rpe_trans_rmse_m").get<double>(), 0.0, 1e-9);
    EXPECT_NEAR(none.at("rpe_trans_mean_m").get<double>(), 0.0, 1e-9);
    EXPECT_NEAR(none.at("rpe_rot_rmse_deg").get<double>(), 0.0, 1e-6);
    EXPECT_DOUBLE_EQ(none.at("rpe_delta_m").get<double>(), 1.0);
    EXPECT_NEAR(none.at("drift_percent").get<double>(), 0.0, 1e-7);
    EXPECT_DOUBLE_EQ(none.at("drift_segment_m").get<double>(), 10.0);
    EXPECT_NEAR(none.at("duration_s").get<double>(), 18.9, 1e-9);
    EXPECT_GT(none.at("distance_m").get<double>(), 30.0);

    // The default se3 alignment takes the offset out; options reach the metrics.
    const nlohmann::json se3 = EvaluateJson(files + " --rpe-delta-m 2 --drift-segment-m 500");
    EXPECT_EQ(se3.at("align"), "se3");
    EXPECT_NEAR(se3.at("ape_trans_rmse_m").get<double>(), 0.0, 1e-6);
    EXPECT_DOUBLE_EQ(se3.at("rpe_delta_m").get<double>(), 2.0);
    EXPECT_TRUE(se3.at("drift_segment_shortened").get<bool>());
    EXPECT_DOUBLE_EQ(se3.at("drift_segment_m").get<double>(), se3.at("distance_m").get<double>());

    // A window narrower than the 3 ms lag leaves nothing to compare: exit 2, both files named.
    const auto narrow = test::RunCommand(kCli + " evaluate " + files + " --max-dt-ms 2");
    EXPECT_EQ(narrow.exit_code, 2);
    EXPECT_NE(narrow.err.find((tmp / "est.tum").string()), std::string::npos) << narrow.err;
    EXPECT_NE(narrow.err.find((tmp / "ref.tum").string()), std::string::npos) << narrow.err;
    EXPECT_NE(narrow.err.find("2 ms"), std::string::npos) << narrow.err;

    // The table a person reads.
    const auto table = test::RunCommand(kCli + " evaluate " + files + " --align none");
    ASSERT_EQ(table.exit_code, 0) << table.err;
    EXPECT_NE(table.out.find("190 poses of est 190 / ref 200"), std::string::npos) << table.out;
    EXPECT_NE(table.out.find("rmse 50.00 cm"), std::string::npos) << table.out;
}

// KITTI poses with a times file (KITTI's times.txt layout: seconds in exponent notation) give the
// figures of the same poses as TUM; without times, or with a times file of another length, exit 2
// naming the file.
TEST(EvaluateCli, KittiPosesWithATimesFileEvaluateAsTum) {
    test::TempDir tmp;
    const auto ref = Walk();
    std::vector<io::StampedPose> est(ref.begin() + 10, ref.end());
    std::vector<Eigen::Isometry3d> kitti;
    std::string times;
    for (auto& p : est) {
        p.translation += Eigen::Vector3d(0.3, 0.4, 0.0);
        p.rotation =
            Eigen::Quaterniond(Eigen::AngleAxisd(0.02, Eigen::Vector3d::UnitX())) * p.rotation;
    }
    for (const auto& p : ref) {
        kitti.push_back(p.Pose());
        char line[64];
        std::snprintf(line, sizeof(line), "%.6e\n", double(p.stamp_ns) * 1e-9);
        times += line;
    }
    io::WriteTum(tmp / "ref.tum", ref);
    io::WriteTum(tmp / "est.tum", est);
    io::WriteKitti(tmp / "ref_kitti.txt", kitti);
    test::WriteBytes(tmp / "times.txt", times);
    const std::string est_arg = "--est " + (tmp / "est.tum").string();
    const nlohmann::json tum = EvaluateJson(est_arg + " --ref " + (tmp / "ref.tum").string());
    const nlohmann::json k = EvaluateJson(est_arg + " --ref " + (tmp / "ref_kitti.txt").string() +
                                          " --ref-times " + (tmp / "times.txt").string());
    EXPECT_EQ(k.at("matched"), 190);
    EXPECT_EQ(k.at("ref_times"), (tmp / "times.txt").string());
    for (const char* key : {"ape_trans_rmse_m", "ape_rot_rmse_deg", "rpe_trans_rmse_m"}) {
        EXPECT_NEAR(k.at(key).get<double>(), tum.at(key).get<double>(), 1e-9) << key;
    }
    EXPECT_GT(tum.at("ape_rot_rmse_deg").get<double>(), 0.5);

    // No times: the message says what the file holds and which option to give.
    const auto no_times = test::RunCommand(kCli + " evaluate " + est_arg + " --ref " +
                                           (tmp / "ref_kitti.txt").string());
    EXPECT_EQ(no_times.exit_code, 2);
    EXPECT_NE(no_times.err.find((tmp / "ref_kitti.txt").string()), std::string::npos);
    EXPECT_NE(no_times.err.find("KITTI poses"), std::string::npos) << no_times.err;
    EXPECT_NE(no_times.err.find("--ref-times"), std::string::npos) << no_times.err;
    // One time short.
    test::WriteBytes(tmp / "short.txt", times.substr(0, times.rfind('\n', times.size() - 2) + 1));
    const auto short_times = test::RunCommand(kCli + " evaluate " + est_arg + " --ref " +
                                              (tmp / "ref_kitti.txt").string() + " --ref-times " +
                                              (tmp / "short.txt").string());
    EXPECT_EQ(short_times.exit_code, 2);
    EXPECT_NE(short_times.err.find("199 times for the 200 poses"), std::string::npos)
        << short_times.err;
}

TEST(EvaluateCli, BadInputExits2NamingTheFile) {
    test::TempDir tmp;
    io::WriteTum(tmp / "ref.tum", Walk());
    test::WriteBytes(tmp / "bad.tum",
                     "# t x y z qx qy qz qw\n42.0 1 2 3 0 0 0 1\n42.1 1 2 3 0 0\n");
    const auto bad = test::RunCommand(kCli + " evaluate --est " + (tmp / "bad.tum").string() +
                                      " --ref " + (tmp / "ref.tum").string());
    EXPECT_EQ(bad.exit_code, 2);
    EXPECT_NE(bad.err.find((tmp / "bad.tum").string() + ":3:"), std::string::npos) << bad.err;

    const auto missing = test::RunCommand(kCli + " evaluate --est " + (tmp / "ref.tum").string() +
                                          " --ref " + (tmp / "nowhere.tum").string());
    EXPECT_EQ(missing.exit_code, 2);
    EXPECT_NE(missing.err.find("nowhere.tum"), std::string::npos) << missing.err;

    EXPECT_EQ(test::RunCommand(kCli + " evaluate --est a.tum").exit_code, 2);  // no --ref
    EXPECT_EQ(test::RunCommand(kCli + " evaluate --est a --ref b --align sim3").exit_code, 2);

    const auto help = test::RunCommand(kCli + " evaluate --help");
    EXPECT_EQ(help.exit_code, 0);
    for (const char* word : {"evo", "APE", "RPE", "drift", "Umeyama", "KITTI"}) {
        EXPECT_NE(help.out.find(word), std::string::npos) << word;
    }
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam
