// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// bimslam ouster replay: a recording's lidar and IMU datagrams sent to a rig at the recorded
// pace (host_tools/capture/udp_replay.hpp), so `bimslam-rig live` can be tested with real packets
// on a real socket.
#include <unistd.h>

#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>

#include "algorithms/common/status.hpp"
#include "algorithms/io/capture_files.hpp"
#include "drivers/net/ipv4.hpp"
#include "drivers/ouster/frame_batcher.hpp"
#include "drivers/ouster/imu_packet.hpp"
#include "drivers/ouster/metadata.hpp"
#include "host_tools/capture/ouster_capture.hpp"
#include "host_tools/capture/udp_replay.hpp"
#include "host_tools/cli/command.hpp"

namespace bimslam::cli {
namespace {

struct ReplayArgs {
    std::string recording;
    std::string to = "127.0.0.1";
    std::string speed = "1";
    std::optional<uint16_t> lidar_port, imu_port;
    double duration_s = 0;
    bool json = false;
};

int Replay(const ReplayArgs& a) {
    const io::CaptureFiles files = io::ResolveCapture(a.recording);
    const ouster::SensorInfo info = capture::LoadRecordingInfo(files);
    const auto to = net::ParseIpv4(a.to);
    if (!to) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            "--to: '" + a.to + "' is not a dotted IPv4 address");
    }
    capture::UdpReplayOptions o;
    o.recording = files.packets;
    o.to_ip = *to;
    if (a.speed == "max") {
        o.speed = 0;
    } else {
        try {
            o.speed = std::stod(a.speed);
        } catch (const std::exception&) {
            o.speed = -1;
        }
        if (!(o.speed > 0 && o.speed <= 100)) {
            throw common::Error(common::StatusCode::kInvalidArgument,
                                "--speed " + a.speed + ": expected a factor in (0, 100] or max");
        }
    }
    // The recorded ports: the metadata's, else guessed from the packet sizes.
    std::optional<uint16_t> lidar = info.udp_port_lidar, imu = info.udp_port_imu;
    if (files.bag) {
        // A bag's topics say which packet is which: its "recorded" ports are labels.
        lidar = o.bag_lidar_port = lidar.value_or(7502);
        imu = o.bag_imu_port = imu.value_or(uint16_t(*lidar == 7503 ? 7502 : 7503));
    }
    if (!lidar) {
        const ouster::FrameBatcher batcher(info);
        const ouster::ImuDecoder decoder(info);
        const net::PortGuess g = net::GuessPortsInCapture(
            files.packets, batcher.format().lidar_packet_size(), decoder.packet_size());
        lidar = g.lidar_port;
        if (!imu) imu = g.imu_port;
    }
    if (!lidar) {
        throw common::FileError(common::StatusCode::kParseError, files.packets.string(), 0,
                                "no Ouster lidar packets found (no port in the metadata)");
    }
    o.ports[*lidar] = a.lidar_port.value_or(*lidar);
    if (imu) o.ports[*imu] = a.imu_port.value_or(*imu);
    o.max_duration_s = a.duration_s;
    const bool tty = !a.json && ::isatty(STDERR_FILENO);
    if (tty) o.progress = [](double t) { std::cerr << "\rsent " << int(t) << " s" << std::flush; };
    const capture::UdpReplayReport r = capture::ReplayUdp(o);
    if (tty) std::cerr << "\r";
    if (a.json) {
        std::cout << nlohmann::json{{"sent", r.sent},
                                    {"failed", r.failed},
                                    {"bytes", r.bytes},
                                    {"skipped", r.skipped},
                                    {"capture_s", r.capture_s},
                                    {"wall_s", r.wall_s},
                                    {"max_late_ms", r.max_late_ms}}
                         .dump(2)
                  << "\n";
    } else {
        std::cout << std::fixed << std::setprecision(1) << "sent " << r.sent << " datagrams ("
                  << r.bytes / 1e6 << " MB, " << r.failed << " failed) to " << a.to << " ports "
                  << o.ports[*lidar] << (imu ? "/" + std::to_string(o.ports[*imu]) : "") << ": "
                  << r.capture_s << " s of capture in " << r.wall_s << " s, at most "
                  << std::setprecision(2) << r.max_late_ms << " ms behind schedule\n";
    }
    return r.failed == 0 ? kExitOk : kExitFailure;
}

}  // namespace

void AddOusterReplayCommand(CLI::App& ouster, int& exit_code) {
    auto a = std::make_shared<ReplayArgs>();
    CLI::App* cmd = ouster.add_subcommand(
        "replay", "Send a recording's lidar and IMU packets to a rig at the recorded pace");
    cmd->add_option("recording", a->recording,
                    "Capture folder, x.pcap with x.json (else metadata.json) beside it, or a "
                    "ROS 1 bag from ouster-ros (.bag)")
        ->required();
    cmd->add_option("--to", a->to, "IPv4 address of the rig")->capture_default_str();
    cmd->add_option("--speed", a->speed, "1, 2, ... times real time, or max")
        ->capture_default_str();
    cmd->add_option("--lidar-port", a->lidar_port, "destination lidar port (default: recorded)");
    cmd->add_option("--imu-port", a->imu_port, "destination IMU port (default: recorded)");
    cmd->add_option("--duration", a->duration_s, "stop after this many seconds of capture")
        ->check(CLI::NonNegativeNumber);
    cmd->add_flag("--json", a->json, "print the summary as JSON");
    cmd->footer(
        "One sendmmsg per batch of datagrams due together. The rig side:\n"
        "  bimslam-rig live --config rig.yaml   (sensor.lidar_port/imu_port as sent here)\n"
        "The same with tcpreplay on a real interface: tcpreplay -i eth0 --multiplier=1 x.pcap\n"
        "(README.md, \"Hardware in the loop\").");
    cmd->callback([a, &exit_code] { exit_code = Run([&] { return Replay(*a); }); });
}

}  // namespace bimslam::cli
