// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "drivers/ouster/imu_packet.hpp"

#include <cmath>
#include <cstring>

#include "drivers/ouster/crc64.hpp"
#include "drivers/ouster/packet_format.hpp"

namespace bimslam::ouster {
namespace {
float LoadF32(const uint8_t* p) {
    float v;
    std::memcpy(&v, p, 4);
    return v;
}
Eigen::Vector3d Load3(const uint8_t* p) {
    return Eigen::Vector3d(LoadF32(p), LoadF32(p + 4), LoadF32(p + 8));
}
constexpr size_t kNmeaHeader = 32, kNmeaBlock = 100, kNmeaSample = 36, kNmeaFooter = 32;
}  // namespace

std::string_view ToString(ImuReject r) {
    switch (r) {
        case ImuReject::kSize:
            return "size";
        case ImuReject::kPacketType:
            return "packet_type";
        case ImuReject::kProdSn:
            return "prod_sn";
        case ImuReject::kInitId:
            return "init_id";
        case ImuReject::kCrc:
            return "crc";
        case ImuReject::kNonFinite:
            return "non_finite";
    }
    return "?";
}

ImuDecoder::ImuDecoder(const SensorInfo& info)
    : info_(info),
      R_sensor_imu_(info.imu_to_sensor_transform.topLeftCorner<3, 3>()),
      packet_size_(info.format.imu_profile == ImuProfile::kLegacy
                       ? 48
                       : kNmeaHeader + kNmeaBlock +
                             kNmeaSample * size_t(info.format.imu_measurements_per_packet) +
                             kNmeaFooter) {}

ImuDecoder::Result ImuDecoder::Drop(ImuReject r) {
    ++stats_.rejected[static_cast<size_t>(r)];
    return {0, r};
}

ImuDecoder::Result ImuDecoder::Decode(const uint8_t* p, size_t size, std::span<ImuSample> out) {
    ++stats_.packets;
    if (size != packet_size_) return Drop(ImuReject::kSize);
    if (info_.format.imu_profile == ImuProfile::kLegacy) {
        ImuSample s;
        s.time_ns = Load64(p + 8);
        s.gyro_time_ns = Load64(p + 16);
        const Eigen::Vector3d a_g = Load3(p + 24), w_deg = Load3(p + 36);
        if (!a_g.allFinite() || !w_deg.allFinite()) return Drop(ImuReject::kNonFinite);
        s.accel = R_sensor_imu_ * (a_g * kStandardGravity);
        s.gyro = R_sensor_imu_ * (w_deg * (M_PI / 180.0));
        if (out.empty()) return {0, std::nullopt};
        out[0] = s;
        ++stats_.samples;
        return {1, std::nullopt};
    }
    // ACCEL32_GYRO32_NMEA: STANDARD header with packet_type 2.
    if (Load16(p) != 2) return Drop(ImuReject::kPacketType);
    if (info_.init_id != 0 && (Load32(p + 4) & 0xFFFFFF) != info_.init_id) {
        return Drop(ImuReject::kInitId);
    }
    uint64_t sn = 0;
    for (int i = 4; i >= 0; --i) sn = (sn << 8) | p[7 + i];
    if (info_.prod_sn != 0 && sn != info_.prod_sn) return Drop(ImuReject::kProdSn);
    const uint64_t crc = Load64(p + size - 8);
    if (crc != 0 && Crc64Xz(p, size - 8) != crc) return Drop(ImuReject::kCrc);
    size_t n = 0;
    const size_t count = size_t(info_.format.imu_measurements_per_packet);
    for (size_t i = 0; i < count && n < out.size(); ++i) {
        const uint8_t* q = p + kNmeaHeader + kNmeaBlock + i * kNmeaSample;
        if ((Load16(q + 10) & 1u) == 0) {
            ++stats_.invalid_samples;
            continue;
        }
        const Eigen::Vector3d a = Load3(q + 12), w = Load3(q + 24);
        if (!a.allFinite() || !w.allFinite()) {
            ++stats_.invalid_samples;
            continue;
        }
        ImuSample& s = out[n++];
        s.time_ns = s.gyro_time_ns = Load64(q);
        s.accel = R_sensor_imu_ * a;
        s.gyro = R_sensor_imu_ * w;
    }
    stats_.samples += n;
    return {n, std::nullopt};
}

}  // namespace bimslam::ouster
