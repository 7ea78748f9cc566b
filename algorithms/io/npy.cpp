// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/io/npy.hpp"

#include <bit>
#include <cstring>
#include <limits>

#include "algorithms/common/status.hpp"
#include "algorithms/io/file_util.hpp"

namespace bimslam::io {
namespace {
using common::Error;
using common::FileError;
using common::StatusCode;

// The data is kept in the file's little-endian byte order and viewed in place by As<T>.
static_assert(std::endian::native == std::endian::little, "npy views assume a little-endian host");

// "\x93NUMPY", major, minor (format spec, "Format Version 1.0").
constexpr std::string_view kMagic("\x93NUMPY", 6);
constexpr size_t kAlign = 64;
constexpr size_t kGrowthAxisMaxDigits = 21;  // numpy.lib.format.GROWTH_AXIS_MAX_DIGITS

struct Dtype {
    std::string_view name;
    size_t size;
};
constexpr Dtype kDtypes[] = {{"<f4", 4}, {"<f8", 8}, {"|u1", 1}, {"|i1", 1}, {"<u2", 2}, {"<i2", 2},
                             {"<u4", 4}, {"<i4", 4}, {"<u8", 8}, {"<i8", 8}, {"|b1", 1}};

// The item size of a canonical dtype, or 0.
size_t DtypeSize(std::string_view dtype) {
    for (const Dtype& d : kDtypes) {
        if (d.name == dtype) return d.size;
    }
    return 0;
}

template <typename T>
constexpr std::string_view DtypeOf() {
    if constexpr (std::is_same_v<T, float>) return "<f4";
    if constexpr (std::is_same_v<T, double>) return "<f8";
    if constexpr (std::is_same_v<T, uint8_t>) return "|u1";
    if constexpr (std::is_same_v<T, int8_t>) return "|i1";
    if constexpr (std::is_same_v<T, uint16_t>) return "<u2";
    if constexpr (std::is_same_v<T, int16_t>) return "<i2";
    if constexpr (std::is_same_v<T, uint32_t>) return "<u4";
    if constexpr (std::is_same_v<T, int32_t>) return "<i4";
    if constexpr (std::is_same_v<T, uint64_t>) return "<u8";
    if constexpr (std::is_same_v<T, int64_t>) return "<i8";
    if constexpr (std::is_same_v<T, bool>) return "|b1";
}

// Product of the shape, or false on overflow.
bool CountOf(const std::vector<size_t>& shape, size_t& count) {
    count = 1;
    for (size_t d : shape) {
        if (d != 0 && count > std::numeric_limits<size_t>::max() / d) return false;
        count *= d;
    }
    return true;
}

// A parser for the header: a Python dict literal as repr() writes it (ast.literal_eval accepts
// more, e.g. comments or nested containers, which numpy never writes and we reject).
class DictParser {
public:
    DictParser(const std::string& name, std::string_view text) : name_(name), text_(text) {}

    [[noreturn]] void Fail(const std::string& what) const {
        throw FileError(StatusCode::kParseError, name_, 0, "npy header: " + what);
    }

    void Parse(std::string& descr, bool& fortran, std::vector<size_t>& shape) {
        bool have_descr = false, have_fortran = false, have_shape = false;
        Expect('{');
        while (!Peek('}')) {
            const std::string key = ParseString();
            Expect(':');
            if (key == "descr") {
                if (have_descr) Fail("'descr' twice");
                have_descr = true;
                if (!Peek('\'') && !Peek('"')) Fail("'descr' is not a string (structured dtype?)");
                descr = ParseString();
            } else if (key == "fortran_order") {
                if (have_fortran) Fail("'fortran_order' twice");
                have_fortran = true;
                fortran = ParseBool();
            } else if (key == "shape") {
                if (have_shape) Fail("'shape' twice");
                have_shape = true;
                ParseShape(shape);
            } else {
                Fail("unexpected key '" + key.substr(0, 40) + "'");
            }
            if (!Peek('}')) Expect(',');
        }
        Expect('}');
        SkipSpace();
        if (pos_ != text_.size()) Fail("text after the dict");
        if (!have_descr || !have_fortran || !have_shape) {
            Fail("the dict needs 'descr', 'fortran_order' and 'shape'");
        }
    }

private:
    void SkipSpace() {
        while (pos_ < text_.size() && (text_[pos_] == ' ' || text_[pos_] == '\n' ||
                                       text_[pos_] == '\t' || text_[pos_] == '\r')) {
            ++pos_;
        }
    }
    bool Peek(char c) {
        SkipSpace();
        return pos_ < text_.size() && text_[pos_] == c;
    }
    void Expect(char c) {
        if (!Peek(c)) Fail(std::string("expected '") + c + "'");
        ++pos_;
    }
    std::string ParseString() {
        SkipSpace();
        if (pos_ >= text_.size() || (text_[pos_] != '\'' && text_[pos_] != '"')) {
            Fail("expected a string");
        }
        const char quote = text_[pos_++];
        const size_t end = text_.find(quote, pos_);
        if (end == std::string_view::npos) Fail("unterminated string");
        std::string s(text_.substr(pos_, end - pos_));
        if (s.find('\\') != std::string::npos) Fail("escapes in a string");
        pos_ = end + 1;
        return s;
    }
    bool ParseBool() {
        SkipSpace();
        for (const auto& [word, value] : {std::pair{"True", true}, std::pair{"False", false}}) {
            if (text_.substr(pos_).starts_with(word)) {
                pos_ += std::strlen(word);
                return value;
            }
        }
        Fail("expected True or False");
    }
    void ParseShape(std::vector<size_t>& shape) {
        Expect('(');
        shape.clear();
        bool trailing_comma = false;
        while (!Peek(')')) {
            size_t v = 0;
            const size_t start = pos_;
            while (pos_ < text_.size() && text_[pos_] >= '0' && text_[pos_] <= '9') {
                const size_t digit = static_cast<size_t>(text_[pos_++] - '0');
                if (v > (std::numeric_limits<size_t>::max() - digit) / 10) Fail("shape overflows");
                v = v * 10 + digit;
            }
            if (pos_ == start) Fail("a shape entry is not a non-negative integer");
            if (pos_ < text_.size() && text_[pos_] == 'L') ++pos_;    // Python 2 long
            if (shape.size() >= 64) Fail("more than 64 dimensions");  // numpy's NPY_MAXDIMS
            shape.push_back(v);
            trailing_comma = Peek(',');
            if (trailing_comma) {
                ++pos_;
            } else if (!Peek(')')) {
                Fail("expected ',' or ')' in the shape");
            }
        }
        // Python: "(5)" is the int 5, not a tuple.
        if (shape.size() == 1 && !trailing_comma) Fail("shape (n) is not a tuple, expected (n,)");
        Expect(')');
    }

    const std::string& name_;
    std::string_view text_;
    size_t pos_ = 0;
};

template <typename T>
T Load(std::string_view bytes, size_t at) {
    T v;
    std::memcpy(&v, bytes.data() + at, sizeof(T));
    return v;
}
}  // namespace

size_t NpyArray::ItemSize() const {
    const size_t size = DtypeSize(dtype);
    if (size == 0) throw Error(StatusCode::kInvalidArgument, "unsupported npy dtype " + dtype);
    return size;
}

size_t NpyArray::ElementCount() const {
    size_t count = 0;
    if (!CountOf(shape, count)) throw Error(StatusCode::kInvalidArgument, "npy shape overflows");
    return count;
}

template <typename T>
const T* NpyArray::As() const {
    if (dtype != DtypeOf<T>()) {
        throw Error(StatusCode::kInvalidArgument,
                    "npy array of dtype " + dtype + " viewed as " + std::string(DtypeOf<T>()));
    }
    if (data.size() / sizeof(T) != ElementCount() || data.size() % sizeof(T) != 0) {
        throw Error(StatusCode::kInvalidArgument, "npy data size does not match its shape");
    }
    // vector storage comes from operator new, aligned for every dtype here.
    return reinterpret_cast<const T*>(data.data());
}

template <typename T>
NpyArray NpyArray::From(const T* values, std::vector<size_t> shape) {
    NpyArray a;
    a.dtype = std::string(DtypeOf<T>());
    a.shape = std::move(shape);
    const size_t n = a.ElementCount();
    if (n > std::numeric_limits<size_t>::max() / sizeof(T)) {
        throw Error(StatusCode::kInvalidArgument, "npy shape overflows");
    }
    if (n > 0 && values == nullptr) throw Error(StatusCode::kInvalidArgument, "null values");
    a.data.resize(n * sizeof(T));
    if (n > 0) std::memcpy(a.data.data(), values, n * sizeof(T));
    return a;
}

#define BIMSLAM_NPY_INSTANTIATE(T)             \
    template const T* NpyArray::As<T>() const; \
    template NpyArray NpyArray::From<T>(const T*, std::vector<size_t>);
BIMSLAM_NPY_INSTANTIATE(float)
BIMSLAM_NPY_INSTANTIATE(double)
BIMSLAM_NPY_INSTANTIATE(uint8_t)
BIMSLAM_NPY_INSTANTIATE(int8_t)
BIMSLAM_NPY_INSTANTIATE(uint16_t)
BIMSLAM_NPY_INSTANTIATE(int16_t)
BIMSLAM_NPY_INSTANTIATE(uint32_t)
BIMSLAM_NPY_INSTANTIATE(int32_t)
BIMSLAM_NPY_INSTANTIATE(uint64_t)
BIMSLAM_NPY_INSTANTIATE(int64_t)
BIMSLAM_NPY_INSTANTIATE(bool)
#undef BIMSLAM_NPY_INSTANTIATE

NpyArray ParseNpy(const std::string& name, std::string_view bytes) {
    auto fail = [&name](StatusCode code, const std::string& what) {
        throw FileError(code, name, 0, what);
    };
    if (bytes.size() < 10 || bytes.substr(0, 6) != kMagic) {
        fail(bytes.size() < 10 && kMagic.starts_with(bytes) ? StatusCode::kDataLoss
                                                            : StatusCode::kParseError,
             "not an npy file (no \\x93NUMPY magic)");
    }
    const uint8_t major = static_cast<uint8_t>(bytes[6]), minor = static_cast<uint8_t>(bytes[7]);
    if (major < 1 || major > 3 || minor != 0) {
        fail(StatusCode::kParseError, "unsupported npy format version " + std::to_string(major) +
                                          "." + std::to_string(minor));
    }
    // 1.0: uint16 header length; 2.0 and 3.0 (UTF-8 header): uint32.
    size_t header_len = 0, start = 10;
    if (major == 1) {
        header_len = Load<uint16_t>(bytes, 8);
    } else {
        if (bytes.size() < 12) fail(StatusCode::kDataLoss, "the file ends in the preamble");
        header_len = Load<uint32_t>(bytes, 8);
        start = 12;
    }
    if (header_len > bytes.size() - start) {
        fail(StatusCode::kDataLoss,
             "header length " + std::to_string(header_len) + " runs past the end of the file");
    }
    NpyArray a;
    bool fortran = false;
    DictParser(name, bytes.substr(start, header_len)).Parse(a.dtype, fortran, a.shape);
    if (fortran) fail(StatusCode::kParseError, "fortran_order True is not supported");
    // numpy writes '|' for 1-byte types; '<' there means the same.
    if (a.dtype.size() == 3 && a.dtype[0] == '<' && a.dtype[2] == '1') a.dtype[0] = '|';
    if (DtypeSize(a.dtype) == 0) {
        fail(StatusCode::kParseError, "unsupported dtype '" + a.dtype.substr(0, 40) + "'" +
                                          (a.dtype.starts_with(">") ? " (big-endian)" : ""));
    }
    size_t count = 0;
    if (!CountOf(a.shape, count) || count > std::numeric_limits<size_t>::max() / a.ItemSize()) {
        fail(StatusCode::kParseError, "the shape's size overflows");
    }
    const std::string_view body = bytes.substr(start + header_len);
    if (body.size() != count * a.ItemSize()) {
        fail(body.size() < count * a.ItemSize() ? StatusCode::kDataLoss : StatusCode::kParseError,
             "the shape needs " + std::to_string(count * a.ItemSize()) +
                 " bytes of data, the file has " + std::to_string(body.size()));
    }
    if (a.dtype == "|b1") {
        for (size_t i = 0; i < body.size(); ++i) {
            if (body[i] != 0 && body[i] != 1) {
                fail(StatusCode::kParseError,
                     "bool element " + std::to_string(i) + " is neither 0 nor 1");
            }
        }
    }
    a.data.assign(body.begin(), body.end());
    return a;
}

NpyArray ReadNpy(const std::filesystem::path& path) {
    const std::string bytes = ReadFileToString(path);
    return ParseNpy(path.string(), bytes);
}

std::string SerializeNpy(const NpyArray& array) {
    if (array.shape.size() > 64) {
        throw Error(StatusCode::kInvalidArgument, "more than 64 dimensions (numpy's limit)");
    }
    if (array.data.size() / array.ItemSize() != array.ElementCount() ||
        array.data.size() % array.ItemSize() != 0) {
        throw Error(StatusCode::kInvalidArgument,
                    "npy data has " + std::to_string(array.data.size()) + " bytes, the shape " +
                        "needs " + std::to_string(array.ElementCount() * array.ItemSize()));
    }
    // numpy.lib.format._write_array_header: repr of the dict with sorted keys.
    std::string dict = "{'descr': '" + array.dtype + "', 'fortran_order': False, 'shape': (";
    for (size_t i = 0; i < array.shape.size(); ++i) {
        if (i > 0) dict += ", ";
        dict += std::to_string(array.shape[i]);
    }
    dict += array.shape.size() == 1 ? ",), }" : "), }";
    if (!array.shape.empty()) {
        const size_t digits = std::to_string(array.shape[0]).size();
        if (digits < kGrowthAxisMaxDigits) dict.append(kGrowthAxisMaxDigits - digits, ' ');
    }
    // _wrap_header: pad with spaces so that the data starts on a 64-byte boundary, end in '\n'.
    // Format 2.0 only when 1.0's uint16 length cannot hold the header (_wrap_header_guess_version).
    auto pad_for = [&dict](size_t prefix) { return kAlign - (prefix + dict.size() + 1) % kAlign; };
    const bool v1 = dict.size() + 1 + pad_for(10) <= 65535;
    const size_t pad = pad_for(v1 ? 10 : 12);
    const size_t header_len = dict.size() + pad + 1;
    std::string out(kMagic);
    out += static_cast<char>(v1 ? 1 : 2);
    out += '\0';
    for (size_t k = 0; k < (v1 ? 2u : 4u); ++k)
        out += static_cast<char>((header_len >> (8 * k)) & 0xff);
    out += dict;
    out.append(pad, ' ');
    out += '\n';
    out.append(reinterpret_cast<const char*>(array.data.data()), array.data.size());
    return out;
}

void WriteNpy(const std::filesystem::path& path, const NpyArray& array) {
    std::string bytes;
    try {
        bytes = SerializeNpy(array);
    } catch (const Error& e) {
        throw FileError(e.code(), path.string(), 0, e.what());
    }
    WriteFileAtomic(path, bytes);
}

}  // namespace bimslam::io
