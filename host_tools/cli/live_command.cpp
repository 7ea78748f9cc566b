// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// bimslam live: the rig's place in the model while it walks (issue 35, item 5): bim_pose_t from
// LCM drawn on the storey's plan in the terminal about twice a second, or the last frame of an
// LCM log (lcm-logger's, or bimslam-rig --lcm-log).
#include <bimslam/bim_pose_t.hpp>
#include <chrono>
#include <cmath>
#include <csignal>
#include <iostream>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <string>
#include <string_view>
#include <thread>

#include "algorithms/common/se3.hpp"
#include "algorithms/common/status.hpp"
#include "algorithms/localization/relocalizer.hpp"
#include "algorithms/localization/rig_map.hpp"
#include "host_tools/cli/command.hpp"
#include "host_tools/live/live_server.hpp"
#include "host_tools/live/plan_view.hpp"

namespace bimslam::cli {
namespace {

struct LiveArgs {
    std::string map;
    std::string url = "udpm://239.255.76.67:7667?ttl=0";
    std::string log;
    std::string channel = "BIMSLAM_BIM_POSE";
    int width = 100;
    double rate_hz = 2;
    double seconds = 0;
    bool serve = false;
    std::string bind = "127.0.0.1";
    int port = 8765;
};

volatile std::sig_atomic_t g_stop = 0;
void OnSignal(int) { g_stop = 1; }

// bim_pose_t.state is RelocalizerState's value (firmware/modules/lcm_bridge.cpp asserts the two
// agree, in the same build), so its names are the relocaliser's, as localization_states.csv and
// `bimslam localize` write them; "?" for a value it does not have.
std::string_view StateName(int8_t s) {
    return localization::ToString(localization::RelocalizerState(uint8_t(s)));
}

// One message into the frame's state: the pose and its storey (by name, else by height) when
// localised, the walk grown by every 10 cm.
void Update(live::LiveState& st, const bimslam::bim_pose_t& m, const localization::RigMap& map) {
    st.state = StateName(m.state);
    st.consistent_loops = m.consistent_loops;
    st.hypotheses = m.num_hypotheses;
    st.t_s = double(m.sample_time_ns) * 1e-9;
    const Eigen::Vector3d p(m.position[0], m.position[1], m.position[2]);
    if (m.state != bimslam::bim_pose_t::STATE_LOCALISED || !p.allFinite()) {
        st.position.reset();
        return;
    }
    st.position = p;
    st.space = m.space_name;
    const Eigen::Quaterniond q(m.orientation[0], m.orientation[1], m.orientation[2],
                               m.orientation[3]);
    st.yaw = common::Heading(q.normalized().toRotationMatrix());
    st.storey = localization::StoreyAt(map.storeys, p.z());
    for (size_t s = 0; s < map.storeys.size(); ++s) {
        if (map.storeys[s].name == m.storey) st.storey = int(s);
    }
    if (st.walk.empty() || (st.walk.back() - p).norm() > 0.1) st.walk.push_back(p);
}

using LiveClock = std::chrono::steady_clock;

bool TimeIsUp(const LiveArgs& a, LiveClock::time_point start) {
    return a.seconds > 0 &&
           std::chrono::duration<double>(LiveClock::now() - start).count() > a.seconds;
}

// With --serve: the page's server, bound and serving (its address printed), else none.
std::unique_ptr<live::LiveServer> Serve(const LiveArgs& a, const live::PlanView& view) {
    if (!a.serve) return nullptr;
    auto server = std::make_unique<live::LiveServer>(view, a.rate_hz);
    server->Start(a.bind, a.port);
    if (a.bind != "127.0.0.1" && a.bind != "::1" && a.bind != "localhost") {
        std::cerr << "bimslam live: serving on " << a.bind
                  << ", not only this machine: anyone who reaches it sees the rig's place\n";
    }
    std::signal(SIGINT, OnSignal);
    std::signal(SIGTERM, OnSignal);
    std::cout << "serving http://"
              << (a.bind.find(':') != std::string::npos ? "[" + a.bind + "]" : a.bind) << ":"
              << server->port() << "/ (Ctrl-C stops)" << std::endl;
    return server;
}

// Serves a log's last frame until Ctrl-C or --seconds.
void WaitForStop(const LiveArgs& a) {
    const auto start = LiveClock::now();
    while (!g_stop && !TimeIsUp(a, start)) {
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
}

int FromLog(const LiveArgs& a, const localization::RigMap& map, const live::PlanView& view) {
    lcm::LogFile log(a.log, "r");
    if (!log.good()) {
        throw common::FileError(common::StatusCode::kNotFound, a.log, 0,
                                "cannot be read as an LCM log");
    }
    live::LiveState st;
    size_t messages = 0;
    while (const lcm::LogEvent* e = log.readNextEvent()) {
        if (e->channel != a.channel) continue;
        bimslam::bim_pose_t m;
        if (m.decode(e->data, 0, int(e->datalen)) < 0) continue;
        Update(st, m, map);
        ++messages;
    }
    if (messages == 0) {
        throw common::FileError(
            common::StatusCode::kInvalidArgument, a.log, 0,
            "no bim_pose_t on " + a.channel + " (is localization.map set on the rig?)");
    }
    if (auto server = Serve(a, view)) {
        server->Publish(st, messages);
        WaitForStop(a);
        return kExitOk;
    }
    std::cout << view.Render(st, a.width);
    return kExitOk;
}

struct Receiver {
    const localization::RigMap* map;
    live::LiveState state;
    size_t messages = 0;
    void Handle(const lcm::ReceiveBuffer*, const std::string&, const bimslam::bim_pose_t* m) {
        Update(state, *m, *map);
        ++messages;
    }
};

int Live(const LiveArgs& a, const localization::RigMap& map, const live::PlanView& view) {
    lcm::LCM lcm(a.url);
    if (!lcm.good()) {
        throw common::Error(common::StatusCode::kUnavailable, "LCM " + a.url + ": cannot open");
    }
    Receiver r{&map, {}};
    lcm.subscribe(a.channel, &Receiver::Handle, &r);
    const auto server = Serve(a, view);
    std::signal(SIGINT, OnSignal);
    std::signal(SIGTERM, OnSignal);
    const auto start = LiveClock::now();
    auto next = start;
    while (!g_stop && !TimeIsUp(a, start)) {
        lcm.handleTimeout(50);
        if (LiveClock::now() < next) continue;
        next += std::chrono::milliseconds(int(1000 / a.rate_hz));
        if (server) {
            server->Publish(r.state, r.messages);
            continue;
        }
        std::cout << "\033[H\033[2J"
                  << (r.messages ? view.Render(r.state, a.width)
                                 : "waiting for bim_pose_t on " + a.channel + " (" + a.url + ")\n")
                  << std::flush;
    }
    return kExitOk;
}

}  // namespace

void AddLiveCommand(CLI::App& app, int& exit_code) {
    auto a = std::make_shared<LiveArgs>();
    auto* cmd = app.add_subcommand(
        "live",
        "The rig's place in the model as it walks: bim_pose_t (bimslam-rig with localization.map) "
        "from LCM drawn on its storey's plan in the terminal, with its walk and the "
        "relocaliser's state, redrawn about twice a second, or (--serve) as a page on this "
        "machine; or, with --log, the last frame of an LCM log (host_tools/live/README.md)");
    cmd->add_option("--map", a->map, "the rig's map package (bimslam rig-map): the plans")
        ->required();
    cmd->add_option("--url", a->url, "LCM provider URL")->capture_default_str();
    cmd->add_option("--log", a->log, "an LCM log instead of LCM: print its last frame and exit");
    cmd->add_option("--channel", a->channel, "bim_pose_t channel")->capture_default_str();
    cmd->add_option("--width", a->width, "plan width, characters")
        ->check(CLI::Range(20, 400))
        ->capture_default_str();
    cmd->add_option("--rate", a->rate_hz, "redraws a second")
        ->check(CLI::Range(0.1, 20.0))
        ->capture_default_str();
    cmd->add_option("--seconds", a->seconds, "stop after this long (0: until Ctrl-C)");
    cmd->add_flag("--serve", a->serve,
                  "instead of the terminal, serve the plan as a page (http://127.0.0.1:8765/ by "
                  "default) redrawn at --rate; with --log, the log's last frame until Ctrl-C");
    cmd->add_option("--bind", a->bind,
                    "the address to serve on: this machine only unless told (0.0.0.0: every "
                    "interface, so anyone on the network sees the rig's place)")
        ->capture_default_str();
    cmd->add_option("--port", a->port, "the page's TCP port (0: any free one, printed)")
        ->check(CLI::Range(0, 65535))
        ->capture_default_str();
    cmd->callback([a, &exit_code] {
        exit_code = Run([&] {
            const localization::RigMap map = localization::ReadRigMap(a->map);
            const live::PlanView view(map);
            return a->log.empty() ? Live(*a, map, view) : FromLog(*a, map, view);
        });
    });
}

}  // namespace bimslam::cli
