// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/io/image.hpp"

#include <zlib.h>

#include "algorithms/common/status.hpp"
#include "algorithms/io/file_util.hpp"

namespace bimslam::io {
namespace {
void Put32(std::string& out, uint32_t v) {
    for (int s = 24; s >= 0; s -= 8) out += static_cast<char>((v >> s) & 0xFF);
}

// A PNG chunk: length, type, data, CRC-32 over type and data (ISO/IEC 15948, 5.3).
void Chunk(std::string& out, const char* type, const std::string& data) {
    Put32(out, static_cast<uint32_t>(data.size()));
    const std::string body = std::string(type, 4) + data;
    out += body;
    Put32(out, static_cast<uint32_t>(
                   crc32(0, reinterpret_cast<const Bytef*>(body.data()), uInt(body.size()))));
}

void Check(const Image& image, const std::string& what) {
    const bool ok = image.width > 0 && image.height > 0 &&
                    (image.channels == 1 || image.channels == 3) &&
                    image.data.size() == size_t(image.width) * image.height * image.channels;
    if (!ok) {
        throw common::Error(common::StatusCode::kInvalidArgument,
                            what + ": image of " + std::to_string(image.width) + "x" +
                                std::to_string(image.height) + "x" +
                                std::to_string(image.channels) + " with " +
                                std::to_string(image.data.size()) + " bytes");
    }
}
}  // namespace

std::string EncodePng(const Image& image) {
    Check(image, "PNG");
    std::string out("\x89PNG\r\n\x1a\n", 8);
    std::string ihdr;
    Put32(ihdr, uint32_t(image.width));
    Put32(ihdr, uint32_t(image.height));
    ihdr += char(8);                            // bit depth
    ihdr += char(image.channels == 1 ? 0 : 2);  // colour type: grey or RGB
    ihdr += std::string("\0\0\0", 3);           // deflate, adaptive filters, no interlace
    Chunk(out, "IHDR", ihdr);
    // Every scanline with filter type 0 (none), then deflate.
    const size_t row = size_t(image.width) * image.channels;
    std::string raw;
    raw.reserve((row + 1) * image.height);
    for (int y = 0; y < image.height; ++y) {
        raw += '\0';
        raw.append(reinterpret_cast<const char*>(image.At(0, y)), row);
    }
    uLongf size = compressBound(uLong(raw.size()));
    std::string z(size, '\0');
    if (compress2(reinterpret_cast<Bytef*>(z.data()), &size,
                  reinterpret_cast<const Bytef*>(raw.data()), uLong(raw.size()), 6) != Z_OK) {
        throw common::Error(common::StatusCode::kInternal, "PNG: zlib compression failed");
    }
    z.resize(size);
    Chunk(out, "IDAT", z);
    Chunk(out, "IEND", "");
    return out;
}

void WritePng(const std::filesystem::path& path, const Image& image) {
    WriteFileAtomic(path, EncodePng(image));
}

void WritePgm(const std::filesystem::path& path, const Image& image) {
    Check(image, path.string());
    if (image.channels != 1) {
        throw common::FileError(common::StatusCode::kInvalidArgument, path.string(), 0,
                                "PGM holds grey images only");
    }
    std::string out =
        "P5\n" + std::to_string(image.width) + " " + std::to_string(image.height) + "\n255\n";
    out.append(reinterpret_cast<const char*>(image.data.data()), image.data.size());
    WriteFileAtomic(path, out);
}

}  // namespace bimslam::io
