// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "tests/support/test_support.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>

namespace bimslam::test {

TempDir::TempDir() {
    const char* base = std::getenv("TMPDIR");
    std::string templ = std::string(base && *base ? base : "/tmp") + "/bimslam-test-XXXXXX";
    if (::mkdtemp(templ.data()) == nullptr) {
        throw std::runtime_error("cannot create a temporary folder from " + templ);
    }
    path_ = templ;
}

TempDir::~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
}

std::optional<std::filesystem::path> SharedDataDir() {
    const char* src = std::getenv("BIMSLAM_SOURCE_DIR");
    const std::filesystem::path root = src && *src ? src : std::filesystem::current_path();
    const std::filesystem::path data = root / ".." / "shared" / "data";
    if (std::filesystem::is_directory(data)) return std::filesystem::canonical(data);
    return std::nullopt;
}

const char* Emulator() {
    const char* emulator = std::getenv("BIMSLAM_EMULATOR");
    return emulator && *emulator ? emulator : nullptr;
}

void WriteBytes(const std::filesystem::path& path, const std::string& bytes) {
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (!f) throw std::runtime_error("cannot write " + path.string());
}

std::string RandomBytes(size_t n, std::mt19937& rng) {
    std::string s(n, '\0');
    for (char& c : s) c = static_cast<char>(rng());
    return s;
}

std::string Identifier(std::string name) {
    for (char& c : name) {
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    }
    return name;
}

CommandResult RunCommand(const std::string& command) {
    TempDir dir;
    const std::string out = (dir / "out").string(), err = (dir / "err").string();
    // In braces, so that a list (`a || b`, `a; b`) is redirected whole, not only its last part.
    const int status = std::system(("{ " + command + "\n} >" + out + " 2>" + err).c_str());
    CommandResult r;
    if (status != -1 && WIFEXITED(status)) {
        r.exit_code = WEXITSTATUS(status);
    } else if (status != -1 && WIFSIGNALED(status)) {
        r.exit_code = 128 + WTERMSIG(status);
    }
    auto slurp = [](const std::string& path) {
        std::ifstream f(path, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(f), {});
    };
    r.out = slurp(out);
    r.err = slurp(err);
    return r;
}

pid_t Spawn(const std::string& command, const std::filesystem::path& out,
            const std::filesystem::path& err) {
    const pid_t pid = ::fork();
    if (pid == 0) {
        const std::string c = "exec " + command + " >" + out.string() + " 2>" + err.string();
        ::execl("/bin/sh", "sh", "-c", c.c_str(), static_cast<char*>(nullptr));
        ::_exit(127);
    }
    return pid;
}

int Wait(pid_t pid) {
    int status = 0;
    ::waitpid(pid, &status, 0);
    if (WIFEXITED(status)) return WEXITSTATUS(status);
    if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
    return -1;
}

std::string OusterBagTool() {
    return std::string("/usr/bin/python3 '") + BIMSLAM_OUSTER_BAG_TOOL + "'";
}

std::string OusterBagToolMissing() {
    // The tool's own imports: a missing one would fail the test instead of skipping it.
    if (RunCommand("/usr/bin/python3 -c 'import rosbag, genpy, std_msgs.msg'").exit_code == 0) {
        return "";
    }
    return "/usr/bin/python3 cannot import rosbag: install the Debian package python3-rosbag "
           "(toolchain/install-deps.sh --test)";
}

std::string Mutate(std::string s, std::mt19937& rng, size_t hot_prefix,
                   std::string_view interesting) {
    const int edits = 1 + static_cast<int>(rng() % 3);
    auto pick = [&] { return interesting[rng() % interesting.size()]; };
    for (int e = 0; e < edits && !s.empty(); ++e) {
        const size_t limit = (rng() % 2 == 0) ? std::min(hot_prefix, s.size()) : s.size();
        const size_t at = rng() % std::max<size_t>(limit, 1);
        switch (rng() % 6) {
            case 0:
                s[at] = static_cast<char>(s[at] ^ (1 << (rng() % 8)));
                break;
            case 1:
                s[at] = pick();
                break;
            case 2:
                s.resize(at);
                break;
            case 3:
                s.erase(at, 1 + rng() % 8);
                break;
            case 4:
                s.insert(at, 1, pick());
                break;
            default:
                s.insert(at, s.substr(rng() % s.size(), 1 + rng() % 16));
                break;
        }
    }
    return s;
}

FuzzCounts FuzzReader(const std::string& name, const std::vector<FuzzSeed>& seeds, int iterations,
                      uint32_t rng_seed, std::string_view interesting,
                      const std::function<void(const std::string&)>& parse) {
    std::mt19937 rng(rng_seed);
    FuzzCounts counts;
    for (const FuzzSeed& seed : seeds) {
        for (int i = 0; i < iterations; ++i) {
            const std::string bytes = Mutate(seed.bytes, rng, seed.hot_prefix, interesting);
            try {
                parse(bytes);
                ++counts.accepted;
            } catch (const common::FileError& e) {
                if (e.path() != name) {
                    ADD_FAILURE() << "error names '" << e.path() << "', not '" << name
                                  << "': " << e.what();
                    return counts;
                }
                ++counts.rejected;
            }
        }
    }
    return counts;
}

common::PointCloud MakeRoomScan(int rings, int columns, uint32_t seed) {
    // Ray-box intersection from a sensor at (0.7, -0.4, 1.0) inside an 8 x 5 x 3 m room; a few
    // pillars break the symmetry so that rotated scans stay distinguishable.
    std::mt19937 rng(seed);
    std::normal_distribution<float> noise(0.0f, 0.005f);
    const Eigen::Vector3d lo(-4.0, -2.5, 0.0), hi(4.0, 2.5, 3.0), origin(0.7, -0.4, 1.0);
    common::PointCloud cloud;
    cloud.Reserve(static_cast<size_t>(rings) * static_cast<size_t>(columns));
    for (int c = 0; c < columns; ++c) {
        const double az = 2.0 * M_PI * c / columns;
        const uint32_t t_ns = static_cast<uint32_t>(100'000'000.0 * c / columns);
        for (int r = 0; r < rings; ++r) {
            const double el = (22.5 - 45.0 * r / std::max(1, rings - 1)) * M_PI / 180.0;
            const Eigen::Vector3d d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az),
                                    std::sin(el));
            double best = 1e9;
            for (int k = 0; k < 3; ++k) {
                if (std::abs(d[k]) < 1e-12) continue;
                const double s = ((d[k] > 0 ? hi[k] : lo[k]) - origin[k]) / d[k];
                best = std::min(best, s);
            }
            // Pillar: a vertical cylinder of radius 0.3 m at (2.5, 1.2).
            const Eigen::Vector2d pc(2.5, 1.2), o2 = origin.head<2>(), d2 = d.head<2>();
            const double a = d2.squaredNorm(), b = 2.0 * d2.dot(o2 - pc);
            const double cc = (o2 - pc).squaredNorm() - 0.09, disc = b * b - 4 * a * cc;
            if (a > 1e-12 && disc > 0) {
                const double s = (-b - std::sqrt(disc)) / (2 * a);
                if (s > 0 && s < best) best = s;
            }
            const Eigen::Vector3d p = origin + best * d - origin;
            cloud.PushBack(p.cast<float>() + Eigen::Vector3f(noise(rng), noise(rng), noise(rng)),
                           static_cast<float>(50 + (r * 7 + c) % 200), static_cast<uint16_t>(r),
                           t_ns);
        }
    }
    return cloud;
}

std::filesystem::path FixtureRootFor(const std::filesystem::path& base,
                                     const std::filesystem::path& program) {
    namespace fs = std::filesystem;
    const auto stamp = fs::last_write_time(program).time_since_epoch().count();
    fs::create_directories(base);
    const fs::path mine = base / std::to_string(stamp);
    for (const auto& e : fs::directory_iterator(base)) {  // other builds' fixtures
        std::error_code ec;  // another test process may be removing it too
        if (e.path() != mine) fs::remove_all(e.path(), ec);
    }
    fs::create_directories(mine);
    return mine;
}

std::filesystem::path CachedFixture(const std::filesystem::path& root, const std::string& name,
                                    const std::function<void(const std::filesystem::path&)>& make) {
    namespace fs = std::filesystem;
    const fs::path dir = root / name;
    if (fs::exists(dir)) return dir;
    // One maker at a time: a process that finds another making it waits and uses theirs rather
    // than making it a second time (ctest -j runs the tests that share it at once).
    const int lock = ::open((root / (name + ".lock")).c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (lock >= 0) ::flock(lock, LOCK_EX);
    struct Unlock {
        int fd;
        ~Unlock() {
            if (fd >= 0) ::close(fd);
        }
    } unlock{lock};
    if (fs::exists(dir)) return dir;
    const fs::path tmp = root / (name + ".tmp" + std::to_string(::getpid()));
    fs::remove_all(tmp);
    fs::create_directories(tmp);
    make(tmp);
    if (::testing::Test::HasFailure()) {
        // Making it failed (or the test had failed before): never kept, so that every later
        // test and test process makes it again and sees the failure itself. The half-made
        // folder stays for a look; the caller's assertions on it fail.
        ADD_FAILURE() << "fixture " << name << " not kept: making it failed (" << tmp.string()
                      << ")";
        return tmp;
    }
    std::error_code ec;
    fs::rename(tmp, dir, ec);  // fails when another process was first: use theirs
    if (ec) fs::remove_all(tmp);
    return dir;
}

std::vector<StoreyTruthRow> ReadStoreyTruth(const std::filesystem::path& csv) {
    std::ifstream in(csv);
    std::string line;
    std::getline(in, line);  // header: stamp_ns,storey,floor_z_m,on_flight
    std::vector<StoreyTruthRow> out;
    for (size_t n = 2; std::getline(in, line); ++n) {
        std::vector<std::string> f;
        std::stringstream row(line);
        for (std::string c; std::getline(row, c, ',');) f.push_back(c);
        if (f.size() != 4) {
            throw std::runtime_error(csv.string() + ":" + std::to_string(n) +
                                     ": not stamp_ns,storey,floor_z_m,on_flight");
        }
        out.push_back({std::stoll(f[0]), f[1], std::stod(f[2]), f[3] == "1"});
    }
    return out;
}

}  // namespace bimslam::test
