// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Real UDP over loopback: the test sends datagrams to the source from its own sockets.
#include "drivers/net/udp_source.hpp"

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <fstream>
#include <string>
#include <vector>

#include "algorithms/common/status.hpp"
#include "algorithms/common/time.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::net {
namespace {
namespace BIMSLAM_UNITY_ID {

// A UDP socket bound to `address` (port chosen by the kernel) that sends to 127.0.0.1:port.
class Sender {
public:
    explicit Sender(const char* address) {
        fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
        EXPECT_GE(fd_, 0);
        sockaddr_in a{};
        a.sin_family = AF_INET;
        a.sin_addr.s_addr = htonl(*ParseIpv4(address));
        EXPECT_EQ(::bind(fd_, reinterpret_cast<const sockaddr*>(&a), sizeof(a)), 0)
            << "bind " << address;
        socklen_t length = sizeof(a);
        ::getsockname(fd_, reinterpret_cast<sockaddr*>(&a), &length);
        port_ = ntohs(a.sin_port);
    }
    ~Sender() { ::close(fd_); }
    void Send(uint16_t port, const std::string& bytes) const {
        sockaddr_in to{};
        to.sin_family = AF_INET;
        to.sin_port = htons(port);
        to.sin_addr.s_addr = htonl(0x7F000001);
        EXPECT_EQ(::sendto(fd_, bytes.data(), bytes.size(), 0,
                           reinterpret_cast<const sockaddr*>(&to), sizeof(to)),
                  static_cast<ssize_t>(bytes.size()));
    }
    uint16_t port() const { return port_; }

private:
    int fd_ = -1;
    uint16_t port_ = 0;
};

UdpSourceConfig LoopbackConfig() {
    UdpSourceConfig config;
    config.bind_address = "127.0.0.1";
    config.port = 0;  // the kernel picks a free port
    config.receive_buffer_bytes = 1 << 20;
    config.batch_size = 8;
    config.max_datagram_bytes = 9000;
    return config;
}

std::vector<std::string> ReceiveAll(UdpSource& source, size_t expected) {
    std::vector<std::string> out;
    for (int tries = 0; tries < 50 && out.size() < expected; ++tries) {
        const UdpBatch batch = source.Receive(common::Duration::FromMilliseconds(100));
        EXPECT_NE(batch.code, common::StatusCode::kIoError) << batch.error_number;
        for (const UdpDatagram& d : batch.datagrams) {
            out.emplace_back(reinterpret_cast<const char*>(d.payload.data()), d.payload.size());
        }
    }
    return out;
}

TEST(UdpSource, ReceivesBatchesWithKernelTimestamps) {
    UdpSource source(LoopbackConfig());
    ASSERT_NE(source.port(), 0);
    // qemu-user (the aarch64 tests) does not pass SO_TIMESTAMPNS to the kernel: the source then
    // stamps each batch with the time it read it (stats.software_timestamps), as on a kernel
    // without it. Natively the kernel's receive time is required.
    const bool kernel = source.kernel_timestamps();
    if (!test::Emulator()) {
        EXPECT_TRUE(kernel);
    }
    // Nothing queued: a timeout, not an error.
    const UdpBatch empty = source.Receive(common::Duration::FromMilliseconds(5));
    EXPECT_EQ(empty.code, common::StatusCode::kDeadlineExceeded);
    EXPECT_TRUE(empty.datagrams.empty());

    Sender sender("127.0.0.1");
    const int64_t before = common::HostNow().ns;
    for (int i = 0; i < 20; ++i)
        sender.Send(source.port(), std::string(6464, static_cast<char>(i)));
    const int64_t sent = common::HostNow().ns;
    // 20 datagrams queued: batches of at most 8.
    UdpBatch batch = source.Receive(common::Duration::FromMilliseconds(500));
    // Kernel times are taken before the last send returns; software ones when the batch is read.
    const int64_t after = kernel ? sent : common::HostNow().ns;
    ASSERT_EQ(batch.code, common::StatusCode::kOk);
    ASSERT_EQ(batch.datagrams.size(), 8u);
    int64_t last = 0;
    for (size_t i = 0; i < batch.datagrams.size(); ++i) {
        const UdpDatagram& d = batch.datagrams[i];
        EXPECT_EQ(d.payload.size(), 6464u);
        EXPECT_EQ(d.payload[0], static_cast<uint8_t>(i));
        EXPECT_EQ(d.src_ip, 0x7F000001u);
        EXPECT_EQ(d.src_port, sender.port());
        EXPECT_EQ(d.dst_ip, 0x7F000001u);  // IP_PKTINFO
        EXPECT_EQ(d.dst_port, source.port());
        EXPECT_GE(d.timestamp_ns, before);  // receive time, CLOCK_REALTIME
        EXPECT_LE(d.timestamp_ns, after);
        EXPECT_GE(d.timestamp_ns, last);
        last = d.timestamp_ns;
    }
    const auto rest = ReceiveAll(source, 12);
    ASSERT_EQ(rest.size(), 12u);
    EXPECT_EQ(rest[11][0], static_cast<char>(19));
    const UdpSourceStats& s = source.stats();
    EXPECT_EQ(s.received, 20u);
    EXPECT_EQ(s.batches, 3u);
    EXPECT_EQ(s.software_timestamps, kernel ? 0u : 20u);
    EXPECT_EQ(s.errors, 0u);
    EXPECT_GE(s.timeouts, 1u);
}

TEST(UdpSource, FiltersOtherSourcesAndDropsTruncated) {
    UdpSourceConfig config = LoopbackConfig();
    config.sensor_address = "127.0.0.1";
    UdpSource source(config);
    Sender sensor("127.0.0.1");
    Sender other("127.0.0.2");  // loopback accepts any 127/8 source address
    for (int i = 0; i < 5; ++i) {
        other.Send(source.port(), "not the sensor");
        sensor.Send(source.port(), "sensor " + std::to_string(i));
    }
    sensor.Send(source.port(), std::string(9001, 'x'));  // above max_datagram_bytes
    sensor.Send(source.port(), "last");
    const auto got = ReceiveAll(source, 6);
    ASSERT_EQ(got.size(), 6u);
    EXPECT_EQ(got[0], "sensor 0");
    EXPECT_EQ(got[4], "sensor 4");
    EXPECT_EQ(got[5], "last");
    EXPECT_EQ(source.stats().filtered, 5u);
    EXPECT_EQ(source.stats().truncated, 1u);
    EXPECT_EQ(source.stats().received, 6u);
}

TEST(UdpSource, ReportsAClampedReceiveBuffer) {
    long rmem_max = 0;
    std::ifstream("/proc/sys/net/core/rmem_max") >> rmem_max;
    ASSERT_GT(rmem_max, 0);
    // Within the limit: the kernel doubles the value and says nothing.
    UdpSourceConfig config = LoopbackConfig();
    config.receive_buffer_bytes = static_cast<int>(std::min<long>(rmem_max, 100'000));
    {
        UdpSource source(config);
        EXPECT_EQ(source.receive_buffer_bytes(), 2 * config.receive_buffer_bytes);
        EXPECT_TRUE(source.receive_buffer_warning().empty()) << source.receive_buffer_warning();
    }
    // Above it: clamped to rmem_max (doubled), with one warning naming the sysctl.
    if (rmem_max < (1L << 30)) {
        config.receive_buffer_bytes = static_cast<int>(rmem_max * 2);
        UdpSource source(config);
        EXPECT_EQ(source.receive_buffer_bytes(), 2 * rmem_max);
        EXPECT_NE(source.receive_buffer_warning().find("net.core.rmem_max"), std::string::npos)
            << source.receive_buffer_warning();
        std::cout << "warning: " << source.receive_buffer_warning() << "\n";
    }
}

TEST(UdpSource, SetupErrors) {
    UdpSourceConfig config = LoopbackConfig();
    config.bind_address = "localhost";
    EXPECT_THROW(UdpSource{config}, common::Error);
    config = LoopbackConfig();
    config.batch_size = 0;
    EXPECT_THROW(config.Validate(), common::Error);
    // A port already taken: kUnavailable naming the address and port.
    UdpSource first(LoopbackConfig());
    config = LoopbackConfig();
    config.port = first.port();
    try {
        UdpSource second(config);
        ADD_FAILURE() << "bound the same port twice";
    } catch (const common::Error& e) {
        EXPECT_EQ(e.code(), common::StatusCode::kUnavailable);
        EXPECT_NE(std::string(e.what()).find("127.0.0.1:" + std::to_string(first.port())),
                  std::string::npos)
            << e.what();
    }
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::net
