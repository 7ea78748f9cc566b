// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// `bimslam live --serve` (issue 35, item 5): the rig's pose on the storey's plan as a page served
// by Debian's cpp-httplib, on this machine only unless told. An LCM log of bim_pose_t (the rig
// searching, then localised on a walk along the sample office's reference keyframes) is served
// as its last frame; the page is opened in headless chromium, and its JSON read with cpp-httplib's
// client. The terminal frame of a real rig's log is checked in rig_lcm_test.cpp.
#include <gtest/gtest.h>
#include <httplib.h>
#include <ifaddrs.h>
#include <netinet/in.h>
#include <signal.h>

#include <bimslam/bim_pose_t.hpp>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <lcm/lcm-cpp.hpp>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>

#include "algorithms/localization/rig_map.hpp"
#include "tests/integration/headless_chromium.hpp"
#include "tests/integration/map_test_support.hpp"

namespace bimslam {
namespace {
namespace BIMSLAM_UNITY_ID {
namespace fs = std::filesystem;
using namespace map_test;

// The sample office's package, from the model alone.
fs::path Package() {
    return Fixture("office_rigmap",
                   [](const fs::path& d) {
                       MustRun("rig-map " + (Building() / "building.ifc").string() + " -o " +
                               (d / "office.rigmap").string());
                   }) /
           "office.rigmap";
}

// bim_pose_t at 10 Hz: five searching, then localised along the first `walked` reference
// keyframes of the ground floor (the base where the keyframe's sensor is).
fs::path WriteLog(const fs::path& file, const localization::RigMap& map, size_t walked) {
    lcm::LogFile log(file.string(), "w");
    EXPECT_TRUE(log.good()) << file;
    int64_t t = 1'700'000'000'000'000'000;
    const auto write = [&](const bimslam::bim_pose_t& m) {
        std::vector<uint8_t> buffer(size_t(m.getEncodedSize()));
        m.encode(buffer.data(), 0, int(buffer.size()));
        lcm::LogEvent e{};
        e.timestamp = t / 1000;
        e.channel = "BIMSLAM_BIM_POSE";
        e.datalen = int32_t(buffer.size());
        e.data = buffer.data();
        EXPECT_EQ(log.writeEvent(&e), 0);
    };
    bimslam::bim_pose_t m{};
    m.schema_version = bimslam::bim_pose_t::SCHEMA_VERSION;
    for (int i = 0; i < 5; ++i, t += 100'000'000) {
        m.sample_time_ns = m.publish_time_ns = t;
        m.state = bimslam::bim_pose_t::STATE_SEARCHING;
        for (double& v : m.position) v = NAN;
        for (double& v : m.orientation) v = NAN;
        write(m);
    }
    size_t n = 0;
    for (size_t k = 0; k < map.keyframes.size() && n < walked; ++k) {
        if (map.keyframe_storey[k] != 0) continue;
        const Eigen::Isometry3d& T = map.keyframes[k];
        const Eigen::Quaterniond q(T.linear());
        m.sample_time_ns = m.publish_time_ns = (t += 100'000'000);
        m.state = bimslam::bim_pose_t::STATE_LOCALISED;
        m.consistent_loops = 4;
        m.num_hypotheses = 1;
        for (int i = 0; i < 3; ++i) m.position[i] = T.translation()[i];
        m.orientation[0] = q.w(), m.orientation[1] = q.x(), m.orientation[2] = q.y(),
        m.orientation[3] = q.z();
        m.storey = map.storeys[0].name;
        const int s = localization::SpaceAt(map, T.translation());
        m.space_name = s >= 0 ? map.spaces[size_t(s)].name : "";
        write(m);
        ++n;
    }
    EXPECT_EQ(n, walked);
    return file;
}

// `bimslam live ... --serve --port 0` started in the background: its pid and the port it printed.
struct Served {
    pid_t pid = -1;
    int port = 0;
    std::string out, err;
};

Served Serve(const std::string& args, const fs::path& dir) {
    Served s;
    const fs::path out = dir / "live.out", err = dir / "live.err";
    s.pid = test::Spawn(kCli + " live " + args, out, err);
    const std::string prefix = "serving http://";
    for (int i = 0; i < 600 && s.port == 0; ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        s.out = io::ReadFileToString(out);
        const size_t a = s.out.find(prefix);
        const size_t colon = s.out.find(':', s.out.find("//", a) + 2);
        if (a != std::string::npos && colon != std::string::npos) {
            s.port = std::atoi(s.out.c_str() + colon + 1);
        }
    }
    s.err = io::ReadFileToString(err);
    return s;
}

void Stop(Served& s) {
    if (s.pid <= 0) return;
    kill(s.pid, SIGTERM);
    EXPECT_EQ(test::Wait(s.pid), 0) << "bimslam live exits 0 on SIGTERM";
    s.pid = -1;
}

// An IPv4 address of this machine that is not loopback, if it has one.
std::optional<std::string> OtherAddress() {
    ifaddrs* list = nullptr;
    if (getifaddrs(&list) != 0) return std::nullopt;
    std::optional<std::string> found;
    for (ifaddrs* i = list; i && !found; i = i->ifa_next) {
        if (!i->ifa_addr || i->ifa_addr->sa_family != AF_INET) continue;
        const auto* in = reinterpret_cast<const sockaddr_in*>(i->ifa_addr);
        const uint32_t a = ntohl(in->sin_addr.s_addr);
        if ((a >> 24) == 127) continue;
        found = std::to_string(a >> 24) + "." + std::to_string((a >> 16) & 255) + "." +
                std::to_string((a >> 8) & 255) + "." + std::to_string(a & 255);
    }
    freeifaddrs(list);
    return found;
}

TEST(LivePage, ALogsLastFrameIsServedOnLoopbackAndDrawnInABrowser) {
    const fs::path package = Package();
    const localization::RigMap map = localization::ReadRigMap(package);
    test::TempDir tmp;
    const fs::path log = WriteLog(tmp / "walk.lcmlog", map, 20);
    Served s = Serve(
        "--map " + package.string() + " --log " + log.string() + " --serve --port 0 --seconds 300",
        tmp.path());
    ASSERT_GT(s.port, 0) << s.out << s.err;
    EXPECT_NE(s.out.find("serving http://127.0.0.1:"), std::string::npos) << s.out;

    // The JSON, through cpp-httplib's client.
    httplib::Client client("127.0.0.1", s.port);
    const auto state = client.Get("/state.json");
    ASSERT_TRUE(state) << httplib::to_string(state.error());
    EXPECT_EQ(state->status, 200);
    const nlohmann::json st = nlohmann::json::parse(state->body);
    EXPECT_EQ(st.at("state"), "localised");
    EXPECT_EQ(st.at("messages"), 25);
    EXPECT_EQ(st.at("storey_name"), map.storeys[0].name);
    EXPECT_GE(st.at("walk").size(), 2u);
    const auto plan = client.Get("/plan.json");
    ASSERT_TRUE(plan);
    const nlohmann::json p = nlohmann::json::parse(plan->body);
    ASSERT_EQ(p.at("storeys").size(), map.storeys.size());
    EXPECT_GT(p.at("storeys").at(0).at("walls").size(), 200u);
    EXPECT_EQ(client.Get("/nothing")->status, 404);

    // Not on the machine's other addresses (the default --bind is 127.0.0.1).
    if (const auto other = OtherAddress()) {
        httplib::Client outside(*other, s.port);
        outside.set_connection_timeout(2);
        EXPECT_FALSE(outside.Get("/state.json")) << "answered on " << *other;
    } else {
        std::cout << "no non-loopback IPv4 address here: the loopback-only check was not run\n";
    }

    // The page in a browser: the header names the state, storey and space; the walls, the walk
    // and the rig are drawn.
    if (test::Chromium().empty()) {
        std::cout << "SKIPPED the page in a browser: chromium is not installed\n";
    } else {
        const test::PageRun run =
            test::OpenHeadless("http://127.0.0.1:" + std::to_string(s.port) + "/#selftest",
                               "live_page.png", "1300,800");
        const nlohmann::json& t = run.selftest;
        ASSERT_TRUE(t.is_object());
        EXPECT_EQ(t.at("state"), "localised");
        EXPECT_EQ(t.at("storey"), map.storeys[0].name);
        EXPECT_NE(t.at("header").get<std::string>().find("on " + map.storeys[0].name),
                  std::string::npos)
            << t;
        EXPECT_EQ(t.at("walls"), p.at("storeys").at(0).at("walls").size());
        EXPECT_GE(t.at("walk"), 2);
        EXPECT_EQ(t.at("rig"), true);
        EXPECT_GT(t.at("painted_pixels"), 2000);
        EXPECT_TRUE(t.at("errors").empty()) << t.at("errors");
        EXPECT_TRUE(run.console.empty()) << run.console;
    }
    Stop(s);
}

// Refused, not shared: httplib's default SO_REUSEPORT let a second server bind the same port
// (and the kernel split the requests between the two pages) until live_server.cpp set its own
// socket options.
TEST(LivePage, AnAddressInUseIsRefusedNamingIt) {
    const fs::path package = Package();
    test::TempDir tmp;
    const fs::path log = WriteLog(tmp / "walk.lcmlog", localization::ReadRigMap(package), 3);
    Served first = Serve(
        "--map " + package.string() + " --log " + log.string() + " --serve --port 0 --seconds 300",
        tmp.path());
    ASSERT_GT(first.port, 0) << first.out << first.err;
    const std::string port = std::to_string(first.port);
    const auto second = test::RunCommand(kCli + " live --map " + package.string() + " --log " +
                                         log.string() + " --serve --seconds 5 --port " + port);
    EXPECT_EQ(second.exit_code, 1) << second.out << second.err;
    EXPECT_NE(second.err.find("127.0.0.1:" + port), std::string::npos) << second.err;
    Stop(first);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam
