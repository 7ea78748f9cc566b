// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The arm64 package (`make deb-arm64`, toolchain/README.md) from the aarch64 cross-build in
// build/aarch64: cpack builds it into a folder of the test's own; it is Architecture arm64, its
// Depends come from the libraries the aarch64 programs link, resolved by dpkg-shlibdeps through
// the staged packages' shlibs/symbols files, and name packages Debian has for arm64; its
// programs are aarch64 ELF files that run under qemu-user (--version, --print-config); lintian
// finds no error. It does not build anything: without a
// cross-build (`make cross` or `make deb-arm64`) it skips, saying so, so that `make test` never
// pays for an aarch64 build. Nothing is installed (the package is not for this machine).
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/test_support.hpp"

namespace bimslam {
namespace {
namespace BIMSLAM_UNITY_ID {
namespace fs = std::filesystem;
using test::RunCommand;

const fs::path kCrossBuild = BIMSLAM_AARCH64_BINARY_DIR;
const fs::path kStaging = "/opt/bimslam-cross/arm64";

// The ELF header's e_machine (offset 18, in the file's byte order: EI_DATA = 1 is little
// endian), or -1 when the file is not a 64-bit little-endian ELF file.
int ElfMachine(const fs::path& file) {
    std::array<unsigned char, 20> h{};
    std::ifstream in(file, std::ios::binary);
    if (!in.read(reinterpret_cast<char*>(h.data()), h.size())) return -1;
    const bool elf = h[0] == 0x7f && h[1] == 'E' && h[2] == 'L' && h[3] == 'F';
    if (!elf || h[4] != 2 /* ELFCLASS64 */ || h[5] != 1 /* ELFDATA2LSB */) return -1;
    return h[18] | (h[19] << 8);
}

// The package names of a Depends field: every alternative of every entry, versions dropped.
std::set<std::string> DependNames(const std::string& depends) {
    std::set<std::string> names;
    std::string field = depends;
    for (char& c : field) {
        if (c == ',' || c == '|') c = '\n';
    }
    std::istringstream lines(field);
    for (std::string line; std::getline(lines, line);) {
        std::istringstream words(line);
        std::string name;
        if (words >> name) names.insert(name);
    }
    return names;
}

// Why the arm64 package cannot be made and inspected here, or "" when it can.
std::string CannotPackage() {
    for (const char* tool : {"cpack", "dpkg-deb", "dpkg-shlibdeps", "lintian",
                             "aarch64-linux-gnu-objdump", "apt-cache"}) {
        if (RunCommand(std::string("command -v ") + tool).exit_code != 0) {
            return std::string(tool) + " is absent (toolchain/install-deps.sh --cross / --test)";
        }
    }
    if (!fs::exists(kStaging / "DEBIAN/shlibs")) {
        return "no arm64 staging with its shlibs in " + kStaging.string() +
               " (sudo toolchain/install-deps.sh --cross)";
    }
    for (const char* program : {"bin/bimslam-rig", "bin/bimslam-go1-bridge", "CPackConfig.cmake"}) {
        if (!fs::exists(kCrossBuild / program)) {
            return (kCrossBuild / program).string() +
                   " is absent: no aarch64 cross-build here (make cross or make deb-arm64 builds "
                   "it; this test does not, to keep make test short)";
        }
    }
    return "";
}

// The package cpack makes of the cross-build, in `out`.
fs::path Package(const fs::path& out) {
    const auto cpack =
        RunCommand("cpack -G DEB --config " + (kCrossBuild / "CPackConfig.cmake").string() +
                   " -B " + out.string());
    EXPECT_EQ(cpack.exit_code, 0) << cpack.out << cpack.err;
    std::vector<fs::path> debs;
    for (const auto& e : fs::directory_iterator(out)) {
        if (e.path().extension() == ".deb") debs.push_back(e.path());
    }
    EXPECT_EQ(debs.size(), 1u) << "a firmware-only build packages bimslam-rig alone\n" << cpack.out;
    return debs.empty() ? fs::path() : debs.front();
}

TEST(DebArm64, IsArm64WithDependsFromTheLinkedLibrariesAndLintianClean) {
    if (const std::string why = CannotPackage(); !why.empty()) GTEST_SKIP() << why;
    const test::TempDir tmp;
    const fs::path deb = Package(tmp / "packages");
    ASSERT_FALSE(deb.empty());
    EXPECT_EQ(deb.filename().string().rfind("bimslam-rig_", 0), 0u) << deb;
    EXPECT_TRUE(deb.filename().string().ends_with("_arm64.deb")) << deb;

    const auto field = [&](const std::string& name) {
        auto r = RunCommand("dpkg-deb -f " + deb.string() + " " + name);
        EXPECT_EQ(r.exit_code, 0) << r.err;
        while (!r.out.empty() && r.out.back() == '\n') r.out.pop_back();
        return r.out;
    };
    EXPECT_EQ(field("Package"), "bimslam-rig");
    EXPECT_EQ(field("Architecture"), "arm64");

    // Depends: the staged libraries' packages (from their shlibs/symbols files), the installed
    // arm64 ones (from dpkg's own), and adduser (the postinst). Every name must be a package
    // Debian has for arm64, not a guess.
    const std::string depends = field("Depends");
    const auto names = DependNames(depends);
    for (const char* expected : {"adduser", "libc6", "libstdc++6", "liblcm1", "libyaml-cpp0.7",
                                 "libgoogle-glog0v6", "librosbag-storage4d", "zlib1g"}) {
        EXPECT_TRUE(names.count(expected)) << expected << " missing from Depends: " << depends;
    }
    // Nothing the programs do not use: ATLAS came from Ceres' link line through libf77blas, which
    // no symbol of ours needs (toolchain/cmake/BimslamDependencies.cmake); Embree and TBB are in
    // the cross-build only for the simulator of the tests.
    for (const char* absent : {"libatlas3-base", "libembree3-3", "libtbb12"}) {
        EXPECT_FALSE(names.count(absent)) << absent << " in Depends: " << depends;
    }
    // One apt-cache call: each name for arm64 and, for packages of every architecture
    // (adduser), as `all`, which apt resolves to the host's for an arm64-only package: so only
    // records whose Architecture is arm64 or all count.
    std::string query = "apt-cache show --no-all-versions";
    for (const auto& name : names) {
        if (name.find(".so") == std::string::npos) query += " " + name + ":arm64 " + name + ":all";
    }
    std::istringstream records(RunCommand(query + " 2>/dev/null").out);
    std::set<std::string> known;
    std::string package;
    for (std::string line; std::getline(records, line);) {
        if (line.rfind("Package: ", 0) == 0) package = line.substr(9);
        if (line == "Architecture: arm64" || line == "Architecture: all") known.insert(package);
    }
    for (const auto& name : names) {
        if (name.find(".so") != std::string::npos) continue;  // liblapack.so.3, a virtual one
        EXPECT_TRUE(known.count(name))
            << name << " (from Depends) is no arm64 package: " << depends;
    }

    // The programs are aarch64 (EM_AARCH64 = 183), stripped to the package.
    const fs::path root = tmp / "root";
    const auto extract = RunCommand("dpkg-deb -x " + deb.string() + " " + root.string());
    ASSERT_EQ(extract.exit_code, 0) << extract.err;
    for (const char* program : {"usr/bin/bimslam-rig", "usr/bin/bimslam-go1-bridge"}) {
        EXPECT_EQ(ElfMachine(root / program), 183) << program;
    }
    EXPECT_TRUE(fs::exists(root / "lib/systemd/system/bimslam-rig.service"));
    EXPECT_TRUE(fs::exists(root / "etc/bimslam/rig.yaml"));

    const auto lint = RunCommand("lintian --fail-on error " + deb.string());
    EXPECT_EQ(lint.exit_code, 0) << lint.out << lint.err;
    std::printf("Depends: %s\nInstalled-Size: %s KiB, file %ju bytes\nlintian:\n%s",
                depends.c_str(), field("Installed-Size").c_str(),
                static_cast<uintmax_t>(fs::file_size(deb)), lint.out.c_str());
}

// The packaged programs run: under qemu-user, with the arm64 loader and libraries of Debian's
// multiarch and the staged ones (as make test-cross runs the unit tests), `bimslam-rig
// --version` names aarch64, `--print-config` checks and prints the packaged configuration, and
// the Go1 bridge answers --help.
TEST(DebArm64, PackagedProgramsRunUnderQemuUser) {
    if (const std::string why = CannotPackage(); !why.empty()) GTEST_SKIP() << why;
    const auto qemu = RunCommand("command -v qemu-aarch64-static || command -v qemu-aarch64");
    if (qemu.exit_code != 0) {
        GTEST_SKIP() << "qemu-user is absent (qemu-user-static: toolchain/install-deps.sh --cross)";
    }
    std::string emulator = qemu.out.substr(0, qemu.out.find('\n'));
    emulator += " -E LD_LIBRARY_PATH=" + (kStaging / "usr/lib/aarch64-linux-gnu").string() + " ";
    const test::TempDir tmp;
    const fs::path deb = Package(tmp / "packages");
    ASSERT_FALSE(deb.empty());
    const fs::path root = tmp / "root";
    const auto extract = RunCommand("dpkg-deb -x " + deb.string() + " " + root.string());
    ASSERT_EQ(extract.exit_code, 0) << extract.err;
    const std::string rig = emulator + (root / "usr/bin/bimslam-rig").string();
    const auto version = RunCommand(rig + " --version");
    ASSERT_EQ(version.exit_code, 0) << version.out << version.err;
    EXPECT_NE(version.out.find("bimslam-rig "), std::string::npos) << version.out;
    EXPECT_NE(version.out.find("aarch64"), std::string::npos) << version.out;
    for (const char* config : {"etc/bimslam/rig.yaml", "etc/bimslam/handheld.yaml"}) {
        const auto printed =
            RunCommand(rig + " live --print-config --config " + (root / config).string());
        EXPECT_EQ(printed.exit_code, 0) << config << "\n" << printed.err;
        EXPECT_NE(printed.out.find("budget_ms: 50"), std::string::npos) << printed.out;
    }
    const auto bad =
        RunCommand(rig + " live --print-config --config " + (tmp / "none.yaml").string());
    EXPECT_EQ(bad.exit_code, 2) << bad.out << bad.err;
    const auto bridge =
        RunCommand(emulator + (root / "usr/bin/bimslam-go1-bridge").string() + " --help");
    EXPECT_EQ(bridge.exit_code, 0) << bridge.out << bridge.err;
    std::printf("%s", version.out.c_str());
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam
