// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/live/live_server.hpp"

#include <httplib.h>
#include <sys/socket.h>

#include <chrono>
#include <cmath>
#include <nlohmann/json.hpp>

#include "algorithms/common/status.hpp"
#include "host_tools/live/live_assets.hpp"

namespace bimslam::live {
namespace {

// Centimetres are the plan's detail: rounding keeps the documents small (a storey's walls are a
// few thousand points).
double Cm(double v) { return std::round(v * 100) / 100; }

nlohmann::json Xy(const Eigen::Vector2d& p) { return {Cm(p.x()), Cm(p.y())}; }
nlohmann::json Xyz(const Eigen::Vector3d& p) { return {Cm(p.x()), Cm(p.y()), Cm(p.z())}; }

}  // namespace

std::string PlanJson(const PlanView& view, double refresh_hz) {
    nlohmann::json storeys = nlohmann::json::array();
    const auto& plans = view.plans();
    for (size_t s = 0; s < plans.size(); ++s) {
        nlohmann::json walls = nlohmann::json::array();
        for (const Eigen::Vector2d& w : plans[s].walls) walls.push_back(Xy(w));
        storeys.push_back({{"name", view.map().storeys[s].name},
                           {"elevation_m", view.map().storeys[s].elevation_m},
                           {"min", Xy(plans[s].min)},
                           {"max", Xy(plans[s].max)},
                           {"walls", std::move(walls)}});
    }
    return nlohmann::json{{"refresh_hz", refresh_hz}, {"storeys", std::move(storeys)}}.dump();
}

std::string StateJson(const PlanView& view, const LiveState& st, size_t messages) {
    const auto& storeys = view.map().storeys;
    const bool known = st.storey >= 0 && size_t(st.storey) < storeys.size();
    nlohmann::json walk = nlohmann::json::array();
    for (const Eigen::Vector3d& p : st.walk) {
        nlohmann::json q = Xyz(p);
        q.push_back(localization::StoreyAt(storeys, p.z()));
        walk.push_back(std::move(q));
    }
    return nlohmann::json{{"state", st.state},
                          {"consistent_loops", st.consistent_loops},
                          {"hypotheses", st.hypotheses},
                          {"t_s", st.t_s},
                          {"localised", st.position.has_value()},
                          {"position", st.position ? Xyz(*st.position) : nlohmann::json()},
                          {"yaw_deg", st.yaw * 180 / M_PI},
                          {"storey", st.storey},
                          {"storey_name", known ? storeys[size_t(st.storey)].name : ""},
                          {"space", st.space},
                          {"walk", std::move(walk)},
                          {"messages", messages}}
        .dump();
}

LiveServer::LiveServer(const PlanView& view, double refresh_hz)
    : view_(view),
      plan_json_(PlanJson(view, refresh_hz)),
      server_(std::make_unique<httplib::Server>()),
      state_json_(StateJson(view, LiveState{}, 0)) {
    // SO_REUSEADDR only: httplib's default adds SO_REUSEPORT, with which a second `bimslam live`
    // on the same port binds too and the kernel shares the requests between the two pages.
    server_->set_socket_options([](int sock) {
        const int yes = 1;
        setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    });
    const std::string page = LiveAsset("live.html");
    server_->Get("/", [page](const httplib::Request&, httplib::Response& res) {
        res.set_content(page, "text/html; charset=utf-8");
    });
    server_->Get("/plan.json", [this](const httplib::Request&, httplib::Response& res) {
        res.set_content(plan_json_, "application/json");
    });
    server_->Get("/state.json", [this](const httplib::Request&, httplib::Response& res) {
        std::string body;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            body = state_json_;
        }
        res.set_header("Cache-Control", "no-store");
        res.set_content(body, "application/json");
    });
}

LiveServer::~LiveServer() { Stop(); }

void LiveServer::Start(const std::string& host, int port) {
    const bool bound = port == 0 ? (port_ = server_->bind_to_any_port(host)) > 0
                                 : server_->bind_to_port(host, port);
    if (!bound) {
        throw common::Error(common::StatusCode::kUnavailable,
                            "cannot serve on " + host + ":" + std::to_string(port) +
                                " (address in use, or not one of this machine's)");
    }
    if (port != 0) port_ = port;
    thread_ = std::thread([this] {
        server_->listen_after_bind();
        ended_ = true;
    });
    // httplib's stop() does nothing before the loop runs, so a Stop() right after Start() would
    // wait forever on the thread: the loop is running when Start() returns.
    while (!server_->is_running() && !ended_) {
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    if (ended_) {
        thread_.join();
        throw common::Error(common::StatusCode::kUnavailable,
                            "cannot serve on " + host + ":" + std::to_string(port_));
    }
}

void LiveServer::Publish(const LiveState& state, size_t messages) {
    std::string json = StateJson(view_, state, messages);
    std::lock_guard<std::mutex> lock(mutex_);
    state_json_.swap(json);
}

void LiveServer::Stop() {
    if (!thread_.joinable()) return;
    server_->stop();
    thread_.join();
}

}  // namespace bimslam::live
