// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// SocketCAN: the configuration and the construction errors everywhere; live frames over `vcan0`
// where the kernel has CAN and the interface exists (specs/go1-can.md: this development machine
// has no CAN at all, and the live test says so when it skips).
#include "drivers/net/can_socket.hpp"

#include <gtest/gtest.h>
#include <linux/can.h>
#include <net/if.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <string>
#include <vector>

#include "algorithms/common/status.hpp"
#include "algorithms/common/time.hpp"

namespace bimslam::net {
namespace {
namespace BIMSLAM_UNITY_ID {

using common::CanFrame;
using common::Duration;

TEST(CanSocketConfig, Validation) {
    CanSocketConfig config;
    config.Validate();
    config.interface_name = "";
    EXPECT_THROW(config.Validate(), common::Error);
    config.interface_name = "a_name_of_16_chr";
    EXPECT_THROW(config.Validate(), common::Error);
    config = {};
    config.batch_size = 0;
    EXPECT_THROW(config.Validate(), common::Error);
    config = {};
    config.receive_buffer_bytes = -1;
    EXPECT_THROW(config.Validate(), common::Error);
    config = {};
    config.filters = {CanIdFilter::Exact(0x800)};
    EXPECT_THROW(config.Validate(), common::Error);
    config.filters = {CanIdFilter::Exact(0x800, true), CanIdFilter::Exact(0x7FF)};
    config.Validate();
    config.filters.assign(513, CanIdFilter::Exact(0x100));
    EXPECT_THROW(config.Validate(), common::Error);
    EXPECT_EQ(CanErrorClassName(0), "tx-timeout");
    EXPECT_EQ(CanErrorClassName(9), "error-counter");
    EXPECT_EQ(CanErrorClassName(10), "unknown");
}

// Without CAN in the kernel, or with CAN but without the interface: an error naming it.
TEST(CanSocket, ConstructionFailureNamesTheInterface) {
    CanSocketConfig config;
    config.interface_name = "bimslamnx0";
    try {
        CanSocket socket(config);
        ADD_FAILURE() << "opened a CAN interface that does not exist";
    } catch (const common::Error& e) {
        EXPECT_EQ(e.code(), common::StatusCode::kUnavailable);
        EXPECT_NE(std::string(e.what()).find("'bimslamnx0'"), std::string::npos) << e.what();
    }
}

// Empty when `vcan0` can be used, else why not.
std::string WhyNoVcan() {
    const int fd = ::socket(PF_CAN, SOCK_RAW, CAN_RAW);
    if (fd < 0) {
        return std::string("no SocketCAN in this kernel: socket(PF_CAN) failed: ") +
               std::strerror(errno);
    }
    ::close(fd);
    if (::if_nametoindex("vcan0") == 0) {
        return "no vcan0 interface (create it: ip link add dev vcan0 type vcan && ip link set up "
               "vcan0)";
    }
    return "";
}

CanFrame Frame(uint32_t id, std::vector<uint8_t> data, bool extended = false) {
    CanFrame f;
    f.id = id;
    f.extended = extended;
    f.len = static_cast<uint8_t>(data.size());
    std::copy(data.begin(), data.end(), f.data.begin());
    return f;
}

// Receives until `count` frames came or a second passed.
std::vector<CanFrame> ReceiveFrames(CanSocket& socket, size_t count) {
    std::vector<CanFrame> out;
    const int64_t until = common::MonotonicNow().ns + 1'000'000'000;
    while (out.size() < count && common::MonotonicNow().ns < until) {
        const CanBatch batch = socket.Receive(Duration::FromMilliseconds(100));
        out.insert(out.end(), batch.frames.begin(), batch.frames.end());
    }
    return out;
}

TEST(CanSocket, LiveFramesOverVcan) {
    const std::string why = WhyNoVcan();
    if (!why.empty()) GTEST_SKIP() << why;

    CanSocketConfig rx_config;
    rx_config.interface_name = "vcan0";
    rx_config.fd_frames = true;
    rx_config.filters = {CanIdFilter::Exact(0x100), CanIdFilter::Exact(0x101),
                         CanIdFilter::Exact(0x1234567, true)};
    CanSocket rx(rx_config);
    CanSocketConfig tx_config;
    tx_config.interface_name = "vcan0";
    tx_config.fd_frames = true;
    CanSocket tx(tx_config);

    // Nothing queued: a timeout.
    EXPECT_EQ(rx.Receive(Duration::FromMilliseconds(10)).code,
              common::StatusCode::kDeadlineExceeded);

    const int64_t before = common::HostNow().ns;
    EXPECT_EQ(tx.Send(Frame(0x100, {1, 2, 3})).code, common::StatusCode::kOk);
    EXPECT_EQ(tx.Send(Frame(0x200, {4})).code, common::StatusCode::kOk);  // filtered out
    EXPECT_EQ(tx.Send(Frame(0x1234567, {5, 6}, true)).code, common::StatusCode::kOk);
    CanFrame remote = Frame(0x101, {});
    remote.remote = true;
    remote.len = 2;
    EXPECT_EQ(tx.Send(remote).code, common::StatusCode::kOk);  // filters pass data frames only
    CanFrame fd = Frame(0x101, std::vector<uint8_t>(12, 0xAB));
    fd.fd = true;
    fd.fd_flags = 1;
    EXPECT_EQ(tx.Send(fd).code, common::StatusCode::kOk);
    EXPECT_EQ(tx.stats().sent, 5u);

    const std::vector<CanFrame> got = ReceiveFrames(rx, 3);
    ASSERT_EQ(got.size(), 3u);
    EXPECT_EQ(got[0].id, 0x100u);
    EXPECT_EQ(got[0].len, 3);
    EXPECT_EQ(got[0].data[2], 3);
    EXPECT_GE(got[0].timestamp_ns, before);
    EXPECT_TRUE(got[1].extended);
    EXPECT_EQ(got[1].id, 0x1234567u);
    EXPECT_TRUE(got[2].fd);
    EXPECT_EQ(got[2].len, 12);
    EXPECT_EQ(got[2].fd_flags & 1, 1);
    EXPECT_EQ(rx.stats().received, 3u);
    EXPECT_EQ(rx.stats().malformed, 0u);
    if (rx.kernel_timestamps()) {
        EXPECT_EQ(rx.stats().software_timestamps, 0u);
    }

    // What Send refuses.
    CanFrame error = Frame(0x04, {0, 0, 0, 0, 0, 0, 0, 0});
    error.error = true;
    EXPECT_EQ(tx.Send(error).code, common::StatusCode::kInvalidArgument);
    EXPECT_EQ(tx.Send(Frame(0x800, {})).code, common::StatusCode::kInvalidArgument);
    CanSocketConfig classic_only;
    classic_only.interface_name = "vcan0";
    CanSocket classic(classic_only);
    EXPECT_EQ(classic.Send(fd).code, common::StatusCode::kInvalidArgument);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::net
