// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/capture/udp_replay.hpp"

#include <algorithm>
#include <chrono>
#include <thread>

#include "drivers/net/ipv4.hpp"
#include "drivers/net/packet_recording.hpp"
#include "drivers/net/udp_sender.hpp"

namespace bimslam::capture {

UdpReplayReport ReplayUdp(const UdpReplayOptions& o) {
    using Clock = std::chrono::steady_clock;
    net::PacketRecordingOptions ro;
    ro.bag_lidar_port = o.bag_lidar_port;
    ro.bag_imu_port = o.bag_imu_port;
    net::PacketRecording recording(o.recording, ro);
    net::UdpSenderConfig sc;
    sc.bind_address = o.bind_address;
    sc.bind_port = o.bind_port;
    net::UdpSender sender(sc);
    UdpReplayReport report;
    const Clock::time_point start = Clock::now();
    int64_t first_ns = -1;
    double next_progress = 1.0;
    net::UdpDatagram d;
    while (recording.Next(d)) {
        ++report.datagrams;
        const auto port = o.ports.find(d.dst_port);
        if (port == o.ports.end()) {
            ++report.skipped;
            continue;
        }
        if (first_ns < 0) first_ns = d.timestamp_ns;
        const double t = double(d.timestamp_ns - first_ns) * 1e-9;
        if (o.max_duration_s > 0 && t > o.max_duration_s) break;
        if (o.speed > 0) {
            const auto due = start + std::chrono::nanoseconds(int64_t(t / o.speed * 1e9));
            if (Clock::now() < due) {
                sender.Flush();  // what is due now goes out before the wait
                std::this_thread::sleep_until(due);
            }
            const double late =
                std::chrono::duration<double, std::milli>(Clock::now() - due).count();
            report.max_late_ms = std::max(report.max_late_ms, late);
        }
        sender.Add(o.to_ip, port->second, d.payload);
        report.capture_s = t;
        if (o.progress && t >= next_progress) {
            o.progress(t);
            next_progress = t + 1.0;
        }
    }
    sender.Flush();
    report.records = recording.records();
    report.sent = sender.stats().sent;
    report.failed = sender.stats().failed;
    report.bytes = sender.stats().bytes;
    report.wall_s = std::chrono::duration<double>(Clock::now() - start).count();
    return report;
}

}  // namespace bimslam::capture
