// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "drivers/ouster/packet_format.hpp"

#include <string>

#include "algorithms/common/status.hpp"

namespace bimslam::ouster {
namespace {
using F = Field;

// Pixel layouts, specs/ouster-lidar.md (bit offsets within one pixel; word = offset / 32).
std::vector<FieldSpec> FieldsOf(LidarProfile p) {
    switch (p) {
        case LidarProfile::kLegacy:  // RANGE 0-19, FLAGS 28-31, REFL 32-39, SIGNAL 48-63, NIR 64-79
            return {{F::kRange, 0, 0, 0xFFFFF, 1},
                    {F::kFlags, 0, 28, 0xF, 1},
                    {F::kReflectivity, 1, 0, 0xFF, 1},
                    {F::kSignal, 1, 16, 0xFFFF, 1},
                    {F::kNearIr, 2, 0, 0xFFFF, 1}};
        case LidarProfile::kRng19Rfl8Sig16Nir16:  // RANGE 0-18, FLAGS 19-23, REFL 32-39, ...
            return {{F::kRange, 0, 0, 0x7FFFF, 1},
                    {F::kFlags, 0, 19, 0x1F, 1},
                    {F::kReflectivity, 1, 0, 0xFF, 1},
                    {F::kSignal, 1, 16, 0xFFFF, 1},
                    {F::kNearIr, 2, 0, 0xFFFF, 1}};
        case LidarProfile::kRng15Rfl8Nir8:  // RANGE 0-14 x8, FLAGS 15, REFL 16-23, NIR 24-31 x16
            return {{F::kRange, 0, 0, 0x7FFF, 8},
                    {F::kFlags, 0, 15, 0x1, 1},
                    {F::kReflectivity, 0, 16, 0xFF, 1},
                    {F::kNearIr, 0, 24, 0xFF, 16}};
        case LidarProfile::kRng19Rfl8Sig16Nir16Dual:
            return {{F::kRange, 0, 0, 0x7FFFF, 1},      {F::kFlags, 0, 19, 0x1F, 1},
                    {F::kReflectivity, 0, 24, 0xFF, 1}, {F::kRange2, 1, 0, 0x7FFFF, 1},
                    {F::kFlags2, 1, 19, 0x1F, 1},       {F::kReflectivity2, 1, 24, 0xFF, 1},
                    {F::kSignal, 2, 0, 0xFFFF, 1},      {F::kSignal2, 2, 16, 0xFFFF, 1},
                    {F::kNearIr, 3, 0, 0xFFFF, 1}};
        case LidarProfile::kRng15Rfl8Nir8Dual:
        case LidarProfile::kFusaRng15Rfl8Nir8Dual:
            return {{F::kRange, 0, 0, 0x7FFF, 8},       {F::kFlags, 0, 15, 0x1, 1},
                    {F::kReflectivity, 0, 16, 0xFF, 1}, {F::kNearIr, 0, 24, 0xFF, 16},
                    {F::kRange2, 1, 0, 0x7FFF, 8},      {F::kFlags2, 1, 15, 0x1, 1},
                    {F::kReflectivity2, 1, 16, 0xFF, 1}};
    }
    return {};
}

size_t PixelSize(LidarProfile p) {
    switch (p) {
        case LidarProfile::kLegacy:
        case LidarProfile::kRng19Rfl8Sig16Nir16:
            return 12;
        case LidarProfile::kRng15Rfl8Nir8:
            return 4;
        case LidarProfile::kRng19Rfl8Sig16Nir16Dual:
            return 16;
        case LidarProfile::kRng15Rfl8Nir8Dual:
        case LidarProfile::kFusaRng15Rfl8Nir8Dual:
            return 8;
    }
    return 0;
}
}  // namespace

std::string_view ToString(Field f) {
    switch (f) {
        case F::kRange:
            return "RANGE";
        case F::kRange2:
            return "RANGE2";
        case F::kSignal:
            return "SIGNAL";
        case F::kSignal2:
            return "SIGNAL2";
        case F::kReflectivity:
            return "REFLECTIVITY";
        case F::kReflectivity2:
            return "REFLECTIVITY2";
        case F::kNearIr:
            return "NEAR_IR";
        case F::kFlags:
            return "FLAGS";
        case F::kFlags2:
            return "FLAGS2";
    }
    return "?";
}

FieldType TypeOf(Field f) {
    switch (f) {
        case F::kRange:
        case F::kRange2:
            return FieldType::kU32;
        case F::kSignal:
        case F::kSignal2:
        case F::kNearIr:
            return FieldType::kU16;
        default:
            return FieldType::kU8;
    }
}

PacketFormat::PacketFormat(const SensorInfo& info)
    : profile_(info.format.lidar_profile),
      header_type_(info.format.header_type),
      h_(info.format.pixels_per_column),
      w_(info.format.columns_per_frame),
      columns_per_packet_(info.format.columns_per_packet),
      fields_(FieldsOf(info.format.lidar_profile)) {
    if (h_ <= 0 || w_ <= 0 || columns_per_packet_ <= 0 || w_ % columns_per_packet_ != 0) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            info.source + ": no packet layout for " + std::to_string(h_) +
                                " pixels x " + std::to_string(w_) + " columns in packets of " +
                                std::to_string(columns_per_packet_) + " columns");
    }
    pixel_size_ = PixelSize(profile_);
    if (legacy()) {
        // timestamp 8, measurement_id 2, frame_id 2, encoder 4; pixels; status 4.
        column_header_size_ = 16;
        column_size_ = 16 + h_ * pixel_size_ + 4;
    } else {
        packet_header_size_ = 32;
        packet_footer_size_ = 32;
        column_header_size_ = 12;
        column_size_ = 12 + h_ * pixel_size_;
    }
    lidar_packet_size_ =
        packet_header_size_ + columns_per_packet_ * column_size_ + packet_footer_size_;
    crc_footer_ = !legacy() && header_type_ == HeaderType::kStandard && info.fw_major >= 3;
    imu_packet_size_ = info.format.imu_profile == ImuProfile::kLegacy
                           ? 48
                           : 32 + 100 + 36 * size_t(info.format.imu_measurements_per_packet) + 32;
}

bool PacketFormat::Has(Field f) const {
    for (const auto& s : fields_) {
        if (s.field == f) return true;
    }
    return false;
}

uint32_t PacketFormat::PacketType(const uint8_t* p) const {
    if (legacy()) return 1;
    return header_type_ == HeaderType::kFusa ? p[0] : Load16(p);
}

uint32_t PacketFormat::FrameId(const uint8_t* p) const {
    if (legacy()) return ColumnFrameId(Column(p, 0));
    return header_type_ == HeaderType::kFusa ? Load32(p + 4) : Load16(p + 2);
}

uint32_t PacketFormat::InitId(const uint8_t* p) const {
    if (legacy()) return 0;
    return (header_type_ == HeaderType::kFusa ? Load32(p) >> 8 : Load32(p + 4)) & 0xFFFFFF;
}

uint64_t PacketFormat::ProdSn(const uint8_t* p) const {
    if (legacy()) return 0;
    // 40 bits at bit 56 (STANDARD) or 88 (FUSA): byte 7 or 11.
    const uint8_t* s = p + (header_type_ == HeaderType::kFusa ? 11 : 7);
    uint64_t v = 0;
    for (int i = 4; i >= 0; --i) v = (v << 8) | s[i];
    return v;
}

uint64_t PacketFormat::FooterCrc(const uint8_t* p) const {
    return HasCrcFooter() ? Load64(p + lidar_packet_size_ - 8) : 0;
}

}  // namespace bimslam::ouster
