// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The byte layout of Ouster lidar packets for every UDP profile (specs/ouster-lidar.md, "LEGACY
// format" and "Newer UDP profiles"): sizes, header fields, column headers and the bit positions
// of every pixel field. Pure arithmetic on a byte pointer; no allocation, no exceptions after
// construction.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string_view>
#include <vector>

#include "drivers/ouster/sensor_info.hpp"

namespace bimslam::ouster {

// Pixel fields, with the dtypes of the Ouster SDK (shared/data/README.md, "What a _digest.json
// holds"): RANGE/RANGE2 uint32 mm, SIGNAL uint16, REFLECTIVITY uint8, NEAR_IR uint16, FLAGS uint8.
enum class Field : uint8_t {
    kRange,
    kRange2,
    kSignal,
    kSignal2,
    kReflectivity,
    kReflectivity2,
    kNearIr,
    kFlags,
    kFlags2,
};
inline constexpr int kNumFields = 9;
enum class FieldType : uint8_t { kU8, kU16, kU32 };

std::string_view ToString(Field f);  // "RANGE", "RANGE2", ... as the SDK names them
FieldType TypeOf(Field f);

// A field inside a pixel: ((32-bit little-endian word `word`) >> shift) & mask, times multiplier.
struct FieldSpec {
    Field field;
    uint8_t word;
    uint8_t shift;
    uint32_t mask;
    uint32_t multiplier;  // RNG15 ranges are in 8 mm units, RNG15 NEAR_IR in 16s
};

inline uint16_t Load16(const uint8_t* p) {
    uint16_t v;
    std::memcpy(&v, p, 2);
    return v;
}
inline uint32_t Load32(const uint8_t* p) {
    uint32_t v;
    std::memcpy(&v, p, 4);
    return v;
}
inline uint64_t Load64(const uint8_t* p) {
    uint64_t v;
    std::memcpy(&v, p, 8);
    return v;
}

class PacketFormat {
public:
    // Throws common::Error (kInvalidArgument) when the metadata describes something no packet
    // can hold (a column count not divisible, an unknown profile).
    explicit PacketFormat(const SensorInfo& info);

    LidarProfile profile() const { return profile_; }
    HeaderType header_type() const { return header_type_; }
    int pixels_per_column() const { return h_; }
    int columns_per_frame() const { return w_; }
    int columns_per_packet() const { return columns_per_packet_; }
    size_t lidar_packet_size() const { return lidar_packet_size_; }
    // LEGACY IMU packets are 48 bytes; ACCEL32_GYRO32_NMEA ones depend on the sample count.
    size_t imu_packet_size() const { return imu_packet_size_; }
    bool legacy() const { return profile_ == LidarProfile::kLegacy; }
    const std::vector<FieldSpec>& fields() const { return fields_; }
    bool Has(Field f) const;
    // Bytes per pixel, and 32-bit words per pixel (RAW32_WORDn of the SDK).
    size_t pixel_size() const { return pixel_size_; }

    // Packet header (not LEGACY). STANDARD: packet_type 0,16 frame_id 16,16 init_id 32,24
    // prod_sn 56,40. FUSA: packet_type 0,8 init_id 8,24 frame_id 32,32 prod_sn 88,40.
    uint32_t PacketType(const uint8_t* p) const;
    uint32_t FrameId(const uint8_t* p) const;  // LEGACY: the frame id of the first column
    uint32_t InitId(const uint8_t* p) const;
    uint64_t ProdSn(const uint8_t* p) const;
    // The CRC-64 footer (last 8 bytes of the packet); 0 when absent or unset.
    uint64_t FooterCrc(const uint8_t* p) const;
    // FW 3.x fills the footer with a CRC-64. FW 2.x does not: 2.2 leaves it zero, but 2.3 sends a
    // constant marker there (0x0000C0DE 0xDEADBEEF in every packet of the shared OS-2-128 and
    // OS-0-128 captures), so a non-zero footer is a CRC only from FW 3.0 on. Unknown firmware
    // (metadata without build_rev): not checked.
    bool HasCrcFooter() const { return crc_footer_; }

    // Column c (0 <= c < columns_per_packet) and its header.
    const uint8_t* Column(const uint8_t* p, int c) const {
        return p + packet_header_size_ + static_cast<size_t>(c) * column_size_;
    }
    uint64_t ColumnTimestamp(const uint8_t* col) const { return Load64(col); }
    uint16_t MeasurementId(const uint8_t* col) const { return Load16(col + 8); }
    // LEGACY: the 32-bit status after the pixels; others: the 16 bits at 80-95 of the header.
    uint32_t ColumnStatus(const uint8_t* col) const {
        return legacy() ? Load32(col + column_header_size_ + h_ * pixel_size_) : Load16(col + 10);
    }
    // LEGACY only (0 otherwise): per-column frame id and encoder count.
    uint16_t ColumnFrameId(const uint8_t* col) const { return legacy() ? Load16(col + 10) : 0; }
    uint32_t EncoderCount(const uint8_t* col) const { return legacy() ? Load32(col + 12) : 0; }
    const uint8_t* Pixels(const uint8_t* col) const { return col + column_header_size_; }

private:
    LidarProfile profile_;
    HeaderType header_type_;
    int h_ = 0, w_ = 0, columns_per_packet_ = 0;
    size_t packet_header_size_ = 0, column_header_size_ = 0, pixel_size_ = 0;
    size_t column_size_ = 0, packet_footer_size_ = 0;
    size_t lidar_packet_size_ = 0, imu_packet_size_ = 0;
    bool crc_footer_ = false;
    std::vector<FieldSpec> fields_;
};

}  // namespace bimslam::ouster
