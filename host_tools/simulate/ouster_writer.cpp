// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/simulate/ouster_writer.hpp"

#include <algorithm>
#include <cstdlib>

#include "algorithms/common/status.hpp"
#include "drivers/net/ipv4.hpp"
#include "drivers/ouster/builtin_sensor.hpp"
#include "drivers/ouster/metadata.hpp"

namespace bimslam::simulate {
namespace {

constexpr int64_t kLatencyNs = 60'000;  // sensor to host over a direct gigabit link
constexpr uint16_t kDefaultLidarPort = 7502, kDefaultImuPort = 7503;

}  // namespace

ouster::SensorInfo SensorFor(const SensorSpec& spec) {
    ouster::SensorInfo info;
    if (!spec.metadata.empty()) {
        info = ouster::LoadMetadata(spec.metadata);
    } else {
        const std::string& m = spec.lidar_mode;
        const size_t x = m.find('x');
        const int columns = x == std::string::npos ? 0 : std::atoi(m.substr(0, x).c_str());
        const int rate = x == std::string::npos ? 0 : std::atoi(m.substr(x + 1).c_str());
        ouster::LidarProfile profile;
        if (spec.udp_profile == "LEGACY") {
            profile = ouster::LidarProfile::kLegacy;
        } else if (spec.udp_profile == "RNG19") {
            profile = ouster::LidarProfile::kRng19Rfl8Sig16Nir16;
        } else if (spec.udp_profile == "RNG15") {
            profile = ouster::LidarProfile::kRng15Rfl8Nir8;
        } else if (spec.udp_profile == "DUAL") {
            profile = ouster::LidarProfile::kRng19Rfl8Sig16Nir16Dual;
        } else {
            throw common::Error(common::StatusCode::kInvalidArgument,
                                "sensor.udp_profile = '" + spec.udp_profile +
                                    "': must be LEGACY, RNG19, RNG15 or DUAL");
        }
        try {
            info = ouster::BuiltinOuster(spec.model, profile, columns, rate);
        } catch (const common::Error& e) {
            throw common::Error(e.code(), "sensor.model = '" + spec.model + "', lidar_mode = '" +
                                              m + "': " + e.what());
        }
        // Firmware 3.x: the newer profiles' packets carry a CRC-64 footer.
        info.build_rev = "v3.0.1";
        info.fw_major = 3;
        info.fw_minor = 0;
        info.fw_patch = 1;
    }
    if (info.format.imu_profile != ouster::ImuProfile::kLegacy) {
        throw common::FileError(common::StatusCode::kInvalidArgument, info.source, 0,
                                "IMU profile " + std::string(ToString(info.format.imu_profile)) +
                                    ": the simulator writes LEGACY IMU packets only");
    }
    return info;
}

OusterWriter::OusterWriter(const ouster::SensorInfo& info, net::PcapWriter& writer,
                           const NetworkSpec& network, uint64_t seed, int64_t host_minus_sensor_ns,
                           int64_t jump_at_ns, int64_t jump_ns)
    : info_(info),
      encoder_(info, /*fill_crc=*/true),
      writer_(writer),
      network_(network),
      loss_rng_(seed ^ 0x1055ull),
      host_minus_sensor_ns_(host_minus_sensor_ns),
      jump_at_ns_(jump_at_ns),
      jump_ns_(jump_ns),
      sensor_ip_(*net::ParseIpv4("169.254.42.10")),
      host_ip_(*net::ParseIpv4("169.254.42.1")) {
    frame_.Reset(encoder_.format());
    packet_.resize(encoder_.format().lidar_packet_size());
}

void OusterWriter::Send(int64_t sensor_ns, uint16_t port, std::span<const uint8_t> payload) {
    // Datagrams are written in order, so one generator decides every loss reproducibly.
    if (network_.packet_loss > 0 &&
        std::uniform_real_distribution<double>(0, 1)(loss_rng_) < network_.packet_loss) {
        ++stats_.lost_packets;
        return;
    }
    writer_.WriteUdp(sensor_ns + kLatencyNs + host_minus_sensor_ns_, sensor_ip_, port, host_ip_,
                     port, payload, network_.fragment ? 1500 : 0);
    stats_.bytes += payload.size();
    port == info_.udp_port_imu.value_or(kDefaultImuPort) ? ++stats_.imu_packets
                                                         : ++stats_.lidar_packets;
}

void OusterWriter::SendImuUpTo(std::span<const ouster::ImuSample> imu, size_t& next,
                               int64_t sensor_ns) {
    for (; next < imu.size() && int64_t(imu[next].time_ns) <= sensor_ns; ++next) {
        ouster::ImuSample stamped = imu[next];
        stamped.time_ns = Stamp(imu[next].time_ns);
        stamped.gyro_time_ns = Stamp(imu[next].gyro_time_ns);
        encoder_.EncodeLegacyImuPacket(stamped, stamped.time_ns, imu_packet_.data());
        Send(int64_t(imu[next].time_ns), info_.udp_port_imu.value_or(kDefaultImuPort), imu_packet_);
    }
}

void OusterWriter::WriteFrame(uint32_t index, const simulation::ScanImage& image,
                              std::span<const uint64_t> column_ns,
                              std::span<const ouster::ImuSample> imu) {
    ouster::LidarFrame& f = frame_;
    std::copy(image.range_mm.begin(), image.range_mm.end(), f.range.begin());
    if (!f.reflectivity.empty())
        std::copy(image.reflectivity.begin(), image.reflectivity.end(), f.reflectivity.begin());
    if (!f.signal.empty()) std::copy(image.signal.begin(), image.signal.end(), f.signal.begin());
    // Ambient light indoors: a dim, even background.
    if (!f.near_ir.empty()) std::fill(f.near_ir.begin(), f.near_ir.end(), uint16_t(320));
    f.frame_id = index & 0xFFFF;
    for (int v = 0; v < f.w; ++v) {
        f.timestamp[size_t(v)] = Stamp(column_ns[size_t(v)]);
        f.measurement_id[size_t(v)] = uint16_t(v);
        f.status[size_t(v)] = 1;
    }
    const int per_packet = encoder_.format().columns_per_packet();
    size_t next_imu = 0;
    for (int p = 0; p < encoder_.packets_per_frame(); ++p) {
        // Sent when its last column is measured.
        const int64_t sent = int64_t(column_ns[size_t(std::min((p + 1) * per_packet, f.w) - 1)]);
        SendImuUpTo(imu, next_imu, sent);
        encoder_.EncodeLidarPacket(f, p, packet_.data());
        Send(sent, info_.udp_port_lidar.value_or(kDefaultLidarPort), packet_);
    }
    SendImuUpTo(imu, next_imu, INT64_MAX);
}

void OusterWriter::WriteImu(std::span<const ouster::ImuSample> imu) {
    size_t next = 0;
    SendImuUpTo(imu, next, INT64_MAX);
}

}  // namespace bimslam::simulate
