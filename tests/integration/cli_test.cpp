// The `bimslam` command as a user runs it: exit codes, messages, --json output.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "tests/support/test_support.hpp"

namespace bimslam {
namespace {
namespace fs = std::filesystem;

const std::string kCli = BIMSLAM_CLI_PATH;

TEST(Cli, HelpListsCommandsAndBadUsageExits2) {
    const auto help = test::RunCommand(kCli + " --help");
    EXPECT_EQ(help.exit_code, 0);
    EXPECT_NE(help.out.find("demo"), std::string::npos);
    EXPECT_NE(help.out.find("session"), std::string::npos);
    EXPECT_EQ(test::RunCommand(kCli + " session info --help").exit_code, 0);
    EXPECT_EQ(test::RunCommand(kCli + " frobnicate").exit_code, 2);
    EXPECT_EQ(test::RunCommand(kCli).exit_code, 2);
    EXPECT_EQ(test::RunCommand(kCli + " demo --columns 7").exit_code, 2);
}

TEST(Cli, DemoRunsEndToEndAndItsSessionReadsBack) {
    test::TempDir tmp;
    const fs::path out = tmp / "demo";
    const auto demo = test::RunCommand(kCli + " demo --columns 512 --out " + out.string());
    ASSERT_EQ(demo.exit_code, 0) << demo.out << demo.err;
    EXPECT_NE(demo.out.find("demo finished"), std::string::npos) << demo.out;
    EXPECT_NE(demo.out.find("bit-identical"), std::string::npos) << demo.out;

    const auto info = test::RunCommand(kCli + " session info --json " + (out / "session").string());
    ASSERT_EQ(info.exit_code, 0) << info.err;
    const auto j = nlohmann::json::parse(info.out);
    EXPECT_TRUE(j.at("complete").get<bool>());
    EXPECT_EQ(j.at("source"), "simulation");
    EXPECT_GT(j.at("keyframes").get<int>(), 50);
    EXPECT_EQ(j.at("edges").get<int>(), j.at("keyframes").get<int>() - 1);
    EXPECT_GT(j.at("scans").get<int>(), j.at("keyframes").get<int>());
    EXPECT_GT(j.at("path_length_m").get<double>(), 100.0);

    // A second run must not replace the results silently.
    const auto again = test::RunCommand(kCli + " demo --columns 512 --out " + out.string());
    EXPECT_EQ(again.exit_code, 2);
    EXPECT_NE(again.err.find((out / "session").string()), std::string::npos) << again.err;
    EXPECT_NE(again.err.find("--overwrite"), std::string::npos) << again.err;
}

TEST(Cli, DamagedSessionExits2NamingFileAndLine) {
    test::TempDir tmp;
    const fs::path out = tmp / "demo";
    ASSERT_EQ(
        test::RunCommand(kCli + " demo --columns 512 --laps 1 --out " + out.string()).exit_code, 0);
    const fs::path session = out / "session";
    {
        std::ofstream f(session / "times.txt", std::ios::app);
        f << "12x\n";
    }
    const auto info = test::RunCommand(kCli + " session info " + session.string());
    EXPECT_EQ(info.exit_code, 2);
    EXPECT_NE(info.err.find((session / "times.txt").string() + ":"), std::string::npos) << info.err;
    EXPECT_NE(info.err.find("'12x' is not a number"), std::string::npos) << info.err;

    // Without its manifest the session is recovered and reported as incomplete.
    fs::remove(session / "session.json");
    fs::remove(session / "times.txt");
    const auto recovered = test::RunCommand(kCli + " session info " + session.string());
    EXPECT_EQ(recovered.exit_code, 0) << recovered.err;
    EXPECT_NE(recovered.out.find("INCOMPLETE"), std::string::npos) << recovered.out;

    const auto missing = test::RunCommand(kCli + " session info " + (tmp / "nope").string());
    EXPECT_EQ(missing.exit_code, 2);
    EXPECT_NE(missing.err.find("nope"), std::string::npos) << missing.err;
}

}  // namespace
}  // namespace bimslam
