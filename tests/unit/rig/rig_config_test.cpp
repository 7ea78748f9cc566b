// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// firmware/app/rig_config: the schema, the strict loader (file, line, key) and --print-config,
// whose output loads back to the same configuration.
#include "firmware/app/rig_config.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "algorithms/common/status.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::rig {
namespace {
namespace BIMSLAM_UNITY_ID {

TEST(RigConfig, SchemaNamesEveryKeyWithTypeAndRange) {
    const auto& keys = ConfigSchema();
    EXPECT_GT(keys.size(), 40u);
    for (const ConfigKey& k : keys) {
        EXPECT_FALSE(k.type.empty()) << k.path;
        EXPECT_FALSE(k.range.empty()) << k.path;
        EXPECT_FALSE(k.doc.empty()) << k.path;
    }
}

TEST(RigConfig, LoadsValuesAndRejectsWithFileLineKey) {
    test::TempDir dir;
    const auto file = dir / "rig.yaml";
    std::ofstream(file) << "sensor:\n  lidar_port: 7600\ncan:\n  source: none\n"
                           "threads:\n  odometry: {priority: 42, cpu: 1}\n";
    RigConfig c;
    LoadConfigFile(file, c);
    EXPECT_EQ(c.lidar_port, 7600);
    EXPECT_EQ(c.can_source, "none");
    EXPECT_EQ(c.odometry.priority, 42);
    EXPECT_EQ(c.odometry.cpu, 1);
    std::ofstream(file) << "sensor:\n  lidar_port: 7600\n  timeout_s: -1\n";
    EXPECT_FILE_ERROR(LoadConfigFile(file, c), file.string(), 3);
    std::ofstream(file) << "\n\nmystery: 1\n";
    EXPECT_FILE_ERROR(LoadConfigFile(file, c), file.string(), 3);
}

TEST(RigConfig, WhereTheWalkStartsIsTwoOrThreeNumbersOrNothing) {
    test::TempDir dir;
    const auto file = dir / "rig.yaml";
    RigConfig c;
    EXPECT_TRUE(c.bim_near.empty());
    std::ofstream(file) << "localization:\n  near: [4.0, -3.8]\n";
    LoadConfigFile(file, c);
    EXPECT_EQ(c.bim_near, (std::vector<double>{4.0, -3.8}));
    std::ofstream(file) << "localization:\n  near: [4.0, -3.8, 5]\n";
    LoadConfigFile(file, c);
    EXPECT_EQ(c.bim_near.size(), 3u);
    std::ofstream(file) << "localization:\n  near: []\n";
    LoadConfigFile(file, c);
    EXPECT_TRUE(c.bim_near.empty());
    std::ofstream(file) << "localization:\n  near: [4.0]\n";
    EXPECT_FILE_ERROR(LoadConfigFile(file, c), file.string(), 2);
    std::ofstream(file) << "localization:\n  near: [4.0, -3.8, -1]\n";
    EXPECT_FILE_ERROR(LoadConfigFile(file, c), file.string(), 2);
    std::ofstream(file) << "localization:\n  near: [4.0, x]\n";
    EXPECT_FILE_ERROR(LoadConfigFile(file, c), file.string(), 2);
}

TEST(RigConfig, PrintedConfigurationLoadsBackUnchanged) {
    RigConfig c;
    c.lidar_port = 1234;
    c.mount = {0.1, 0.2, 0.3, 1, 2, 3};
    c.bim_near = {4.0, -3.8, 2.5};
    c.can_source = "lcm";
    const std::string printed = PrintConfig(c);
    test::TempDir dir;
    std::ofstream(dir / "p.yaml") << printed;
    RigConfig back;
    LoadConfigFile(dir / "p.yaml", back);
    EXPECT_EQ(PrintConfig(back), printed);
}

TEST(RigConfig, RelationsBetweenKeys) {
    RigConfig c;
    c.budget_ms = 200;
    EXPECT_THROW(ValidateConfig(c), common::Error);
    c = RigConfig{};
    c.can_source = "log";
    EXPECT_THROW(ValidateConfig(c), common::Error);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::rig
