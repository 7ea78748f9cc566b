// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// CRC-64/XZ (ECMA-182 polynomial, reflected form 0xC96C5795D7870F42, init and final xor all
// ones; check value of "123456789" is 0x995DC9BBDF1939FA): the footer of Ouster packets from
// FW 3.x (specs/ouster-lidar.md, "Footer").
#pragma once

#include <cstddef>
#include <cstdint>

namespace bimslam::ouster {

// The packet footer's CRC. On x86-64 it is liblzma's lzma_crc64 (carry-less multiplication: 3x
// our table's speed on a quiet machine); elsewhere, the aarch64 rig included, Crc64XzTable, because liblzma 5.4 has
// no such path there and falls back to a slice-by-4 table, 0.64x ours (ARCHITECTURE.md, "What we
// write by hand").
uint64_t Crc64Xz(const uint8_t* data, size_t size);

// Slice-by-8 table lookup (~8x bytewise), on every architecture: Crc64Xz off x86-64, and the
// reference the tests hold liblzma to.
uint64_t Crc64XzTable(const uint8_t* data, size_t size);

}  // namespace bimslam::ouster
