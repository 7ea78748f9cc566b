// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include <gtest/gtest.h>
#include <png.h>
#include <zlib.h>

#include "algorithms/io/file_util.hpp"
#include "algorithms/io/image.hpp"
#include "algorithms/io/sha256.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::io {
namespace {
namespace BIMSLAM_UNITY_ID {

uint32_t Get32(const std::string& s, size_t at) {
    return uint32_t(uint8_t(s[at])) << 24 | uint32_t(uint8_t(s[at + 1])) << 16 |
           uint32_t(uint8_t(s[at + 2])) << 8 | uint8_t(s[at + 3]);
}

// The chunks' order and CRCs, then the pixels as libpng's reader decodes them.
void ExpectPngOf(const Image& img, const std::string& png) {
    ASSERT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
    std::vector<std::string> types;
    for (size_t at = 8; at + 12 <= png.size();) {
        const uint32_t len = Get32(png, at);
        const std::string body = png.substr(at + 4, 4 + len);
        types.push_back(body.substr(0, 4));
        EXPECT_EQ(Get32(png, at + 8 + len),
                  crc32(0, reinterpret_cast<const Bytef*>(body.data()), uInt(body.size())));
        if (types.back() == "IHDR") {
            EXPECT_EQ(Get32(body, 4), uint32_t(img.width));
            EXPECT_EQ(Get32(body, 8), uint32_t(img.height));
            EXPECT_EQ(body[13], img.channels == 3 ? 2 : 0);  // RGB or grey
        }
        at += 12 + len;
    }
    ASSERT_GE(types.size(), 3u);
    EXPECT_EQ(types.front(), "IHDR");
    EXPECT_EQ(types.back(), "IEND");
    for (size_t i = 1; i + 1 < types.size(); ++i) EXPECT_EQ(types[i], "IDAT");

    png_image read{};
    read.version = PNG_IMAGE_VERSION;
    ASSERT_TRUE(png_image_begin_read_from_memory(&read, png.data(), png.size())) << read.message;
    read.format = img.channels == 3 ? PNG_FORMAT_RGB : PNG_FORMAT_GRAY;
    std::vector<uint8_t> pixels(PNG_IMAGE_SIZE(read));
    ASSERT_TRUE(png_image_finish_read(&read, nullptr, pixels.data(), 0, nullptr)) << read.message;
    EXPECT_EQ(pixels, img.data);
}

TEST(Png, ChunksCrcsAndPixelsDecodeBack) {
    Image img(5, 3, 3);
    for (size_t i = 0; i < img.data.size(); ++i) img.data[i] = uint8_t(i * 7);
    ExpectPngOf(img, EncodePng(img));
    ExpectPngOf(img, EncodePng(img, PngCompression::kFast));
    // A map-sized grey picture, in several IDAT chunks; the small setting is the smaller file.
    Image grid(700, 300, 1, 205);
    for (int y = 0; y < grid.height; ++y) {
        for (int x = 0; x < grid.width; ++x) {
            if ((x / 20 + y / 20) % 5 == 0 || (x * 31 + y * 17) % 97 == 0) *grid.At(x, y) = 0;
        }
    }
    const std::string small = EncodePng(grid), fast = EncodePng(grid, PngCompression::kFast);
    ExpectPngOf(grid, small);
    ExpectPngOf(grid, fast);
    EXPECT_LT(small.size(), fast.size());
    EXPECT_THROW(EncodePng(Image(0, 3, 1)), common::Error);
    Image bad(2, 2, 3);
    bad.data.pop_back();
    EXPECT_THROW(EncodePng(bad), common::Error);
}

TEST(Pgm, HeaderAndBytes) {
    test::TempDir tmp;
    Image img(4, 2, 1, 205);
    img.At(1, 1)[0] = 0;
    WritePgm(tmp / "m.pgm", img);
    const std::string s = ReadFileToString(tmp / "m.pgm");
    EXPECT_EQ(s.substr(0, 11), "P5\n4 2\n255\n");
    EXPECT_EQ(s.size(), 11u + 8u);
    EXPECT_EQ(uint8_t(s[11 + 5]), 0);
    EXPECT_THROW(WritePgm(tmp / "c.pgm", Image(2, 2, 3)), common::FileError);
}

TEST(Sha256, Fips180Vectors) {
    EXPECT_EQ(Sha256Hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
    EXPECT_EQ(Sha256Hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    EXPECT_EQ(Sha256Hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
              "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
    test::TempDir tmp;
    const std::string million(1'000'000, 'a');
    test::WriteBytes(tmp / "a", million);
    EXPECT_EQ(Sha256File(tmp / "a"),
              "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
    EXPECT_FILE_ERROR(Sha256File(tmp / "missing"), (tmp / "missing").string(), 0);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::io
