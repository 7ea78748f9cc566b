// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// CRC-8/SAE-J1850 (polynomial 0x1D, init 0xFF, final xor 0xFF, neither input nor output
// reflected; check value of "123456789" is 0x4B): byte 0 of every Go1 frame (specs/go1-can.md,
// "Rules every frame follows"; the DBC's network comment says the same).
#pragma once

#include <cstddef>
#include <cstdint>

namespace bimslam::can {

// The CRC of `size` bytes, table driven (one lookup per byte).
uint8_t Crc8SaeJ1850(const uint8_t* data, size_t size);

// The CRC a Go1 frame carries in byte 0: over the CAN identifier's low byte, its high byte, then
// data bytes 1..7 (the AUTOSAR E2E profile-1 style "Data ID" prefix, so that a frame copied to
// another identifier fails the check). `data` holds the 8 data bytes; byte 0 is not read.
uint8_t Go1FrameCrc(uint32_t can_id, const uint8_t* data);

}  // namespace bimslam::can
