// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// `bimslam live --serve`: the same plan and state as the terminal frame, as a local web page
// (issue 35, item 5). The HTTP server is Debian's cpp-httplib (libcpp-httplib-dev), in a thread
// of its own; the page (assets/live.html, embedded at build time) fetches plan.json once and
// state.json at the refresh rate and draws them on a canvas.
//
//   GET /            the page
//   GET /plan.json   {"refresh_hz", "storeys": [{"name", "elevation_m", "min": [x, y],
//                    "max": [x, y], "walls": [[x, y], ...]}]}, the model's metres
//   GET /state.json  {"state", "consistent_loops", "hypotheses", "t_s", "localised",
//                    "position": [x, y, z] | null, "yaw_deg", "storey", "storey_name", "space",
//                    "walk": [[x, y, z, storey], ...], "messages"}
#pragma once

#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "host_tools/live/plan_view.hpp"

namespace httplib {
class Server;
}

namespace bimslam::live {

class LiveServer {
public:
    // `view` (and the package under it) must outlive the server.
    LiveServer(const PlanView& view, double refresh_hz);
    ~LiveServer();
    LiveServer(const LiveServer&) = delete;
    LiveServer& operator=(const LiveServer&) = delete;

    // Binds host:port (port 0: a free one, see port()) and serves from a thread of its own.
    // Throws common::Error (kUnavailable) naming the address when it cannot be bound.
    void Start(const std::string& host, int port);
    int port() const { return port_; }
    // What /state.json answers from now on; `messages` is how many bim_pose_t came so far.
    void Publish(const LiveState& state, size_t messages);
    // Stops serving and joins the thread (also on destruction).
    void Stop();

private:
    const PlanView& view_;
    std::string plan_json_;
    std::unique_ptr<httplib::Server> server_;
    std::thread thread_;
    std::atomic<bool> ended_{false};
    std::mutex mutex_;
    std::string state_json_;
    int port_ = 0;
};

// The JSON documents of the two endpoints (above), exposed for the tests.
std::string PlanJson(const PlanView& view, double refresh_hz);
std::string StateJson(const PlanView& view, const LiveState& state, size_t messages);

}  // namespace bimslam::live
