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

    // Typed views; throw common::Error (kInvalidArgument) when T does not match dtype.
    template <typename T>
    const T* As() const;
    template <typename T>
    static NpyArray From(const T* values, std::vector<size_t> shape);
};

void WriteNpy(const std::filesystem::path& path, const NpyArray& array);

// Reads .npy files; rejects (common::FileError naming the file) a wrong magic, an unsupported
// version, a malformed header dict, fortran_order True, a big-endian or object dtype, a shape
// whose size overflows, and data shorter or longer than the shape says.
NpyArray ReadNpy(const std::filesystem::path& path);

NpyArray ParseNpy(const std::string& name, std::string_view bytes);
std::string SerializeNpy(const NpyArray& array);

}  // namespace bimslam::io
