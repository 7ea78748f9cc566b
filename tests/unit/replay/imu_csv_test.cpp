// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// imu.csv, the IMU beside a folder of per-scan clouds (host_tools/replay/imu_csv.hpp): what is
// written reads back, and a damaged file is refused naming the file and the line.
#include "host_tools/replay/imu_csv.hpp"

#include <gtest/gtest.h>

#include <string>

#include "algorithms/common/status.hpp"
#include "algorithms/io/file_util.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::replay {
namespace {
namespace BIMSLAM_UNITY_ID {

TEST(ImuCsv, WhatIsWrittenReadsBack) {
    test::TempDir tmp;
    std::vector<odometry::ImuMeasurement> samples(3);
    for (size_t i = 0; i < samples.size(); ++i) {
        samples[i].t_ns = 1'700'000'000'123'456'789 + int64_t(i) * 10'000'000;
        samples[i].gyro = Eigen::Vector3d(0.0123456789, -1.5, 3e-7) * double(i + 1);
        samples[i].accel = Eigen::Vector3d(0.1, -0.2, 9.80665) * double(i + 1);
    }
    WriteImuCsv(tmp / "imu.csv", samples);
    const auto back = ReadImuCsv(tmp / "imu.csv");
    ASSERT_EQ(back.size(), samples.size());
    for (size_t i = 0; i < samples.size(); ++i) {
        EXPECT_EQ(back[i].t_ns, samples[i].t_ns);  // exact nanoseconds
        EXPECT_LT((back[i].gyro - samples[i].gyro).norm(), 1e-8 * samples[i].gyro.norm());
        EXPECT_LT((back[i].accel - samples[i].accel).norm(), 1e-8 * samples[i].accel.norm());
    }
}

// Each damaged file: the message names the file, the line and what is wrong.
TEST(ImuCsv, ADamagedFileIsRefusedNamingTheFileAndLine) {
    test::TempDir tmp;
    const std::string header = "t_s,gyro_x,gyro_y,gyro_z,accel_x,accel_y,accel_z\n";
    const struct {
        std::string text, expected;
    } cases[] = {
        {"t,gx,gy,gz,ax,ay,az\n", ":1: expected the header line"},
        {header + "1.0,0,0,0,0,0\n", ":2: 6 fields, expected 7"},
        {header + "1.0,0,0,0,0,0,9.8\n0.5,0,0,0,0,0,9.8\n", ":3: t_s goes back in time"},
        {header + "1.0,0,nan,0,0,0,9.8\n", ":2:"},
        {header + "1.0,0,x,0,0,0,9.8\n", ":2:"},
    };
    for (const auto& c : cases) {
        const auto file = tmp / "imu.csv";
        io::WriteFileAtomic(file, c.text);
        try {
            ReadImuCsv(file);
            ADD_FAILURE() << "accepted: " << c.text;
        } catch (const common::FileError& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find(file.string()), std::string::npos) << what;
            EXPECT_NE(what.find(c.expected), std::string::npos) << what;
        }
    }
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::replay
