// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// web-ifc (That Open Company's IFC engine, independent of IFC++) as the integration tests run it:
// tests/tools/web_ifc/check.mjs prints what it read of a file as JSON. The test target defines
// BIMSLAM_SOURCE_ROOT (ctest's BIMSLAM_SOURCE_DIR overrides it).
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/support/test_support.hpp"

namespace bimslam::web_ifc {

inline std::filesystem::path ToolDir() {
    const char* env = std::getenv("BIMSLAM_SOURCE_DIR");  // set by ctest
    const std::filesystem::path root =
        env && *env ? std::filesystem::path(env) : std::filesystem::path(BIMSLAM_SOURCE_ROOT);
    return root / "tests" / "tools" / "web_ifc";
}

inline std::string Quote(const std::filesystem::path& p) { return "'" + p.string() + "'"; }

// Why web-ifc cannot run here, or "" when it can.
inline std::string Missing() {
    if (test::RunCommand("node --version").exit_code != 0) {
        return "node is not installed: run toolchain/install-deps.sh --test";
    }
    if (!std::filesystem::exists(ToolDir() / "node_modules" / "web-ifc")) {
        return (ToolDir() / "node_modules").string() +
               " is missing: run toolchain/install-deps.sh --test (or npm ci --prefix "
               "tests/tools/web_ifc)";
    }
    return "";
}

// What check.mjs prints about the file; null (and a test failure) when it fails.
inline nlohmann::json Read(const std::filesystem::path& file) {
    const test::CommandResult r =
        test::RunCommand("node " + Quote(ToolDir() / "check.mjs") + " " + Quote(file));
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
    if (r.exit_code != 0) return nullptr;
    return nlohmann::json::parse(r.out);
}

}  // namespace bimslam::web_ifc
