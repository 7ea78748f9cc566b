// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// A rig map package's header made to agree with its bytes (algorithms/localization/README.md,
// "The rig map format": the size at byte 16, the contents' CRC-32 at 24, the header's at 28), so
// that a cut or mutated package gets past the checksums to the section parser: the sanitized
// tests and the fuzz target test what the parser does with bytes the CRC would otherwise hide.
#pragma once

#include <zlib.h>

#include <cstdint>
#include <cstring>
#include <string>

namespace bimslam::test {

inline void MakeRigMapHeaderAgree(std::string* bytes) {
    constexpr size_t kHeader = 32;
    if (bytes->size() < kHeader) return;
    const auto crc = [](const char* p, size_t n) {
        return uint32_t(crc32(crc32(0L, Z_NULL, 0), reinterpret_cast<const Bytef*>(p), uInt(n)));
    };
    const uint64_t size = bytes->size();
    std::memcpy(bytes->data() + 16, &size, sizeof size);
    const uint32_t body = crc(bytes->data() + kHeader, bytes->size() - kHeader);
    std::memcpy(bytes->data() + 24, &body, sizeof body);
    const uint32_t header = crc(bytes->data(), 28);
    std::memcpy(bytes->data() + 28, &header, sizeof header);
}

}  // namespace bimslam::test
