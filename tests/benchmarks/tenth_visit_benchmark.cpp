// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// What adding the tenth visit to a project costs against the same visit processed alone (issue 33's
// target: at most 1.2x). A harness that prints figures, not a timed assertion.
//
// Ten 30 s hand-held OS1-16 walks of the unchanged sample office a month apart (the mapping
// README's recipe, seeds base+1 .. base+10), made with the `bimslam` program. Nine are mapped as
// one project; then, `reps` times each, alternating:
//   tenth   a copy of the nine-visit project, `bimslam map P --add w10`;
//   alone   a new project of w10 alone, its reference copied from the nine-visit project (the
//           model's reference session is made once per model and sensor, for both).
// Per run: the process's CPU time (user + system, from getrusage of the child), its wall time and
// each step's wall time from --json; then the medians' ratios. CPU time is the cost measure: on
// the shared 2-core machine wall times follow the other processes' load.
//   BIMSLAM_TENTH_SEED (default 10), BIMSLAM_TENTH_REPS (default 3), BIMSLAM_TENTH_KEEP=DIR keeps
//   the walks and the nine-visit project in DIR (and reuses them).
//   cmake --build --preset release --target tenth_visit_benchmark bimslam
//   build/release/bin/tenth_visit_benchmark
#include <sys/resource.h>
#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "algorithms/io/file_util.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

const std::string kCli = BIMSLAM_CLI_PATH;

struct Run {
    double cpu_s = 0, wall_s = 0;
    std::map<std::string, double> steps;  // step kind (odometry, anchor, ...) -> wall s
};

double ChildrenCpu() {
    rusage u{};
    getrusage(RUSAGE_CHILDREN, &u);
    return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
           1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

// Runs `bimslam <args>`; throws with its output when it fails.
void Bimslam(const std::string& args, const fs::path& stdout_file = "/dev/null") {
    const std::string cmd = kCli + " " + args + " > " + stdout_file.string() + " 2>/tmp/tenth.err";
    const int rc = std::system(cmd.c_str());
    if (rc != 0) {
        throw std::runtime_error(cmd + " failed (" + std::to_string(WEXITSTATUS(rc)) +
                                 "): " + io::ReadFileToString("/tmp/tenth.err"));
    }
}

Run Timed(const std::string& args, const fs::path& json_file) {
    const double cpu0 = ChildrenCpu();
    const auto t0 = std::chrono::steady_clock::now();
    Bimslam(args + " --json", json_file);
    Run r;
    r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    r.cpu_s = ChildrenCpu() - cpu0;
    const json out = json::parse(io::ReadFileToString(json_file));  // kept: .at() refers into it
    for (const json& s : out.at("steps")) {
        if (s.at("skipped").get<bool>()) continue;
        const std::string step = s.at("step");
        r.steps[step.substr(0, step.find(' '))] += s.at("seconds").get<double>();
    }
    return r;
}

double Median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

void Print(const char* what, const Run& r) {
    std::printf("  %-6s cpu %5.2f s  wall %5.2f s  |", what, r.cpu_s, r.wall_s);
    for (const auto& [step, s] : r.steps) std::printf(" %s %.2f", step.c_str(), s);
    std::printf("\n");
    std::fflush(stdout);
}

std::string LoadAverage() {
    double load[3] = {0, 0, 0};
    if (getloadavg(load, 3) != 3) return "unknown";
    char b[64];
    std::snprintf(b, sizeof b, "%.2f %.2f %.2f", load[0], load[1], load[2]);
    return b;
}

void Prepare(const fs::path& dir, int seed) {
    if (!fs::exists(dir / "building.ifc"))
        Bimslam("bim sample -o " + (dir / "building.ifc").string());
    io::WriteFileAtomic(dir / "w.yaml",
                        "platform: handheld\nduration_s: 30\n"
                        "sensor: {model: OS1-16, lidar_mode: 512x10}\n");
    for (int v = 1; v <= 10; ++v) {
        const fs::path w = dir / ("w" + std::to_string(v));
        if (fs::exists(w)) continue;
        char start[32];
        std::snprintf(start, sizeof start, "2025-%02d-02T09:00:00Z", v);
        Bimslam("simulate --model " + (dir / "building.ifc").string() + " --scenario " +
                (dir / "w.yaml").string() + " --seed " + std::to_string(seed + v) + " --start " +
                start + " -o " + w.string());
    }
    if (!fs::exists(dir / "p9" / "history.json")) {
        std::string walks;
        for (int v = 1; v <= 9; ++v) walks += " " + (dir / ("w" + std::to_string(v))).string();
        Bimslam("map " + (dir / "building.ifc").string() + walks + " -o " + (dir / "p9").string() +
                " --budget-ms 10000 --no-report");
    }
}

}  // namespace
}  // namespace bimslam

int main() {
    using namespace bimslam;
    const char* seed_env = std::getenv("BIMSLAM_TENTH_SEED");
    const char* reps_env = std::getenv("BIMSLAM_TENTH_REPS");
    const char* keep = std::getenv("BIMSLAM_TENTH_KEEP");
    const int seed = seed_env && *seed_env ? std::stoi(seed_env) : 10;
    const int reps = reps_env && *reps_env ? std::stoi(reps_env) : 3;
    test::TempDir tmp;
    const fs::path dir = keep && *keep ? fs::path(keep) : tmp.path();
    fs::create_directories(dir);
    Prepare(dir, seed);
    const std::string model = (dir / "building.ifc").string(), w10 = (dir / "w10").string();
    std::printf("tenth visit against the same visit alone: seeds %d-%d, load %s\n", seed + 1,
                seed + 10, LoadAverage().c_str());
    std::vector<double> tenth_cpu, alone_cpu, tenth_wall, alone_wall;
    for (int r = 0; r < reps; ++r) {
        const fs::path p10 = dir / "p10", alone = dir / "alone";
        fs::remove_all(p10);
        fs::remove_all(alone);
        fs::copy(dir / "p9", p10, fs::copy_options::recursive);
        const Run t =
            Timed("map " + p10.string() + " --add " + w10 + " --budget-ms 10000 --no-report",
                  dir / "tenth.json");
        fs::create_directories(alone / "stamps");
        fs::copy(dir / "p9" / "reference", alone / "reference", fs::copy_options::recursive);
        fs::copy(dir / "p9" / "stamps" / "reference.json", alone / "stamps" / "reference.json");
        const Run a = Timed(
            "map " + model + " " + w10 + " -o " + alone.string() + " --budget-ms 10000 --no-report",
            dir / "alone.json");
        if (a.steps.count("reference")) throw std::runtime_error("alone made the reference again");
        std::printf("run %d (load %s)\n", r + 1, LoadAverage().c_str());
        Print("tenth", t);
        Print("alone", a);
        tenth_cpu.push_back(t.cpu_s);
        alone_cpu.push_back(a.cpu_s);
        tenth_wall.push_back(t.wall_s);
        alone_wall.push_back(a.wall_s);
    }
    std::printf("median: tenth cpu %.2f s, alone %.2f s: %.2fx (wall %.2f s, %.2f s: %.2fx)\n",
                Median(tenth_cpu), Median(alone_cpu), Median(tenth_cpu) / Median(alone_cpu),
                Median(tenth_wall), Median(alone_wall), Median(tenth_wall) / Median(alone_wall));
    return 0;
}
