// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The Debian packages (`make deb`, toolchain/debian/README.md) as a user installs them on this
// machine: cpack builds them from this build tree, lintian finds no error, dpkg -i installs
// them, systemd-analyze verify accepts the installed units, the installed programs run, the
// system user records a session in /var/lib/bimslam, and removing then purging bimslam-rig
// leaves that session in place. Needs root (dpkg); skips, saying why, when not root, when a
// tool is missing or when a bimslam package is already installed (it would replace it).
// Whatever happens, the packages are purged at the end and what the test made is removed.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "tests/integration/rig_test_support.hpp"

namespace bimslam {
namespace {
namespace BIMSLAM_UNITY_ID {
namespace fs = std::filesystem;
using test::RunCommand;

const fs::path kVarLib = "/var/lib/bimslam";
const fs::path kSessions = kVarLib / "sessions";

bool Installed(const std::string& package) {
    return RunCommand("dpkg-query -W -f='${db:Status-Abbrev}' " + package + " 2>/dev/null")
               .out.rfind("ii", 0) == 0;
}

// Leaves the machine as it was: the packages purged, and the session, the folders and the user
// the test made removed (the package keeps them on purpose).
class Cleanup {
public:
    Cleanup()
        : had_user_(RunCommand("getent passwd bimslam").exit_code == 0),
          had_var_lib_(fs::exists(kVarLib)),
          had_sessions_(fs::exists(kSessions)) {}
    ~Cleanup() {
        RunCommand("dpkg --purge bimslam-rig bimslam-tools");
        std::error_code ec;
        if (!session_.empty()) fs::remove_all(session_, ec);
        if (!had_sessions_) fs::remove(kSessions, ec);  // only when empty
        if (!had_var_lib_) fs::remove(kVarLib, ec);
        if (!had_user_) RunCommand("userdel bimslam; groupdel bimslam");
    }
    void set_session(const fs::path& dir) { session_ = dir; }

private:
    bool had_user_, had_var_lib_, had_sessions_;
    fs::path session_;
};

class DebPackage : public test::rig::RigFixture {};

TEST_F(DebPackage, InstallsRunsVerifiesAndKeepsSessionsOnRemoval) {
    if (::geteuid() != 0) GTEST_SKIP() << "installing packages needs root (dpkg -i)";
    for (const char* tool : {"dpkg-deb", "dpkg-shlibdeps", "lintian", "systemd-analyze"}) {
        if (RunCommand(std::string("command -v ") + tool).exit_code != 0) {
            GTEST_SKIP() << tool << " is absent (toolchain/install-deps.sh --test)";
        }
    }
    for (const char* p : {"bimslam-rig", "bimslam-tools"}) {
        if (Installed(p)) GTEST_SKIP() << p << " is installed here: the test would replace it";
    }

    // The packages of this build tree, into a folder of the test's own.
    const fs::path out = Tmp() / "packages";
    const auto cpack = RunCommand("cpack -G DEB --config " + std::string(BIMSLAM_BINARY_DIR) +
                                  "/CPackConfig.cmake -B " + out.string());
    ASSERT_EQ(cpack.exit_code, 0) << cpack.out << cpack.err;
    std::vector<fs::path> debs;
    for (const auto& e : fs::directory_iterator(out)) {
        if (e.path().extension() == ".deb") debs.push_back(e.path());
    }
    ASSERT_EQ(debs.size(), 2u) << cpack.out;
    std::string deb_list;
    for (const auto& d : debs) deb_list += " " + d.string();

    // lintian: no error (warnings are printed, not failed on).
    const auto lint = RunCommand("lintian --fail-on error" + deb_list);
    EXPECT_EQ(lint.exit_code, 0) << lint.out << lint.err;
    std::printf("lintian:\n%s", lint.out.c_str());

    Cleanup cleanup;
    const auto install = RunCommand("dpkg -i" + deb_list);
    ASSERT_EQ(install.exit_code, 0) << install.out << install.err;
    ASSERT_TRUE(Installed("bimslam-rig") && Installed("bimslam-tools"));
    // Each package carries the project's licence (LICENSE, in DEP-5 form).
    for (const char* p : {"bimslam-rig", "bimslam-tools"}) {
        std::ifstream in(fs::path("/usr/share/doc") / p / "copyright");
        const std::string copyright((std::istreambuf_iterator<char>(in)), {});
        EXPECT_NE(copyright.find("Files: *\nCopyright: 2026 The bimslam authors\n"
                                 "License: BSD-3-Clause\n"),
                  std::string::npos)
            << p << ":\n"
            << copyright;
    }

    // Dependencies from the linked libraries (dpkg-shlibdeps): LCM and yaml-cpp at least.
    const auto depends = RunCommand("dpkg-query -W -f='${Depends}' bimslam-rig").out;
    EXPECT_NE(depends.find("liblcm1"), std::string::npos) << depends;
    EXPECT_NE(depends.find("libyaml-cpp"), std::string::npos) << depends;
    EXPECT_NE(depends.find("adduser"), std::string::npos) << depends;
    // ATLAS came from Ceres' link line through libf77blas, which no symbol of ours needs
    // (toolchain/cmake/BimslamDependencies.cmake); Embree and TBB are the host tool's.
    for (const char* absent : {"libatlas3-base", "libembree3-3", "libtbb12"}) {
        EXPECT_EQ(depends.find(absent), std::string::npos) << absent << " in: " << depends;
    }

    // The installed units, against the installed programs and the user the postinst made.
    const auto verify = RunCommand(
        "systemd-analyze verify /lib/systemd/system/bimslam-rig.service "
        "/lib/systemd/system/bimslam-go1-bridge.service");
    EXPECT_EQ(verify.exit_code, 0) << verify.out << verify.err;
    EXPECT_EQ(RunCommand("getent passwd bimslam").exit_code, 0);

    const auto version = RunCommand("/usr/bin/bimslam-rig --version");
    EXPECT_EQ(version.exit_code, 0) << version.err;
    EXPECT_NE(version.out.find("bimslam-rig 0."), std::string::npos) << version.out;
    const auto bridge = RunCommand("/usr/bin/bimslam-go1-bridge --version");
    EXPECT_EQ(bridge.exit_code, 0) << bridge.err;
    const auto config =
        RunCommand("/usr/bin/bimslam-rig live --print-config --config /etc/bimslam/rig.yaml");
    EXPECT_EQ(config.exit_code, 0) << config.err;
    EXPECT_NE(config.out.find(kSessions.string()), std::string::npos) << config.out;
    EXPECT_EQ(RunCommand("/usr/bin/bimslam --help").exit_code, 0);

    // A session recorded by the installed rig as its service's user, where the service puts it.
    const fs::path cap = Capture("handheld", 4);
    fs::permissions(Tmp().path(), fs::perms::others_read | fs::perms::others_exec,
                    fs::perm_options::add);
    const auto rec =
        RunCommand("runuser -u bimslam -- /usr/bin/bimslam-rig replay " + cap.string() +
                   " --handheld --speed max --json --config /etc/bimslam/handheld.yaml");
    ASSERT_EQ(rec.exit_code, 0) << rec.out << rec.err;
    const fs::path session = nlohmann::json::parse(rec.out)["session"].get<std::string>();
    cleanup.set_session(session);
    ASSERT_EQ(session.parent_path(), kSessions);
    ASSERT_TRUE(fs::exists(session / "session.json"));

    // Removed, then purged: the programs and configurations go, the session stays.
    const auto remove = RunCommand("dpkg --remove bimslam-rig");
    ASSERT_EQ(remove.exit_code, 0) << remove.out << remove.err;
    EXPECT_FALSE(fs::exists("/usr/bin/bimslam-rig"));
    EXPECT_TRUE(fs::exists("/etc/bimslam/rig.yaml")) << "conffiles stay until purge";
    EXPECT_TRUE(fs::exists(session / "session.json"));
    const auto purge = RunCommand("dpkg --purge bimslam-rig");
    ASSERT_EQ(purge.exit_code, 0) << purge.out << purge.err;
    EXPECT_FALSE(fs::exists("/etc/bimslam/rig.yaml"));
    EXPECT_TRUE(fs::exists(session / "session.json")) << "purge removed a recorded session";
    EXPECT_NE(purge.out.find("kept"), std::string::npos) << purge.out;
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam
