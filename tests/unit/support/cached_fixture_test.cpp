// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// test::CachedFixture (tests/support/test_support.hpp): a fixture whose maker failed is never kept,
// so that every later test process makes it again and sees the failure itself, instead of reading
// a half-made folder as if it were good. The failing maker has to run in a test process of its
// own: the refusal reads the test's own failures (HasFailure), which EXPECT_NONFATAL_FAILURE
// would intercept. So this binary runs itself on the disabled test below, as ctest would run a
// test that uses the fixture.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "tests/support/test_support.hpp"

namespace bimslam::test {
namespace {
namespace BIMSLAM_UNITY_ID {
namespace fs = std::filesystem;

// The maker counts its runs in root/runs, then fails when $FIXTURE_FAIL is set.
void MakeCountedFixture() {
    const fs::path root = std::getenv("FIXTURE_ROOT");
    CachedFixture(root, "made", [&](const fs::path& d) {
        int runs = 0;
        std::ifstream(root / "runs") >> runs;
        std::ofstream(root / "runs") << runs + 1;
        std::ofstream(d / "half_made") << "1";
        if (std::getenv("FIXTURE_FAIL")) ADD_FAILURE() << "a step of the maker failed";
    });
}
TEST(CachedFixtureChild, DISABLED_Make) { MakeCountedFixture(); }

// Runs the disabled test above in a process of its own; its exit code.
int MakeInChild(const fs::path& root, bool fail) {
    if (Emulator()) return -1;  // /proc/self/exe is the emulator
    const std::string self = fs::read_symlink("/proc/self/exe").string();
    return RunCommand("env FIXTURE_ROOT=" + root.string() + (fail ? " FIXTURE_FAIL=1" : "") + " " +
                      self + " --gtest_also_run_disabled_tests --gtest_filter=CachedFixtureChild.*")
        .exit_code;
}

int Runs(const fs::path& root) {
    int runs = 0;
    std::ifstream(root / "runs") >> runs;
    return runs;
}

TEST(CachedFixture, AFailedMakerIsNotKeptAndRunsAgainNextTime) {
    if (Emulator()) GTEST_SKIP() << "runs itself as a child, which qemu-user cannot re-exec";
    const TempDir tmp;
    EXPECT_NE(MakeInChild(tmp.path(), true), 0);
    EXPECT_FALSE(fs::exists(tmp.path() / "made")) << "a failed fixture was kept";
    EXPECT_NE(MakeInChild(tmp.path(), true), 0);
    EXPECT_EQ(Runs(tmp.path()), 2) << "the second process did not make it again";
}

TEST(CachedFixture, AGoodFixtureIsMadeOnceAndShared) {
    if (Emulator()) GTEST_SKIP() << "runs itself as a child, which qemu-user cannot re-exec";
    const TempDir tmp;
    EXPECT_EQ(MakeInChild(tmp.path(), false), 0);
    EXPECT_TRUE(fs::exists(tmp.path() / "made" / "half_made"));
    EXPECT_EQ(MakeInChild(tmp.path(), false), 0);
    EXPECT_EQ(Runs(tmp.path()), 1);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::test
