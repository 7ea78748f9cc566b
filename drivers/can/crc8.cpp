// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "drivers/can/crc8.hpp"

#include <array>

namespace bimslam::can {
namespace {
constexpr uint8_t kPoly = 0x1D;  // x^8 + x^4 + x^3 + x^2 + 1, MSB first (not reflected)

constexpr std::array<uint8_t, 256> MakeTable() {
    std::array<uint8_t, 256> t{};
    for (int i = 0; i < 256; ++i) {
        uint8_t c = static_cast<uint8_t>(i);
        for (int k = 0; k < 8; ++k) {
            c = (c & 0x80) ? static_cast<uint8_t>((c << 1) ^ kPoly) : static_cast<uint8_t>(c << 1);
        }
        t[static_cast<size_t>(i)] = c;
    }
    return t;
}
constexpr std::array<uint8_t, 256> kTable = MakeTable();

inline uint8_t Step(uint8_t crc, uint8_t byte) { return kTable[crc ^ byte]; }
}  // namespace

uint8_t Crc8SaeJ1850(const uint8_t* data, size_t size) {
    uint8_t crc = 0xFF;
    for (size_t i = 0; i < size; ++i) crc = Step(crc, data[i]);
    return static_cast<uint8_t>(crc ^ 0xFF);
}

uint8_t Go1FrameCrc(uint32_t can_id, const uint8_t* data) {
    uint8_t crc = 0xFF;
    crc = Step(crc, static_cast<uint8_t>(can_id & 0xFF));
    crc = Step(crc, static_cast<uint8_t>((can_id >> 8) & 0xFF));
    for (int i = 1; i < 8; ++i) crc = Step(crc, data[i]);
    return static_cast<uint8_t>(crc ^ 0xFF);
}

}  // namespace bimslam::can
