// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/cli/rig_replay.hpp"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "algorithms/common/status.hpp"

namespace bimslam::cli {
namespace fs = std::filesystem;

namespace {
pid_t Start(const std::string& command) {
    const pid_t pid = ::fork();
    if (pid == 0) {
        ::execl("/bin/sh", "sh", "-c", ("exec " + command).c_str(), static_cast<char*>(nullptr));
        ::_exit(127);
    }
    return pid;
}
int Finish(pid_t pid) {
    int status = 0;
    ::waitpid(pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}
}  // namespace

RigReplayRun RunRigReplay(const fs::path& capture, const fs::path& work_dir) {
    const fs::path rig = fs::read_symlink("/proc/self/exe").parent_path() / "bimslam-rig";
    if (!fs::exists(rig)) {
        throw common::Error(common::StatusCode::kNotFound,
                            rig.string() + " is missing: build the bimslam-rig target");
    }
    fs::create_directories(work_dir);
    // Its own LCM port, so that a rig running on this host is not disturbed.
    const std::string url = "udpm://239.255.76.67:7669?ttl=0";
    const fs::path config = work_dir / "rig.yaml";
    std::ofstream(config) << "lcm:\n  url: " << url
                          << "\nruntime:\n  lock_memory: false\nthreads:\n  ingest: {priority: 0}\n"
                             "  can: {priority: 0}\n  odometry: {priority: 0}\n";
    RigReplayRun run;
    pid_t logger = -1;
    if (std::system("command -v lcm-logger >/dev/null 2>&1") == 0) {
        run.lcm_log = work_dir / "rig.lcmlog";
        logger = Start("lcm-logger -f --lcm-url='" + url + "&recv_buf_size=4194304' " +
                       run.lcm_log.string() + " >/dev/null 2>&1");
        std::this_thread::sleep_for(std::chrono::milliseconds(300));
    }
    const fs::path out = work_dir / "rig.json", err = work_dir / "rig.log";
    const std::string command = rig.string() + " replay " + capture.string() +
                                " --speed max --json --config " + config.string() +
                                " --session-root " + (work_dir / "sessions").string() + " >" +
                                out.string() + " 2>" + err.string();
    const int code = Finish(Start(command));
    if (logger > 0) {
        std::this_thread::sleep_for(std::chrono::milliseconds(300));
        ::kill(logger, SIGINT);
        Finish(logger);
    }
    if (code != 0) {
        throw common::Error(
            common::StatusCode::kInternal,
            "bimslam-rig replay exited " + std::to_string(code) + "; see " + err.string());
    }
    std::ifstream in(out);
    const nlohmann::json j = nlohmann::json::parse(in);
    run.session = j.at("session").get<std::string>();
    run.scans = j.at("scans").get<size_t>();
    run.keyframes = j.at("keyframes_written").get<size_t>();
    run.scans_dropped = j.at("scans_dropped").get<size_t>();
    run.wall_s = j.at("wall_s").get<double>();
    run.lcm_paced_s = j.at("lcm_paced_s").get<double>();
    return run;
}

}  // namespace bimslam::cli
