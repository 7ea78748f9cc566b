// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "drivers/can/crc8.hpp"

#include <gtest/gtest.h>

#include <array>
#include <random>
#include <string>
#include <vector>

namespace bimslam::can {
namespace {
namespace BIMSLAM_UNITY_ID {

// Bit by bit, straight from the definition: the reference the table must reproduce.
uint8_t Reference(const std::vector<uint8_t>& data) {
    uint8_t c = 0xFF;
    for (uint8_t b : data) {
        c ^= b;
        for (int k = 0; k < 8; ++k) c = (c & 0x80) ? uint8_t((c << 1) ^ 0x1D) : uint8_t(c << 1);
    }
    return c ^ 0xFF;
}

TEST(Crc8, CheckValueOf123456789Is0x4B) {
    const std::string s = "123456789";
    EXPECT_EQ(Crc8SaeJ1850(reinterpret_cast<const uint8_t*>(s.data()), s.size()), 0x4B);
}

TEST(Crc8, AutosarCrcLibraryExamples) {
    // AUTOSAR SWS CRC Library, Crc_CalculateCRC8 (SAE J1850) examples.
    const std::vector<std::pair<std::vector<uint8_t>, uint8_t>> cases = {
        {{0x00, 0x00, 0x00, 0x00}, 0x59},
        {{0xF2, 0x01, 0x83}, 0x37},
        {{0x0F, 0xAA, 0x00, 0x55}, 0x79},
        {{0x00, 0xFF, 0x55, 0x11}, 0xB8},
        {{0x33, 0x22, 0x55, 0xAA, 0xBB, 0xCC, 0xDD, 0xEE, 0xFF}, 0xCB},
        {{0x92, 0x6B, 0x55}, 0x8C},
        {{0xFF, 0xFF, 0xFF, 0xFF}, 0x74},
    };
    for (const auto& [bytes, crc] : cases) {
        EXPECT_EQ(Crc8SaeJ1850(bytes.data(), bytes.size()), crc);
    }
    EXPECT_EQ(Crc8SaeJ1850(nullptr, 0), 0x00);  // init 0xFF, final xor 0xFF
}

TEST(Crc8, TableMatchesTheBitwiseDefinition) {
    std::mt19937 rng(7);
    for (int i = 0; i < 2000; ++i) {
        std::vector<uint8_t> d(rng() % 20);
        for (auto& b : d) b = static_cast<uint8_t>(rng());
        ASSERT_EQ(Crc8SaeJ1850(d.data(), d.size()), Reference(d));
    }
}

TEST(Crc8, Go1FrameCrcCoversIdLowIdHighAndBytes1To7) {
    std::mt19937 rng(3);
    for (int i = 0; i < 500; ++i) {
        const uint32_t id = rng() & 0x7FF;
        std::array<uint8_t, 8> d{};
        for (auto& b : d) b = static_cast<uint8_t>(rng());
        const std::vector<uint8_t> covered = {
            uint8_t(id & 0xFF), uint8_t(id >> 8), d[1], d[2], d[3], d[4], d[5], d[6], d[7]};
        const uint8_t crc = Go1FrameCrc(id, d.data());
        ASSERT_EQ(crc, Reference(covered));
        d[0] ^= 0xFF;  // byte 0 (the CRC itself) is not covered
        ASSERT_EQ(Go1FrameCrc(id, d.data()), crc);
    }
    // Hand-checked: id 0x100, bytes 1..7 = 01..07.
    const std::array<uint8_t, 8> d = {0, 1, 2, 3, 4, 5, 6, 7};
    EXPECT_EQ(Go1FrameCrc(0x100, d.data()), 0x6D);
    // The id is covered: the same bytes under another id fail.
    EXPECT_NE(Go1FrameCrc(0x101, d.data()), 0x6D);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::can
