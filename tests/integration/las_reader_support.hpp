// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The LAS readers the integration tests run on bimslam's LAS files: tests/tools/las/check.mjs
// reads a file with loaders.gl and copc (npm; no code shared with algorithms/io/las) and prints
// what each found as JSON. The test target defines BIMSLAM_SOURCE_ROOT (ctest's
// BIMSLAM_SOURCE_DIR overrides it).
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/support/test_support.hpp"

namespace bimslam::las_readers {

inline std::filesystem::path ToolDir() {
    const char* env = std::getenv("BIMSLAM_SOURCE_DIR");  // set by ctest
    const std::filesystem::path root =
        env && *env ? std::filesystem::path(env) : std::filesystem::path(BIMSLAM_SOURCE_ROOT);
    return root / "tests" / "tools" / "las";
}

// Why the readers cannot run here, or "" when they can.
inline std::string Missing() {
    if (test::RunCommand("node --version").exit_code != 0) {
        return "node is not installed: run toolchain/install-deps.sh --test";
    }
    for (const char* package : {"copc", "@loaders.gl/las", "@loaders.gl/core"}) {
        if (!std::filesystem::exists(ToolDir() / "node_modules" / package)) {
            return (ToolDir() / "node_modules" / package).string() +
                   " is missing: run toolchain/install-deps.sh --test (or npm ci --prefix "
                   "tests/tools/las)";
        }
    }
    return "";
}

// What check.mjs prints about the file: {"loadersGl": {...}, "copc": {...}}; null (and a test
// failure) when it fails.
inline nlohmann::json Read(const std::filesystem::path& file) {
    const test::CommandResult r = test::RunCommand("node '" + (ToolDir() / "check.mjs").string() +
                                                   "' '" + file.string() + "'");
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
    if (r.exit_code != 0) return nullptr;
    return nlohmann::json::parse(r.out);
}

}  // namespace bimslam::las_readers
