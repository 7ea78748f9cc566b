// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// CRC-64/XZ (ECMA-182 polynomial, reflected form 0xC96C5795D7870F42, init and final xor all
// ones; check value of "123456789" is 0x995DC9BBDF1939FA): the footer of Ouster packets from
// FW 3.x (specs/ouster-lidar.md, "Footer").
#pragma once

#include <cstddef>
#include <cstdint>

namespace bimslam::ouster {

// Slice-by-8 table lookup: ~8x faster than bytewise, so checking every packet of a 2048x10
// OS-128 stream stays far below one core.
uint64_t Crc64Xz(const uint8_t* data, size_t size);

}  // namespace bimslam::ouster
