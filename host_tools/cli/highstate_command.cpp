// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// bimslam can highstate: what a recording of a Go1's own UDP traffic holds (tcpdump on the
// bridge's host, or the simulator's go1_highstate.pcap): the HighStates the robot sent, checked
// as the bridge checks them (drivers/go1/high_state.hpp: size, head, levelFlag, CRC in either
// form), and which CRC form the robot uses. The bench check of firmware/go1_bridge/README.md.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>

#include "algorithms/common/status.hpp"
#include "drivers/go1/high_state.hpp"
#include "drivers/net/packet_recording.hpp"
#include "host_tools/cli/command.hpp"

namespace bimslam::cli {
namespace {

struct HighStateOptions {
    std::string file;
    uint16_t go1_port = 8082;  // the sport-mode computer's HighState port (comm.h examples)
    bool json = false;
};

// The checks' outcome over the recording.
struct HighStateCounts {
    uint64_t from_go1 = 0;  // datagrams from the Go1's port
    uint64_t to_go1 = 0;    // datagrams to it (HighCmds)
    uint64_t other = 0;     // neither
    uint64_t plain = 0, scrambled = 0;
    uint64_t wrong_size = 0, bad_head = 0, bad_level_flag = 0, bad_crc = 0;
    int64_t first_ns = 0, last_ns = 0;
    bool have_first = false;
    go1::HighState first, last;  // the first and last accepted

    uint64_t accepted() const { return plain + scrambled; }
    const char* FormName() const {
        if (plain > 0 && scrambled > 0) return "mixed";
        if (scrambled > 0) return "scrambled";
        return plain > 0 ? "plain" : "none";
    }
    const char* Form() const {
        if (plain > 0 && scrambled > 0) return "plain and scrambled (mixed)";
        if (scrambled > 0) return "scrambled (the SDK's encryptCRC)";
        if (plain > 0) return "plain CRC-32";
        return "none: no HighState passed the checks";
    }
};

void Count(const net::UdpDatagram& d, HighStateCounts& c) {
    go1::HighState hs;
    go1::CrcForm form = go1::CrcForm::kPlain;
    switch (go1::ParseHighState(d.payload, hs, &form)) {
        case go1::ParseResult::kOk:
            ++(form == go1::CrcForm::kScrambled ? c.scrambled : c.plain);
            if (!c.have_first) {
                c.first = hs;
                c.first_ns = d.timestamp_ns;
                c.have_first = true;
            }
            c.last = hs;
            c.last_ns = d.timestamp_ns;
            return;
        case go1::ParseResult::kWrongSize:
            ++c.wrong_size;
            return;
        case go1::ParseResult::kBadHead:
            ++c.bad_head;
            return;
        case go1::ParseResult::kBadLevelFlag:
            ++c.bad_level_flag;
            return;
        case go1::ParseResult::kBadCrc:
            ++c.bad_crc;
            return;
    }
}

nlohmann::json Values(const go1::HighState& s) {
    return {{"mode", s.mode},
            {"gait_type", s.gait_type},
            {"position_m", s.position},
            {"velocity", s.velocity},
            {"yaw_speed_radps", s.yaw_speed},
            {"body_height_m", s.body_height},
            {"imu_rpy_rad", s.imu.rpy},
            {"foot_force_raw", s.foot_force},
            {"battery_soc_percent", s.bms.soc}};
}

nlohmann::json ToJson(const HighStateOptions& o, const HighStateCounts& c) {
    const double span_s = c.accepted() > 1 ? 1e-9 * double(c.last_ns - c.first_ns) : 0.0;
    nlohmann::json j = {{"file", o.file},
                        {"go1_port", o.go1_port},
                        {"datagrams_from_go1", c.from_go1},
                        {"datagrams_to_go1", c.to_go1},
                        {"other_datagrams", c.other},
                        {"accepted", c.accepted()},
                        {"crc_plain", c.plain},
                        {"crc_scrambled", c.scrambled},
                        {"crc_form", c.FormName()},
                        {"rejected",
                         {{"size", c.wrong_size},
                          {"head", c.bad_head},
                          {"level_flag", c.bad_level_flag},
                          {"crc", c.bad_crc}}},
                        {"span_s", span_s},
                        {"rate_hz", span_s > 0 ? double(c.accepted() - 1) / span_s : 0.0}};
    if (c.have_first) {
        j["first"] = Values(c.first);
        j["last"] = Values(c.last);
    }
    return j;
}

void PrintText(const nlohmann::json& j, const HighStateCounts& c) {
    std::printf("file        %s\n", j["file"].get<std::string>().c_str());
    std::printf("datagrams   %llu from the Go1's port %u, %llu to it (HighCmds), %llu other\n",
                static_cast<unsigned long long>(c.from_go1), j["go1_port"].get<unsigned>(),
                static_cast<unsigned long long>(c.to_go1),
                static_cast<unsigned long long>(c.other));
    std::printf(
        "accepted    %llu HighStates over %.2f s (%.1f Hz): %llu with the plain CRC, %llu "
        "with the scrambled CRC\n",
        static_cast<unsigned long long>(c.accepted()), j["span_s"].get<double>(),
        j["rate_hz"].get<double>(), static_cast<unsigned long long>(c.plain),
        static_cast<unsigned long long>(c.scrambled));
    std::printf("rejected    %llu size, %llu head, %llu levelFlag, %llu CRC (neither form)\n",
                static_cast<unsigned long long>(c.wrong_size),
                static_cast<unsigned long long>(c.bad_head),
                static_cast<unsigned long long>(c.bad_level_flag),
                static_cast<unsigned long long>(c.bad_crc));
    std::printf("CRC form    %s\n", c.Form());
    if (!c.have_first) return;
    for (const auto& [which, s] : {std::pair{"first", &c.first}, std::pair{"last", &c.last}}) {
        std::printf(
            "%-11s mode %u gait %u, position %.3f %.3f %.3f m, velocity %.3f %.3f %.3f, "
            "yawSpeed %.3f rad/s, body height %.3f m, SoC %u %%\n",
            which, s->mode, s->gait_type, s->position[0], s->position[1], s->position[2],
            s->velocity[0], s->velocity[1], s->velocity[2], s->yaw_speed, s->body_height,
            s->bms.soc);
    }
}

int HighStates(const HighStateOptions& o) {
    net::PacketRecording recording(o.file);
    HighStateCounts c;
    net::UdpDatagram d;
    while (recording.Next(d)) {
        if (d.src_port == o.go1_port) {
            ++c.from_go1;
            Count(d, c);
        } else if (d.dst_port == o.go1_port) {
            ++c.to_go1;
        } else {
            ++c.other;
        }
    }
    if (c.from_go1 == 0) {
        throw common::Error(common::StatusCode::kParseError,
                            o.file + ": no UDP datagram from port " + std::to_string(o.go1_port) +
                                " (" + std::to_string(c.to_go1 + c.other) +
                                " others): not a recording of a Go1's HighStates (--go1-port?)");
    }
    const nlohmann::json j = ToJson(o, c);
    if (o.json) {
        std::cout << j.dump(2) << "\n";
    } else {
        PrintText(j, c);
    }
    // Nothing that passed the checks: the recording cannot say which form the robot sends.
    return c.accepted() > 0 ? kExitOk : kExitFailure;
}

}  // namespace

void AddHighStateCommand(CLI::App& can, int& exit_code) {
    auto o = std::make_shared<HighStateOptions>();
    CLI::App* cmd = can.add_subcommand(
        "highstate",
        "The Go1's HighState datagrams in a UDP recording (e.g. tcpdump -w on the bridge's "
        "host): checked as bimslam-go1-bridge checks them (size, head, levelFlag, CRC), with "
        "the CRC form the robot sends (plain or scrambled) and the first and last values. Exit "
        "1 when none passes the checks");
    cmd->add_option("FILE", o->file, "pcap or pcapng, optionally .gz")->required();
    cmd->add_option("--go1-port", o->go1_port, "The Go1's UDP port (HighStates come from it)")
        ->capture_default_str();
    cmd->add_flag("--json", o->json, "machine-readable output");
    cmd->callback([o, &exit_code] { exit_code = Run([&] { return HighStates(*o); }); });
}

}  // namespace bimslam::cli
