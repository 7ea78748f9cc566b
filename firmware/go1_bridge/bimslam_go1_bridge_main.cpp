// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// bimslam-go1-bridge: polls the Unitree Go1's HighState over UDP and emits the frames of
// drivers/can/go1_odometry.dbc on a CAN bus, into a candump log or over LCM
// (firmware/go1_bridge/README.md). It only ever sends the idle HighCmd: it commands no motion.
//
// Exit codes (DESIGN.md): 0 success, 1 failure while working (no CAN in the kernel, socket
// errors, a log that could not be written), 2 bad usage or bad option values.
#include <poll.h>
#include <signal.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <limits>
#include <memory>
#include <string>

#include "algorithms/common/can_frame.hpp"
#include "algorithms/common/status.hpp"
#include "algorithms/common/time.hpp"
#include "drivers/go1/high_state.hpp"
#include "firmware/go1_bridge/bridge.hpp"
#include "firmware/go1_bridge/sinks.hpp"
#include "firmware/go1_bridge/status_lcm.hpp"
#include "firmware/go1_bridge/udp_client.hpp"

namespace bimslam::go1_bridge {
namespace {

constexpr int kExitOk = 0;
constexpr int kExitFailure = 1;
constexpr int kExitBadInput = 2;
constexpr char kName[] = "bimslam-go1-bridge";

volatile std::sig_atomic_t g_stop_signal = 0;

extern "C" void OnStopSignal(int signal_number) { g_stop_signal = signal_number; }

void InstallSignalHandlers() {
    struct sigaction action {};
    action.sa_handler = OnStopSignal;
    sigemptyset(&action.sa_mask);
    action.sa_flags = 0;  // no SA_RESTART: ppoll returns EINTR at once
    sigaction(SIGINT, &action, nullptr);
    sigaction(SIGTERM, &action, nullptr);
}

struct Options {
    std::string go1 = "192.168.123.161:8082";
    std::string local_address = "0.0.0.0";
    uint16_t local_port = 8090;
    double poll_hz = 500;
    double link_timeout_ms = 0;
    std::string can_interface;
    std::string candump_path;
    std::string candump_interface = "can0";
    std::string lcm_url;
    std::string lcm_channel = "BIMSLAM_GO1_CAN";
    std::string status_lcm_url;  // empty: the --lcm URL, if any
    std::string status_lcm_channel = kStatusLcmChannel;
    double duration_s = 0;
    double status_interval_s = 2;
    int contact_on = BridgeConfig{}.contact_on_raw;
    int contact_off = BridgeConfig{}.contact_off_raw;
    bool no_crc_check = false;
};

int ExitCodeFor(common::StatusCode code) {
    using common::StatusCode;
    switch (code) {
        case StatusCode::kInvalidArgument:
        case StatusCode::kParseError:
        case StatusCode::kNotFound:
        case StatusCode::kAlreadyExists:
        case StatusCode::kOutOfRange:
            return kExitBadInput;
        default:
            return kExitFailure;
    }
}

std::string Number(double v) {
    char text[32];
    std::snprintf(text, sizeof(text), "%g", v);
    return text;
}

// Moves `deadline` past `now` by whole periods (absolute deadlines: no drift); counts the periods
// skipped when the loop fell behind by more than one.
void Advance(int64_t& deadline, int64_t period, int64_t now, uint64_t& skipped) {
    deadline += period;
    if (deadline <= now) {
        const int64_t behind = (now - deadline) / period + 1;
        skipped += static_cast<uint64_t>(behind);
        deadline += behind * period;
    }
}

struct LoopStats {
    uint64_t send_errors = 0;
    int last_send_error = 0;
    uint64_t receive_errors = 0;
    int last_receive_error = 0;
    uint64_t late_polls = 0;
    uint64_t late_ticks = 0;
};

void PrintStatus(double t, const Bridge& bridge, bool link, const FrameSink& sink,
                 const LoopStats& loop) {
    const BridgeStats& s = bridge.stats();
    const auto u = [](uint64_t v) { return static_cast<unsigned long long>(v); };
    std::printf(
        "%s: t=%.1f s  HighStates %llu (CRC %s)  CAN samples %llu  lost %llu  rejected %llu "
        "(CRC) %llu (size) %llu (head) %llu (levelFlag)  link %s  state %s  frames %llu  sink "
        "failures %llu  UDP errors %llu/%llu\n",
        kName, t, u(s.highstates), bridge.crc_forms_seen(), u(s.samples), u(s.lost),
        u(s.crc_failures), u(s.wrong_size), u(s.bad_head), u(s.bad_level_flag),
        link ? "up" : "DOWN", ToString(bridge.state()), u(s.frames), u(sink.stats().failed),
        u(loop.send_errors), u(loop.receive_errors));
    std::fflush(stdout);
}

void PrintSummary(double t, const Bridge& bridge, const FrameSink& sink, const LoopStats& loop,
                  int stop_signal) {
    const BridgeStats& s = bridge.stats();
    const auto u = [](uint64_t v) { return static_cast<unsigned long long>(v); };
    std::printf("%s: summary: ran %.2f s%s\n", kName, t,
                stop_signal == SIGINT    ? " (stopped by SIGINT)"
                : stop_signal == SIGTERM ? " (stopped by SIGTERM)"
                                         : "");
    std::printf(
        "  UDP: %llu HighCmds sent (%llu send errors%s%s), %llu datagrams, %llu HighStates "
        "accepted (%llu with the plain CRC, %llu with the scrambled CRC), %llu rejected for CRC, "
        "%llu for size, %llu for head, %llu for levelFlag, %llu samples lost, %llu receive "
        "errors\n",
        u(s.polls), u(loop.send_errors), loop.last_send_error ? ", last: " : "",
        loop.last_send_error ? std::strerror(loop.last_send_error) : "", u(s.datagrams),
        u(s.highstates), u(s.crc_plain), u(s.crc_scrambled), u(s.crc_failures), u(s.wrong_size),
        u(s.bad_head), u(s.bad_level_flag), u(s.lost), u(loop.receive_errors));
    std::printf("  HighState CRC form: %s\n", bridge.crc_forms_seen());
    std::printf(
        "  CAN: %llu samples (%llu with the link down, %llu ticks waited for data), %llu "
        "frames, %llu to %s, %llu failed\n",
        u(s.samples), u(s.placeholder_samples), u(s.skipped_ticks), u(s.frames),
        u(sink.stats().sent), sink.description().c_str(), u(sink.stats().failed));
    std::printf(
        "  link losses %llu, odometry resets %llu, groups sent not valid for bad values "
        "%llu, late polls/ticks %llu/%llu, final state %s\n",
        u(s.link_losses), u(s.odom_resets), u(s.unusable_groups), u(loop.late_polls),
        u(loop.late_ticks), ToString(bridge.state()));
    std::fflush(stdout);
}

// The options as the bridge's configuration (bad values: common::Error, exit 2).
BridgeConfig MakeBridgeConfig(const Options& o) {
    BridgeConfig config;
    if (!(o.poll_hz >= 100 && o.poll_hz <= 2000)) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            "--poll-hz: " + Number(o.poll_hz) +
                                " (must be 100 .. 2000: the CAN sample period is 10 ms)");
    }
    if (o.link_timeout_ms < 0) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            "--link-timeout-ms: " + Number(o.link_timeout_ms) + " is negative");
    }
    config.poll_period_ns = static_cast<int64_t>(std::llround(1e9 / o.poll_hz));
    config.link_timeout_ns = static_cast<int64_t>(std::llround(o.link_timeout_ms * 1e6));
    config.contact_on_raw = o.contact_on;
    config.contact_off_raw = o.contact_off;
    config.check_crc = !o.no_crc_check;
    return config;
}

// Where the CAN frames go (failures: exit 1, except files the user named wrongly: 2).
std::unique_ptr<FrameSink> OpenSink(const Options& o) {
    if (!o.can_interface.empty()) {
        try {
            return OpenSocketCanSink(o.can_interface);
        } catch (const common::Error& e) {
            throw common::Error(
                e.code(), std::string(e.what()) + "; without CAN, use --candump FILE or --lcm URL");
        }
    }
    if (!o.candump_path.empty()) {
        const std::filesystem::path folder =
            std::filesystem::absolute(o.candump_path).parent_path();
        if (!std::filesystem::is_directory(folder)) {
            throw common::Error(common::StatusCode::kNotFound,
                                "--candump: " + o.candump_path + ": the folder " + folder.string() +
                                    " does not exist");
        }
        return OpenCandumpSink(o.candump_path, o.candump_interface);
    }
    return OpenLcmSink(o.lcm_url, o.lcm_channel);
}

// The status on LCM: --status-lcm, else the --lcm URL, else none.
std::unique_ptr<StatusPublisher> OpenStatusPublisher(const Options& o) {
    const std::string& url = o.status_lcm_url.empty() ? o.lcm_url : o.status_lcm_url;
    if (url.empty()) return nullptr;
    return std::make_unique<StatusPublisher>(url, o.status_lcm_channel);
}

// The parts of one run, and its poll / tick / status loop on absolute deadlines.
class Runner {
public:
    Runner(const Options& o, const UdpClientConfig& udp_config, const BridgeConfig& config)
        : options_(o),
          config_(config),
          bridge_(config),  // validates
          sink_(OpenSink(o)),
          status_lcm_(OpenStatusPublisher(o)),
          udp_(udp_config) {
        SerializeHighCmd(MakeIdleHighCmd(), request_);
        std::printf(
            "%s: polling the Go1 at %s:%u from %s:%u at %.0f Hz (idle HighCmd, no motion); "
            "link timeout %.1f ms; CAN to %s%s%s%s\n",
            kName, udp_config.go1_address.c_str(), udp_config.go1_port,
            udp_config.local_address.c_str(), udp_.local_port(), o.poll_hz,
            static_cast<double>(config.EffectiveLinkTimeoutNs()) * 1e-6,
            sink_->description().c_str(), status_lcm_ ? "; status to " : "",
            status_lcm_ ? status_lcm_->description().c_str() : "",
            config.check_crc ? "" : "; HighState CRC NOT checked");
        std::fflush(stdout);
    }

    // Runs until SIGINT/SIGTERM or --duration; returns the exit code.
    int Run();

private:
    void ReceiveAll();
    void PublishStatus(int64_t now);
    int Finish();

    const Options& options_;
    BridgeConfig config_;
    Bridge bridge_;
    std::unique_ptr<FrameSink> sink_;
    std::unique_ptr<StatusPublisher> status_lcm_;
    UdpClient udp_;
    std::array<uint8_t, kHighCmdSize> request_{};
    std::array<uint8_t, 2048> datagram_{};
    std::array<common::CanFrame, Bridge::kMaxFramesPerTick> frames_{};
    LoopStats loop_;
    int64_t start_ = 0;
};

// Everything queued from the Go1, each stamped at its receive.
void Runner::ReceiveAll() {
    for (;;) {
        const UdpClient::Received r = udp_.Receive(datagram_);
        if (!r.got) {
            if (r.error != 0) {
                ++loop_.receive_errors;
                loop_.last_receive_error = r.error;
            }
            return;
        }
        const size_t size = r.truncated ? datagram_.size() : r.size;
        bridge_.OnDatagram(std::span<const uint8_t>(datagram_.data(), size),
                           common::MonotonicNow().ns);
    }
}

void Runner::PublishStatus(int64_t now) {
    if (!status_lcm_) return;
    StatusContext context;
    context.link_ok = bridge_.link_ok(now);
    context.uptime_ns = now - start_;
    context.host_now_ns = common::HostNow().ns;
    context.udp_errors = loop_.send_errors + loop_.receive_errors;
    context.sink = sink_->stats();
    status_lcm_->Publish(MakeStatusMessage(bridge_, context));
}

int Runner::Run() {
    InstallSignalHandlers();
    start_ = common::MonotonicNow().ns;
    const int64_t end = options_.duration_s > 0
                            ? start_ + static_cast<int64_t>(std::llround(options_.duration_s * 1e9))
                            : std::numeric_limits<int64_t>::max();
    const int64_t status_period =
        static_cast<int64_t>(std::llround(options_.status_interval_s * 1e9));
    constexpr int64_t kNever = std::numeric_limits<int64_t>::max();
    int64_t next_poll = start_;
    int64_t next_tick = start_ + bridge_.tick_ns();
    int64_t next_status = status_period > 0 ? start_ + status_period : kNever;
    int64_t next_status_lcm = status_lcm_ ? start_ + kStatusLcmPeriodNs : kNever;
    uint64_t unused = 0;

    pollfd pfd{};
    pfd.fd = udp_.fd();
    pfd.events = POLLIN;
    while (g_stop_signal == 0) {
        int64_t now = common::MonotonicNow().ns;
        if (now >= end) break;
        ReceiveAll();

        now = common::MonotonicNow().ns;
        if (now >= next_poll) {
            bridge_.OnPoll(now);
            const int err = udp_.Send(request_);
            if (err != 0) {
                ++loop_.send_errors;
                loop_.last_send_error = err;
            }
            Advance(next_poll, config_.poll_period_ns, now, loop_.late_polls);
        }
        if (now >= next_tick) {
            const size_t n = bridge_.OnTick(now, common::HostNow().ns, frames_);
            for (size_t i = 0; i < n; ++i) sink_->Send(frames_[i]);
            Advance(next_tick, bridge_.tick_ns(), now, loop_.late_ticks);
        }
        if (now >= next_status) {
            PrintStatus(static_cast<double>(now - start_) * 1e-9, bridge_, bridge_.link_ok(now),
                        *sink_, loop_);
            Advance(next_status, status_period, now, unused);
        }
        if (now >= next_status_lcm) {
            PublishStatus(now);
            Advance(next_status_lcm, kStatusLcmPeriodNs, now, unused);
        }

        // Sleep until the next deadline or a datagram.
        const int64_t wake = std::min({next_poll, next_tick, next_status, next_status_lcm, end});
        const int64_t wait = wake - common::MonotonicNow().ns;
        if (wait > 0) {
            timespec ts{};
            ts.tv_sec = static_cast<time_t>(wait / 1'000'000'000);
            ts.tv_nsec = static_cast<long>(wait % 1'000'000'000);
            ::ppoll(&pfd, 1, &ts, nullptr);
        }
    }
    return Finish();
}

// Closes the sink, publishes the final status and prints the summary.
int Runner::Finish() {
    const int64_t now = common::MonotonicNow().ns;
    int code = kExitOk;
    try {
        sink_->Close();
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s: error: %s\n", kName, e.what());
        code = kExitFailure;
    }
    PublishStatus(now);
    PrintSummary(static_cast<double>(now - start_) * 1e-9, bridge_, *sink_, loop_, g_stop_signal);
    if (status_lcm_ && status_lcm_->failures() > 0) {
        std::printf("  status messages that LCM refused: %llu\n",
                    static_cast<unsigned long long>(status_lcm_->failures()));
    }
    if (sink_->lossless() && sink_->stats().failed > 0) {
        std::fprintf(stderr, "%s: error: %llu frames could not be written to %s\n", kName,
                     static_cast<unsigned long long>(sink_->stats().failed),
                     sink_->description().c_str());
        code = kExitFailure;
    }
    return code;
}

int Run(const Options& o) {
    UdpClientConfig udp_config;
    ParseAddressAndPort(o.go1, "--go1", udp_config.go1_address, udp_config.go1_port);
    udp_config.local_address = o.local_address;
    udp_config.local_port = o.local_port;
    udp_config.Validate();
    Runner runner(o, udp_config, MakeBridgeConfig(o));
    return runner.Run();
}

}  // namespace
}  // namespace bimslam::go1_bridge

int main(int argc, char** argv) {
    using namespace bimslam::go1_bridge;
    Options o;
    CLI::App app{
        "bimslam-go1-bridge: polls a Unitree Go1's HighState over UDP (sending only the idle "
        "HighCmd: it never commands motion) and emits the frames of go1_odometry.dbc at their "
        "cycle times on SocketCAN, into a candump log or over LCM. Exactly one of --can, "
        "--candump, --lcm.\n"
        "Exit codes: 0 ok, 1 failure while working (e.g. no CAN in the kernel), 2 bad usage."};
    app.set_version_flag("--version", "bimslam-go1-bridge " BIMSLAM_VERSION " (" BIMSLAM_ARCH ")");
    app.add_option("--go1", o.go1, "The Go1 sport-mode computer's HighState endpoint, IP:PORT")
        ->capture_default_str();
    app.add_option("--local-address", o.local_address, "Local IPv4 address to bind")
        ->capture_default_str();
    app.add_option("--local-port", o.local_port,
                   "Local UDP port to bind (0: any free port; the SDK examples use 8090)")
        ->capture_default_str();
    app.add_option("--poll-hz", o.poll_hz, "HighCmd/HighState poll rate, 100..2000 Hz")
        ->capture_default_str();
    app.add_option("--link-timeout-ms", o.link_timeout_ms,
                   "UdpLinkOk drops when no valid HighState arrived for this long (0: 3 poll "
                   "periods)")
        ->capture_default_str();
    auto* can = app.add_option("--can", o.can_interface, "Send on this SocketCAN interface");
    auto* candump = app.add_option("--candump", o.candump_path, "Write a candump -l log file");
    auto* lcm = app.add_option("--lcm", o.lcm_url,
                               "Publish bimslam::can_frame_t on LCM, e.g. "
                               "udpm://239.255.76.67:7667?ttl=0");
    can->excludes(candump)->excludes(lcm);
    candump->excludes(lcm);
    app.add_option("--candump-interface", o.candump_interface,
                   "Interface name written into the candump log")
        ->capture_default_str();
    app.add_option("--lcm-channel", o.lcm_channel, "LCM channel for --lcm")->capture_default_str();
    app.add_option("--status-lcm", o.status_lcm_url,
                   "Publish the bridge's status (bimslam::go1_bridge_status_t: state, link, "
                   "counters, the HighState CRC form seen) at 2 Hz on this LCM URL; default: "
                   "the --lcm URL, if given");
    app.add_option("--status-lcm-channel", o.status_lcm_channel,
                   "LCM channel of the status messages")
        ->capture_default_str();
    app.add_option("--duration", o.duration_s, "Run this many seconds (0: until SIGINT/SIGTERM)")
        ->capture_default_str()
        ->check(CLI::NonNegativeNumber);
    app.add_option("--status-interval", o.status_interval_s,
                   "Seconds between status lines (0: none)")
        ->capture_default_str()
        ->check(CLI::NonNegativeNumber);
    app.add_option("--contact-on", o.contact_on, "Foot contact starts at this raw foot force")
        ->capture_default_str();
    app.add_option("--contact-off", o.contact_off,
                   "Foot contact ends at this raw foot force or below")
        ->capture_default_str();
    app.add_flag("--no-crc-check", o.no_crc_check,
                 "Forward HighStates whose CRC matches neither form, plain or scrambled "
                 "(HighStateCrcOk says so): bench diagnosis only. Wrong size, head or levelFlag "
                 "are always rejected");
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int code = app.exit(e);
        return code == 0 ? 0 : 2;
    }
    if (o.can_interface.empty() && o.candump_path.empty() && o.lcm_url.empty()) {
        std::fprintf(stderr,
                     "%s: error: choose where the frames go: --can IFACE, --candump FILE "
                     "or --lcm URL (see --help)\n",
                     kName);
        return 2;
    }
    try {
        return Run(o);
    } catch (const bimslam::common::Error& e) {
        std::fprintf(stderr, "%s: error: %s\n", kName, e.what());
        return ExitCodeFor(e.code());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s: error: %s\n", kName, e.what());
        return 1;
    }
}
