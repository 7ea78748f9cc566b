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

// PNG (ISO/IEC 15948): IHDR, one zlib-compressed IDAT, IEND. Atomic; throws common::FileError.
void WritePng(const std::filesystem::path& path, const Image& image);
std::string EncodePng(const Image& image);

// Binary PGM (P5) of a grey image. Atomic; throws common::FileError.
void WritePgm(const std::filesystem::path& path, const Image& image);

}  // namespace bimslam::io
