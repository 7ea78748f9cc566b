// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/common/status.hpp"

#include <gtest/gtest.h>

namespace bimslam::common {
namespace {
namespace BIMSLAM_UNITY_ID {

TEST(Status, OkAndError) {
    EXPECT_TRUE(Status::Ok().ok());
    EXPECT_EQ(Status::Ok().ToString(), "ok");
    const Status s(StatusCode::kDeadlineExceeded, "scan 12 over budget");
    EXPECT_FALSE(s.ok());
    EXPECT_EQ(s.code(), StatusCode::kDeadlineExceeded);
    EXPECT_EQ(s.ToString(), "deadline exceeded: scan 12 over budget");
}

TEST(Status, FileErrorNamesFileAndLine) {
    const FileError e(StatusCode::kParseError, "poses.txt", 12, "x: 'abc' is not a number");
    EXPECT_STREQ(e.what(), "poses.txt:12: x: 'abc' is not a number");
    EXPECT_EQ(e.path(), "poses.txt");
    EXPECT_EQ(e.line(), 12u);
    EXPECT_EQ(e.code(), StatusCode::kParseError);
    const FileError no_line(StatusCode::kNotFound, "a.pcd", 0, "cannot open");
    EXPECT_STREQ(no_line.what(), "a.pcd: cannot open");
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::common
