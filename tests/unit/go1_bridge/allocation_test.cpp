// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The bridge's per-cycle path must not allocate once set up (DESIGN.md, "Hot path"): Bridge
// OnPoll / OnDatagram / OnTick (through a link loss and back), UdpClient Send / Receive, and the
// candump sink's Send. Its binary links the counting operator new of
// tests/support/allocation_counter.hpp.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <memory>

#include "drivers/go1/high_state.hpp"
#include "firmware/go1_bridge/bridge.hpp"
#include "firmware/go1_bridge/sinks.hpp"
#include "firmware/go1_bridge/udp_client.hpp"
#include "tests/support/allocation_counter.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::go1_bridge {
namespace {
namespace BIMSLAM_UNITY_ID {

constexpr int64_t kMs = 1'000'000;

TEST(HotPath, BridgeCycleAndSinksDoNotAllocate) {
    test::TempDir dir;
    std::unique_ptr<FrameSink> sink = OpenCandumpSink((dir / "a.log").string());
    Bridge bridge;
    std::array<uint8_t, kHighStateSize> bytes{};
    std::array<uint8_t, kHighCmdSize> request{};
    std::array<common::CanFrame, Bridge::kMaxFramesPerTick> frames{};
    HighState hs;
    hs.head = kFrameHead;
    hs.level_flag = kHighLevel;
    hs.imu.quaternion = {1, 0, 0, 0};
    SerializeHighCmd(MakeIdleHighCmd(), request);

    const size_t before = test::Allocations();
    int64_t now = 1000 * kMs;
    for (int step = 0; step < 4000; ++step) {  // 2 s in 0.5 ms steps
        now += kMs / 2;
        const bool silent = step > 1000 && step < 2000;
        if (now % (2 * kMs) == 0) {
            bridge.OnPoll(now);
            if (!silent) {
                hs.position[0] = 0.001f * static_cast<float>(step);
                SerializeHighState(hs, bytes);
                bridge.OnDatagram(bytes, now + 100'000);
            }
        }
        if (now % (5 * kMs) == 0) {
            const size_t n = bridge.OnTick(now, now, frames);
            for (size_t i = 0; i < n; ++i) sink->Send(frames[i]);
        }
    }
    EXPECT_EQ(test::Allocations() - before, 0u);
    EXPECT_EQ(bridge.stats().link_losses, 1u);
    EXPECT_GT(sink->stats().sent, 1500u);
    EXPECT_EQ(sink->stats().failed, 0u);
    sink->Close();
}

TEST(HotPath, UdpClientSendAndReceiveDoNotAllocate) {
    // A peer on loopback that the client talks to.
    const int peer = ::socket(AF_INET, SOCK_DGRAM, 0);
    ASSERT_GE(peer, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ASSERT_EQ(::bind(peer, reinterpret_cast<sockaddr*>(&a), sizeof(a)), 0);
    socklen_t n = sizeof(a);
    ::getsockname(peer, reinterpret_cast<sockaddr*>(&a), &n);
    UdpClientConfig config;
    config.go1_address = "127.0.0.1";
    config.go1_port = ntohs(a.sin_port);
    config.local_address = "127.0.0.1";
    config.local_port = 0;
    UdpClient client(config);
    sockaddr_in to{};
    to.sin_family = AF_INET;
    to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    to.sin_port = htons(client.local_port());

    std::array<uint8_t, kHighCmdSize> request{};
    std::array<uint8_t, kHighStateSize> reply{};
    std::array<uint8_t, 2048> buffer{};
    int received = 0;
    const size_t before = test::Allocations();
    for (int i = 0; i < 200; ++i) {
        EXPECT_EQ(client.Send(request), 0);
        ::sendto(peer, reply.data(), reply.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof(to));
        for (int tries = 0; tries < 1000; ++tries) {
            const UdpClient::Received r = client.Receive(buffer);
            if (r.got) {
                EXPECT_EQ(r.size, kHighStateSize);
                ++received;
                break;
            }
        }
    }
    EXPECT_EQ(test::Allocations() - before, 0u);
    EXPECT_EQ(received, 200);
    ::close(peer);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::go1_bridge
