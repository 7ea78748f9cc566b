// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Images for maps and plots: 8-bit grey or RGB, written as PNG (what every viewer shows) or PGM
// (what ROS map_server reads). Writing only: the project never needs to read them back.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace bimslam::io {

struct Image {
    int width = 0;
    int height = 0;
    int channels = 1;           // 1 grey, 3 RGB
    std::vector<uint8_t> data;  // row-major from the top row, channels interleaved

    Image() = default;
    Image(int w, int h, int c, uint8_t fill = 0)
        : width(w), height(h), channels(c), data(size_t(w) * h * c, fill) {}
    uint8_t* At(int x, int y) { return data.data() + (size_t(y) * width + x) * channels; }
    const uint8_t* At(int x, int y) const {
        return data.data() + (size_t(y) * width + x) * channels;
    }
};

// PNG (ISO/IEC 15948) by libpng. kSmall: zlib level 6 and libpng's adaptive filters, for maps
// and plots (2.4-24 times smaller than unfiltered rows, and 15-20 % faster: ARCHITECTURE.md,
// "What we write by hand"); kFast: level 1 and the Sub filter, for rendered pictures, many and
// small (the BCF snapshots). Throws common::Error (kInternal) when libpng fails.
enum class PngCompression { kSmall, kFast };
std::string EncodePng(const Image& image, PngCompression compression = PngCompression::kSmall);
// Atomic; throws common::FileError naming the file.
void WritePng(const std::filesystem::path& path, const Image& image);

// Binary PGM (P5) of a grey image. Atomic; throws common::FileError.
void WritePgm(const std::filesystem::path& path, const Image& image);

}  // namespace bimslam::io
