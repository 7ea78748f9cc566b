// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Helpers for tests and benchmarks.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <random>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "algorithms/common/point_cloud.hpp"
#include "algorithms/common/status.hpp"

namespace bimslam::test {

// A fresh folder under $TMPDIR (or /tmp), removed with its contents on destruction.
class TempDir {
public:
    TempDir();
    ~TempDir();
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    const std::filesystem::path& path() const { return path_; }
    std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

private:
    std::filesystem::path path_;
};

// ../shared/data next to the project root (BIMSLAM_SOURCE_DIR, set by ctest), or nullopt.
std::optional<std::filesystem::path> SharedDataDir();

// The emulator the test program runs under, or nullptr when it runs natively: the aarch64
// cross-build's tests run under qemu-user, whose CMAKE_CROSSCOMPILING_EMULATOR sets
// BIMSLAM_EMULATOR (toolchain/aarch64-linux-gnu.cmake). For what an emulator cannot do (qemu-user
// has no kernel receive timestamps); never for accuracy or logic.
const char* Emulator();

// Skips the current test, saying why, when ../shared/data (or a file in it) is missing.
#define BIMSLAM_REQUIRE_SHARED_DATA(var, relative)                                            \
    const auto var##_root = ::bimslam::test::SharedDataDir();                                 \
    if (!var##_root || !std::filesystem::exists(*var##_root / (relative))) {                  \
        GTEST_SKIP() << "../shared/data/" << (relative)                                       \
                     << " is absent: this test needs the shared real-data folder beside the " \
                        "project (see ../shared/data/README.md)";                             \
    }                                                                                         \
    const std::filesystem::path var = *var##_root / (relative)

// Expects `statement` to throw common::FileError naming the file and line (0: no line).
#define EXPECT_FILE_ERROR(statement, expected_file, expected_line)           \
    try {                                                                    \
        statement;                                                           \
        ADD_FAILURE() << "no error from " #statement;                        \
    } catch (const ::bimslam::common::FileError& e) {                        \
        EXPECT_EQ(e.path(), std::string(expected_file)) << e.what();         \
        EXPECT_EQ(e.line(), static_cast<size_t>(expected_line)) << e.what(); \
    }

// Writes bytes to a file as they are (no atomic rename): for feeding damaged input to readers.
void WriteBytes(const std::filesystem::path& path, const std::string& bytes);

// The bytes of a string, for APIs that take spans of bytes.
inline std::span<const uint8_t> AsBytes(const std::string& s) {
    return {reinterpret_cast<const uint8_t*>(s.data()), s.size()};
}
// n random bytes.
std::string RandomBytes(size_t n, std::mt19937& rng);

// `name` with every character but ASCII letters and digits made '_': a gtest parameter's name,
// or a folder's.
std::string Identifier(std::string name);

// Runs a shell command; returns its exit code (128 + signal when killed) and what it printed.
struct CommandResult {
    int exit_code = -1;
    std::string out;  // stdout
    std::string err;  // stderr
};
CommandResult RunCommand(const std::string& command);

// Starts `command` in the background (through sh, exec'd so the pid is the command's), its
// stdout and stderr into the files `out` and `err`.
pid_t Spawn(const std::string& command, const std::filesystem::path& out,
            const std::filesystem::path& err);
// Waits for a Spawn'ed process; its exit code (128 + signal when killed).
int Wait(pid_t pid);

// tests/support/ouster_bag.py run by Debian's python3 (which has python3-rosbag; plain `python3`
// may be another interpreter), ready for its arguments.
std::string OusterBagTool();
// Why OusterBagTool() cannot run here (a skip message), or "" when it can.
std::string OusterBagToolMissing();

// Bytes that readers of numbers and text headers react to (digits, separators, NUL, 0xff, DEL).
inline constexpr std::string_view kMutationBytes{"0123456789 \n-.e+n\0\xff\x7f", 20};
static_assert(kMutationBytes.back() == '\x7f');

// One to three random byte edits of `bytes` (bit flips, bytes from `interesting`, truncation,
// deletion, insertion, duplication), half of them within the first `hot_prefix` bytes where
// parsers make the most decisions. For mutation fuzzing of readers.
std::string Mutate(std::string bytes, std::mt19937& rng, size_t hot_prefix,
                   std::string_view interesting = kMutationBytes);

// Mutation fuzzing of a reader: `iterations` mutants (Mutate) of every seed go to `parse`, which
// must either accept them or throw common::FileError naming `name`; anything else fails the test
// (a crash, another exception, or a FileError naming another file). Returns how many of each.
struct FuzzSeed {
    std::string bytes;
    size_t hot_prefix = 256;  // where the header ends: half the edits land before it
};
struct FuzzCounts {
    size_t accepted = 0;
    size_t rejected = 0;
};
FuzzCounts FuzzReader(const std::string& name, const std::vector<FuzzSeed>& seeds, int iterations,
                      uint32_t rng_seed, std::string_view interesting,
                      const std::function<void(const std::string&)>& parse);

// An Ouster-like scan: `rings` x `columns` points on the walls, floor and ceiling of a box room
// seen from its centre, with intensity, ring and per-column time offsets. Deterministic in seed.
common::PointCloud MakeRoomScan(int rings, int columns, uint32_t seed);

// Where the fixtures of one build of `program` live: `base`/<program's modification time>; the
// folders of other builds under `base` are removed.
std::filesystem::path FixtureRootFor(const std::filesystem::path& base,
                                     const std::filesystem::path& program);

// A test fixture made once and shared by later tests and test processes: `make` fills a
// private temporary folder beside `root / name`, which is then renamed into place; a process
// that finds another making it waits for it (a lock file) and uses theirs. When the test has a
// failure after `make` (a step of it failed), the folder is not kept: the failure is reported and
// every later caller makes it again, so a fixture that failed to build cannot pass as made.
std::filesystem::path CachedFixture(const std::filesystem::path& root, const std::string& name,
                                    const std::function<void(const std::filesystem::path&)>& make);

// One row of a simulated capture's ground_truth_storeys.csv (host_tools/simulate, `storey: all`):
// a frame's stamp, the storey under the platform, that floor's height, on a flight or not.
struct StoreyTruthRow {
    int64_t stamp_ns = 0;
    std::string storey;
    double floor_z_m = 0;
    bool on_flight = false;
};
// Every row, in order. Throws std::runtime_error naming the file and line on a malformed row.
std::vector<StoreyTruthRow> ReadStoreyTruth(const std::filesystem::path& csv);

}  // namespace bimslam::test
