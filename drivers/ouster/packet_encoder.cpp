// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "drivers/ouster/packet_encoder.hpp"

#include <cstring>

#include "drivers/ouster/crc64.hpp"

namespace bimslam::ouster {
namespace {
void Store16(uint8_t* p, uint16_t v) { std::memcpy(p, &v, 2); }
void Store32(uint8_t* p, uint32_t v) { std::memcpy(p, &v, 4); }
void Store64(uint8_t* p, uint64_t v) { std::memcpy(p, &v, 8); }
void StoreF32(uint8_t* p, double v) {
    const float f = static_cast<float>(v);
    std::memcpy(p, &f, 4);
}

uint32_t FieldValue(const LidarFrame& frame, Field f, size_t i) {
    return frame.VisitField(f, [i](const auto& image) { return static_cast<uint32_t>(image[i]); });
}
}  // namespace

PacketEncoder::PacketEncoder(const SensorInfo& info, bool fill_crc)
    : info_(info), format_(info), fill_crc_(fill_crc) {}

int PacketEncoder::packets_per_frame() const {
    return format_.columns_per_frame() / format_.columns_per_packet();
}

void PacketEncoder::EncodeLidarPacket(const LidarFrame& frame, int k, uint8_t* out) const {
    const PacketFormat& f = format_;
    std::memset(out, 0, f.lidar_packet_size());
    if (!f.legacy()) {
        // STANDARD: packet_type 0,16 frame_id 16,16 init_id 32,24 prod_sn 56,40.
        // FUSA: packet_type 0,8 init_id 8,24 frame_id 32,32 prod_sn 88,40.
        const bool fusa = f.header_type() == HeaderType::kFusa;
        uint8_t* sn = out + (fusa ? 11 : 7);
        if (fusa) {
            Store32(out, 1u | (info_.init_id & 0xFFFFFF) << 8);
            Store32(out + 4, frame.frame_id);
        } else {
            Store16(out, 1);
            Store16(out + 2, static_cast<uint16_t>(frame.frame_id));
            Store32(out + 4, info_.init_id & 0xFFFFFF);  // byte 7 is overwritten by prod_sn
        }
        for (int i = 0; i < 5; ++i) sn[i] = static_cast<uint8_t>(info_.prod_sn >> (8 * i));
    }
    const int w = f.columns_per_frame(), h = f.pixels_per_column();
    for (int c = 0; c < f.columns_per_packet(); ++c) {
        const int v = k * f.columns_per_packet() + c;
        uint8_t* col = out + (f.Column(out, c) - out);
        Store64(col, frame.timestamp[v]);
        Store16(col + 8, static_cast<uint16_t>(v));
        if (f.legacy()) {
            Store16(col + 10, static_cast<uint16_t>(frame.frame_id));
            // 90112 encoder ticks per turn (spec, LEGACY column header).
            Store32(col + 12, static_cast<uint32_t>(uint64_t(v) * 90112 / w));
            Store32(col + 16 + h * f.pixel_size(), frame.status[v]);
        } else {
            Store16(col + 10, static_cast<uint16_t>(frame.status[v]));
        }
        if ((frame.status[v] & 1u) == 0) continue;  // invalid columns carry zeros
        uint8_t* pixels = col + (f.Pixels(col) - col);
        for (int u = 0; u < h; ++u) {
            uint8_t* px = pixels + u * f.pixel_size();
            for (const FieldSpec& s : f.fields()) {
                const uint32_t value = FieldValue(frame, s.field, frame.Index(u, v));
                uint32_t word = Load32(px + 4 * s.word);
                word |= ((value / s.multiplier) & s.mask) << s.shift;
                Store32(px + 4 * s.word, word);
            }
        }
    }
    if (fill_crc_ && f.HasCrcFooter()) {
        const size_t n = f.lidar_packet_size();
        Store64(out + n - 8, Crc64Xz(out, n - 8));
    }
}

void PacketEncoder::EncodeLegacyImuPacket(const ImuSample& s, uint64_t sys_time_ns,
                                          uint8_t* out) const {
    const Eigen::Matrix3d R_imu_sensor =
        info_.imu_to_sensor_transform.topLeftCorner<3, 3>().transpose();
    const Eigen::Vector3d a_g = R_imu_sensor * s.accel / kStandardGravity;
    const Eigen::Vector3d w_deg = R_imu_sensor * s.gyro * (180.0 / M_PI);
    Store64(out, sys_time_ns);
    Store64(out + 8, s.time_ns);
    Store64(out + 16, s.gyro_time_ns);
    for (int i = 0; i < 3; ++i) StoreF32(out + 24 + 4 * i, a_g[i]);
    for (int i = 0; i < 3; ++i) StoreF32(out + 36 + 4 * i, w_deg[i]);
}

}  // namespace bimslam::ouster
