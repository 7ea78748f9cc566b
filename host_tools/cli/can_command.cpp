// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// bimslam can info | decode: what a CAN recording holds, and the Go1 samples in it.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>

#include "drivers/can/go1_decoder.hpp"
#include "host_tools/capture/can_log.hpp"
#include "host_tools/cli/command.hpp"

namespace bimslam::cli {
namespace {

struct CanOptions {
    std::string file;
    bool json = false;
    bool csv = false;
};

std::string HexId(const common::CanFrame& f) {
    char buf[16];
    std::snprintf(buf, sizeof(buf), f.extended ? "0x%08X" : "0x%03X", f.id);
    return buf;
}

// Decoder counters that are faults (not "frames", "accepted", "samples", nor the benign second
// copy of a 5 ms message), plus what the log reader skipped.
nlohmann::json Faults(const can::Go1DecoderStats& s, const capture::CanLog& log) {
    nlohmann::json out = nlohmann::json::object();
    s.ForEach([&](const char* name, uint64_t v) {
        const std::string n = name;
        if (n != "frames" && n != "accepted" && n != "samples" && n != "duplicate") out[n] = v;
    });
    for (const auto& [cause, n] : log.Skipped()) out["log_" + cause] = n;
    return out;
}

int Info(const CanOptions& o) {
    capture::CanLog log(o.file);
    can::Go1Decoder decoder;
    common::CanFrame f;
    std::map<std::string, uint64_t> ids;
    uint64_t frames = 0, extended = 0, fd = 0, remote = 0, errors = 0, samples = 0;
    int64_t first = 0, last = 0;
    while (log.Next(f)) {
        if (frames++ == 0) first = f.timestamp_ns;
        last = f.timestamp_ns;
        ++ids[HexId(f)];
        extended += f.extended;
        fd += f.fd;
        remote += f.remote;
        errors += f.error;
        samples += static_cast<uint64_t>(decoder.Feed(f).samples);
    }
    samples += static_cast<uint64_t>(decoder.Flush());
    const double span_s = frames > 1 ? 1e-9 * double(last - first) : 0.0;
    const nlohmann::json faults = Faults(decoder.stats(), log);
    if (o.json) {
        const nlohmann::json j = {{"file", o.file},
                                  {"format", log.format()},
                                  {"frames", frames},
                                  {"ids", ids},
                                  {"span_s", span_s},
                                  {"extended", extended},
                                  {"fd", fd},
                                  {"remote", remote},
                                  {"error_frames", errors},
                                  {"go1_frames", decoder.stats().accepted},
                                  {"go1_samples", samples},
                                  {"faults", faults},
                                  {"truncated", log.truncated()}};
        std::cout << j.dump(2) << "\n";
        return kExitOk;
    }
    std::cout << "file        " << o.file << " (" << log.format()
              << (log.truncated() ? ", cut off" : "") << ")\n"
              << "frames      " << frames << " over " << span_s << " s: " << ids.size() << " ids, "
              << extended << " extended, " << fd << " FD, " << remote << " remote, " << errors
              << " error frames\n"
              << "ids        ";
    for (const auto& [id, n] : ids) std::cout << " " << id << ":" << n;
    std::cout << "\ngo1         " << decoder.stats().accepted << " frames accepted, " << samples
              << " samples\nfaults     ";
    bool any = false;
    for (const auto& [cause, n] : faults.items()) {
        if (n.get<uint64_t>() == 0) continue;
        std::cout << " " << cause << ":" << n;
        any = true;
    }
    std::cout << (any ? "" : " none") << "\n";
    return kExitOk;
}

// One row per sample; NaN (a signal sent as "not available") prints as nan / null.
const char* kColumns[] = {"host_time_s",
                          "bridge_time_s",
                          "counter",
                          "valid",
                          "fresh",
                          "vx",
                          "vy",
                          "yaw_rate",
                          "vz",
                          "body_height",
                          "foot_raise_height",
                          "gyro_x",
                          "gyro_y",
                          "gyro_z",
                          "accel_x",
                          "accel_y",
                          "accel_z",
                          "qw",
                          "qx",
                          "qy",
                          "qz",
                          "contact_fr",
                          "contact_fl",
                          "contact_rr",
                          "contact_rl",
                          "force_fr",
                          "force_fl",
                          "force_rr",
                          "force_rl",
                          "odom_x",
                          "odom_y",
                          "odom_z",
                          "odom_yaw",
                          "odom_reset",
                          "mode",
                          "gait",
                          "battery_soc",
                          "imu_temperature_c",
                          "udp_rx_lost",
                          "bridge_state",
                          "udp_link_ok",
                          "highstate_crc_ok"};

std::vector<double> Row(const can::Go1Sample& s) {
    std::vector<double> r = {1e-9 * double(s.host_time_ns),
                             1e-9 * double(s.bridge_time_ns),
                             double(s.counter),
                             double(s.valid),
                             double(s.fresh),
                             s.vx,
                             s.vy,
                             s.yaw_rate,
                             s.vz,
                             s.body_height,
                             s.foot_raise_height};
    r.insert(r.end(), s.gyro.begin(), s.gyro.end());
    r.insert(r.end(), s.accel.begin(), s.accel.end());
    r.insert(r.end(), s.quat_wxyz.begin(), s.quat_wxyz.end());
    for (bool c : s.foot_contact) r.push_back(c);
    for (uint16_t f : s.foot_force_raw) r.push_back(f);
    for (double v :
         {s.odom_x, s.odom_y, s.odom_z, s.odom_yaw, double(s.odom_reset), double(s.mode),
          double(s.gait), double(s.battery_soc), double(s.imu_temperature_c), double(s.udp_rx_lost),
          double(s.bridge_state), double(s.udp_link_ok), double(s.highstate_crc_ok)}) {
        r.push_back(v);
    }
    return r;
}

void Print(const can::Go1Sample& s, const CanOptions& o) {
    const std::vector<double> row = Row(s);
    if (o.json) {
        nlohmann::json j = nlohmann::json::object();
        for (size_t i = 0; i < row.size(); ++i) {
            j[kColumns[i]] = std::isfinite(row[i]) ? nlohmann::json(row[i]) : nullptr;
        }
        std::cout << j.dump() << "\n";
        return;
    }
    char buf[64];
    for (size_t i = 0; i < row.size(); ++i) {
        std::snprintf(buf, sizeof(buf), i < 2 ? "%.6f" : "%.9g", row[i]);
        std::cout << (i ? (o.csv ? "," : " ") : "") << buf;
    }
    std::cout << "\n";
}

int Decode(const CanOptions& o) {
    capture::CanLog log(o.file);
    can::Go1Decoder decoder;
    if (o.csv || !o.json) {
        for (size_t i = 0; i < std::size(kColumns); ++i) {
            std::cout << (i ? (o.csv ? "," : " ") : (o.csv ? "" : "# ")) << kColumns[i];
        }
        std::cout << "\n";
    }
    common::CanFrame f;
    uint64_t samples = 0;
    auto print_ready = [&] {
        for (const can::Go1Sample& s : decoder.ready()) {
            Print(s, o);
            ++samples;
        }
    };
    while (log.Next(f)) {
        if (decoder.Feed(f).samples > 0) print_ready();
    }
    if (decoder.Flush() > 0) print_ready();
    if (samples == 0) {
        std::cerr << "bimslam: " << o.file << ": no Go1 samples (" << decoder.stats().frames
                  << " frames, " << decoder.stats().foreign_id << " with other ids)\n";
    }
    return kExitOk;
}

}  // namespace

void AddCanCommands(CLI::App& app, int& exit_code) {
    CLI::App* can = app.add_subcommand("can",
                                       "CAN recordings (candump -l logs, pcaps): inspect, "
                                       "decode the Go1 frames of go1_odometry.dbc; check a "
                                       "recording of the Go1's HighState datagrams");
    can->require_subcommand(1);
    auto info_opt = std::make_shared<CanOptions>();
    CLI::App* info = can->add_subcommand(
        "info", "Frames, ids, time span and faults (E2E checks and unreadable lines) of a log");
    info->add_option("FILE", info_opt->file, "candump -l log or pcap/pcapng, optionally .gz")
        ->required();
    info->add_flag("--json", info_opt->json, "machine-readable output");
    info->callback([info_opt, &exit_code] { exit_code = Run([&] { return Info(*info_opt); }); });

    auto dec_opt = std::make_shared<CanOptions>();
    CLI::App* dec = can->add_subcommand(
        "decode", "Print the Go1 samples of a log, one a line (SI units; NaN = not available)");
    dec->add_option("FILE", dec_opt->file, "candump -l log or pcap/pcapng, optionally .gz")
        ->required();
    auto* json = dec->add_flag("--json", dec_opt->json, "JSON Lines: one object per sample");
    auto* csv = dec->add_flag("--csv", dec_opt->csv, "CSV with a header line");
    json->excludes(csv);
    dec->callback([dec_opt, &exit_code] { exit_code = Run([&] { return Decode(*dec_opt); }); });
    AddHighStateCommand(*can, exit_code);
}

}  // namespace bimslam::cli
