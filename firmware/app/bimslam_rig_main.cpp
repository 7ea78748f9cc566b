// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// bimslam-rig: the on-board firmware (firmware/app/README.md).
//   bimslam-rig live --config rig.yaml [--handheld]
//   bimslam-rig replay RECORDING [--can LOG] [--speed 1|2|max] [--config rig.yaml] [--handheld]
// Exit codes (DESIGN.md): 0 success, 1 failure while working (a socket, LCM, the disk), 2 bad
// usage, a bad configuration or a bad recording (the message names the file, line and key).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>

#include "algorithms/common/status.hpp"
#include "firmware/app/rig.hpp"
#include "firmware/app/rig_config.hpp"
#include "firmware/modules/lcm_bridge.hpp"

namespace {
using bimslam::common::StatusCode;

constexpr int kExitOk = 0, kExitFailure = 1, kExitBadInput = 2;

int ExitCodeFor(StatusCode code) {
    switch (code) {
        case StatusCode::kInvalidArgument:
        case StatusCode::kParseError:
        case StatusCode::kNotFound:
        case StatusCode::kAlreadyExists:
        case StatusCode::kOutOfRange:
        case StatusCode::kDataLoss:
            return kExitBadInput;
        default:
            return kExitFailure;
    }
}

struct Args {
    std::string config_file;
    std::string recording;
    std::string can_log;
    std::string speed = "1";
    std::string session_root;
    bool handheld = false;
    bool print_config = false;
    bool no_record = false;
    bool json = false;
    double duration_s = 0;
    std::string lcm_log;
};

// {"writer": 1, ...}: the threads that stalled and how often.
nlohmann::json Stalls(const bimslam::rig::RunSummary& s) {
    nlohmann::json j = nlohmann::json::object();
    for (const auto& [name, stalls] : s.threads_stalled) j[name] = stalls;
    return j;
}

// [{"stage": "receive", "p50": ms, "p99": ms, "max": ms}, ...] in the order a scan passes them.
nlohmann::json Stages(const bimslam::rig::RunSummary& s) {
    nlohmann::json j = nlohmann::json::array();
    for (const bimslam::rig::StageLatency& st : s.latency_stages) {
        j.push_back(
            {{"stage", st.name}, {"p50", st.p50_ms}, {"p99", st.p99_ms}, {"max", st.max_ms}});
    }
    return j;
}

// The map package (localization.map) and the localiser's run (firmware/app/README.md).
nlohmann::json BimMapJson(const bimslam::rig::RunSummary& s) {
    return {{"path", s.bim_map},
            {"loaded", !s.bim_map.empty() && s.bim_map_error.empty()},
            {"error", s.bim_map_error},
            {"model", s.bim_map_model},
            {"keyframes", s.bim_map_keyframes},
            {"storeys", s.bim_map_storeys},
            {"bytes", s.bim_map_bytes},
            {"load_ms", s.bim_map_load_ms}};
}

nlohmann::json LocalizationJson(const bimslam::rig::RunSummary& s) {
    nlohmann::json states = nlohmann::json::object();
    for (const auto& [state, n] : s.localization_states) states[state] = n;
    return {{"keyframes", s.localization_keyframes},
            {"states", states},
            {"final_state", s.localization_final},
            {"time_to_localised_s", s.localization_time_to_localised_s >= 0
                                        ? nlohmann::json(s.localization_time_to_localised_s)
                                        : nlohmann::json()},
            {"cpu_ms_p50", s.localization_cpu_ms_p50},
            {"cpu_ms_p99", s.localization_cpu_ms_p99},
            {"cpu_percent", s.localization_cpu_percent},
            {"deadline_misses", s.localization_deadline_misses}};
}

void PrintSummary(const bimslam::rig::RunSummary& s, bool json) {
    if (json) {
        nlohmann::json j = {{"session", s.session_dir},
                            {"scans", s.scans},
                            {"keyframes", s.keyframes},
                            {"keyframes_written", s.keyframes_written},
                            {"keyframes_skipped_disk", s.keyframes_skipped_disk},
                            {"scans_dropped", s.scans_dropped},
                            {"deadline_misses", s.deadline_misses},
                            {"lidar_packets", s.lidar_packets},
                            {"imu_samples", s.imu_samples},
                            {"go1_samples", s.go1_samples},
                            {"frames_incomplete", s.frames_incomplete},
                            {"columns_lost", s.columns_lost},
                            {"crc_failures", s.crc_failures},
                            {"silences", s.silences},
                            {"sensor_restarts", s.sensor_restarts},
                            {"clock_jumps", s.clock_jumps},
                            {"can_timeouts", s.can_timeouts},
                            {"can_e2e_errors", s.can_e2e_errors},
                            {"can_late", s.can_late},
                            {"go1_bridge_link_down", s.go1_bridge_link_down},
                            {"go1_bridge_not_running", s.go1_bridge_not_running},
                            {"go1_bridge_lost", s.go1_bridge_lost},
                            {"go1_bridge_state", s.go1_bridge_state},
                            {"queue_drops", s.queue_drops},
                            {"threads_stalled", Stalls(s)},
                            {"lcm_failures", s.lcm_failures},
                            {"lcm_published",
                             {{bimslam::rig::kOdometryChannel, s.lcm_odometry},
                              {bimslam::rig::kKeyframeChannel, s.lcm_keyframes},
                              {bimslam::rig::kImuChannel, s.lcm_imu},
                              {bimslam::rig::kGo1StateChannel, s.lcm_go1_state},
                              {bimslam::rig::kRigHealthChannel, s.lcm_rig_health},
                              {bimslam::rig::kOusterStatsChannel, s.lcm_ouster_stats},
                              {bimslam::rig::kBimPoseChannel, s.lcm_bim_pose}}},
                            {"lcm_paced_s", s.lcm_paced_s},
                            {"lcm_logged", s.lcm_logged},
                            {"write_errors", s.write_errors},
                            {"latency_ms_p50", s.latency_p50_ms},
                            {"latency_ms_p99", s.latency_p99_ms},
                            {"latency_ms_max", s.latency_max_ms},
                            {"latency_stages_ms", Stages(s)},
                            {"cpu_percent", s.cpu_percent},
                            {"rss_mb", s.rss_mb},
                            {"wall_s", s.wall_s},
                            {"stop_signal", s.stop_signal},
                            {"warnings", s.warnings}};
        // The verdict with the keys `bimslam odometry --json` gives it (TrajectoryTrust::ToJson).
        j.update(s.trust.ToJson());
        j["bim_map"] = BimMapJson(s);
        j["localization"] = LocalizationJson(s);
        std::cout << j.dump(2) << std::endl;
        return;
    }
    std::printf(
        "bimslam-rig: %llu scans, %llu keyframes (%llu written), %llu scans dropped, %llu "
        "deadline misses in %.1f s\n",
        (unsigned long long)s.scans, (unsigned long long)s.keyframes,
        (unsigned long long)s.keyframes_written, (unsigned long long)s.scans_dropped,
        (unsigned long long)s.deadline_misses, s.wall_s);
    std::printf("  latency last packet -> odometry on LCM: p50 %.2f ms, p99 %.2f ms, max %.2f ms\n",
                s.latency_p50_ms, s.latency_p99_ms, s.latency_max_ms);
    for (const bimslam::rig::StageLatency& st : s.latency_stages) {
        std::printf("    %-9s p50 %.2f ms, p99 %.2f ms, max %.2f ms\n", st.name.c_str(), st.p50_ms,
                    st.p99_ms, st.max_ms);
    }
    std::printf("  CPU %.1f %% of one core, RSS %.0f MB\n", s.cpu_percent, s.rss_mb);
    std::printf(
        "  faults: %llu incomplete frames, %llu CRC failures, %llu silences, %llu sensor "
        "restarts, %llu clock jumps, %llu CAN timeouts, %llu CAN E2E errors, %llu queue drops, "
        "%llu Go1 samples with the bridge's link down, %llu bridge STATUS not RUNNING\n",
        (unsigned long long)s.frames_incomplete, (unsigned long long)s.crc_failures,
        (unsigned long long)s.silences, (unsigned long long)s.sensor_restarts,
        (unsigned long long)s.clock_jumps, (unsigned long long)s.can_timeouts,
        (unsigned long long)s.can_e2e_errors, (unsigned long long)s.queue_drops,
        (unsigned long long)s.go1_bridge_link_down, (unsigned long long)s.go1_bridge_not_running);
    std::printf("  trajectory %s\n", s.trust.Describe().c_str());
    if (!s.bim_map.empty() && s.bim_map_error.empty()) {
        std::printf(
            "  map package %s: %s, %llu keyframes on %llu storeys, %.1f MB read in %.0f ms\n",
            s.bim_map.c_str(), s.bim_map_model.c_str(), (unsigned long long)s.bim_map_keyframes,
            (unsigned long long)s.bim_map_storeys, double(s.bim_map_bytes) / 1e6,
            s.bim_map_load_ms);
        std::printf("  localisation: %llu keyframes, last state %s, ",
                    (unsigned long long)s.localization_keyframes, s.localization_final.c_str());
        if (s.localization_time_to_localised_s >= 0) {
            std::printf("localised %.1f s after the first keyframe",
                        s.localization_time_to_localised_s);
        } else {
            std::printf("never localised");
        }
        std::printf("; CPU per keyframe p50 %.1f ms, p99 %.1f ms, %.2f %% of one core\n",
                    s.localization_cpu_ms_p50, s.localization_cpu_ms_p99,
                    s.localization_cpu_percent);
    } else if (!s.bim_map.empty()) {
        std::printf("  %s (FAULT_BIM_MAP): the rig mapped in its own frame\n",
                    s.bim_map_error.c_str());
    }
    for (const auto& [name, stalls] : s.threads_stalled) {
        std::printf("  thread '%s' stalled %llu times (FAULT_THREAD_STALLED)\n", name.c_str(),
                    (unsigned long long)stalls);
    }
    if (!s.session_dir.empty()) std::printf("  session %s\n", s.session_dir.c_str());
    std::fflush(stdout);
}

int Run(const Args& a, bool live) {
    bimslam::rig::RunOptions o;
    try {
        if (!a.config_file.empty()) bimslam::rig::LoadConfigFile(a.config_file, o.config);
        o.config.handheld = a.handheld;
        if (!a.can_log.empty()) {
            o.config.can_source = "log";
            o.config.can_log = a.can_log;
        }
        if (!a.session_root.empty()) o.config.session_root = a.session_root;
        if (a.no_record) o.config.record = false;
        if (a.print_config) {
            std::cout << bimslam::rig::PrintConfig(o.config);
            return kExitOk;
        }
        if (!live) {
            o.recording = a.recording;
            if (a.speed == "max") {
                o.speed = 0;
            } else {
                try {
                    o.speed = std::stod(a.speed);
                } catch (const std::exception&) {
                    o.speed = -1;
                }
                if (!(o.speed > 0 && o.speed <= 100)) {
                    std::cerr << "bimslam-rig: --speed " << a.speed
                              << ": expected a factor in (0, 100] or max\n";
                    return kExitBadInput;
                }
            }
        }
        o.duration_s = a.duration_s;
        o.lcm_log = a.lcm_log;
        const bimslam::rig::RunSummary s = bimslam::rig::RunRig(o);
        PrintSummary(s, a.json);
        return kExitOk;
    } catch (const bimslam::common::Error& e) {
        std::cerr << "bimslam-rig: " << e.what() << "\n";
        return ExitCodeFor(e.code());
    } catch (const std::exception& e) {
        std::cerr << "bimslam-rig: " << e.what() << "\n";
        return kExitFailure;
    }
}

void CommonOptions(CLI::App* cmd, Args& a) {
    cmd->add_option("--config", a.config_file, "YAML configuration (--print-config lists keys)");
    cmd->add_flag("--handheld", a.handheld, "No CAN: LiDAR + Ouster IMU only");
    cmd->add_flag("--print-config", a.print_config,
                  "Print the effective configuration (every key, unit and range) and exit");
    cmd->add_option("--session-root", a.session_root, "Overrides session.root");
    cmd->add_flag("--no-record", a.no_record, "Write no session");
    cmd->add_option("--duration", a.duration_s,
                    "Stop after this many seconds of running, on this machine's clock (a replay at "
                    "--speed max covers more of its recording in them; 0: never)")
        ->check(CLI::NonNegativeNumber);
    cmd->add_flag("--json", a.json, "Print the summary at exit as JSON");
    cmd->add_option("--lcm-log", a.lcm_log,
                    "Also write every LCM message published to this LCM log (the format of "
                    "lcm-logger, read by lcm-logplayer): the lossless record of the run's LCM "
                    "output, which UDP multicast cannot promise to a busy receiver");
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{
        "bimslam-rig: the on-board mapping firmware (Ouster OS1 + Go1 CAN -> LiDAR odometry, "
        "keyframes, LCM, sessions).\nRun 'bimslam-rig <mode> --help' for the options."};
    app.require_subcommand(1);
    // BIMSLAM_VERSION and BIMSLAM_ARCH from CMake (the project's version, the target's processor).
    app.set_version_flag("--version", "bimslam-rig " BIMSLAM_VERSION " (" BIMSLAM_ARCH ")");
    Args a;
    int exit_code = kExitOk;
    CLI::App* live = app.add_subcommand("live", "Run on the sensor's UDP stream and the CAN bus");
    CommonOptions(live, a);
    live->footer(
        "Listens on sensor.lidar_port / sensor.imu_port (else the metadata's) for the Ouster,\n"
        "reads the Go1 from can.source, publishes on LCM and writes a new session under\n"
        "session.root. SIGINT/SIGTERM finish the session. Under systemd: Type=notify.");
    live->callback([&] { exit_code = Run(a, true); });
    CLI::App* rp = app.add_subcommand(
        "replay", "Hardware-in-the-loop from a recording: the live ingest code, paced");
    rp->add_option("recording", a.recording,
                   "Capture folder (lidar.pcap, metadata.json, go1_can.log), x.pcap with "
                   "x.json beside it, or a ROS 1 bag from ouster-ros (.bag: packet topics and "
                   "the metadata topic)")
        ->required();
    rp->add_option("--can", a.can_log, "Go1 CAN log (candump -l or pcap) to use");
    rp->add_option("--speed", a.speed,
                   "1, 2, ... times real time, or max (as fast as possible); a replay loses "
                   "nothing at any speed")
        ->capture_default_str();
    CommonOptions(rp, a);
    rp->callback([&] { exit_code = Run(a, false); });
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int code = app.exit(e);
        return code == 0 ? kExitOk : kExitBadInput;
    }
    return exit_code;
}
