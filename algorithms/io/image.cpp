// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/io/image.hpp"

#include <png.h>

#include <csetjmp>

#include "algorithms/common/status.hpp"
#include "algorithms/io/file_util.hpp"

namespace bimslam::io {
namespace {
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

void Append(png_structp png, png_bytep data, png_size_t n) {
    static_cast<std::string*>(png_get_io_ptr(png))->append(reinterpret_cast<char*>(data), n);
}

// libpng reports errors by longjmp to the setjmp below: nothing in this function's frame needs
// destroying between the two (`out` is the caller's), so the jump skips no destructor.
bool WriteRows(const Image& image, PngCompression compression, std::string* out) {
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    if (!info) {
        png_destroy_write_struct(&png, nullptr);
        return false;
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        return false;
    }
    png_set_write_fn(png, out, Append, nullptr);
    png_set_IHDR(png, info, png_uint_32(image.width), png_uint_32(image.height), 8,
                 image.channels == 3 ? PNG_COLOR_TYPE_RGB : PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    if (compression == PngCompression::kFast) {
        png_set_compression_level(png, 1);
        png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
    } else {
        png_set_compression_level(png, 6);
        png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_ALL_FILTERS);
    }
    png_write_info(png, info);
    for (int y = 0; y < image.height; ++y) png_write_row(png, image.At(0, y));
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    return true;
}
}  // namespace

std::string EncodePng(const Image& image, PngCompression compression) {
    Check(image, "PNG");
    std::string out;
    if (!WriteRows(image, compression, &out)) {
        throw common::Error(common::StatusCode::kInternal,
                            "libpng could not encode a " + std::to_string(image.width) + "x" +
                                std::to_string(image.height) + " image");
    }
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
