// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "drivers/ouster/crc64.hpp"

#include <array>
#include <cstring>

#ifdef BIMSLAM_CRC64_LIBLZMA
#include <lzma.h>
#endif

namespace bimslam::ouster {
namespace {
constexpr uint64_t kPoly = 0xC96C5795D7870F42ull;  // ECMA-182, reflected

struct Tables {
    std::array<std::array<uint64_t, 256>, 8> t{};
    constexpr Tables() {
        for (uint64_t i = 0; i < 256; ++i) {
            uint64_t c = i;
            for (int k = 0; k < 8; ++k) c = (c & 1) ? (c >> 1) ^ kPoly : c >> 1;
            t[0][i] = c;
        }
        // t[k][i]: the CRC of byte i followed by k zero bytes, for eight bytes at a time.
        for (int k = 1; k < 8; ++k) {
            for (int i = 0; i < 256; ++i) t[k][i] = (t[k - 1][i] >> 8) ^ t[0][t[k - 1][i] & 0xFF];
        }
    }
};
constexpr Tables kTables;
}  // namespace

uint64_t Crc64XzTable(const uint8_t* data, size_t size) {
    const auto& t = kTables.t;
    uint64_t crc = ~uint64_t{0};
    while (size >= 8) {
        uint64_t w;
        std::memcpy(&w, data, 8);  // little-endian host assumed (x86-64, aarch64)
        crc ^= w;
        crc = t[7][crc & 0xFF] ^ t[6][(crc >> 8) & 0xFF] ^ t[5][(crc >> 16) & 0xFF] ^
              t[4][(crc >> 24) & 0xFF] ^ t[3][(crc >> 32) & 0xFF] ^ t[2][(crc >> 40) & 0xFF] ^
              t[1][(crc >> 48) & 0xFF] ^ t[0][crc >> 56];
        data += 8;
        size -= 8;
    }
    while (size-- > 0) crc = (crc >> 8) ^ t[0][(crc ^ *data++) & 0xFF];
    return ~crc;
}

uint64_t Crc64Xz(const uint8_t* data, size_t size) {
#ifdef BIMSLAM_CRC64_LIBLZMA
    return lzma_crc64(data, size, 0);  // 0 starts a new CRC; init and final xor are its own
#else
    return Crc64XzTable(data, size);
#endif
}

}  // namespace bimslam::ouster
