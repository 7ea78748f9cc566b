// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "tests/support/md5.hpp"

#include <gtest/gtest.h>

#include <cstring>

namespace bimslam::test {
namespace {
namespace BIMSLAM_UNITY_ID {

TEST(Md5, Rfc1321TestSuite) {
    // RFC 1321, appendix A.5.
    const std::pair<const char*, const char*> cases[] = {
        {"", "d41d8cd98f00b204e9800998ecf8427e"},
        {"a", "0cc175b9c0f1b6a831c399e269772661"},
        {"abc", "900150983cd24fb0d6963f7d28e17f72"},
        {"message digest", "f96b697d7cb7938d525a2f31aaf161d0"},
        {"abcdefghijklmnopqrstuvwxyz", "c3fcd3d76192e4007dfb496cca67e13b"},
        {"12345678901234567890123456789012345678901234567890123456789012345678901234567890",
         "57edf4a22be3c955ac49da2e2107b67a"}};
    for (const auto& [text, digest] : cases) EXPECT_EQ(Md5Hex(text, std::strlen(text)), digest);
    // Streaming in odd pieces gives the same digest.
    const std::string s(1000, 'x');
    Md5 md5;
    for (size_t i = 0; i < s.size(); i += 37)
        md5.Update(s.data() + i, std::min<size_t>(37, s.size() - i));
    EXPECT_EQ(md5.HexDigest(), Md5Hex(s.data(), s.size()));
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::test
