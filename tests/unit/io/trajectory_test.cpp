// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/io/trajectory.hpp"

#include <gtest/gtest.h>

#include <random>

#include "algorithms/common/se3.hpp"
#include "algorithms/io/file_util.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::io {
namespace {
namespace BIMSLAM_UNITY_ID {
using common::FileError;

std::vector<StampedPose> RandomTrajectory(int n, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-3.0, 3.0);
    std::vector<StampedPose> out;
    int64_t t = 1'699'999'999'000'000'000;
    for (int i = 0; i < n; ++i) {
        common::Vector6d xi;
        for (int k = 0; k < 6; ++k) xi[k] = u(rng);
        xi.tail<3>() *= 0.9;
        t += 100'000'000 + i;
        out.push_back(StampedPose::FromIsometry(t, common::ExpSE3(xi)));
    }
    return out;
}

TEST(Tum, RoundTripIsBitExact) {
    test::TempDir dir;
    const auto poses = RandomTrajectory(500, 1);
    WriteTum(dir / "t.tum", poses);
    const auto back = ReadTum(dir / "t.tum");
    ASSERT_EQ(back.size(), poses.size());
    for (size_t i = 0; i < poses.size(); ++i) {
        EXPECT_EQ(back[i].stamp_ns, poses[i].stamp_ns);
        EXPECT_EQ(back[i].translation, poses[i].translation);
        EXPECT_EQ(back[i].rotation.coeffs(), poses[i].rotation.coeffs());
    }
    EXPECT_EQ(SerializeTum(back), ReadFileToString(dir / "t.tum"));
}

TEST(Tum, ReadsCommentsAndThirdPartyPrecision) {
    const auto p = ParseTum("gt.tum",
                            "# timestamp tx ty tz qx qy qz qw\n\n"
                            "1305031102.175304 1.3405 0.6266 1.6575 0.6574 0.6126 "
                            "-0.2949 -0.3248\n");
    ASSERT_EQ(p.size(), 1u);
    EXPECT_EQ(p[0].stamp_ns, 1'305'031'102'175'304'000);
    EXPECT_TRUE(common::IsValidRigid(p[0].Pose()));
}

TEST(Tum, RejectsBadInputNamingFileAndLine) {
    EXPECT_TRUE(ParseTum("e.tum", "").empty());
    EXPECT_FILE_ERROR(ParseTum("a.tum", "1 0 0 0 0 0 0 1\n2 0 0 0 0 0 1\n"), "a.tum", 2);
    EXPECT_FILE_ERROR(ParseTum("a.tum", "1 0 0 0 0 0 0 1\n2 0 nan 0 0 0 0 1\n"), "a.tum", 2);
    EXPECT_FILE_ERROR(ParseTum("a.tum", "1 0 0 0 0 0 0 x\n"), "a.tum", 1);
    EXPECT_FILE_ERROR(ParseTum("a.tum", "1 0 0 0 0 0 0 2\n"), "a.tum", 1);  // not unit
    EXPECT_FILE_ERROR(ParseTum("a.tum", "2 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 1\n"), "a.tum", 2);
    EXPECT_FILE_ERROR(ParseTum("a.tum", std::string("1 0 0\0 0 0 0 0 1\n", 18)), "a.tum", 1);
    // A file cut off in the middle of a line.
    const std::string full = SerializeTum(RandomTrajectory(3, 2));
    EXPECT_FILE_ERROR(ParseTum("cut.tum", full.substr(0, full.size() - 20)), "cut.tum", 3);
    EXPECT_FILE_ERROR(ReadTum("/nonexistent/x.tum"), "/nonexistent/x.tum", 0);
}

TEST(Kitti, RoundTripIsBitExact) {
    std::vector<Eigen::Isometry3d> poses;
    for (const auto& p : RandomTrajectory(300, 3)) poses.push_back(p.Pose());
    test::TempDir dir;
    WriteKitti(dir / "k.txt", poses);
    const auto back = ReadKitti(dir / "k.txt");
    ASSERT_EQ(back.size(), poses.size());
    for (size_t i = 0; i < poses.size(); ++i) EXPECT_EQ(back[i].matrix(), poses[i].matrix());
}

TEST(Kitti, ReadsSixDigitFilesAndRejectsBadOnes) {
    // KITTI ground truth has 6 significant digits: re-orthonormalised on read.
    const auto p = ParseKitti("00.txt",
                              "1.000000e+00 9.043680e-12 2.326809e-11 5.551115e-17 "
                              "9.043683e-12 1.000000e+00 2.392370e-10 3.330669e-16 "
                              "2.326810e-11 2.392370e-10 9.999999e-01 -4.440892e-16\n");
    ASSERT_EQ(p.size(), 1u);
    EXPECT_TRUE(common::IsValidRigid(p[0], 1e-12));
    EXPECT_FILE_ERROR(ParseKitti("k.txt", "1 0 0 0 0 1 0 0 0 0 1\n"), "k.txt", 1);
    EXPECT_FILE_ERROR(ParseKitti("k.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n\n"), "k.txt", 2);
    EXPECT_FILE_ERROR(ParseKitti("k.txt", "1 0 0 0 0 1 0 0 0 0 1 inf\n"), "k.txt", 1);
    EXPECT_FILE_ERROR(ParseKitti("k.txt", "2 0 0 0 0 1 0 0 0 0 1 0\n"), "k.txt", 1);
    EXPECT_FILE_ERROR(ParseKitti("k.txt", "-1 0 0 0 0 1 0 0 0 0 1 0\n"), "k.txt", 1);
}

TEST(Trajectory, GarbageNeverCrashes) {
    const std::string tum = SerializeTum(RandomTrajectory(20, 4));
    std::vector<Eigen::Isometry3d> poses;
    for (const auto& p : RandomTrajectory(20, 5)) poses.push_back(p.Pose());
    const std::string kitti = SerializeKitti(poses);
    constexpr std::string_view interesting{"0123456789 \n-.e+n#\0\xff", 20};
    static_assert(interesting.back() == '\xff');
    const auto t = test::FuzzReader("fuzz.tum", {{tum, tum.size()}}, 2000, 7, interesting,
                                    [](const std::string& b) { ParseTum("fuzz.tum", b); });
    const auto k = test::FuzzReader("fuzz.txt", {{kitti, kitti.size()}}, 2000, 8, interesting,
                                    [](const std::string& b) { ParseKitti("fuzz.txt", b); });
    EXPECT_GT(t.rejected, 500u);
    EXPECT_GT(t.accepted, 50u);
    EXPECT_GT(k.rejected, 500u);
    EXPECT_GT(k.accepted, 50u);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::io
