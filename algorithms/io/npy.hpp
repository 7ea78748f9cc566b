// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// NumPy .npy arrays (format versions 1.0, 2.0 and 3.0,
// https://numpy.org/doc/stable/reference/generated/numpy.lib.format.html), for handing images,
// descriptors and matrices to Python tools.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace bimslam::io {

// An n-dimensional array in C (row-major) order with a little-endian numpy dtype
// ("<f4", "<f8", "|u1", "|i1", "<u2", "<i2", "<u4", "<i4", "<u8", "<i8", "|b1").
struct NpyArray {
    std::string dtype;
    std::vector<size_t> shape;
    std::vector<uint8_t> data;  // element count * item size bytes

    size_t ItemSize() const;
    size_t ElementCount() const;

    // Typed views; throw common::Error (kInvalidArgument) when T does not match dtype or data
    // does not hold ElementCount() values. T is one of float, double, uint8_t, int8_t, uint16_t,
    // int16_t, uint32_t, int32_t, uint64_t, int64_t, bool (instantiated in npy.cpp).
    template <typename T>
    const T* As() const;
    // Copies product(shape) values (1 for an empty shape, numpy's 0-d array).
    template <typename T>
    static NpyArray From(const T* values, std::vector<size_t> shape);
};

// Writes format 1.0, or 2.0 when the header does not fit 1.0's 16-bit length, with the header
// numpy writes: the dict with sorted keys, numpy's spare room for growing the first axis, spaces
// to a 64-byte boundary and '\n'. Throws common::FileError naming the file on an unknown dtype or
// a data size that does not match the shape.
void WriteNpy(const std::filesystem::path& path, const NpyArray& array);

// Reads .npy files of format 1.0, 2.0 and 3.0; rejects (common::FileError naming the file, no
// line) a wrong magic, an unsupported version, a malformed header dict, fortran_order True, a
// big-endian, structured, object or other unsupported dtype, a shape whose size overflows, data
// shorter or longer than the shape says, and bool bytes other than 0 and 1. The 1-byte dtypes
// are accepted with '|' or '<' and returned in the canonical form above.
NpyArray ReadNpy(const std::filesystem::path& path);

NpyArray ParseNpy(const std::string& name, std::string_view bytes);
// Throws common::Error (kInvalidArgument) where WriteNpy throws FileError.
std::string SerializeNpy(const NpyArray& array);

}  // namespace bimslam::io
