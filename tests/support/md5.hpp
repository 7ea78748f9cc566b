// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// MD5 (RFC 1321), to compare decoded data with the Ouster SDK's digests (shared/data/ouster/
// *_digest.json). Test support only: MD5 is no security measure here, just a fingerprint.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

namespace bimslam::test {

class Md5 {
public:
    Md5();
    void Update(const void* data, size_t size);
    // The digest as 32 lowercase hex digits; the object must not be updated afterwards.
    std::string HexDigest();

private:
    void Block(const uint8_t* block);
    std::array<uint32_t, 4> state_;
    std::array<uint8_t, 64> buffer_{};
    uint64_t length_ = 0;  // bytes
};

std::string Md5Hex(const void* data, size_t size);

}  // namespace bimslam::test
