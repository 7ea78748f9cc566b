// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// bimslam-rig's figures against the targets of issue 16 (a harness that prints them; no
// assertions on time): OS1-32 1024x10 simulated in the sample building, sent over loopback UDP at
// 1x real time by `bimslam ouster replay` to `bimslam-rig live` (handheld: LiDAR + Ouster IMU),
// then the same recording through `bimslam-rig replay --speed max`. Printed: latency from a
// frame's last packet to its odometry message on LCM (p50, p99, max), CPU % of one core, RSS
// (from rig_health_t, at 1/2 of the run and at its end, or at 5 and 30 minutes in the long run),
// dropped scans and deadline misses.
//   rig_benchmark                       60 s at 1x and at max
//   BIMSLAM_BENCH_LONG=1 rig_benchmark  30 minutes at 1x (RSS at 5 and 30 min, misses over the
//                                       first 10), about 7.7 GB of pcap under $TMPDIR
// Set BIMSLAM_BENCH_SECONDS to choose another length, BIMSLAM_BENCH_RIG to measure another
// bimslam-rig binary (a build of another commit, for before/after runs interleaved).
// The latency is also printed by stage (LatencyStages, firmware/modules/lcm_bridge.hpp): the
// last packet taken up by the ingest thread, the scan assembled and queued, taken by the
// odometry thread, its odometry done, queued for LCM, published.
#include <signal.h>

#include <bimslam/rig_health_t.hpp>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <lcm/lcm-cpp.hpp>
#include <mutex>
#include <nlohmann/json.hpp>
#include <thread>
#include <vector>

#include "tests/integration/rig_test_support.hpp"

namespace {
namespace fs = std::filesystem;
using namespace bimslam::test::rig;

struct RssWatch {
    std::mutex m;
    std::vector<std::pair<double, double>> samples;  // uptime s, RSS MB
    void Handle(const lcm::ReceiveBuffer*, const std::string&, const bimslam::rig_health_t* h) {
        std::lock_guard<std::mutex> lock(m);
        samples.push_back({double(h->uptime_ns) * 1e-9, double(h->process_rss_bytes) / 1e6});
    }
    double At(double t) {
        std::lock_guard<std::mutex> lock(m);
        double best = -1, rss = 0;
        for (const auto& [u, r] : samples) {
            if (best < 0 || std::abs(u - t) < std::abs(best - t)) best = u, rss = r;
        }
        return rss;
    }
};

// The latency by stage (bimslam-rig --json's latency_stages_ms; absent from older builds).
void PrintStages(const nlohmann::json& run) {
    if (!run.contains("latency_stages_ms")) return;
    std::printf(
        "  latency by stage (each stage's own percentiles; they do not add up; odometry_cpu: the\n"
        "  odometry thread's CPU time in the odometry stage, the rest of that stage it waited):\n");
    for (const auto& st : run["latency_stages_ms"]) {
        std::printf("    %-9s p50 %6.2f ms  p99 %6.2f ms  max %6.2f ms\n",
                    st["stage"].get<std::string>().c_str(), st["p50"].get<double>(),
                    st["p99"].get<double>(), st["max"].get<double>());
    }
}

}  // namespace

int main() {
    const bool long_run = std::getenv("BIMSLAM_BENCH_LONG") != nullptr;
    int seconds = long_run ? 1800 : 60;
    if (const char* s = std::getenv("BIMSLAM_BENCH_SECONDS")) seconds = std::atoi(s);
    const char* rig_env = std::getenv("BIMSLAM_BENCH_RIG");
    const std::string rig_path = rig_env != nullptr ? rig_env : kRig;
    // BIMSLAM_BENCH_FIFO=1: the thread table of the shipped handheld.yaml (ingest and odometry
    // SCHED_FIFO on CPU 1; needs the privilege, else the rig warns and runs them normally).
    const bool fifo = std::getenv("BIMSLAM_BENCH_FIFO") != nullptr;
    bimslam::test::TempDir tmp;
    // BIMSLAM_BENCH_CAPTURE=DIR: simulate into DIR once and reuse it on later runs.
    const char* cap_env = std::getenv("BIMSLAM_BENCH_CAPTURE");
    const fs::path cap = cap_env != nullptr ? fs::path(cap_env) : tmp / "capture";
    bimslam::test::CommandResult r;
    if (!fs::exists(cap / "metadata.json")) {
        const fs::path model = tmp / "building.ifc";
        bimslam::test::RunCommand(kCli + " bim sample -o " + model.string());
        std::ofstream(tmp / "s.yaml") << "platform: handheld\n";
        std::printf("simulating %d s of a handheld walk (OS1-32 1024x10)...\n", seconds);
        std::fflush(stdout);
        r = bimslam::test::RunCommand(kCli + " simulate --model " + model.string() +
                                      " --scenario " + (tmp / "s.yaml").string() + " --duration " +
                                      std::to_string(seconds) + " -o " + cap.string());
        if (r.exit_code != 0) {
            std::fprintf(stderr, "simulate failed: %s\n", r.err.c_str());
            return 1;
        }
    }
    const int port = FreeUdpPortPair();
    const std::string url = "udpm://239.255.76.67:7671?ttl=0";
    std::ofstream(tmp / "live.yaml")
        << "sensor:\n  metadata: " << (cap / "metadata.json").string()
        << "\n  bind_address: 127.0.0.1\n  lidar_port: " << port << "\n  imu_port: " << port + 1
        << "\ncan:\n  source: none\nlcm:\n  url: " << url << "\nruntime:\n  lock_memory: false\n"
        << (fifo
                ? "threads:\n  ingest: {priority: 80, cpu: 1}\n  odometry: {priority: 60, cpu: 1}\n"
                : "");
    RssWatch watch;
    lcm::LCM lcm(url);
    lcm.subscribe("BIMSLAM_RIG_HEALTH", &RssWatch::Handle, &watch);
    std::atomic<bool> stop{false};
    std::thread listener([&] {
        while (!stop) lcm.handleTimeout(100);
    });
    const pid_t rig = Spawn(rig_path + " live --json --config " + (tmp / "live.yaml").string() +
                                " --session-root " + (tmp / "sessions").string(),
                            tmp / "live.json", tmp / "live.err");
    std::this_thread::sleep_for(std::chrono::seconds(2));
    r = bimslam::test::RunCommand(kCli + " ouster replay " + cap.string() +
                                  " --to 127.0.0.1 --json --lidar-port " + std::to_string(port) +
                                  " --imu-port " + std::to_string(port + 1));
    std::this_thread::sleep_for(std::chrono::seconds(2));
    ::kill(rig, SIGINT);
    Wait(rig);
    stop = true;
    listener.join();
    std::ifstream in(tmp / "live.json");
    const nlohmann::json live = nlohmann::json::parse(in, nullptr, false);
    if (live.is_discarded()) {
        std::fprintf(stderr, "bimslam-rig live failed\n");
        return 1;
    }
    const double t1 = long_run ? 300 : seconds / 2.0, t2 = long_run ? 1800 : seconds;
    std::printf(
        "live 1x over loopback, %d s (machine shared while measured):\n"
        "  latency last packet -> odometry on LCM  p50 %.2f ms  p99 %.2f ms  max %.2f ms\n"
        "  CPU %.1f %% of one core, RSS %.1f MB at %.0f s, %.1f MB at %.0f s\n"
        "  scans %d, dropped %d, deadline misses %d (deadline 100 ms); replayer at most %.1f ms "
        "behind schedule\n",
        seconds, live["latency_ms_p50"].get<double>(), live["latency_ms_p99"].get<double>(),
        live["latency_ms_max"].get<double>(), live["cpu_percent"].get<double>(), watch.At(t1), t1,
        watch.At(t2), t2, live["scans"].get<int>(), live["scans_dropped"].get<int>(),
        live["deadline_misses"].get<int>(),
        nlohmann::json::parse(r.out, nullptr, false).value("max_late_ms", -1.0));
    PrintStages(live);
    const auto max =
        RigJson(rig_path + " replay " + cap.string() + " --speed max --json --no-record --config " +
                (tmp / "live.yaml").string());
    if (!max.is_null()) {
        std::printf(
            "replay --speed max: %d scans in %.1f s (%.1fx real time), CPU %.0f %%, dropped %d "
            "(lossless), queue drops %d (LCM queues)\n",
            max["scans"].get<int>(), max["wall_s"].get<double>(),
            seconds / std::max(1e-9, max["wall_s"].get<double>()), max["cpu_percent"].get<double>(),
            max["scans_dropped"].get<int>(), max["queue_drops"].get<int>());
    }
    return 0;
}
